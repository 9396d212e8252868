//! Temperature selection for thermal error models (NISTIR 5236 §3.6): a synthetic campaign of five
//! sensors where only two drive the error, `E = 5 + 3 T1 - 1.5 T3` (um, T in degC) plus 0.05 um
//! noise. Correlation ranking and stepwise regression (partial F at 99.99 %) each pick exactly
//! T1 and T3, and the coefficients are recovered; the same through `thermal fit --select`.

use crate::support::{json, trueaxis};
use std::f64::consts::PI;
use trueaxis::thermal::regression::{correlation_ranking, fit_regression, fit_stepwise, select_by_correlation};

const SAMPLES: usize = 1200;

/// Deterministic uniform noise in [-1, 1) (splitmix64 of the index).
fn noise(i: usize) -> f64 {
    let mut z = (i as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

/// `(sensor names, series [sensor][sample], error)`: T1 a warm-up, T2 and T5 fast oscillations,
/// T3 a slow oscillation, T4 noise; pairwise correlations below 0.07.
fn campaign() -> (Vec<String>, Vec<Vec<f64>>, Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..SAMPLES).map(|i| 60.0 * i as f64).collect();
    let series: Vec<Vec<f64>> = vec![
        t.iter().map(|t| 20.0 + 10.0 * (1.0 - (-t / 6000.0).exp())).collect(),
        t.iter().map(|t| 20.0 + 3.0 * (2.0 * PI * t / 1777.0 + 1.0).sin()).collect(),
        t.iter().map(|t| 20.0 + 4.0 * (2.0 * PI * t / 5000.0).sin()).collect(),
        (0..SAMPLES).map(|i| 20.0 + noise(i)).collect(),
        t.iter().map(|t| 20.0 + 2.0 * (2.0 * PI * t / 900.0).cos()).collect(),
    ];
    let error = (0..SAMPLES).map(|i| 5.0 + 3.0 * series[0][i] - 1.5 * series[2][i] + 0.05 * noise(i + 1000)).collect();
    ((1..=5).map(|k| format!("T:{k}")).collect(), series, error, t)
}

#[test]
fn correlation_and_stepwise_select_the_two_driving_sensors() {
    let (names, series, error, _) = campaign();
    let ranking = correlation_ranking(&series, &error);
    // T1 (r = 0.81) and T3 (r = -0.64) first; the others below 0.05 in magnitude
    assert_eq!((ranking[0].0, ranking[1].0), (0, 2));
    assert!((ranking[0].1 - 0.8126).abs() < 1e-3 && (ranking[1].1 + 0.6378).abs() < 1e-3, "{ranking:?}");
    assert!(ranking[2..].iter().all(|r| r.1.abs() < 0.05));
    // ranges: T1 10 (1 - exp(-71940 / 6000)) degC, T3 at most 8 degC
    assert!((ranking[0].2 - 10.0 * (1.0 - (-71940.0f64 / 6000.0).exp())).abs() < 1e-9);
    assert!(ranking[1].2 <= 8.0 && ranking[1].2 > 7.9);
    assert_eq!(select_by_correlation(&series, &error, 2, 0.0), vec![0, 2]);
    // a minimum range of 9 degC keeps only T1
    assert_eq!(select_by_correlation(&series, &error, 2, 9.0), vec![0]);

    let (model, fit, kept) = fit_stepwise("E", &names, &series, None, 0, true, &error, 0.9999).unwrap();
    assert_eq!(kept, vec!["intercept", "T:1", "T:3"]);
    let c = &model.coefficients[0];
    // standard uncertainties are ~3e-4 (slopes) and ~0.01 um (intercept): tolerances of ~10 u
    assert!((c[0] - 5.0).abs() < 0.1 && (c[1] - 3.0).abs() < 3e-3 && (c[3] + 1.5).abs() < 3e-3, "{c:?}");
    assert_eq!((c[2], c[4], c[5]), (0.0, 0.0, 0.0));
    let rms = (fit.residuals.iter().map(|r| r * r).sum::<f64>() / SAMPLES as f64).sqrt();
    let noise_rms = 0.05 * ((0..SAMPLES).map(|i| noise(i + 1000).powi(2)).sum::<f64>() / SAMPLES as f64).sqrt();
    assert!((rms - noise_rms).abs() < 0.1 * noise_rms, "{rms} vs {noise_rms}");
    // the two selected sensors alone give the same model
    let two: Vec<Vec<f64>> = vec![series[0].clone(), series[2].clone()];
    let (alone, _) = fit_regression("E", &["T:1".into(), "T:3".into()], &two, None, 0, true, &error).unwrap();
    for (a, b) in alone.coefficients[0].iter().zip([c[0], c[1], c[3]]) {
        assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()));
    }
}

#[test]
fn thermal_fit_select_picks_the_driving_sensors() {
    let (names, series, error, t) = campaign();
    let mut csv = format!("t,{},E\n", names.join(","));
    for i in 0..SAMPLES {
        let temps: Vec<String> = series.iter().map(|s| format!("{:.6}", s[i])).collect();
        csv += &format!("{},{},{:.6}\n", t[i], temps.join(","), error[i]);
    }
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("five.csv");
    std::fs::write(&data, csv).unwrap();
    let run =
        |select: &str| json(&trueaxis(&["thermal", "fit", "--data", data.to_str().unwrap(), "--error", "E", "--select", select, "--json"]));
    let stepwise = run("stepwise");
    assert_eq!(stepwise["kept"], serde_json::json!(["intercept", "T:1", "T:3"]));
    let correlation = run("correlation:2");
    assert_eq!(correlation["kept"], serde_json::json!(["T:1", "T:3"]));
    assert_eq!(correlation["model"]["sensors"], serde_json::json!(["T:1", "T:3"]));
    let c: Vec<f64> = correlation["model"]["coefficients"][0].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert!((c[0] - 5.0).abs() < 0.1 && (c[1] - 3.0).abs() < 3e-3 && (c[2] + 1.5).abs() < 3e-3, "{c:?}");
    // both selections give the same fit: same training residual RMS
    let rms = |doc: &serde_json::Value| doc["training"]["rms"].as_f64().unwrap();
    assert!((rms(&stepwise) - rms(&correlation)).abs() < 1e-9, "{} vs {}", rms(&stepwise), rms(&correlation));
}
