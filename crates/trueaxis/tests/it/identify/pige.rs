//! Identification of the 8 PIGEs of the A and C axes of the Jiang 2014 C600U (X. Jiang, PhD thesis,
//! 2014) from double-ballbar traces simulated on the exact chain: noise-free round trips of the
//! Table 3.1 conditions through the ch. 5, ch. 4 and ch. 6 methods, one sign test per PIGE, the
//! thesis errata of the digest (`specs/jiang.md`), the start-angle correction (Eq. 4.1), a Monte
//! Carlo of 1 um bar noise, repeatability statistics and the simulated compensation residual.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use trueaxis::geometry::Vec3;
use trueaxis::identify::pige::{compensation_residual, identify_piges, kasa_fit, repeatability, start_angle_error, DbbTrace, Piges};
use trueaxis::instruments::ballbar::{
    jiang_spec, jiang_step, rotary_test, sweep_angles, BallbarTest, BarLengths, JiangStep, RotaryPair, RotarySpec,
};
use trueaxis::machine::Machine;

/// Table 3.1: position PIGEs 10 um, orientation PIGEs 0.01 deg (mm, rad).
const POSITION: f64 = 0.010;
const ORIENTATION: f64 = 0.01 * std::f64::consts::PI / 180.0;
/// The eight PIGEs in the thesis order with whether each is a rotation.
const NAMES: [(&str, bool); 8] =
    [("EY0A", false), ("EZ0A", false), ("EB0A", true), ("EC0A", true), ("EX0C", false), ("EY0C", false), ("EA0C", true), ("EB0C", true)];
/// Noise-free recovery tolerances. The thesis's method is first order: the bar readings also carry
/// second-order terms such as `t^2 / (2 L)` of a displacement `t` of the pivot across the bar (up to
/// |e| + R theta + D theta ~ 50 um with Table 3.1: (0.05 mm)^2 / 300 mm ~ 0.008 um), which a 90 deg
/// arc fit amplifies a few times in the centre: 0.05 um on positions, and divided by D = 111.8 mm,
/// 0.5 urad (0.1 arcsec) on orientations. That is 20x below the 1 um / 1 arcsec repeatability the
/// thesis works to; the sign tests use values 200x and 350x larger than the tolerances.
const POSITION_TOL: f64 = 0.05e-3;
const ORIENTATION_TOL: f64 = 0.5e-6;

fn machine() -> Machine {
    Machine::from_toml_str(include_str!("../../../../../examples/machines/c600u.toml"), "c600u.toml").unwrap()
}

fn parameters(m: &Machine, values: &[f64; 8]) -> Vec<f64> {
    let mut p = vec![0.0; m.parameter_count()];
    for ((name, _), v) in NAMES.iter().zip(values) {
        p[m.parse_parameter(name).unwrap().1] = *v;
    }
    p
}

fn table_3_1() -> [f64; 8] {
    NAMES.map(|(_, rot)| if rot { ORIENTATION } else { POSITION })
}

struct Campaign {
    outer: Vec<(BallbarTest, Vec<f64>)>,
    inner: Vec<(BallbarTest, Vec<f64>)>,
}

impl Campaign {
    fn identify(&self, m: &Machine) -> Piges {
        let traces = |set: &[(BallbarTest, Vec<f64>)]| -> Vec<DbbTrace> {
            set.iter().map(|(t, dl)| DbbTrace::of_test(t, dl.clone()).unwrap()).collect()
        };
        identify_piges(m, RotaryPair::of_machine(m).unwrap(), &traces(&self.outer), &traces(&self.inner)).unwrap()
    }
}

/// The four steps of ch. 5, simulated on the exact chain, every `step` deg, with optional noise.
fn chapter_5(m: &Machine, params: &[f64], step: f64, noise: Option<(&mut ChaCha8Rng, f64)>) -> Campaign {
    let pair = RotaryPair::of_machine(m).unwrap();
    let mut noise = noise;
    let mut run = |s: JiangStep| {
        let test = jiang_step(m, pair, s, BarLengths::TABLE_3_1, step).unwrap();
        let mut dl = test.simulate_params(m, params);
        if let Some((rng, sigma)) = noise.as_mut() {
            let normal = Normal::new(0.0, *sigma).unwrap();
            dl.iter_mut().for_each(|v| *v += normal.sample(*rng));
        }
        (test, dl)
    };
    let outer = vec![run(JiangStep::A1), run(JiangStep::A2)];
    let inner = vec![run(JiangStep::C1), run(JiangStep::C2)];
    Campaign { outer, inner }
}

/// The test of `spec` (a setup of `step`) simulated on the exact chain every 2 deg, the outer axis
/// over -20 ... 90 deg and the inner one over a turn: the test and its noise-free readings.
fn simulated(m: &Machine, params: &[f64], step: JiangStep, spec: &RotarySpec) -> (BallbarTest, Vec<f64>) {
    let angles = if step.is_outer() { sweep_angles(-20.0, 90.0, 2.0) } else { sweep_angles(0.0, 360.0, 2.0) };
    let test = rotary_test(m, spec, &angles, &[0.0; 5]).unwrap();
    let dl = test.simulate_params(m, params);
    (test, dl)
}

fn assert_recovered(piges: &Piges, truth: &[f64; 8], what: &str) {
    for ((name, rot), value) in NAMES.iter().zip(truth) {
        let got = piges.get(name).unwrap_or_else(|| panic!("{what}: {name} missing"));
        let tol = if *rot { ORIENTATION_TOL } else { POSITION_TOL };
        assert!((got - value).abs() < tol, "{what}: {name} identified {got:e}, true {value:e} (tolerance {tol:e})");
    }
}

#[test]
fn noise_free_round_trip_of_table_3_1_chapter_5() {
    let m = machine();
    let truth = table_3_1();
    let campaign = chapter_5(&m, &parameters(&m, &truth), 1.0, None);
    let piges = campaign.identify(&m);
    let names: Vec<String> = piges.values.iter().map(|(id, _)| id.to_string()).collect();
    assert_eq!(names, NAMES.map(|n| n.0.to_string()), "the thesis order of the PIGEs");
    let worst = |rot: bool| {
        NAMES.iter().zip(&truth).filter(|((_, r), _)| *r == rot).map(|((n, _), v)| (piges.get(n).unwrap() - v).abs()).fold(0.0, f64::max)
    };
    eprintln!("ch. 5 round trip: worst position error {:.2e} um, orientation {:.2e} urad", worst(false) * 1e3, worst(true) * 1e6);
    assert_recovered(&piges, &truth, "ch. 5, Table 3.1");
}

#[test]
fn each_pige_alone_is_identified_with_its_sign() {
    // One sign test per PIGE (digest 2.6(d) and checklist item 11): +value and -value of each PIGE
    // alone come back under the right ISO name with the right sign, and nothing leaks into the
    // other seven. With the thesis ch. 5 formulas as printed (Y and Z swapped, erratum 3), EB0A
    // would come back as EC0A and vice versa.
    let m = machine();
    for (k, (name, rot)) in NAMES.iter().enumerate() {
        for sign in [1.0, -1.0] {
            let mut truth = [0.0; 8];
            truth[k] = sign * if *rot { ORIENTATION } else { POSITION };
            let piges = chapter_5(&m, &parameters(&m, &truth), 2.0, None).identify(&m);
            assert_recovered(&piges, &truth, &format!("{name} = {:+e} alone", truth[k]));
        }
    }
}

#[test]
fn erratum_3_printed_chapter_5_orientation_formulas_swap_the_components() {
    // Thesis ch. 5 prints theta_y0a = atan(Y_OE / |SO|), theta_z0a = atan(Z_OE / |SO|). With
    // theta_z0a alone, O->E has only a Y component (D theta_z0a): the printed formula would report
    // it as theta_y0a.
    let m = machine();
    let mut truth = [0.0; 8];
    truth[3] = ORIENTATION; // EC0A = theta_z0a
    let piges = chapter_5(&m, &parameters(&m, &truth), 2.0, None).identify(&m);
    let stations = &piges.outer.stations;
    let (s1, c1) = (stations[0].0, stations[0].1);
    let (s2, c2) = (stations[1].0, stations[1].1);
    let d = s1 - s2; // A1 at s = 0, A2 at s = -D
    assert!((d - BarLengths::TABLE_3_1.extended_offset()).abs() < 1e-12);
    let oe = [c1[0] - c2[0], c1[1] - c2[1]]; // O->E = step-1 centre minus step-2 centre (Y, Z)
    let printed_theta_y0a = (oe[0] / d).atan();
    let printed_theta_z0a = (oe[1] / d).atan();
    assert!((printed_theta_y0a - ORIENTATION).abs() < ORIENTATION_TOL, "printed formula puts theta_z0a into theta_y0a");
    assert!(printed_theta_z0a.abs() < ORIENTATION_TOL);
    assert!((piges.get("EC0A").unwrap() - ORIENTATION).abs() < ORIENTATION_TOL && piges.get("EB0A").unwrap().abs() < ORIENTATION_TOL);
}

#[test]
fn erratum_2_kasa_right_hand_side_needs_the_minus_sign() {
    // Points on a circle about (0.03, -0.02) mm: the fit with the corrected sign returns that centre;
    // the thesis's printed normal equations (no minus sign) return the mirrored centre.
    let pts: Vec<[f64; 2]> = (0..36)
        .map(|i| {
            let t = f64::from(i * 10).to_radians();
            [0.03 + 100.0 * t.cos(), -0.02 + 100.0 * t.sin()]
        })
        .collect();
    let fit = kasa_fit(&pts).unwrap();
    assert!((fit.centre[0] - 0.03).abs() < 1e-12 && (fit.centre[1] + 0.02).abs() < 1e-12);
    // The printed form: solve M [a b c] = +rhs, i.e. the negated solution: centre (-0.03, +0.02).
    let n = pts.len() as f64;
    let (mut m, mut rhs) = (nalgebra::Matrix3::<f64>::zeros(), nalgebra::Vector3::<f64>::zeros());
    for p in &pts {
        let row = nalgebra::Vector3::new(p[0], p[1], 1.0);
        m += row * row.transpose();
        rhs += row * (p[0] * p[0] + p[1] * p[1]);
    }
    assert_eq!(m[(2, 2)], n);
    let abc = m.lu().solve(&rhs).unwrap();
    let printed_centre = [-abc[0] / 2.0, -abc[1] / 2.0];
    assert!((printed_centre[0] + 0.03).abs() < 1e-9 && (printed_centre[1] - 0.02).abs() < 1e-9, "{printed_centre:?}");
}

#[test]
fn erratum_8_pivot_at_minus_r_gives_the_same_piges() {
    // Eq. 3.4 puts the pivot at -R, Eq. 3.9 at +R: with the angle counted from the pivot's own
    // start direction, both placements identify the same PIGEs.
    let m = machine();
    let truth = table_3_1();
    let params = parameters(&m, &truth);
    let pair = RotaryPair::of_machine(&m).unwrap();
    let bars = BarLengths::TABLE_3_1;
    let mut sets: [Vec<(BallbarTest, Vec<f64>)>; 2] = [Vec::new(), Vec::new()];
    for step in JiangStep::ALL {
        let mut spec = jiang_spec(&m, pair, step, bars, 0.0).unwrap();
        spec.radial = -spec.radial;
        let (test, dl) = simulated(&m, &params, step, &spec);
        assert!((test.setup.work_point.norm() - 100.0).abs() < 1e-12);
        sets[usize::from(!step.is_outer())].push((test, dl));
    }
    let [outer, inner] = sets;
    assert_recovered(&Campaign { outer, inner }.identify(&m), &truth, "pivot at -R");
}

#[test]
fn chapter_4_two_pivot_method_with_the_a_pivot_off_centre() {
    // Ch. 4: the A-axis pivot sits off the C table centre along X (here 150 mm); the local centres are
    // converted to the reference frame with the orientation PIGEs (e_lcs = e_rcs + x theta).
    let m = machine();
    let truth = table_3_1();
    let params = parameters(&m, &truth);
    let pair = RotaryPair::of_machine(&m).unwrap();
    let bars = BarLengths::TABLE_3_1;
    let run = |step: JiangStep, offset: f64| simulated(&m, &params, step, &jiang_spec(&m, pair, step, bars, offset).unwrap());
    let campaign = Campaign {
        outer: vec![run(JiangStep::A1, 150.0), run(JiangStep::A2, 150.0)],
        inner: vec![run(JiangStep::C1, 0.0), run(JiangStep::C2, 0.0)],
    };
    let piges = campaign.identify(&m);
    // the local A1 centre differs from the reference-frame PIGE by x theta_z0a = 150 mm * 174.5 urad
    let local_y = piges.outer.stations[0].1[0];
    assert!((local_y - (POSITION + 150.0 * ORIENTATION)).abs() < POSITION_TOL, "local e_y0a {local_y}");
    assert_recovered(&piges, &truth, "ch. 4");
}

/// The ch. 6 (Lee & Yang) four setups with the normal bar only: A at x1 and x2 along the A axis,
/// C at heights 0 and `dc`.
fn chapter_6(m: &Machine, params: &[f64], x: [f64; 2], dc: f64) -> Campaign {
    let pair = RotaryPair::of_machine(m).unwrap();
    let bars = BarLengths::TABLE_3_1;
    let run = |step: JiangStep, along: f64| {
        let mut spec = jiang_spec(m, pair, step, bars, 0.0).unwrap();
        spec.pivot_position = along;
        spec.spindle_position = along;
        simulated(m, params, step, &spec)
    };
    Campaign {
        outer: vec![run(JiangStep::A1, x[0]), run(JiangStep::A1, x[1])],
        inner: vec![run(JiangStep::C1, 0.0), run(JiangStep::C1, dc)],
    }
}

#[test]
fn chapter_6_four_setups_and_the_printed_sign_erratum() {
    // Erratum 5: D_A = 550 mm is ambiguous (offset or separation) and does not fit the C600U's X
    // travel; the positions are given explicitly here, asymmetric on purpose: x = -200 and +250 mm.
    // D_C = 78 mm (Table 6.2).
    let m = machine();
    let truth = table_3_1();
    let campaign = chapter_6(&m, &parameters(&m, &truth), [-200.0, 250.0], 78.0);
    let piges = campaign.identify(&m);
    assert_recovered(&piges, &truth, "ch. 6");
    // Erratum 4: the thesis prints theta_y0a = atan((e''_z0a - e'_z0a) / (2 D_A)) and
    // theta_x0c = atan((e'_y0c - e_y0c) / D_C); the chain (Eq. 3.2-3.3) gives the opposite signs.
    let a = &piges.outer.stations;
    let printed_theta_y0a = ((a[1].1[1] - a[0].1[1]) / (a[1].0 - a[0].0)).atan();
    let c = &piges.inner.stations;
    let printed_theta_x0c = ((c[1].1[1] - c[0].1[1]) / (c[1].0 - c[0].0)).atan();
    assert!((printed_theta_y0a + ORIENTATION).abs() < ORIENTATION_TOL, "printed theta_y0a {printed_theta_y0a:e}");
    assert!((printed_theta_x0c + ORIENTATION).abs() < ORIENTATION_TOL, "printed theta_x0c {printed_theta_x0c:e}");
}

#[test]
fn erratum_6_and_7_the_three_methods_agree_on_simulated_data() {
    // The thesis's ch. 4 and ch. 5 position results differ by up to 1.9 um on the machine (erratum 6);
    // on one simulated machine state the three methods, all simulated on the same chain
    // (erratum 7: the simulation does not depend on the chosen method), agree within POSITION_TOL / ORIENTATION_TOL.
    let m = machine();
    let truth = [0.0353, -0.0334, -6.25e-6, 5.8e-6, 0.0013, -0.0529, -108.0e-6, 21.7e-6]; // Table 5.2 size
    let params = parameters(&m, &truth);
    let five = chapter_5(&m, &params, 2.0, None).identify(&m);
    let six = chapter_6(&m, &params, [-250.0, 250.0], 78.0).identify(&m);
    for ((name, rot), _) in NAMES.iter().zip(&truth) {
        let tol = if *rot { ORIENTATION_TOL } else { POSITION_TOL };
        let (a, b) = (five.get(name).unwrap(), six.get(name).unwrap());
        assert!((a - b).abs() < tol, "{name}: ch. 5 {a:e}, ch. 6 {b:e}");
    }
    assert_recovered(&five, &truth, "ch. 5, Table 5.2-sized state");
}

#[test]
fn start_angle_correction_of_eq_4_1() {
    // The C-test pivot placed 5 mm off along the path (P0P0' = (0, 5) mm): without the correction the
    // fitted C1 centre is turned by delta_e = atan(5/100) = 2.86 deg, i.e. off by |c| delta_e ~ 0.7 um;
    // with delta_e from Eq. 4.1 it is right.
    let m = machine();
    let truth = table_3_1();
    let params = parameters(&m, &truth);
    let pair = RotaryPair::of_machine(&m).unwrap();
    let mut spec = jiang_spec(&m, pair, JiangStep::C1, BarLengths::TABLE_3_1, 0.0).unwrap();
    let nominal_pivot = spec.radial * spec.radius;
    let actual_pivot = nominal_pivot + Vec3::new(0.0, 5.0, 0.0);
    spec.radial = actual_pivot.normalize();
    spec.radius = actual_pivot.norm();
    let test = rotary_test(&m, &spec, &sweep_angles(0.0, 360.0, 2.0), &[0.0; 5]).unwrap();
    // The bar reads relative to its nominal 100 mm: add the constant length difference.
    let dl: Vec<f64> = test.simulate_params(&m, &params).iter().map(|v| v + test.nominal_length - 100.0).collect();
    let mut trace = DbbTrace::of_test(&test, dl).unwrap();
    trace.bar_length = 100.0;
    // the angles of the data are the C positions; the trace basis is the nominal one (+X)
    trace.geometry.u1 = Vec3::x();
    trace.geometry.u2 = Vec3::y();
    let expected = [truth[4], truth[5] + truth[0]]; // (e_x0c, e_y0c + e_y0a), Table 5.1
    let off = |c: [f64; 2]| (c[0] - expected[0]).hypot(c[1] - expected[1]);
    let uncorrected = off(trace.fit().unwrap().centre);
    trace.start_angle = start_angle_error(0.0, 5.0, 100.0);
    let corrected = off(trace.fit().unwrap().centre);
    eprintln!("C1 centre error: uncorrected {:.3} um, corrected {:.2e} um", uncorrected * 1e3, corrected * 1e3);
    assert!(uncorrected > 0.5e-3, "{uncorrected}");
    assert!(corrected < POSITION_TOL, "{corrected}");
}

#[test]
fn compensation_residual_is_the_noise() {
    // Jiang 2014 §4.3: the traces minus the model of the identified PIGEs. Noise-free: < 0.05 um (POSITION_TOL);
    // with 1 um noise the residual RMS is the noise (0.8 ... 1.2 um) (thesis Fig. 4.8: < 1 um band
    // on the machine).
    let m = machine();
    let params = parameters(&m, &table_3_1());
    let clean = chapter_5(&m, &params, 1.0, None);
    let piges = clean.identify(&m);
    for (test, dl) in clean.outer.iter().chain(&clean.inner) {
        let r = compensation_residual(&m, test, dl, &piges);
        let worst = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let raw = dl.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        eprintln!("{}: raw max |dL| {:.3} um, compensated max {:.2e} um", test.name, raw * 1e3, worst * 1e3);
        assert!(raw > 5e-3 && worst < POSITION_TOL, "{}: raw {raw}, residual {worst}", test.name);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let noisy = chapter_5(&m, &params, 1.0, Some((&mut rng, 1e-3)));
    let piges = noisy.identify(&m);
    for (test, dl) in noisy.outer.iter().chain(&noisy.inner) {
        let r = compensation_residual(&m, test, dl, &piges);
        let rms = (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt();
        assert!((0.8e-3..1.2e-3).contains(&rms), "{}: residual RMS {rms}", test.name);
    }
}

#[test]
fn monte_carlo_of_1_um_noise_orientation_is_the_weak_part() {
    // 200 repeats of the ch. 5 test (1 deg sampling: A1/A2 91 points over 90 deg, C1/C2 360 points)
    // with 1 um Gaussian noise on every reading, around the Table 5.2-sized machine state.
    //
    // Closed forms for the full C circle (first order; the Kåsa centre is the first Fourier
    // coefficient of the trace): sd(e_x0c) = sigma sqrt(2/N); the C2 points carry the noise
    // magnified by L_e / EP = 1.5, so sd(theta_x0c) = sigma sqrt(2/N) sqrt(1 + 1.5^2) / D.
    // Both are checked to 15 %. The A arc is only 90 deg, which makes the A-axis values weaker.
    //
    let m = machine();
    let truth = [0.0353, -0.0334, -6.25e-6, 5.8e-6, 0.0013, -0.0529, -108.0e-6, 21.7e-6];
    let params = parameters(&m, &truth);
    let mut rng = ChaCha8Rng::seed_from_u64(2014);
    let sigma = 1e-3;
    let runs: Vec<Piges> = (0..200).map(|_| chapter_5(&m, &params, 1.0, Some((&mut rng, sigma))).identify(&m)).collect();
    let stats = repeatability(&runs, 1e-3, (1.0f64 / 3600.0).to_radians()).unwrap();
    let sd = |name: &str| stats.parameters.iter().find(|p| p.0.to_string() == name).unwrap().2;
    let mean = |name: &str| stats.parameters.iter().find(|p| p.0.to_string() == name).unwrap().1;
    for (name, rot) in NAMES {
        let unit = if rot { 1e6 } else { 1e3 };
        eprintln!("{name}: mean {:+.3}, sd {:.3} {}", mean(name) * unit, sd(name) * unit, if rot { "urad" } else { "um" });
    }
    let n = 360.0;
    let d = BarLengths::TABLE_3_1.extended_offset();
    let sd_position = sigma * (2.0f64 / n).sqrt();
    let sd_orientation = sd_position * (1.0f64 + 1.5 * 1.5).sqrt() / d;
    assert!((sd("EX0C") / sd_position - 1.0).abs() < 0.15, "sd EX0C {} vs {sd_position}", sd("EX0C"));
    assert!((sd("EA0C") / sd_orientation - 1.0).abs() < 0.15, "sd EA0C {} vs {sd_orientation}", sd("EA0C"));
    // unbiased: every mean within 4 standard errors of the truth
    for ((name, _), v) in NAMES.iter().zip(&truth) {
        assert!((mean(name) - v).abs() < 4.0 * sd(name) / (runs.len() as f64).sqrt() + 1e-12, "{name} biased");
    }
    // Relative to the machine's own values (thesis Table 5.2), the position PIGEs are known to a few
    // percent, three of the four orientation PIGEs to no better than 30 % (the orientation is the
    // difference of two centres that differ by D theta, a few um, against 1 um bar noise).
    let rel = |name: &str, v: f64| sd(name) / v.abs();
    let mut position_rel: Vec<f64> = NAMES.iter().zip(&truth).filter(|(n, _)| !n.1).map(|(n, v)| rel(n.0, *v)).collect();
    let mut orientation_rel: Vec<f64> = NAMES.iter().zip(&truth).filter(|(n, _)| n.1).map(|(n, v)| rel(n.0, *v)).collect();
    position_rel.sort_by(f64::total_cmp);
    orientation_rel.sort_by(f64::total_cmp);
    eprintln!("relative sd: positions {position_rel:.3?}, orientations {orientation_rel:.3?}");
    assert!(position_rel[3] < 0.1, "{position_rel:?}");
    assert!(orientation_rel[1] > 0.3, "{orientation_rel:?}");
    let median = |v: &[f64]| 0.5 * (v[1] + v[2]);
    assert!(median(&orientation_rel) > 10.0 * median(&position_rel));
    // The A-axis orientation (90 deg arc) is the weakest of all: above the thesis's 1 arcsec
    // repeatability limit, while every position PIGE stays near 1 um; so the stopping rule fails.
    let arcsec = (1.0f64 / 3600.0).to_radians();
    assert!(sd("EB0A") > arcsec && sd("EC0A") > arcsec);
    assert!(NAMES.iter().filter(|n| !n.1).all(|n| sd(n.0) < 1.2e-3));
    assert!(!stats.within_tolerance);
    assert_eq!(stats.runs, 200);
}
