//! Motion errors as parametric functions in a campaign (`[basis.NAME]`, Soons 1993 ch. 3 and eq. 4.2):
//! the shipped `examples/campaigns/vmc3_tracer` campaign, whose readings were simulated on the exact
//! chain with known piecewise-polynomial, Legendre and periodic motion errors of vmc3 (laser
//! multilateration: lengths from four stations), is identified back within 3 standard
//! uncertainties; the written `[basis.NAME]` error-values file reproduces the readings through
//! `predict` (library and command line). The campaign builder of `support/basis_campaign.rs` (also
//! the way to build the 10^5 x 500 problem) is checked on piecewise bases with 60 unknowns.

#[path = "../../../../trueaxis/tests/it/support/basis_campaign.rs"]
mod basis_campaign;

use crate::support::{arg, json, root, trueaxis, vmc3};
use basis_campaign::{bspline_bases, piecewise_bases, random_poses, simulate_into, write_campaign, SQUARENESS, STATIONS};

use trueaxis::error_model::{ErrorFunction, ErrorModel};
use trueaxis::geometry::Vec3;
use trueaxis::identify::{error_values_text, identify, Campaign, IndirectOptions};
use trueaxis::machine::{Machine, ParameterId};
use trueaxis::model::{Predictor, Setup};

const EXAMPLE: &str = "examples/campaigns/vmc3_tracer";

fn machine() -> Machine {
    Machine::load(root().join("examples/machines/vmc3.toml")).unwrap()
}

#[test]
fn piecewise_legendre_and_periodic_motion_errors_round_trip() {
    // the shipped campaign: piecewise EXX and EYX (straightness), periodic EYY, Legendre EZZ and
    // three squareness errors; readings simulated on the exact chain with truth.toml and 0.2 um noise
    let m = machine();
    let zero = ErrorModel::zero(&m);
    let path = root().join(EXAMPLE).join("campaign.toml");
    let campaign = Campaign::load(&path, &m).unwrap();
    let truth = ErrorModel::load(root().join(EXAMPLE).join("truth.toml"), &m).unwrap();
    // the shipped readings are what its comment says: `design simulate --seed 5` with truth.toml
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for file in ["campaign.toml", "station1.csv", "station2.csv", "station3.csv", "station4.csv"] {
        std::fs::copy(root().join(EXAMPLE).join(file), d.join(file)).unwrap();
    }
    let again = simulate_into(&d.join("campaign.toml"), &m, &truth, 5);
    for (a, b) in campaign.measurements.iter().zip(&again.measurements) {
        assert_eq!(a.readings, b.readings, "{}", a.name);
    }
    // 3 squareness, then the coefficients by parameter name: EXX 6, EYX 2, EYY 3, EZZ 4
    assert_eq!(campaign.unknowns.len(), 18);
    assert_eq!(campaign.unknowns[3].name, "EXX#1");
    assert_eq!(campaign.unknowns[3].unit, "um/mm");
    assert_eq!(campaign.unknowns[6].function.as_deref(), Some("(x+200)_+^3"));
    // the true value of every unknown: the truth's constants and basis coefficients
    let true_values = campaign.nominal_values(&truth).unwrap();
    assert!((true_values[3] - 5.0e-3).abs() < 1e-15 && (true_values[17] + 5.0).abs() < 1e-12);
    let result = identify(&campaign, &m, &zero, &IndirectOptions::default()).unwrap();
    assert_eq!(result.identifiability.rank, 18, "{:?}", result.identifiability.unidentifiable);
    for (j, name) in result.names.iter().enumerate() {
        let u = result.std_uncertainty[j].unwrap();
        assert!((result.values[j] - true_values[j]).abs() < 3.0 * u, "{name}: {} vs {} (u {u})", result.values[j], true_values[j]);
    }
    assert!((result.sigma0 - 1.0).abs() < 0.1, "s0 {}", result.sigma0);

    // the written file: [basis.NAME] entries that `predict` accepts, reproducing the readings
    let text = error_values_text(&result, &campaign, &zero, "").unwrap();
    for name in ["EXX", "EYX", "EYY", "EZZ"] {
        assert!(text.contains(&format!("[basis.{name}]")), "{text}");
    }
    let identified_path = d.join("identified.toml");
    std::fs::write(&identified_path, &text).unwrap();
    let identified = ErrorModel::load(&identified_path, &m).unwrap();
    let mut row = 0;
    let mut sum_squares = 0.0;
    for (k, meas) in campaign.measurements.iter().enumerate() {
        let mut predictor = Predictor::new(&m, &identified);
        predictor.setup = Setup { tool_point: m.tool_point, work_point: Vec3::from(STATIONS[k]) };
        let mut q = vec![0.0; 3];
        for r in 0..meas.records() {
            m.pose_to_internal(&meas.poses[3 * r..3 * r + 3], &mut q);
            let predicted = predictor.predict(&q).length * 1e3;
            let reading = meas.readings.as_ref().unwrap()[r];
            // the exact chain with the identified values = the fitted first-order model, to second order
            assert!((predicted - (reading - result.residuals[row])).abs() < 2e-3, "station {k} record {r}");
            sum_squares += (reading - predicted).powi(2);
            row += 1;
        }
    }
    let rms = (sum_squares / row as f64).sqrt();
    assert!((rms / 0.2 - 1.0).abs() < 0.1, "readings minus predictions: RMS {rms} um for 0.2 um noise");

    // the same from the command line: identify --out, then predict on the station 1 poses
    let cli = d.join("cli.toml");
    let cli = arg(&cli);
    let doc = json(&trueaxis(&vmc3(&["identify"], &["--campaign", arg(&path), "--json", "--out", cli])));
    assert_eq!(doc["parameters"]["EXX#6"]["function"], "(x-200)_+^3");
    assert_eq!(doc["parameters"]["EYY#1"]["unit"], "um");
    let station = format!("{},{},{}", STATIONS[0][0], STATIONS[0][1], STATIONS[0][2]);
    let poses = root().join(EXAMPLE).join("station1.csv");
    let predicted = json(&trueaxis(&vmc3(&["predict"], &["--errors", cli, "--poses", arg(&poses), "--work-point", &station, "--json"])));
    let first = &campaign.measurements[0];
    for r in [0, 100, 299] {
        let dl = predicted["poses"][r]["dL"].as_f64().unwrap();
        let fitted = first.readings.as_ref().unwrap()[r] - result.residuals[r];
        assert!((dl - fitted).abs() < 2e-3, "record {r}: predict {dl} vs fitted {fitted}");
    }
}

#[test]
fn the_campaign_builder_makes_identifiable_piecewise_problems() {
    // 4 knots per axis: 21 + 9 x 4 = 57 coefficients and 3 squareness errors from 4 x 400 lengths
    let m = machine();
    round_trip(&m, &piecewise_bases(&m, 4), 3 + 21 + 9 * 4);
}

#[test]
fn bspline_maps_with_many_knots_are_identified() {
    // the same cubic splines with 12 knots per axis as B-splines: 21 + 9 x 12 coefficients
    let m = machine();
    round_trip(&m, &bspline_bases(&m, 12), 3 + 21 + 9 * 12);
}

/// Noise-free readings of known errors (squareness and every basis function) come back.
fn round_trip(m: &Machine, bases: &str, unknowns: usize) {
    let dir = tempfile::tempdir().unwrap();
    let path = write_campaign(dir.path(), m, &SQUARENESS, bases, &random_poses(m, 400, 3), 0.2);
    let planned = Campaign::load(&path, m).unwrap();
    assert_eq!(planned.unknowns.len(), unknowns);
    assert_eq!(planned.bases.len(), 9);
    // truth: every function contributes up to 0.1 um over its domain (small enough that the
    // first-order model is exact to well below the 0.1 nm resolution of the written readings)
    let mut truth = ErrorModel::zero(m);
    let mut expected = vec![0.0; planned.unknowns.len()];
    for (j, v) in [(0usize, 1.0), (1, -0.8), (2, 0.6)] {
        let id = ParameterId::parse(SQUARENESS[j]).unwrap();
        truth.set(m, id, ErrorFunction::Constant(v)).unwrap();
        expected[j] = v;
    }
    for b in &planned.bases {
        let [lo, hi] = b.basis.spec.domain;
        let mut largest = vec![0.0f64; b.basis.len()];
        let mut values = vec![0.0; b.basis.len()];
        for i in 0..=200 {
            b.basis.eval_into(lo + (hi - lo) * i as f64 / 200.0, &mut values);
            largest.iter_mut().zip(&values).for_each(|(l, v)| *l = l.max(v.abs()));
        }
        let coefficients: Vec<f64> = largest.iter().map(|l| 0.1 / l).collect();
        expected[b.first..b.first + b.basis.len()].copy_from_slice(&coefficients);
        truth.set(m, b.id, ErrorFunction::basis(b.basis.clone(), coefficients).unwrap()).unwrap();
    }
    let readings = trueaxis::identify::simulate_campaign(&planned, m, &truth, None).unwrap();
    for (meas, r) in planned.measurements.iter().zip(&readings) {
        std::fs::write(&meas.data, trueaxis::identify::measurement_csv(m, meas, r)).unwrap();
    }
    let campaign = Campaign::load(&path, m).unwrap();
    let result = identify(&campaign, m, &ErrorModel::zero(m), &IndirectOptions::default()).unwrap();
    assert_eq!(result.identifiability.rank, unknowns);
    assert!(result.residual_rms_um < 1e-3, "noise-free residual {} um", result.residual_rms_um);
    // the readings are written with 0.1 nm resolution: that rounding (about 3e-5 um RMS) is the
    // noise of this test, and the uncertainties estimated from the residuals (s0) cover it
    assert!(result.sigma0 < 1e-3, "s0 {}", result.sigma0);
    for (j, name) in result.names.iter().enumerate() {
        let u = result.std_uncertainty[j].unwrap();
        assert!((result.values[j] - expected[j]).abs() < 3.0 * u, "{name}: {} vs {} (u {u})", result.values[j], expected[j]);
        assert!((result.values[j] / expected[j] - 1.0).abs() < 0.05, "{name}: {} vs {}", result.values[j], expected[j]);
    }
}
