//! The setup of the two-length rotary-table test (Zhu 2008 §5.3): the choice of the table-ball
//! radius R_x and the effect of setup dimensions that are off, against closed forms.

use trueaxis::identify::tmbb::TmbbSetup;
use trueaxis::identify::tmbb_setup::{exact_readings, rx_choice, setup_dimension_sensitivity, TableErrors};

/// 36 table angles over one turn, every 10 deg (no repeated end point).
fn turn() -> Vec<f64> {
    (0..36).map(|i| f64::from(i * 10).to_radians()).collect()
}

#[test]
fn uncertainty_per_bar_noise_is_the_closed_form_and_falls_with_r_x() {
    let setup = TmbbSetup::ZHU_TABLE_5_1;
    let angles = turn();
    let noise = 1e-3; // mm
    let candidates: Vec<f64> = (1..=17).map(|i| 5.0 * i as f64).collect(); // 5 .. 85 mm < L1 = 90.85
    let choices = rx_choice(&setup, &angles, &candidates, noise).unwrap();
    let n = angles.len() as f64;
    let sigma_delta = 2.0 * (setup.l1.powi(2) + setup.l2.powi(2)).sqrt() * noise;
    for c in &choices {
        // a full turn of equally spaced angles: J^T J = diag(4 R_x^2 dH^2 n/2, same, 4 dH^2 n)
        let dh = c.height_difference;
        let u_tilt = sigma_delta / (2.0 * c.rx * dh * (n / 2.0).sqrt());
        let u_dz = sigma_delta / (2.0 * dh * n.sqrt());
        assert!((c.u_ex / u_tilt - 1.0).abs() < 1e-9 && (c.u_ey / u_tilt - 1.0).abs() < 1e-9, "{c:?}");
        assert!((c.u_dz / u_dz - 1.0).abs() < 1e-9, "{c:?}");
        // unit-length columns of a full turn are orthogonal: conditioning is no criterion here
        assert!((c.cond_unit_columns - 1.0).abs() < 1e-9, "{c:?}");
    }
    for w in choices.windows(2) {
        assert!(w[1].u_ex < w[0].u_ex && w[1].u_dz < w[0].u_dz && w[1].height_difference > w[0].height_difference);
    }
    // the thesis's R_x = 71.842 mm, 36 angles: 1 um of bar noise gives 5.16 urad (1.06 arcsec) of
    // tilt and 0.26 um of D_z
    let chosen = &rx_choice(&setup, &angles, &[setup.rx], noise).unwrap()[0];
    eprintln!("R_x = {}: u(E_x) = {:.3} urad, u(D_z) = {:.3} um per um of bar noise", setup.rx, chosen.u_ex * 1e6, chosen.u_dz * 1e3);
    assert!((5.1..5.2).contains(&(chosen.u_ex * 1e6)) && (0.25..0.27).contains(&(chosen.u_dz * 1e3)));
}

#[test]
fn setup_dimensions_off_act_as_their_closed_forms() {
    let setup = TmbbSetup::ZHU_TABLE_5_1;
    let angles = turn();
    let arcsec = std::f64::consts::PI / 180.0 / 3600.0;
    // the example's table: 8 / 7.4 arcsec tilts, 2.7 um axial, radial errors and a 0.1 mm eccentricity
    let truth = TableErrors { ex: 8.0 * arcsec, ey: 7.4 * arcsec, ez: 6.0 * arcsec, dx: 0.015, dy: 0.015, dz: 0.0027, hx: 0.1, hy: -0.05 };
    let deviations = [0.0, 0.1, 0.5, 1.0];
    let result = setup_dimension_sensitivity(&setup, &angles, &truth, &deviations).unwrap();
    let find = |dim: &str, d: f64| result.iter().find(|r| r.dimension == dim && r.deviation_mm == d).unwrap();
    // no deviation: the first-order method on exact readings is off by far less than the errors
    let nominal = find("R_x", 0.0);
    assert!(nominal.ex.abs() < 0.01 * truth.ex && nominal.ey.abs() < 0.01 * truth.ey && nominal.dz.abs() < 1e-5, "{nominal:?}");
    for &d in &deviations[1..] {
        // R_x off by d: the tilt terms scale by (R_x + d) / R_x, the axial term not at all
        let r = find("R_x", d);
        assert!(((r.ex - nominal.ex) / (truth.ex * d / setup.rx) - 1.0).abs() < 0.02, "{r:?}");
        assert!(((r.ey - nominal.ey) / (truth.ey * d / setup.rx) - 1.0).abs() < 0.02, "{r:?}");
        assert!((r.dz - nominal.dz).abs() < 1e-6, "{r:?}");
        // the table ball higher by d, or the spindle datum higher by d: an axial offset of the
        // table, which D_z takes one for one (+d and -d); the tilts do not move
        let z = find("R_z", d);
        assert!((z.dz - nominal.dz - d).abs() < 1e-6 * d.max(1.0), "{z:?}");
        let h = find("H", d);
        assert!((h.dz - nominal.dz + d).abs() < 1e-6 * d.max(1.0), "{h:?}");
        for x in [z, h] {
            assert!((x.ex - nominal.ex).abs() < 1e-3 * truth.ex && (x.ey - nominal.ey).abs() < 1e-3 * truth.ey, "{x:?}");
        }
    }
    // the simulation itself: with no error and the nominal setup every reading is zero
    let (dl1, dl2) = exact_readings(&setup, setup.rx, setup.rz, 0.0, &TableErrors::default(), &angles).unwrap();
    assert!(dl1.iter().chain(&dl2).all(|v| v.abs() < 1e-12));
}
