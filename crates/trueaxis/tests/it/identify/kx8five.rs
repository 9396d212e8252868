//! Andolfatto et al. 2011: simulate the 807-pose CapBall test of the KX8-Five with the
//! Table 1 values and the Table 3 sensor noise, identify, and compare.
//!
//! In this model's ISO parameters two combinations of the paper's 14 are unseen (named by the
//! identifiability report); the 12-parameter campaign recovers the equivalent values (Table 1 moved
//! along those combinations) within 3 standard uncertainties, with residuals matching the noise.

use std::path::{Path, PathBuf};
use trueaxis::error_model::{ErrorFunction, ErrorModel};
use trueaxis::geometry::Vec3;
use trueaxis::identify::{identify, measurement_csv, simulate_campaign, Campaign, IdentifyError, IndirectOptions};
use trueaxis::instruments::{ball_trajectory, Sweep};
use trueaxis::machine::Machine;
use trueaxis::model::Setup;

const PAPER14: &str = r#"["EC0Y", "EA0Z", "EB0Z", "EB0A", "EC0A", "EA0C", "EB0C", "EY0C", "TX", "TY", "TZ", "WX", "WY", "WZ"]"#;
const SEPARABLE12: &str = r#"["EC0Y", "EA0Z", "EB0Z", "EB0A", "EA0C", "EB0C", "TX", "TY", "TZ", "WX", "WY", "WZ"]"#;
const BALL: [f64; 3] = [150.0, 0.0, 100.0];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn machine() -> Machine {
    Machine::load(root().join("../../examples/machines/kx8five.toml")).unwrap()
}

/// The Table 1 values (the constants of the shipped Table 1 file).
fn table1(machine: &Machine) -> ErrorModel {
    ErrorModel::load(root().join("../../examples/errors/kx8five_table1.toml"), machine).unwrap()
}

fn value_of(model: &ErrorModel, name: &str) -> f64 {
    model
        .entries()
        .find(|(id, _)| id.to_string() == name)
        .map(|(_, f)| match f {
            ErrorFunction::Constant(v) => *v,
            _ => panic!("{name} is not a constant"),
        })
        .unwrap_or(0.0)
}

/// A campaign directory with the 807-pose trajectory, simulated with `truth` and noise `seed`.
fn campaign(dir: &Path, parameters: &str, extra: &str, truth: &ErrorModel, seed: u64) -> (Campaign, Machine) {
    let m = machine();
    let setup = Setup { tool_point: m.tool_point, work_point: Vec3::from(BALL) };
    let sweeps = [Sweep::parse("A=0:120").unwrap(), Sweep::parse("C=0:1440").unwrap()];
    let poses = ball_trajectory(&m, &setup, &sweeps, 807, Vec3::zeros()).unwrap();
    let mut csv = String::from("X,Y,Z,A,C\n");
    for p in poses.chunks(5) {
        csv += &p.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(",");
        csv.push('\n');
    }
    std::fs::write(dir.join("capball.csv"), csv).unwrap();
    let toml = format!(
        "parameters = {parameters}\n{extra}\n[[measurement]]\nname = \"capball\"\ninstrument = \"ball3d\"\ndata = \"capball.csv\"\n\
         tool_point = [0, 0, 300]\nwork_point = [{}, {}, {}]\nframe = \"machine\"\nsigma_um = [0.28, 0.28, 0.40]\n",
        BALL[0], BALL[1], BALL[2]
    );
    let path = dir.join("campaign.toml");
    std::fs::write(&path, toml).unwrap();
    let planned = Campaign::load(&path, &m).unwrap();
    let readings = simulate_campaign(&planned, &m, truth, Some(seed)).unwrap();
    std::fs::write(dir.join("capball.csv"), measurement_csv(&m, &planned.measurements[0], &readings[0])).unwrap();
    (Campaign::load(&path, &m).unwrap(), m)
}

#[test]
fn the_paper_parameter_set_has_two_unseen_combinations_named_in_iso_terms() {
    let dir = tempfile::tempdir().unwrap();
    let m = machine();
    let (c, m2) = campaign(dir.path(), PAPER14, "", &table1(&m), 4);
    let nominal = ErrorModel::zero(&m2);
    match identify(&c, &m2, &nominal, &IndirectOptions::default()) {
        Err(IdentifyError::RankDeficient { message }) => {
            assert!(message.contains("EB0A, EC0A, EB0C and WY cannot be separated"), "{message}");
            assert!(message.contains("EY0C, TY, TZ and WZ cannot be separated"), "{message}");
        }
        other => panic!("expected a rank-deficiency error, got {:?}", other.map(|r| r.values)),
    }
    let options = IndirectOptions { allow_rank_deficient: true, ..IndirectOptions::default() };
    let result = identify(&c, &m2, &nominal, &options).unwrap();
    let report = &result.identifiability;
    assert_eq!(report.rank, 12);
    assert_eq!(report.unidentifiable.len(), 2);
    // closed forms: a rotation about the A axis (0,1,1)/sqrt2 as EB0A = EC0A = 1 urad, minus
    // EB0C = 1 urad, is a rotation about the C axis (z), i.e. a shift of the ball by
    // 1e-3 um/(urad mm) * (z x ball) = (0, 0.150, 0) um in the workpiece frame: WY = -0.150 um
    let first = &report.unidentifiable[0];
    let coefficient = |name: &str| first.coefficients[first.parameters.iter().position(|p| p == name).unwrap()];
    let scale = coefficient("EB0A");
    assert!((coefficient("EC0A") / scale - 1.0).abs() < 1e-6);
    assert!((coefficient("EB0C") / scale + 1.0).abs() < 1e-6);
    assert!((coefficient("WY") / scale + 1e-3 * BALL[0]).abs() < 1e-6, "{}", coefficient("WY") / scale);
    // EY0C + WZ moves the ball by R_A (0,1,1) = (0,1,1) um for every A: the same as TY = TZ = 1 um
    let second = &report.unidentifiable[1];
    assert_eq!(second.parameters, vec!["EY0C", "TY", "TZ", "WZ"]);
    for c in &second.coefficients {
        assert!((c - 1.0).abs() < 1e-6, "{:?}", second.coefficients);
    }
    // the separable parameters are reported with uncertainties, the others without
    let separable = ["EC0Y", "EA0Z", "EB0Z", "EA0C", "TX", "WX"];
    for (j, name) in result.names.iter().enumerate() {
        assert_eq!(result.std_uncertainty[j].is_some(), separable.contains(&name.as_str()), "{name}");
    }
}

#[test]
fn separable_set_recovers_table_1_within_three_uncertainties_and_the_noise() {
    let m = machine();
    let truth = table1(&m);
    // the equivalent truth: Table 1 moved along the two unseen combinations to EC0A = EY0C = 0, with
    // the combinations as the 14-parameter report gives them
    let dir14 = tempfile::tempdir().unwrap();
    let (c14, _) = campaign(dir14.path(), PAPER14, "", &truth, 11);
    let options = IndirectOptions { allow_rank_deficient: true, ..IndirectOptions::default() };
    let report = identify(&c14, &m, &ErrorModel::zero(&m), &options).unwrap().identifiability;
    let mut equivalent: Vec<(String, f64)> = c14.unknowns.iter().map(|u| (u.name.clone(), value_of(&truth, &u.name))).collect();
    for (combination, zeroed) in report.unidentifiable.iter().zip(["EC0A", "EY0C"]) {
        let at = |name: &str| combination.parameters.iter().position(|p| p == name).unwrap();
        let t = equivalent.iter().find(|(n, _)| n == zeroed).unwrap().1 / combination.coefficients[at(zeroed)];
        for (name, value) in equivalent.iter_mut() {
            if let Some(k) = combination.parameters.iter().position(|p| p == name) {
                *value -= t * combination.coefficients[k];
            }
        }
    }
    // e.g. EB0A = -23.0 - 6.9 = -29.9 urad, TY = -14.7 + 2.9 = -11.8 um
    let expected = |name: &str| equivalent.iter().find(|(n, _)| n == name).unwrap().1;
    assert!((expected("EB0A") + 29.9).abs() < 1e-6 && (expected("TY") + 11.8).abs() < 1e-6);

    for seed in [1, 2, 3] {
        let dir = tempfile::tempdir().unwrap();
        let (c, _) = campaign(dir.path(), SEPARABLE12, "", &truth, seed);
        let result = identify(&c, &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap();
        assert_eq!(result.identifiability.rank, 12);
        assert!(result.identifiability.unidentifiable.is_empty());
        let k = result.identifiability.condition_number.unwrap();
        assert!(k > 1.0 && k < 100.0, "condition number {k}");
        for (j, name) in result.names.iter().enumerate() {
            let u = result.std_uncertainty[j].unwrap();
            let error = result.values[j] - expected(name);
            assert!(error.abs() < 3.0 * u, "seed {seed}: {name} = {} vs {} (u = {u})", result.values[j], expected(name));
        }
        // residual RMS per channel matches the Table 3 noise: 807 samples give a relative standard
        // deviation of the RMS of 1/sqrt(2 * 807) = 2.5 %, so within 10 %
        for (ch, sigma) in result.channels.iter().zip([0.28, 0.28, 0.40]) {
            assert!((ch.rms / sigma - 1.0).abs() < 0.10, "seed {seed}: {} rms {} vs {sigma}", ch.name, ch.rms);
            assert!(ch.mean.abs() < 0.05, "{}: mean {}", ch.name, ch.mean);
        }
        assert!((result.sigma0 - 1.0).abs() < 0.10, "s0 {}", result.sigma0);
    }
}

#[test]
fn exact_chain_refinement_and_svd_agree_with_the_linear_qr_solution() {
    let m = machine();
    let dir = tempfile::tempdir().unwrap();
    let (c, _) = campaign(dir.path(), SEPARABLE12, "", &table1(&m), 5);
    let nominal = ErrorModel::zero(&m);
    let qr = identify(&c, &m, &nominal, &IndirectOptions::default()).unwrap();
    let svd = identify(&c, &m, &nominal, &IndirectOptions { solver: trueaxis::identify::Solver::Svd, ..Default::default() }).unwrap();
    let lm = identify(&c, &m, &nominal, &IndirectOptions { refine: true, ..Default::default() }).unwrap();
    for j in 0..qr.values.len() {
        let u = qr.std_uncertainty[j].unwrap();
        assert!((qr.values[j] - svd.values[j]).abs() < 1e-9 * (1.0 + qr.values[j].abs()), "{}", qr.names[j]);
        assert!((svd.std_uncertainty[j].unwrap() / u - 1.0).abs() < 1e-9);
        // the exact chain differs from the first-order model by second-order terms (|EA0Z|^2 * 500 mm
        // ~ 1e-5 um): the refined values stay within 0.3 u of the linear ones
        assert!((lm.values[j] - qr.values[j]).abs() < 0.3 * u, "{}: {} vs {}", qr.names[j], lm.values[j], qr.values[j]);
    }
    let r = lm.refinement.unwrap();
    assert!(r.final_weighted_rms <= r.initial_weighted_rms);
    // noise-free data and the refinement: the exact-chain solution reproduces the readings to 1e-4 um
    let (c0, _) = campaign(dir.path(), SEPARABLE12, "", &table1(&m), 5);
    let readings = simulate_campaign(&c0, &m, &table1(&m), None).unwrap();
    std::fs::write(dir.path().join("capball.csv"), measurement_csv(&m, &c0.measurements[0], &readings[0])).unwrap();
    let c0 = Campaign::load(dir.path().join("campaign.toml"), &m).unwrap();
    let exact = identify(&c0, &m, &nominal, &IndirectOptions { refine: true, ..Default::default() }).unwrap();
    assert!(exact.residual_rms_um < 1e-4, "noise-free exact residual {}", exact.residual_rms_um);
}

#[test]
fn a_deliberately_rank_deficient_campaign_names_the_combination() {
    // EZ0C moves the C body along its own axis, WZ the ball along the workpiece z, which is the same
    // direction at every pose: the two columns are equal
    let m = machine();
    let dir = tempfile::tempdir().unwrap();
    let (c, _) = campaign(dir.path(), r#"["EA0C", "EB0C", "EZ0C", "WX", "WY", "WZ"]"#, "", &table1(&m), 1);
    let e = identify(&c, &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap_err().to_string();
    assert!(e.contains("EZ0C and WZ cannot be separated: changing EZ0C by +1.0000 um, WZ by -1.0000 um"), "{e}");
    // a zero offset of C (EC0C) rotates the ball about the C axis: the same as WY = 0.150 um per urad
    let (c, _) = campaign(dir.path(), r#"["EC0C", "WX", "WY", "WZ", "TX"]"#, "", &table1(&m), 1);
    let e = identify(&c, &m, &ErrorModel::zero(&m), &IndirectOptions::default()).unwrap_err().to_string();
    assert!(e.contains("EC0C and WY cannot be separated"), "{e}");
    let options = IndirectOptions { allow_rank_deficient: true, ..IndirectOptions::default() };
    let r = identify(&c, &m, &ErrorModel::zero(&m), &options).unwrap();
    let combo = &r.identifiability.unidentifiable[0];
    let ratio = combo.coefficients[1] / combo.coefficients[0];
    assert!((ratio + 1e-3 * BALL[0]).abs() < 1e-9, "WY per EC0C {ratio}");
}

/// The built-in machine of the demo (`trueaxis::simulation`): the shipped files, its errors without
/// the campaign's set-up those of the machine alone, and its ballbar circle on the machine without
/// errors nothing but the stated noise: mean 0 and standard deviation 0.3 um over 2 x 361 readings.
#[test]
fn the_demo_simulation_is_the_shipped_machine_and_its_circle_reads_its_noise() {
    use trueaxis::simulation::{circle, kx8five};
    let machine = kx8five::machine().unwrap();
    assert_eq!(machine.name, self::machine().name);
    let truth = kx8five::true_errors(&machine).unwrap();
    assert_eq!(value_of(&truth, "EA0Z"), value_of(&table1(&machine), "EA0Z"));
    let alone = ErrorModel::from_toml_str(&kx8five::machine_errors_toml(), "alone", &machine).unwrap();
    for setup in ["TX", "TY", "TZ", "WX", "WY", "WZ"] {
        assert_eq!(value_of(&alone, setup), 0.0, "{setup}");
    }
    assert_eq!(value_of(&alone, "EC0Y"), -8.8);
    let none = ErrorModel::from_toml_str("", "no errors", &machine).unwrap();
    let centre = circle::centre(&machine);
    let pose: Vec<f64> = machine.axes().iter().map(|a| "XYZ".find(a.letter).map_or(0.0, |k| centre[k])).collect();
    let csv = circle::simulate(&machine, &none, centre, pose).unwrap();
    let dl: Vec<f64> = csv.lines().skip(3).map(|l| l.split(',').nth(1).unwrap().parse().unwrap()).collect();
    assert_eq!(dl.len(), 2 * 361);
    let n = dl.len() as f64;
    let mean = dl.iter().sum::<f64>() / n;
    let sd = (dl.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    assert!(mean.abs() < 4.0 * circle::NOISE_UM / n.sqrt(), "mean {mean} um");
    assert!((sd / circle::NOISE_UM - 1.0).abs() < 0.1, "standard deviation {sd} um");
}
