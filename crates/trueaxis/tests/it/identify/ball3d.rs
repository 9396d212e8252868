//! 3D-ball round trips beyond the Andolfatto et al. 2011 CapBall test:
//! - an R-test (`frame = "workpiece"`: sensors on the C table, ball in the spindle) on the c600u
//!   (Jiang 2014 machine): the rotary-axis location errors and the setup, simulated with noise on the
//!   exact chain, identified back within 3 standard uncertainties; the three position errors the
//!   R-test cannot tell from the ball offset are named;
//! - a CapBall test on the KX8-Five whose sensing head is misaligned (gains, skew, a rotation of its
//!   frame, offsets): the sensor-frame calibration of Andolfatto et al. 2011 eqs. 6-10, from a simulated cube data
//!   file or from the given matrix, removes it and the parameters come back; without it they do not.

use std::fmt::Write;
use std::path::{Path, PathBuf};
use trueaxis::error_model::ErrorModel;
use trueaxis::geometry::Vec3;
use trueaxis::identify::{identify, measurement_csv, simulate_campaign, Campaign, Identification, IdentifyError, IndirectOptions};
use trueaxis::instruments::{ball_trajectory, SensorCalibration, Sweep};
use trueaxis::machine::Machine;
use trueaxis::model::Setup;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Pose CSV (axis columns only) of 3D-ball trajectories: each entry of `sweeps` is one trajectory of
/// `count` poses (Andolfatto et al. 2011 Fig. 2: the rotary axes sweep, the linear axes keep the head on the ball).
fn trajectories(m: &Machine, setup: &Setup, sweeps: &[&[&str]], count: usize) -> String {
    let mut csv = format!("{}\n", m.axis_letters().chars().map(String::from).collect::<Vec<_>>().join(","));
    for sweep in sweeps {
        let s: Vec<Sweep> = sweep.iter().map(|t| Sweep::parse(t).unwrap()).collect();
        let poses = ball_trajectory(m, setup, &s, count, Vec3::zeros()).unwrap();
        for p in poses.chunks(m.axis_count()) {
            let _ = writeln!(csv, "{}", p.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(","));
        }
    }
    csv
}

/// Writes `campaign` into `dir`, simulates its readings with `truth` and noise `seed`, applies
/// `transform` to each measurement's readings (um) and loads it again.
fn simulated(dir: &Path, m: &Machine, campaign: &str, truth: &ErrorModel, seed: u64, transform: impl Fn(&mut Vec<f64>)) -> Campaign {
    let path = dir.join("campaign.toml");
    std::fs::write(&path, campaign).unwrap();
    let planned = Campaign::load(&path, m).unwrap();
    let readings = simulate_campaign(&planned, m, truth, Some(seed)).unwrap();
    for (meas, mut r) in planned.measurements.iter().zip(readings) {
        transform(&mut r);
        std::fs::write(&meas.data, measurement_csv(m, meas, &r)).unwrap();
    }
    Campaign::load(&path, m).unwrap()
}

fn assert_within_3u(result: &Identification, expected: &[(&str, f64)]) {
    for (name, want) in expected {
        let j = result.names.iter().position(|n| n == name).unwrap_or_else(|| panic!("{name} not identified"));
        let u = result.std_uncertainty[j].unwrap();
        assert!((result.values[j] - want).abs() < 3.0 * u, "{name}: {} vs {want} (u {u})", result.values[j]);
    }
}

const R_TEST_TRUTH: &str = "[constant]\nEY0A = 10.0\nEZ0A = 10.0\nEB0A = 174.533\nEC0A = 174.533\nEX0C = 10.0\nEY0C = 10.0\n\
EA0C = 174.533\nEB0C = 174.533\nTX = 3.0\nTY = -4.0\nTZ = 5.0\nWX = -2.0\nWY = 6.0\nWZ = 1.5\n";

fn r_test_campaign(parameters: &str) -> String {
    format!(
        "parameters = {parameters}\n[[measurement]]\nname = \"rtest\"\ninstrument = \"ball3d\"\ndata = \"rtest.csv\"\n\
         work_point = [80, 0, -100]\nframe = \"workpiece\"\nsigma_um = [0.3, 0.3, 0.4]\n"
    )
}

#[test]
fn r_test_in_the_workpiece_frame_round_trip() {
    // c600u (wCAbYXZt): sensor nest on the C table at (80, 0, -100) mm, ball at the spindle point;
    // three trajectories: A and C together, C alone at A = 0, A alone at C = 90 deg; Jiang 2014 Table 3.1
    // PIGE sizes (10 um, 0.01 deg) plus ball and nest offsets
    let m = Machine::load(root().join("../../examples/machines/c600u.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let setup = Setup { tool_point: m.tool_point, work_point: Vec3::new(80.0, 0.0, -100.0) };
    let poses = trajectories(&m, &setup, &[&["A=-20:40", "C=0:720"], &["C=0:360"], &["A=-20:40", "C=90:90"]], 120);
    std::fs::write(dir.path().join("rtest.csv"), &poses).unwrap();
    let truth = ErrorModel::from_toml_str(R_TEST_TRUTH, "truth", &m).unwrap();

    // all 14: the positions of the A and C axes along the ball offsets are not seen by one nest
    let all14 = r#"["EY0A", "EZ0A", "EB0A", "EC0A", "EX0C", "EY0C", "EA0C", "EB0C", "TX", "TY", "TZ", "WX", "WY", "WZ"]"#;
    let c14 = simulated(dir.path(), &m, &r_test_campaign(all14), &truth, 11, |_| {});
    match identify(&c14, &m, &ErrorModel::zero(&m), &IndirectOptions::default()) {
        Err(IdentifyError::RankDeficient { message }) => {
            for pair in ["EY0A and TY", "EZ0A and TZ", "EX0C and TX"] {
                assert!(message.contains(&format!("{pair} cannot be separated")), "{pair}: {message}");
            }
        }
        other => panic!("expected rank deficiency, got {:?}", other.map(|r| r.values)),
    }

    // the 11 separable ones; EY0A, EZ0A, EX0C held at 0 are absorbed by the ball offset:
    // (EY0A, TY) = (10, -4) reads as (0, -4 - 10), and so on
    std::fs::write(dir.path().join("rtest.csv"), &poses).unwrap();
    let separable = r#"["EB0A", "EC0A", "EY0C", "EA0C", "EB0C", "TX", "TY", "TZ", "WX", "WY", "WZ"]"#;
    let c = simulated(dir.path(), &m, &r_test_campaign(separable), &truth, 11, |_| {});
    assert_eq!(c.measurements[0].records(), 360);
    let result = identify(&c, &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap();
    assert_eq!(result.identifiability.rank, 11);
    assert_within_3u(
        &result,
        &[
            ("EB0A", 174.533),
            ("EC0A", 174.533),
            ("EY0C", 10.0),
            ("EA0C", 174.533),
            ("EB0C", 174.533),
            ("TX", 3.0 - 10.0),
            ("TY", -4.0 - 10.0),
            ("TZ", 5.0 - 10.0),
            ("WX", -2.0),
            ("WY", 6.0),
            ("WZ", 1.5),
        ],
    );
    assert!((result.sigma0 - 1.0).abs() < 0.15, "s0 {}", result.sigma0);
    // the frame matters: the same readings taken as machine-frame (CapBall) readings do not fit
    let as_capball = std::fs::read_to_string(dir.path().join("campaign.toml")).unwrap().replace("\"workpiece\"", "\"machine\"");
    std::fs::write(dir.path().join("campaign.toml"), as_capball).unwrap();
    let wrong = Campaign::load(dir.path().join("campaign.toml"), &m).unwrap();
    let misfit = identify(&wrong, &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap();
    assert!(misfit.sigma0 > 10.0, "s0 {} with the wrong frame", misfit.sigma0);
}

const KX8_CAMPAIGN: &str = r#"parameters = ["EC0Y", "EA0Z", "EB0Z", "EB0A", "EA0C", "EB0C", "TX", "TY", "TZ", "WX", "WY", "WZ"]
[[measurement]]
name = "capball"
instrument = "ball3d"
data = "capball.csv"
tool_point = [0, 0, 300]
work_point = [150, 0, 100]
frame = "machine"
sigma_um = [0.28, 0.28, 0.40]
"#;

#[test]
fn a_sensor_misalignment_is_calibrated_out() {
    let m = Machine::load(root().join("../../examples/machines/kx8five.toml")).unwrap();
    let truth = ErrorModel::load(root().join("../../examples/errors/kx8five_table1.toml"), &m).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let setup = Setup { tool_point: m.tool_point, work_point: Vec3::new(150.0, 0.0, 100.0) };
    let poses = trajectories(&m, &setup, &[&["A=0:120", "C=0:1440"]], 807);
    // the head: gains 0.998 / 0.996 / 0.996 and skews of Andolfatto et al. 2011 Table 2, its frame turned by
    // 20 mrad about z, offsets of a few um (Andolfatto et al. 2011: below 10 um)
    let (c, s) = (0.02f64.cos(), 0.02f64.sin());
    let turn = nalgebra::Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
    let a = turn * nalgebra::Matrix3::new(0.998, -0.030, -0.029, 0.0, 0.996, -0.021, 0.0, 0.0, 0.996);
    let offset = Vec3::new(4.0, -7.5, 9.0);
    let head = SensorCalibration::from_matrix(a, offset).unwrap();
    // the calibration cube: 125 programmed offsets on a 0.2 mm cube and what the head reads there
    // (noise-free here: the noise of the cube readings is an uncertainty source of its own, Andolfatto et al. 2011
    // Table 5 "transformation", see `trueaxis uncertainty`)
    let mut cube = String::from("# programmed displacement (um), sensor readings (um)\ntx,ty,tz,sx,sy,sz\n");
    for t in SensorCalibration::cube(Vec3::zeros(), 200.0, 5) {
        let r = head.reading_of(&t);
        let _ = writeln!(cube, "{},{},{},{},{},{}", t.x, t.y, t.z, r.x, r.y, r.z);
    }
    std::fs::write(d.join("cube.csv"), cube).unwrap();
    std::fs::write(d.join("capball.csv"), &poses).unwrap();
    let calibrated = format!("{KX8_CAMPAIGN}calibration = {{ cube = \"cube.csv\" }}\n");
    // simulate (the calibrated campaign writes raw readings itself), then identify
    let with_cube = simulated(d, &m, &calibrated, &truth, 4, |_| {});
    let fitted = with_cube.measurements[0].calibration.unwrap();
    assert!((fitted.matrix - head.matrix).amax() < 1e-9, "{}", fitted.matrix);
    let result = identify(&with_cube, &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap();
    // the six parameters that are Table 1 itself in this set (docs/identification.md)
    let table1 = [("EC0Y", -8.8), ("EA0Z", 138.3), ("EB0Z", -35.7), ("EA0C", -34.4), ("TX", -1.1), ("WX", 1.5)];
    assert_within_3u(&result, &table1);
    assert!((result.sigma0 - 1.0).abs() < 0.15, "s0 {}", result.sigma0);

    // the same raw readings with the given matrix instead of the cube: the same values
    let raw_text = std::fs::read_to_string(d.join("capball.csv")).unwrap();
    let rows: Vec<String> = (0..3).map(|r| format!("[{}, {}, {}]", a[(r, 0)], a[(r, 1)], a[(r, 2)])).collect();
    let given = format!(
        "{KX8_CAMPAIGN}calibration = {{ matrix = [{}], offset_um = [{}, {}, {}] }}\n",
        rows.join(", "),
        offset.x,
        offset.y,
        offset.z
    );
    std::fs::write(d.join("campaign.toml"), &given).unwrap();
    let with_matrix =
        identify(&Campaign::load(d.join("campaign.toml"), &m).unwrap(), &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap();
    for j in 0..result.values.len() {
        let u = result.std_uncertainty[j].unwrap();
        assert!((with_matrix.values[j] - result.values[j]).abs() < 1e-6 * u, "{}", result.names[j]);
    }

    // without the calibration the raw readings leave the misalignment in the parameters
    std::fs::write(d.join("campaign.toml"), KX8_CAMPAIGN).unwrap();
    std::fs::write(d.join("capball.csv"), &raw_text).unwrap();
    let uncalibrated =
        identify(&Campaign::load(d.join("campaign.toml"), &m).unwrap(), &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap();
    let worst = table1
        .iter()
        .map(|(name, want)| {
            let j = uncalibrated.names.iter().position(|n| n == name).unwrap();
            (uncalibrated.values[j] - want).abs() / result.std_uncertainty[j].unwrap()
        })
        .fold(0.0, f64::max);
    // most of the misalignment is absorbed by the setup parameters (the offsets by T and W), biasing
    // them by 200 u; the rest shows as residuals: s0 1.33 (its sampling spread is 0.014)
    assert!(worst > 10.0, "the misalignment biases some parameter by {worst:.1} u");
    assert!(uncalibrated.sigma0 > 1.2, "s0 {} without the calibration", uncalibrated.sigma0);

    // a calibration on an instrument other than ball3d, or with both forms, is refused
    let bad = KX8_CAMPAIGN.replace("instrument = \"ball3d\"", "instrument = \"probe\"").replace("frame = \"machine\"\n", "")
        + "calibration = { cube = \"cube.csv\" }\n";
    std::fs::write(d.join("campaign.toml"), bad).unwrap();
    let e = Campaign::load(d.join("campaign.toml"), &m).unwrap_err().to_string();
    assert!(e.contains("campaign.toml") && e.contains("ball3d measurements only"), "{e}");
    std::fs::write(
        d.join("campaign.toml"),
        format!("{KX8_CAMPAIGN}calibration = {{ cube = \"cube.csv\", matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]] }}\n"),
    )
    .unwrap();
    let e = Campaign::load(d.join("campaign.toml"), &m).unwrap_err().to_string();
    assert!(e.contains("either `cube`"), "{e}");
}
