//! Round trips through the length and probing instruments on the 3-axis machine (vmc3): a
//! calibrated ballbar at several pivots, a machine checking gauge of unknown length (Soons 1993
//! §5.2.2: the length appended to the parameters), a hole plate whose misalignment is removed
//! by fitting it with the machine parameters, and bars probed at both ends (`point_length`, Soons 1993
//! eq. 4.5), one of them uncalibrated. Squareness and scale errors (polynomial powers) are recovered
//! within 3 standard uncertainties, and so are the gauge and bar offsets and the plate pose.

use std::fmt::Write;
use std::path::Path;
use trueaxis::error_model::ErrorModel;
use trueaxis::geometry::Vec3;
use trueaxis::identify::{identify, measurement_csv, simulate_campaign, Campaign, IndirectOptions};
use trueaxis::instruments::{ball_trajectory, nominal_vector, plate_displacement};
use trueaxis::machine::Machine;
use trueaxis::model::Setup;

const TRUTH: &str = "[constant]\nEC0X = 20.0\nEB0Z = -15.0\nEA0Z = 30.0\n\
[polynomial.EXX]\ncoefficients = [0.0, 0.010]\n[polynomial.EYY]\ncoefficients = [0.0, -0.008]\n[polynomial.EZZ]\ncoefficients = [0.0, 0.012]\n";
const PARAMETERS: [&str; 6] = ["EC0X", "EB0Z", "EA0Z", "EXX[1]", "EYY[1]", "EZZ[1]"];
const TRUE_VALUES: [f64; 6] = [20.0, -15.0, 30.0, 0.010, -0.008, 0.012];
const GAUGE_OFFSET_UM: f64 = 3.0;
const PLATE: ([f64; 3], [f64; 3]) = ([5.0, -3.0, 2.0], [0.0, 0.0, 20.0]);

fn machine() -> Machine {
    Machine::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/machines/vmc3.toml")).unwrap()
}

/// A pose putting the tool point at `offset` (mm, workpiece frame) from the work point.
fn pose_at(m: &Machine, setup: &Setup, offset: Vec3) -> Option<Vec<f64>> {
    ball_trajectory(m, setup, &[], 1, offset).ok()
}

fn lengths_csv(m: &Machine, setup: &Setup, lengths: &[f64]) -> String {
    let mut csv = String::from("X,Y,Z\n");
    for &l in lengths {
        for elevation in [0.0f64, 30.0, 60.0, 90.0] {
            for azimuth in (0..12).map(|k| 30.0 * k as f64) {
                let (e, a) = (elevation.to_radians(), azimuth.to_radians());
                let u = Vec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin());
                if let Some(p) = pose_at(m, setup, u * l) {
                    let _ = writeln!(csv, "{},{},{}", p[0], p[1], p[2]);
                }
            }
        }
    }
    csv
}

#[test]
fn ballbar_gauge_and_hole_plate_round_trip() {
    let m = machine();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let ballbar = Setup { tool_point: m.tool_point, work_point: Vec3::new(0.0, 0.0, 50.0) };
    let gauge = Setup { tool_point: m.tool_point, work_point: Vec3::new(-150.0, 100.0, 20.0) };
    std::fs::write(d.join("ballbar.csv"), lengths_csv(&m, &ballbar, &[150.0, 300.0])).unwrap();
    std::fs::write(d.join("mcg.csv"), lengths_csv(&m, &gauge, &[226.0, 380.0])).unwrap();
    // hole plate in the XY plane: 7 x 5 holes at 50 mm pitch, probed with the tool point
    let probe = Setup { tool_point: m.tool_point, work_point: Vec3::zeros() };
    let mut plate = String::from("X,Y,Z\n");
    for i in 0..7 {
        for j in 0..5 {
            let p = pose_at(&m, &probe, Vec3::new(-150.0 + 50.0 * i as f64, -100.0 + 50.0 * j as f64, 10.0)).unwrap();
            let _ = writeln!(plate, "{},{},{}", p[0], p[1], p[2]);
        }
    }
    std::fs::write(d.join("plate.csv"), plate).unwrap();
    let list = PARAMETERS.iter().map(|p| format!("\"{p}\"")).collect::<Vec<_>>().join(", ");
    let toml = format!(
        "parameters = [{list}]\n\
         [[measurement]]\ninstrument = \"length\"\ndata = \"ballbar.csv\"\nwork_point = [0, 0, 50]\nsigma_um = 0.5\n\
         [[measurement]]\ninstrument = \"length\"\nname = \"mcg\"\ndata = \"mcg.csv\"\nwork_point = [-150, 100, 20]\nsigma_um = 0.5\nlength_offset = true\n\
         [[measurement]]\ninstrument = \"probe\"\nname = \"plate\"\ndata = \"plate.csv\"\nsigma_um = [0.4, 0.4, 0.6]\nplate = true\n"
    );
    std::fs::write(d.join("campaign.toml"), toml).unwrap();
    let planned = Campaign::load(d.join("campaign.toml"), &m).unwrap();
    assert_eq!(planned.unknowns.len(), 6 + 1 + 6);
    let truth = ErrorModel::from_toml_str(TRUTH, "truth", &m).unwrap();
    let mut readings = simulate_campaign(&planned, &m, &truth, Some(9)).unwrap();
    // the gauge reads GAUGE_OFFSET_UM long; the plate lies displaced by PLATE (um, urad) about its centre
    readings[1].iter_mut().for_each(|r| *r += GAUGE_OFFSET_UM);
    let centre = planned.measurements[2].plate_centre.unwrap();
    let (t, w) = (Vec3::from(PLATE.0) * 1e-3, Vec3::from(PLATE.1) * 1e-6);
    let mut q = vec![0.0; 3];
    for r in 0..planned.measurements[2].records() {
        m.pose_to_internal(&planned.measurements[2].poses[3 * r..3 * r + 3], &mut q);
        let shift = plate_displacement(&nominal_vector(&m, &q, &probe), &centre, &t, &w) * 1e3;
        for c in 0..3 {
            readings[2][3 * r + c] += shift[c];
        }
    }
    for (meas, r) in planned.measurements.iter().zip(&readings) {
        std::fs::write(&meas.data, measurement_csv(&m, meas, r)).unwrap();
    }
    let campaign = Campaign::load(d.join("campaign.toml"), &m).unwrap();
    let result = identify(&campaign, &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap();
    assert!(result.identifiability.unidentifiable.is_empty());
    let mut expected: Vec<f64> = TRUE_VALUES.to_vec();
    expected.push(GAUGE_OFFSET_UM);
    expected.extend(PLATE.0);
    expected.extend(PLATE.1);
    for (j, name) in result.names.iter().enumerate() {
        let u = result.std_uncertainty[j].unwrap();
        assert!((result.values[j] - expected[j]).abs() < 3.0 * u, "{name}: {} vs {} (u {u})", result.values[j], expected[j]);
    }
    assert_eq!(result.names[6], "offset:mcg");
    assert_eq!(result.names[7], "plate:plate:tx");
    assert!((result.sigma0 - 1.0).abs() < 0.2, "s0 {}", result.sigma0);
    // the stated noise of each channel is seen in its residuals (86..140 readings: within 25 %)
    for ch in &result.channels {
        assert!((ch.rms / ch.sigma - 1.0).abs() < 0.25, "{}: rms {} sigma {}", ch.name, ch.rms, ch.sigma);
    }
    // prediction variance (Soons 1993 eq. 4.12) of a design row equals g^T Cov g, and the volumetric
    // covariance at a pose is positive
    let design = campaign.design_matrix(&m, &ErrorModel::zero(&m)).unwrap();
    let g: Vec<f64> = design.matrix.row(0).iter().copied().collect();
    let v = result.prediction_variance(&g);
    assert!(v > 0.0 && v < 0.5 * 0.5, "prediction variance {v} um^2 below the single-reading noise");
    let cov = result.volumetric_covariance(&campaign, &m, &[100.0, 50.0, -100.0], &ballbar, trueaxis::model::Frame::Workpiece);
    assert!(cov[(0, 0)] > 0.0 && cov[(2, 2)] > 0.0);
}

/// Bars probed at both ends (`point_length`, Soons 1993 eq. 4.5): `length` mm long along the 13
/// directions of the axes, face and body diagonals, centred at four places in the work volume.
fn bars_csv(m: &Machine, probe: &Setup, length: f64) -> String {
    let mut csv = String::from("X,Y,Z,X2,Y2,Z2\n");
    let directions = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 0.0, 1.0],
        [1.0, 0.0, -1.0],
        [0.0, 1.0, 1.0],
        [0.0, 1.0, -1.0],
        [1.0, 1.0, 1.0],
        [1.0, 1.0, -1.0],
        [1.0, -1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ];
    for centre in [[0.0, 0.0, 200.0], [-100.0, 50.0, 150.0], [120.0, -60.0, 250.0], [50.0, 80.0, 200.0]] {
        for d in directions {
            let u = Vec3::from(d).normalize();
            let c = Vec3::from(centre);
            if let (Some(a), Some(b)) = (pose_at(m, probe, c - u * (0.5 * length)), pose_at(m, probe, c + u * (0.5 * length))) {
                let _ = writeln!(csv, "{},{},{},{},{},{}", a[0], a[1], a[2], b[0], b[1], b[2]);
            }
        }
    }
    csv
}

#[test]
fn probed_bars_round_trip() {
    // a calibrated 300 mm bar and a 450 mm bar of unknown length (offset), probed at both ends on
    // vmc3 used as a measuring machine: squareness and scale errors within 3 u, and the bar offset
    let m = machine();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let probe = Setup { tool_point: m.tool_point, work_point: Vec3::zeros() };
    std::fs::write(d.join("bar300.csv"), bars_csv(&m, &probe, 300.0)).unwrap();
    std::fs::write(d.join("bar450.csv"), bars_csv(&m, &probe, 450.0)).unwrap();
    let list = PARAMETERS.iter().map(|p| format!("\"{p}\"")).collect::<Vec<_>>().join(", ");
    let toml = format!(
        "parameters = [{list}]\n\
         [[measurement]]\ninstrument = \"point_length\"\ndata = \"bar300.csv\"\nsigma_um = 0.3\n\
         [[measurement]]\ninstrument = \"point_length\"\ndata = \"bar450.csv\"\nsigma_um = 0.3\nlength_offset = true\n"
    );
    std::fs::write(d.join("campaign.toml"), toml).unwrap();
    let planned = Campaign::load(d.join("campaign.toml"), &m).unwrap();
    let truth = ErrorModel::from_toml_str(TRUTH, "truth", &m).unwrap();
    let mut readings = simulate_campaign(&planned, &m, &truth, Some(17)).unwrap();
    // the 450 mm bar is not calibrated: its assumed length is off, which shifts every reading by
    // the same GAUGE_OFFSET_UM
    readings[1].iter_mut().for_each(|r| *r += GAUGE_OFFSET_UM);
    for (meas, r) in planned.measurements.iter().zip(&readings) {
        assert!(meas.records() >= 35, "{}: {} bars in the work volume", meas.name, meas.records());
        std::fs::write(&meas.data, measurement_csv(&m, meas, r)).unwrap();
    }
    let campaign = Campaign::load(d.join("campaign.toml"), &m).unwrap();
    let result = identify(&campaign, &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap();
    assert_eq!(result.identifiability.rank, 7);
    let mut expected = TRUE_VALUES.to_vec();
    expected.push(GAUGE_OFFSET_UM);
    for (j, name) in result.names.iter().enumerate() {
        let u = result.std_uncertainty[j].unwrap();
        assert!((result.values[j] - expected[j]).abs() < 3.0 * u, "{name}: {} vs {} (u {u})", result.values[j], expected[j]);
    }
    assert_eq!(result.names[6], "offset:bar450");
    assert!((result.sigma0 - 1.0).abs() < 0.25, "s0 {}", result.sigma0);
}
