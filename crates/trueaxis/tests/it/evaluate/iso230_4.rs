//! ISO 230-4 circular test and ballbar diagnostics on the 3-axis machine of
//! `examples/machines/vmc3.toml` (X and Y carry the table with directions -x, -y; ISO 841 primed
//! axes): the squareness ellipse of Jiang 2014 Fig. 2.14, a round trip of every diagnostic, G, F, H
//! against closed forms.

use trueaxis::error_model::ErrorModel;
use trueaxis::evaluate::ballbar_diagnostics::{diagnose, CircularRun, DiagnosticOptions};
use trueaxis::evaluate::iso230_4::{circular_values, evaluate};
use trueaxis::instruments::ballbar::{circle_test, sweep_angles, CircleSpec, Plane, Rotation};
use trueaxis::machine::Machine;

const R: f64 = 100.0;
/// Programmed centre (X, Y, Z), mm.
const CENTRE: [f64; 3] = [0.0, 0.0, -200.0];

fn vmc3() -> Machine {
    Machine::from_toml_str(include_str!("../../../../../examples/machines/vmc3.toml"), "vmc3.toml").unwrap()
}

fn options() -> DiagnosticOptions {
    DiagnosticOptions {
        plane: Plane::Xy,
        radius: R,
        centre: [CENTRE[0], CENTRE[1]],
        pitch: None,
        spike_width: 3f64.to_radians(),
        feed: None,
    }
}

fn run(m: &Machine, rotation: Rotation, errors: &ErrorModel) -> CircularRun {
    run_from(m, rotation, errors, 0.0)
}

/// A full circle every 1 deg from `start` (deg).
fn run_from(m: &Machine, rotation: Rotation, errors: &ErrorModel, start: f64) -> CircularRun {
    let span = if rotation == Rotation::Ccw { 360.0 } else { -360.0 };
    let angles: Vec<f64> = sweep_angles(start, span, 1.0).iter().map(|a| a.to_radians()).collect();
    let test = circle_test(m, &CircleSpec { plane: Plane::Xy, centre: CENTRE.to_vec(), radius: R, angles, rotation }).unwrap();
    let dl = test.simulate(m, errors);
    CircularRun { rotation, test, dl }
}

fn errors(m: &Machine, text: &str) -> ErrorModel {
    ErrorModel::from_toml_str(text, "test errors", m).unwrap()
}

/// The value of a diagnostic; a term refitted out as not significant (|value| below its standard
/// uncertainty, listed in `omitted`) counts as 0.
fn value(d: &trueaxis::evaluate::ballbar_diagnostics::Diagnostics, name: &str) -> f64 {
    match d.items.iter().find(|i| i.name == name) {
        Some(item) => item.value,
        None => {
            assert!(d.omitted.iter().any(|o| o.starts_with(&format!("{name}: not significant"))), "no {name}: {:?}", d.omitted);
            0.0
        }
    }
}

#[test]
fn squareness_of_0_01_deg_gives_the_45_degree_ellipse_and_is_identified() {
    // Jiang 2014 §2.3.2 / Fig. 2.14 (digest 2.2): an XY squareness of 0.01 deg on a 100 mm circle gives
    // an ellipse with its axes at 45 and 135 deg; to first order dL = (R alpha / 2) sin 2t with
    // amplitude R alpha / 2 = 8.727 um. The sign of the squareness decides which diagonal is the long
    // one. On vmc3 X rides on Y, so the squareness is EC0X (EC0Y turns the whole table: no signal).
    let m = vmc3();
    let alpha_urad = 0.01f64.to_radians() * 1e6; // 174.533 urad
    let amplitude = R * alpha_urad * 1e-6 / 2.0 * 1e3; // um
    assert!((amplitude - 8.7266).abs() < 1e-3);
    let mut long_axes = Vec::new();
    for sign in [1.0, -1.0] {
        let e = errors(&m, &format!("[constant]\nEC0X = {}\n", sign * alpha_urad));
        let runs = [run(&m, Rotation::Ccw, &e), run(&m, Rotation::Cw, &e)];
        let ccw = &runs[0];
        let (imax, dmax) = ccw.dl.iter().enumerate().fold((0, f64::MIN), |acc, (i, &v)| if v > acc.1 { (i, v) } else { acc });
        let dmin = ccw.dl.iter().copied().fold(f64::MAX, f64::min);
        let long_axis = ccw.test.angles[imax].to_degrees().rem_euclid(180.0);
        long_axes.push(long_axis);
        eprintln!("EC0X = {:+.3} urad: long axis at {long_axis} deg, dL {:+.4} / {:+.4} um", sign * alpha_urad, dmax * 1e3, dmin * 1e3);
        assert!((long_axis - 45.0).abs() < 1e-9 || (long_axis - 135.0).abs() < 1e-9, "long axis at {long_axis} deg");
        assert!((dmax * 1e3 - amplitude).abs() < 0.01 && (dmin * 1e3 + amplitude).abs() < 0.01);
        // the first-order shape at every sample
        for (t, d) in ccw.test.angles.iter().zip(&ccw.dl) {
            let model = (dmax * 1e3) * (2.0 * (t - ccw.test.angles[imax]) + std::f64::consts::FRAC_PI_2).sin();
            assert!((d * 1e3 - model).abs() < 0.01, "at {} deg", t.to_degrees());
        }
        // the same ellipse for CW and CCW: squareness, not servo mismatch
        let values = circular_values(Rotation::Ccw, &ccw.test.angles, &ccw.dl, R).unwrap();
        assert!((values.g_um - 2.0 * amplitude).abs() < 0.01, "G = {}", values.g_um);
        let result = evaluate(&m, &runs, &options()).unwrap();
        assert!(result.hysteresis_um.unwrap() < 1e-6);
        let sq = value(&result.diagnostics, "squareness");
        eprintln!("identified squareness {sq:+.4} urad, residual {:.2e} um", result.diagnostics.residual_rms_um);
        assert!((sq - sign * alpha_urad).abs() < 0.05, "squareness {sq} urad");
        assert_eq!(result.diagnostics.items.iter().find(|d| d.effect_um > 0.0).unwrap().name, "squareness", "largest effect");
    }
    assert!((long_axes[0] - long_axes[1]).abs() > 89.0, "the sign of the squareness flips the ellipse: {long_axes:?}");
}

/// Tool displacement relative to the workpiece (um, in programmed X, Y) of along-axis errors that
/// the static chain cannot hold (velocity- and history-dependent), added to a chain-simulated run:
/// the exact bar length `|R u + e| - R`.
fn add_geometric(run: &mut CircularRun, along: impl Fn(f64, Rotation) -> [f64; 2]) {
    for (t, dl) in run.test.angles.iter().zip(run.dl.iter_mut()) {
        let e = along(*t, run.rotation).map(|v| v * 1e-3);
        let (x, y) = (R * t.cos() + e[0], R * t.sin() + e[1]);
        *dl += x.hypot(y) - R;
    }
}

#[test]
fn every_diagnostic_round_trips() {
    // Chain-simulated: squareness EC0X (X rides on Y in vmc3, so X's orientation is the squareness), scale mismatch (EXX, EYY polynomials: X long by 20 um/m, Y
    // short by 10 um/m along the axes' own directions -x, -y, hence the coefficient signs), backlash
    // (EXX+/EXX-, EYY+/EYY-), lateral play of X (EYX+/EYX-), straightness of Y (EXY quadratic).
    // Added geometrically (tool relative to workpiece in programmed coordinates): a reversal spike of
    // X, a cyclic error of Y (pitch 10 mm), a servo lag of X behind Y.
    let m = vmc3();
    // EXX = d_x u with d_x = -1: u = -2 um moving +, +2 um moving -, so lost motion B_X = 4 um;
    // likewise EYY (d_y = -1): u = -1.5 um moving +, +1.5 moving -: B_Y = 3 um. Scale: u_X = 20 um/m X,
    // u_Y = -10 um/m Y: mismatch +30 um/m. Lateral play of X: EYX = +1 um moving +, -1 moving -:
    // p = 2 um. Straightness of Y: EXY = 0.8 (1 - (y / 100 mm)^2) um.
    let text = r#"
[constant]
EC0X = 30.0
[polynomial."EXX+"]
coefficients = [2.0, -0.020]
[polynomial."EXX-"]
coefficients = [-2.0, -0.020]
[polynomial."EYY+"]
coefficients = [1.5, 0.010]
[polynomial."EYY-"]
coefficients = [-1.5, 0.010]
[polynomial."EYX+"]
coefficients = [1.0]
[polynomial."EYX-"]
coefficients = [-1.0]
[polynomial.EXY]
coefficients = [0.8, 0.0, -8.0e-5]
"#;
    let e = errors(&m, text);
    let spike_h = 3.0; // um
    let width = 3f64.to_radians();
    let cyclic = (0.7, -0.4); // um, cos and sin of 2 pi Y / 10 mm
    let lag = 40e-6; // rad of path angle, X behind Y
                     // samples half a degree off the reversal points, where the direction of motion is defined
    let mut runs = vec![run_from(&m, Rotation::Ccw, &e, 0.5), run_from(&m, Rotation::Cw, &e, 0.5)];
    for r in &mut runs {
        add_geometric(r, |t, rot| {
            let sigma = rot.sign();
            let vx = -sigma * R * t.sin(); // dX / d(path angle)
            let sx = vx.signum();
            let since = (sigma * t).rem_euclid(std::f64::consts::PI);
            let spike = -spike_h * sx * (-since / width).exp();
            let servo = -vx * lag * 1e3;
            let y = CENTRE[1] + R * t.sin();
            let phase = 2.0 * std::f64::consts::PI * y / 10.0;
            [spike + servo, cyclic.0 * phase.cos() + cyclic.1 * phase.sin()]
        });
    }
    let opts = DiagnosticOptions { pitch: Some(10.0), ..options() };
    let d = diagnose(&m, &runs, &opts).unwrap();
    for item in &d.items {
        eprintln!(
            "{:<22} {:>10} {:+9.4} ± {:.4} {:<5} effect {:7.3} um {:5.1} %",
            item.name, item.parameter, item.value, item.std_uncertainty, item.unit, item.effect_um, item.share_percent
        );
    }
    eprintln!("residual RMS {:.2e} um over {} samples; omitted {:?}", d.residual_rms_um, d.samples, d.omitted);
    let expect = [
        ("squareness", 30.0, 0.1),
        ("scale mismatch", 30.0, 0.3),
        ("backlash X", 4.0, 0.02),
        ("backlash Y", 3.0, 0.02),
        ("lateral play X", 2.0, 0.02),
        ("lateral play Y", 0.0, 0.02),
        ("straightness X", 0.0, 0.02),
        ("straightness Y", 0.8, 0.02),
        ("reversal spike X", spike_h, 0.03),
        ("reversal spike Y", 0.0, 0.03),
        ("cyclic error Y", 0.7f64.hypot(0.4), 0.02),
        ("cyclic error X", 0.0, 0.02),
        ("servo mismatch", lag * 1e6, 0.2),
    ];
    for (name, truth, tol) in expect {
        let v = value(&d, name);
        assert!((v - truth).abs() < tol, "{name}: identified {v}, true {truth} (tolerance {tol})");
    }
    assert!(d.residual_rms_um < 0.01, "residual {}", d.residual_rms_um);
    // with a feed of 1000 mm/min (omega = 0.1667 rad/s on R = 100 mm), 40 urad of lag is 0.24 ms
    let with_feed = diagnose(&m, &runs, &DiagnosticOptions { feed: Some(1000.0), ..opts }).unwrap();
    let servo = with_feed.items.iter().find(|i| i.name == "servo mismatch").unwrap();
    assert_eq!(servo.unit, "ms");
    assert!((servo.value - lag / (1000.0 / 60.0 / R) * 1e3).abs() < 0.002, "{}", servo.value);
}

#[test]
fn g_f_and_h_against_closed_forms() {
    // A pure centre offset (c_x, c_y) = (6, -8) um of the pivot: dL = c . u to first order. F_max =
    // |c| = 10 um, F_min = -10 um; the LSC centre is the offset, G ~ 0 (a shifted circle is round).
    // Backlash B_X = 4 um (lost motion): CW and CCW differ by up to B at the X reversals: H = B.
    let m = vmc3();
    let zero = ErrorModel::zero(&m);
    let mut ccw = run(&m, Rotation::Ccw, &zero);
    add_geometric(&mut ccw, |_, _| [6.0, -8.0]);
    let v = circular_values(Rotation::Ccw, &ccw.test.angles, &ccw.dl, R).unwrap();
    assert!((v.f_max_um - 10.0).abs() < 0.01 && (v.f_min_um + 10.0).abs() < 0.01, "{v:?}");
    assert!((v.centre_um[0] - 6.0).abs() < 1e-3 && (v.centre_um[1] + 8.0).abs() < 1e-3, "{v:?}");
    // (R + dL) u(t) with the nominal angle t ovalises a shifted circle by |c|^2 / R = 1e-3 um
    assert!(v.g_um < 0.01 && (v.arc_deg - 359.0).abs() < 1e-9, "{v:?}");
    let e = errors(&m, "[constant]\n\"EXX+\" = 2.0\n\"EXX-\" = -2.0\n");
    let runs = [run(&m, Rotation::Ccw, &e), run(&m, Rotation::Cw, &e)];
    let result = evaluate(&m, &runs, &options()).unwrap();
    let h = result.hysteresis_um.unwrap();
    assert!((h - 4.0).abs() < 0.01, "H = {h}");
    assert!((value(&result.diagnostics, "backlash X") - 4.0).abs() < 0.01);
    let json = result.to_json();
    assert!(json["runs"][0]["G_um"].as_f64().unwrap() > 0.0);
    assert_eq!(json["plane"], "xy");
}
