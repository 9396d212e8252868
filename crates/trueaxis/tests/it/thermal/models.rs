//! Thermal error models: the eq. 3.17 fit recovers 363.6 / 61.7 / 27.0 min (Zhu 2008 §3.5), the
//! Sodick models eqs. 4.3-4.5 evaluate as printed and through the kinematic chain, the state-space
//! model of Soons 1993 §3.4.2 is recovered by Levenberg-Marquardt, thermal links equal the direct
//! rigid-body formula, and sensor placement reproduces Zhu 2008 §3.4.2.

use std::path::Path;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::model::Predictor;
use trueaxis::thermal::assembly::{assemble, Boundary, Material, Section, ThermalProblem};
use trueaxis::thermal::links::{add_terms, link_terms, model_terms, LinkTarget, ThermalLink};
use trueaxis::thermal::mesh::StructuredMesh;
use trueaxis::thermal::placement::{effective_independence, exhaustive, log_det_information, modal_rule, PlacedSensor};
use trueaxis::thermal::regression::RegressionModel;
use trueaxis::thermal::state_space::{identify_state_space, StateSpaceModel};
use trueaxis::thermal::time_constants::{fit_time_constants, Series};
use trueaxis::thermal::{dominant_modes, modal_analysis, mode_weights, ModalOptions};

/// Deterministic noise in [-1, 1].
fn noise(i: usize) -> f64 {
    2.0 * ((i as f64 * 12.9898 + 78.233).sin() * 43758.5453).fract().abs() - 1.0
}

fn spindle_series(noise_k: f64) -> Vec<Series> {
    // three tests (warm-up 6 h, 3 h, 9 h) x two sensors, sampled every 2 min, eq. 3.17
    let tau = [363.6 * 60.0, 61.7 * 60.0, 27.0 * 60.0];
    let amplitudes = [[6.0, 2.5, 1.2], [4.0, -1.5, 2.0]];
    let mut out = Vec::new();
    let mut k = 0;
    for hours in [6.0, 3.0, 9.0] {
        for (s, a) in amplitudes.iter().enumerate() {
            let scale = 1.0 + 0.2 * s as f64;
            let times: Vec<f64> = (0..=(hours * 30.0) as usize).map(|i| 120.0 * i as f64).collect();
            let values = times
                .iter()
                .map(|t| {
                    k += 1;
                    20.0 + (0..3).map(|j| scale * a[j] * (1.0 - (-t / tau[j]).exp())).sum::<f64>() + noise_k * noise(k)
                })
                .collect();
            out.push(Series { times_s: times, values });
        }
    }
    out
}

#[test]
fn eq_3_17_recovers_the_spindle_time_constants() {
    let fit = fit_time_constants(&spindle_series(0.0), 3, true).unwrap();
    for (got, want) in fit.tau_s.iter().zip([363.6, 61.7, 27.0]) {
        assert!((got / 60.0 - want).abs() < 1e-5 * want, "{} min vs {want}", got / 60.0);
    }
    assert!((fit.offsets[0] - 20.0).abs() < 1e-6 && (fit.amplitudes[0][0] - 6.0).abs() < 1e-5);
    // with +-0.01 K sensor noise the three are within 2 % (measured: < 1 %)
    let noisy = fit_time_constants(&spindle_series(0.01), 3, true).unwrap();
    for (got, want) in noisy.tau_s.iter().zip([363.6, 61.7, 27.0]) {
        assert!((got / 60.0 - want).abs() < 0.02 * want, "noisy: {} min vs {want}", got / 60.0);
    }
    assert!(noisy.residual_rms < 0.01);
}

fn sodick() -> [RegressionModel; 3] {
    let m = |error: &str, axis: &str, sensors: &[&str], c: Vec<Vec<f64>>| RegressionModel {
        error: error.into(),
        sensors: sensors.iter().map(|s| format!("T:{s}")).collect(),
        position: Some(axis.into()),
        intercept: true,
        coefficients: c,
    };
    [
        // eq. 4.3: D_z = [-3.35 + 0.40 T1 - 0.11 T3 - 0.15 T5] + [-0.12 + 0.01 T1 - 0.01 T5] P(z)
        m("EZZ", "Z", &["1", "3", "5"], vec![vec![-3.35, 0.40, -0.11, -0.15], vec![-0.12, 0.01, 0.0, -0.01]]),
        // eq. 4.4
        m("EXX", "X", &["7", "8", "10", "13"], vec![vec![103.68, -13.08, -12.48, 27.77, -6.64], vec![-0.18, -0.17, -0.02, 0.26, 0.02]]),
        // eq. 4.5
        m("EYY", "Y", &["6", "16", "17"], vec![vec![28.01, -7.64, -10.20, 1.22], vec![-0.05, -0.01, 0.03, -0.19]]),
    ]
}

#[test]
fn sodick_models_evaluate_as_printed_and_through_the_chain() {
    let [dz, dx, dy] = sodick();
    let (t1, t3, t5) = (21.0, 20.5, 22.0);
    let want_z = (-3.35 + 0.40 * t1 - 0.11 * t3 - 0.15 * t5) + (-0.12 + 0.01 * t1 - 0.01 * t5) * -100.0;
    assert!((dz.evaluate(-100.0, &[t1, t3, t5]) - want_z).abs() < 1e-12);
    assert!((want_z - 12.495).abs() < 1e-9);
    let (t7, t8, t10, t13) = (21.0, 21.5, 22.0, 20.5);
    let want_x =
        (103.68 - 13.08 * t7 - 12.48 * t8 + 27.77 * t10 - 6.64 * t13) + (-0.18 - 0.17 * t7 - 0.02 * t8 + 0.26 * t10 + 0.02 * t13) * 200.0;
    assert!((dx.evaluate(200.0, &[t7, t8, t10, t13]) - want_x).abs() < 1e-10);
    let (t6, t16, t17) = (20.8, 21.2, 23.0);
    let want_y = (28.01 - 7.64 * t6 - 10.20 * t16 + 1.22 * t17) + (-0.05 - 0.01 * t6 + 0.03 * t16 - 0.19 * t17) * -150.0;
    assert!((dy.evaluate(-150.0, &[t6, t16, t17]) - want_y).abs() < 1e-10);
    // the TOML form round-trips
    assert_eq!(RegressionModel::from_toml_str(&dx.to_toml(), "dx.toml").unwrap(), dx);
    // as error terms (T - 20) on a 3-axis machine: Z carries the tool (dz = +EZZ), X and Y carry the
    // workpiece (the tool moves the opposite way relative to it: dx = -EXX, dy = -EYY)
    let machine = Machine::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/machines/vmc3.toml")).unwrap();
    let mut errors = ErrorModel::zero(&machine);
    for m in [&dz, &dx, &dy] {
        add_terms(&mut errors, &machine, &model_terms(&m.error, m, 1.0).unwrap()).unwrap();
    }
    let sensors: Vec<String> = errors.sensors().to_vec();
    let value = |s: &str| match s {
        "T:1" => t1,
        "T:3" => t3,
        "T:5" => t5,
        "T:7" => t7,
        "T:8" => t8,
        "T:10" => t10,
        "T:13" => t13,
        "T:6" => t6,
        "T:16" => t16,
        _ => t17,
    };
    let temps: Vec<f64> = sensors.iter().map(|s| value(s)).collect();
    let pose = [200.0, -150.0, -100.0];
    let mut q = [0.0; 3];
    machine.pose_to_internal(&pose, &mut q);
    let v = Predictor::new(&machine, &errors).predict_states(&q, None, &temps)[0];
    assert!((v.position.z * 1e3 - want_z).abs() < 1e-6, "dz {} vs {want_z}", v.position.z * 1e3);
    assert!((v.position.x * 1e3 + want_x).abs() < 1e-6, "dx {} vs {}", v.position.x * 1e3, -want_x);
    assert!((v.position.y * 1e3 + want_y).abs() < 1e-6);
}

#[test]
fn bending_link_in_the_chain_equals_the_rigid_body_formula() {
    // column under the Z slide of a vmc3: free end f, along +z, deflection +y, slope about -x
    let machine = Machine::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/machines/vmc3.toml")).unwrap();
    let one = |c: Vec<f64>, sensors: &[&str]| RegressionModel {
        error: "link".into(),
        sensors: sensors.iter().map(|s| s.to_string()).collect(),
        position: None,
        intercept: true,
        coefficients: vec![c],
    };
    let link = ThermalLink {
        name: "column".into(),
        target: LinkTarget::Axis('Z'),
        free_end_mm: [0.0, -300.0, 500.0],
        along: [0.0, 0.0, 1.0],
        across: [0.0, 1.0, 0.0],
        epsilon: Some(one(vec![-10.0, 0.5], &["T:col"])),
        delta: Some(one(vec![0.0, 2.0, -2.0], &["T:front", "T:back"])),
        theta: Some(one(vec![0.0, 1.5, -1.5], &["T:front", "T:back"])),
    };
    let mut errors = ErrorModel::zero(&machine);
    add_terms(&mut errors, &machine, &link_terms(&link, &machine).unwrap()).unwrap();
    let temperature = |s: &str| match s {
        "T:col" => 26.0,
        "T:front" => 24.0,
        _ => 21.0,
    };
    let temps: Vec<f64> = errors.sensors().iter().map(|s| temperature(s)).collect();
    let (eps, delta, theta) = (-10.0 + 0.5 * 26.0, 2.0 * 3.0, 1.5 * 3.0); // um, um, urad
    for pose in [[0.0, 0.0, 0.0], [150.0, -80.0, -300.0], [-400.0, 250.0, -50.0]] {
        let mut q = [0.0; 3];
        machine.pose_to_internal(&pose, &mut q);
        let v = Predictor::new(&machine, &errors).predict_states(&q, None, &temps)[0];
        // tool point at this pose (tool side: Z only), in M
        let x = [0.0, 0.0, 400.0 + pose[2]];
        let r = [x[0] - 0.0, x[1] + 300.0, x[2] - 500.0];
        // w = u x v = -x: theta w x (x - f) = theta (0, r_z, -r_y) * (-1)... w x r = (-1,0,0) x r = (0, r_z, -r_y)
        let want = [0.0, delta + theta * 1e-3 * r[2], eps - theta * 1e-3 * r[1]];
        let got = [v.position.x * 1e3, v.position.y * 1e3, v.position.z * 1e3];
        for d in 0..3 {
            // first-order formula vs exact chain: the difference is of order theta^2 |r| < 1e-4 um
            assert!((got[d] - want[d]).abs() < 1e-4, "pose {pose:?} axis {d}: {} vs {}", got[d], want[d]);
        }
        // the orientation error is the slope about -x
        assert!((v.orientation.x * 1e6 + theta).abs() < 1e-6);
    }
}

#[test]
fn state_space_rates_and_outputs_are_recovered() {
    // two inputs, two rates (time constants 40 and 8 min), two outputs; irregular sampling
    let truth = StateSpaceModel {
        gammas: vec![1.0 / 2400.0, 1.0 / 480.0],
        inputs: 2,
        c: nalgebra::DMatrix::from_row_slice(2, 4, &[2e-4, 1e-3, -5e-5, 2e-4, 1e-4, -4e-4, 3e-4, 6e-4]),
    };
    let record = |period: f64, n: usize| {
        let times: Vec<f64> = (0..n).map(|k| 60.0 * k as f64 + 20.0 * noise(k).abs()).collect();
        let u: Vec<Vec<f64>> =
            times.iter().map(|t| vec![if (t / period) as usize % 2 == 0 { 5.0 } else { 0.5 }, 1.0 + (t / 1800.0).sin()]).collect();
        let y = truth.simulate(&times, &u);
        (times, u, y)
    };
    let records = vec![record(3600.0, 300), record(1500.0, 200)];
    let (model, rms) = identify_state_space(&records, 2, None).unwrap();
    assert!(rms < 1e-9, "{rms}");
    for (got, want) in model.time_constants_s().iter().zip([2400.0, 480.0]) {
        assert!((got - want).abs() < 1e-5 * want, "{got} vs {want}");
    }
    // a held-out duty cycle is predicted exactly
    let (t, u, y) = record(900.0, 240);
    let p = model.simulate(&t, &u);
    for (a, b) in p.iter().flatten().zip(y.iter().flatten()) {
        assert!((a - b).abs() < 1e-8);
    }
}

fn fin(end: Boundary, elements: usize) -> ThermalProblem {
    ThermalProblem {
        mesh: StructuredMesh::bar(1.0, elements).unwrap(),
        material: Material { conductivity_w_mk: 60.5, density_kg_m3: 7800.0, specific_heat_j_kgk: 434.0 },
        section: Section::Bar { area_m2: 0.0314, perimeter_m: 2.0 * std::f64::consts::PI * 0.1 },
        lateral_convection_w_m2k: 20.0,
        boundaries: vec![[end, end]],
        fluxes: vec![(0, 100.0)],
    }
}

#[test]
fn placement_reproduces_seed_002_and_the_d_optimal_design() {
    // elongation element of Zhu 2008 §3.4 (h = 20 on all surfaces, flux at the fixed end), 9 equally
    // spaced candidates (positions 1..9): the modal rule places Position 5 (modes I and III) and
    // Position 1 (mode II), as in the thesis
    let sys = assemble(&fin(Boundary::Convection(20.0), 24)).unwrap();
    let modes = modal_analysis(&sys, &ModalOptions::default()).unwrap();
    let candidates: Vec<usize> = (0..9).map(|i| 3 * i).collect();
    let first_three = [0, 1, 2];
    let placed = modal_rule(&modes, &first_three, &candidates, 0.8, |node| node as f64).unwrap();
    assert_eq!(placed, vec![PlacedSensor { node: 12, modes: vec![0, 2] }, PlacedSensor { node: 0, modes: vec![1] }]);
    // modes I, II, III are the three heaviest; truncation keeps the fewest reaching 90 %
    let w = mode_weights(&modes, &sys.load);
    let kept = dominant_modes(&w, 0.9);
    assert_eq!(&kept[..3], &first_three);
    let share = |k: &[usize]| k.iter().map(|&i| w[i].share).sum::<f64>();
    assert!(share(&kept) >= 0.9 && share(&kept[..kept.len() - 1]) < 0.9);
    // insulated ends: modes 1, cos(pi x), cos(2 pi x) = quadratic in u = cos(pi x); the D-optimal
    // 3-point design for a quadratic on [-1, 1] is u = -1, 0, 1: x = 0, L/2, L (nodes 0, 11, 22)
    let sys = assemble(&fin(Boundary::Insulated, 22)).unwrap();
    let modes = modal_analysis(&sys, &ModalOptions::default()).unwrap();
    let all: Vec<usize> = (0..23).collect();
    let (best, _) = exhaustive(&all, 3, |s| log_det_information(&modes, &first_three, s)).unwrap();
    assert_eq!(best, vec![0, 11, 22]);
    assert_eq!(effective_independence(&modes, &first_three, &all, 3).unwrap(), vec![0, 11, 22]);
}
