//! `thermal tune`: boundary conditions tuned to measured time constants (Zhu 2008 §4.4.2). The fin
//! with insulated ends has a uniform mode whose time constant is rho c A / (h P) exactly, so one
//! measured time constant gives h in closed form; two coefficients of the elongation element are
//! recovered from the two time constants of a model made with known values; the written file keeps
//! its comments and has the tuned time constants.

use crate::support::{arg, json, read, trueaxis};

#[test]
fn uniform_mode_of_the_fin_gives_h_in_closed_form() {
    // Zhu 2008 spindle: tau_1 = 363.6 min; fin of Table 3.1: rho c A / (P tau)
    let doc = json(&trueaxis(&[
        "thermal",
        "tune",
        "--model",
        "examples/thermal/fin.toml",
        "--tau-min",
        "363.6",
        "--tune",
        "convection_w_m2k",
        "--json",
    ]));
    let h = doc["coefficients"][0]["tuned_w_m2k"].as_f64().unwrap();
    let want = 7800.0 * 434.0 * 0.0314 / (0.6283185307179586 * 363.6 * 60.0);
    assert!((h / want - 1.0).abs() < 1e-8, "{h} vs {want}");
    assert!((want - 7.7546).abs() < 1e-4);
}

#[test]
fn two_coefficients_are_recovered_from_two_time_constants() {
    let dir = tempfile::tempdir().unwrap();
    let text = read("examples/thermal/elongation.toml");
    let truth = dir.path().join("truth.toml");
    std::fs::write(
        &truth,
        text.replace("convection_w_m2k = 20.0", "convection_w_m2k = 12.5").replace("right_end = 20.0", "right_end = 60.0"),
    )
    .unwrap();
    let modes = json(&trueaxis(&["thermal", "modes", "--model", arg(&truth), "--count", "2", "--json"]));
    let taus: Vec<String> = modes["modes"].as_array().unwrap().iter().map(|m| format!("{:.12}", m["tau_min"].as_f64().unwrap())).collect();
    let out = dir.path().join("tuned.toml");
    let doc = json(&trueaxis(&[
        "thermal",
        "tune",
        "--model",
        "examples/thermal/elongation.toml",
        "--tau-min",
        &taus.join(","),
        "--tune",
        "convection_w_m2k,right_end",
        "--out",
        arg(&out),
        "--json",
    ]));
    let tuned: Vec<f64> = doc["coefficients"].as_array().unwrap().iter().map(|c| c["tuned_w_m2k"].as_f64().unwrap()).collect();
    assert!((tuned[0] / 12.5 - 1.0).abs() < 1e-6, "{tuned:?}");
    assert!((tuned[1] / 60.0 - 1.0).abs() < 1e-6, "{tuned:?}");
    // the written file: comments kept, its modes are the measured ones
    let written = std::fs::read_to_string(&out).unwrap();
    let comments = |t: &str| t.lines().filter(|l| l.contains('#')).count();
    assert_eq!(comments(&written), comments(&text));
    let h: f64 =
        written.lines().find_map(|l| l.strip_prefix("convection_w_m2k = ")).unwrap().split('#').next().unwrap().trim().parse().unwrap();
    assert!((h / 12.5 - 1.0).abs() < 1e-6, "{written}");
    let again = json(&trueaxis(&["thermal", "modes", "--model", arg(&out), "--count", "2", "--json"]));
    for (a, b) in again["modes"].as_array().unwrap().iter().zip(modes["modes"].as_array().unwrap()) {
        assert!((a["tau_min"].as_f64().unwrap() / b["tau_min"].as_f64().unwrap() - 1.0).abs() < 1e-8);
    }
}

#[test]
fn tuning_refuses_what_it_cannot_do() {
    let bad = |args: &[&str], fragment: &str| {
        let mut all = vec!["thermal", "tune", "--model"];
        all.extend_from_slice(args);
        let out = trueaxis(&all);
        assert_eq!(out.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(fragment), "expected `{fragment}` in {stderr}");
    };
    bad(&["examples/thermal/fin.toml", "--tau-min", "100", "--tune", "left_end"], "an insulated face cannot be tuned");
    bad(&["examples/thermal/fin.toml", "--tau-min", "100", "--tune", "top_end"], "no key `top_end`");
    bad(
        &["examples/thermal/elongation.toml", "--tau-min", "100", "--tune", "left_end,right_end"],
        "1 measured time constants cannot determine 2",
    );
    bad(&["examples/thermal/fin.toml", "--tau-min", "-5", "--tune", "convection_w_m2k"], "positive numbers of seconds");
}
