//! Correlated inputs (`kind = "correlated"`, JCGM 101 §6.4.8) against the closed form of a sum of
//! correlated normals; the uncertainty of predicted volumetric errors at poses (GUM `F Cov F^T`
//! and its Monte Carlo counterpart) on the Andolfatto et al. 2011 campaign; the bound on the trials.

use crate::support::trueaxis;
use nalgebra::DMatrix;
use trueaxis::uncertainty::{run_adaptive, DesignMatrix, Evaluation, IdentificationMap, McSettings, Sources};

/// Three points of two channels x, y (t = 1, 2, 3 s) and one parameter `a` read by every
/// observation with sensitivity 1: `a` is the mean of the six observations.
fn mean_design() -> DesignMatrix {
    let channels: Vec<String> = ["x", "y", "x", "y", "x", "y"].iter().map(|c| c.to_string()).collect();
    let time = vec![1.0, 1.0, 2.0, 2.0, 3.0, 3.0];
    DesignMatrix::new(vec!["a".into()], &channels, time, None, None, DMatrix::from_element(6, 1, 1.0)).unwrap()
}

fn sources(rho: f64) -> Sources {
    let text = format!(
        "tolerance = 0.002\nseed = 11\n[[source]]\nname = \"head\"\nkind = \"correlated\"\nchannels = [\"x\", \"y\"]\n\
         u = [1.0, 2.0]\ncorrelation = [[1, {rho}], [{rho}, 1]]\n"
    );
    Sources::from_toml_str(&text, "test").unwrap()
}

#[test]
fn correlated_channels_against_the_sum_of_correlated_normals() {
    // a = (1/6) sum over 3 points of (e_x + e_y), each point (e_x, e_y) ~ N(0, [[1, 2 rho], [2 rho, 4]]):
    // u(a) = sqrt(3 (u_x^2 + u_y^2 + 2 rho u_x u_y)) / 6, Gaussian: 95 % interval +-1.96 u(a).
    // rho = 0.5: sqrt(21) / 6 = 0.76376; rho = 0: sqrt(15) / 6 = 0.64550; rho = -0.9: sqrt(3.6) / 6.
    let map = IdentificationMap::new(mean_design()).unwrap();
    for rho in [0.5f64, 0.0, -0.9] {
        let closed = (3.0 * (1.0 + 4.0 + 2.0 * rho * 2.0)).sqrt() / 6.0;
        let s = sources(rho);
        let gum = map.gum_covariance(&s.sources[0]).unwrap()[(0, 0)].sqrt();
        assert!((gum - closed).abs() < 1e-12, "rho {rho}: GUM {gum} vs {closed}");
        // (BruteForce equals PerObservation trial by trial: crates/trueaxis/tests/it/uncertainty/linear_map.rs)
        for evaluation in [Evaluation::Reduced, Evaluation::PerObservation] {
            let model = map.model(&[&s.sources[0]], evaluation).unwrap();
            let r = run_adaptive(&model, &s.settings, &mut |_, _| {}).unwrap();
            let o = &r.outputs[0];
            // the adaptive loop stabilises u and the endpoints to delta = 0.002 (2 s <= delta)
            assert!((o.std_uncertainty - closed).abs() < 0.005, "rho {rho} {evaluation:?}: u {} vs {closed}", o.std_uncertainty);
            assert!((o.symmetric.high - 1.959964 * closed).abs() < 0.01, "rho {rho} {evaluation:?}: {:?}", o.symmetric);
            assert!(o.mean.abs() < 0.005);
        }
    }
}

#[test]
fn correlated_sources_are_checked() {
    let bad = |body: &str| {
        Sources::from_toml_str(&format!("[[source]]\nname = \"h\"\nkind = \"correlated\"\n{body}"), "s.toml").unwrap_err().to_string()
    };
    assert!(bad("channels = [\"x\", \"y\"]\nu = [1, 1]\ncorrelation = [[1, 1.5], [1.5, 1]]").contains("within [-1, 1]"));
    assert!(bad("channels = [\"x\", \"y\", \"z\"]\ncovariance = [[1, 0.9, 0.9], [0.9, 1, -0.9], [0.9, -0.9, 1]]")
        .contains("not positive semidefinite"));
    assert!(bad("channels = [\"x\", \"y\"]\ncovariance = [[1, 0], [0.5, 1]]").contains("symmetric"));
    assert!(bad("channels = [\"x\", \"y\"]\ncovariance = [[1, 0, 0], [0, 1, 0]]").contains("2 x 2"));
    assert!(bad("channels = [\"x\", \"y\"]\nu = [1, 1]").contains("either covariance"));
    assert!(bad("channels = [\"x\", \"x\"]\ncovariance = [[1, 0], [0, 1]]").contains("twice"));
    // two observations of one channel at one time cannot be one joint draw
    let channels: Vec<String> = ["x", "x", "y", "x"].iter().map(|c| c.to_string()).collect();
    let design =
        DesignMatrix::new(vec!["a".into()], &channels, vec![1.0, 1.0, 1.0, 2.0], None, None, DMatrix::from_element(4, 1, 1.0)).unwrap();
    let map = IdentificationMap::new(design).unwrap();
    let err = map.gum_covariance(&sources(0.0).sources[0]).unwrap_err().to_string();
    assert!(err.contains("two observations at t = 1"), "{err}");
}

#[test]
fn trials_are_bounded() {
    let err = Sources::from_toml_str("trials_per_sequence = 100000000000\n[[source]]\nname = \"n\"\nkind = \"noise\"\nchannels.x = { distribution = \"normal\", u = 1 }\n", "s.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("more than 1000000"), "{err}");
    let mut s = McSettings::new(0.95, 0.05);
    s.trials_per_sequence = 1_000_000;
    s.max_sequences = 1000;
    let map = IdentificationMap::new(mean_design()).unwrap();
    let src = sources(0.0);
    let model = map.model(&[&src.sources[0]], Evaluation::Reduced).unwrap();
    let err = run_adaptive(&model, &s, &mut |_, _| {}).unwrap_err().to_string();
    assert!(err.contains("lower max_sequences"), "{err}");
}

#[test]
fn volumetric_uncertainty_at_poses_gum_and_monte_carlo() {
    // Andolfatto et al. 2011 campaign (examples/campaigns/kx8five) with the cyclic-drift sources, at the poses of
    // examples/poses/kx8five.csv. GUM: F Cov F^T with Cov the sum of the sources' GUM covariances;
    // Monte Carlo: F Cov_MC F^T, the covariance of the parameter trials mapped through F. They
    // agree within 3 % on every standard uncertainty (the MC covariance of 3 x 10^4 or more trials
    // has a relative sd of about 1 / sqrt(trials), and the cyclic part is sampled on a phase grid).
    // The ellipsoid semi-axes are sqrt(chi2_3(0.95) lambda_i): checked with the invariants
    // sum a_i^2 = chi2 trace(C) and prod a_i = chi2^(3/2) sqrt(det C), chi2_3(0.95) = 7.814728.
    let out = trueaxis(&[
        "uncertainty",
        "--machine",
        "examples/machines/kx8five.toml",
        "--campaign",
        "examples/campaigns/kx8five/campaign.toml",
        "--sources",
        "examples/uncertainty/kx8five_cyclic.toml",
        "--no-budget",
        "--poses",
        "examples/poses/kx8five.csv",
        "--json",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let n = doc["parameter_order"].as_array().unwrap().len();
    for kind in ["gum", "monte_carlo"] {
        let c = doc["covariance"][kind].as_array().unwrap();
        assert_eq!(c.len(), n);
        for (i, row) in c.iter().enumerate() {
            let u = doc["parameters"][doc["parameter_order"][i].as_str().unwrap()][if kind == "gum" { "gum" } else { "std_uncertainty" }]
                .clone();
            let u = if kind == "gum" { u["std_uncertainty"].as_f64().unwrap() } else { u.as_f64().unwrap() };
            assert!((row[i].as_f64().unwrap().sqrt() - u).abs() < 1e-9 * u.max(1.0), "{kind} diagonal {i}");
        }
    }
    let poses = doc["poses"].as_array().unwrap();
    assert_eq!(
        poses.len(),
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/poses/kx8five.csv"))
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .count()
            - 1
    );
    let mut compared = 0;
    for p in poses {
        let (g, m) = (&p["gum"], &p["monte_carlo"]);
        for k in 0..3 {
            let (ug, um) = (g["std_uncertainty_um"][k].as_f64().unwrap(), m["std_uncertainty_um"][k].as_f64().unwrap());
            if ug > 0.05 {
                assert!((um / ug - 1.0).abs() < 0.03, "pose {}: u {k} GUM {ug} MC {um}", p["pose"]);
                compared += 1;
            }
        }
        for v in [g, m] {
            let c: Vec<Vec<f64>> = v["covariance_um2"]
                .as_array()
                .unwrap()
                .iter()
                .map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect())
                .collect();
            let cm = nalgebra::Matrix3::from_fn(|i, j| c[i][j]);
            let axes: Vec<f64> = v["ellipsoid"]["axes"].as_array().unwrap().iter().map(|a| a["semi_axis_um"].as_f64().unwrap()).collect();
            assert_eq!(axes.len(), 3);
            let chi2 = v["ellipsoid"]["chi2"].as_f64().unwrap();
            assert!((chi2 - 7.814728).abs() < 1e-5);
            let sum2: f64 = axes.iter().map(|a| a * a).sum();
            assert!((sum2 / (chi2 * cm.trace()) - 1.0).abs() < 1e-9, "{sum2} vs {}", chi2 * cm.trace());
            let prod: f64 = axes.iter().product();
            assert!((prod / (chi2.powf(1.5) * cm.determinant().sqrt()) - 1.0).abs() < 1e-6);
            assert!(axes[0] >= axes[1] && axes[1] >= axes[2]);
        }
    }
    assert!(compared >= 3, "{compared}");
    // --poses needs the campaign
    let out = trueaxis(&[
        "uncertainty",
        "--design",
        "examples/uncertainty/kx8five_design.csv",
        "--sources",
        "examples/uncertainty/kx8five_cyclic.toml",
        "--poses",
        "examples/poses/kx8five.csv",
    ]);
    assert_eq!(out.status.code(), Some(2));
}
