//! `trueaxis ballbar simulate|identify` round trips through the command line for every method
//! (Jiang 2014 ch. 4 two pivots, ch. 5 extended bar, ch. 6 four setups) and every kind of rotary
//! pair (table-tilting c600u, spindle-tilting head5, the KX8-Five's 45 deg A axis); independence of
//! the simulated noise; the input checks of `identify`; ISO 230-4 significance and shares.

use crate::support::{arg, json, refused, trueaxis, vmc3};
use std::path::Path;

/// Simulates the four steps of `method` (extra CLI arguments) into `dir` and identifies them.
fn round_trip(dir: &Path, machine: &str, errors: &str, method: &[&str], noise: &str) -> serde_json::Value {
    let mut files = Vec::new();
    for step in ["a1", "a2", "c1", "c2"] {
        let path = dir.join(format!("{step}.csv")).to_str().unwrap().to_string();
        let mut args =
            vec!["ballbar", "simulate", "--machine", machine, "--errors", errors, "--test", step, "--noise", noise, "--out", &path];
        args.extend_from_slice(method);
        let out = trueaxis(&args);
        assert!(out.status.success(), "{step}: {}", String::from_utf8_lossy(&out.stderr));
        files.push(path);
    }
    let mut args = vec!["ballbar", "identify", "--machine", machine, "--json"];
    for (flag, f) in ["--a1", "--a2", "--c1", "--c2"].iter().zip(&files) {
        args.extend_from_slice(&[flag, f]);
    }
    args.extend_from_slice(method);
    json(&trueaxis(&args))
}

/// Every value of `truth` (um or urad) within 0.05 um / 0.5 urad (the noise-free tolerances of
/// crates/trueaxis/tests/it/identify/pige.rs: second-order terms of the first-order method), and nothing else named.
fn assert_truth(doc: &serde_json::Value, truth: &[(&str, f64)], what: &str) {
    let params = doc["parameters"].as_object().unwrap();
    assert_eq!(params.len(), truth.len(), "{what}: {params:?}");
    for (name, value) in truth {
        let p = &params[*name];
        let tol = if p["unit"] == "urad" { 0.5 } else { 0.05 };
        let got = p["value"].as_f64().unwrap();
        assert!((got - value).abs() < tol, "{what}: {name} = {got}, true {value}");
    }
}

const C600U_TRUTH: [(&str, f64); 8] =
    [("EY0A", 35.3), ("EZ0A", -33.4), ("EB0A", -6.25), ("EC0A", 5.8), ("EX0C", 1.3), ("EY0C", -52.9), ("EA0C", -108.0), ("EB0C", 21.7)];

#[test]
fn the_three_methods_round_trip_on_the_c600u() {
    let dir = tempfile::tempdir().unwrap();
    let m = "examples/machines/c600u.toml";
    let e = "examples/ballbar/c600u_piges.toml";
    for method in [
        &["--method", "extended-bar"][..],
        &["--method", "two-pivot", "--outer-offset", "150"][..],
        &["--method", "four-setup", "--outer-positions", "-200,250", "--inner-positions", "0,78"][..],
    ] {
        let doc = round_trip(dir.path(), m, e, method, "0");
        assert_eq!(doc["method"], method[1]);
        assert_truth(&doc, &C600U_TRUTH, method[1]);
        // one run: the repeatability is not assessed
        assert!(doc["repeatability_ok"].is_null() && doc["parameters"]["EY0A"]["std"].is_null());
        assert!(doc["warnings"].as_array().unwrap().is_empty());
    }
}

#[test]
fn a_spindle_tilting_head_and_a_tilted_axis_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    // head5 (wXYbZCBt): C carries B on the tool side; the spindle ball rides at the radius.
    let head = dir.path().join("head.toml");
    std::fs::write(
        &head,
        "[constant]\nEX0C = 12.0\nEY0C = -8.0\nEA0C = 30.0\nEB0C = -20.0\nEX0B = 5.0\nEZ0B = -7.0\nEA0B = 15.0\nEC0B = 25.0\n",
    )
    .unwrap();
    let doc = round_trip(dir.path(), "examples/machines/head5.toml", arg(&head), &[], "0");
    let truth =
        [("EX0C", 12.0), ("EY0C", -8.0), ("EA0C", 30.0), ("EB0C", -20.0), ("EX0B", 5.0), ("EZ0B", -7.0), ("EA0B", 15.0), ("EC0B", 25.0)];
    assert_truth(&doc, &truth, "head5");
    // kx8five: A along (0, 1, 1)/sqrt 2 has no pair of ISO names across it: all three components
    // of its offset and tilt (each perpendicular to A) are given; C (on A) has the thesis's four.
    let kx = dir.path().join("kx.toml");
    let s = std::f64::consts::FRAC_1_SQRT_2 * 10.0;
    std::fs::write(
        &kx,
        format!("[constant]\nEY0A = {s}\nEZ0A = {}\nEA0A = 20.0\nEB0A = 10.0\nEC0A = -10.0\nEX0C = 4.0\nEY0C = -3.0\nEA0C = 12.0\nEB0C = -9.0\n", -s),
    )
    .unwrap();
    let doc = round_trip(dir.path(), "examples/machines/kx8five.toml", arg(&kx), &[], "0");
    let truth = [
        ("EX0A", 0.0),
        ("EY0A", s),
        ("EZ0A", -s),
        ("EA0A", 20.0),
        ("EB0A", 10.0),
        ("EC0A", -10.0),
        ("EX0C", 4.0),
        ("EY0C", -3.0),
        ("EA0C", 12.0),
        ("EB0C", -9.0),
    ];
    assert_truth(&doc, &truth, "kx8five");
}

#[test]
fn one_rotary_axis_on_each_side_simulates_but_is_not_identified() {
    // wCXYbZAt (swivelling head A, rotary table C): the steps simulate; identify refuses with the
    // reason (a common shift of both axis lines moves tool and workpiece together).
    let dir = tempfile::tempdir().unwrap();
    let machine = dir.path().join("mixed.toml");
    std::fs::write(
        &machine,
        "name = \"head A + table C\"\nstructure = \"wCXYbZAt\"\n[axes]\n\
         X = { kind = \"linear\", direction = [-1, 0, 0], range = [-500, 500] }\n\
         Y = { kind = \"linear\", direction = [0, -1, 0], range = [-300, 300] }\n\
         Z = { kind = \"linear\", direction = [0, 0, 1], range = [-450, 0] }\n\
         A = { kind = \"rotary\", direction = [1, 0, 0], point = [0, 0, 400], range = [-100, 100] }\n\
         C = { kind = \"rotary\", direction = [0, 0, 1], point = [0, 0, 0] }\n[tool]\npoint = [0, 0, 200]\n",
    )
    .unwrap();
    let m = arg(&machine);
    let mut files = Vec::new();
    for step in ["a1", "a2", "c1", "c2"] {
        let path = dir.path().join(format!("{step}.csv")).to_str().unwrap().to_string();
        let out = trueaxis(&["ballbar", "simulate", "--machine", m, "--test", step, "--out", &path]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        files.push(path);
    }
    let out =
        trueaxis(&["ballbar", "identify", "--machine", m, "--a1", &files[0], "--a2", &files[1], "--c1", &files[2], "--c2", &files[3]]);
    refused(&out, 2, &["different sides of the chain", "changes no bar length", "wCAbYXZt", "wXYbZCBt"]);
}

/// Pearson correlation of two equally long series.
fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

/// The noise (um) of a simulated error-free circle, CCW then CW run.
fn circle_noise(seed: &str) -> (Vec<f64>, Vec<f64>) {
    let out = trueaxis(&vmc3(
        &["ballbar", "simulate"],
        &["--test", "circle", "--centre", "0,0,-200", "--dir", "both", "--step", "0.5", "--noise", "1", "--seed", seed],
    ));
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let (mut ccw, mut cw) = (Vec::new(), Vec::new());
    for line in text.lines().skip(2) {
        let f: Vec<&str> = line.split(',').collect();
        let v: f64 = f[f.len() - 1].parse().unwrap();
        if f[f.len() - 2] == "ccw" {
            ccw.push(v)
        } else {
            cw.push(v)
        }
    }
    (ccw, cw)
}

#[test]
fn simulated_noise_is_independent_across_seeds_and_runs() {
    // 720 readings per run of N(0, 1 um): independent series have |r| < 4 / sqrt(720) = 0.149
    // except with probability 7e-5. The former generator gave seed n + 2 the noise of seed n
    // shifted by one sample (r = 1 at lag 1) and made the CW run share draws with the CCW run.
    let (a_ccw, a_cw) = circle_noise("1");
    let (b_ccw, b_cw) = circle_noise("3");
    let n = a_ccw.len();
    assert_eq!(n, 720);
    let bound = 4.0 / (n as f64).sqrt();
    let sd = (a_ccw.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
    assert!((sd - 1.0).abs() < 0.1, "noise sd {sd}");
    for (what, x, y) in [
        ("seed 1 vs 3", &a_ccw[..], &b_ccw[..]),
        ("seed 1 vs 3, lag 1", &a_ccw[1..], &b_ccw[..n - 1]),
        ("seed 3 vs 1, lag 1", &b_ccw[1..], &a_ccw[..n - 1]),
        ("CCW vs CW", &a_ccw[..], &a_cw[..]),
        ("CCW vs CW, lag 1", &a_ccw[1..], &a_cw[..n - 1]),
        ("CW seed 1 vs 3", &a_cw[..], &b_cw[..]),
    ] {
        let r = correlation(x, y);
        assert!(r.abs() < bound, "{what}: r = {r}");
    }
    // the same seed repeats exactly
    assert_eq!(circle_noise("1").0, a_ccw);
}

#[test]
fn identify_refuses_what_it_cannot_fit() {
    let dir = tempfile::tempdir().unwrap();
    let m = "examples/machines/c600u.toml";
    let three = dir.path().join("a1_3.csv");
    std::fs::write(&three, "X,Y,Z,A,C,angle,dir,dL\n0,0,0,-20,0,-20,ccw,-8.3\n0,0,0,-10,0,-10,ccw,-9.0\n0,0,0,0,0,0,ccw,-9.5\n").unwrap();
    let empty = dir.path().join("empty.csv");
    std::fs::write(&empty, "").unwrap();
    // identify on the c600u with the given step files and extra options
    let identify = |files: [&str; 4], extra: &[&str]| {
        let mut args = vec!["ballbar", "identify", "--machine", m];
        for (flag, f) in ["--a1", "--a2", "--c1", "--c2"].iter().zip(files) {
            args.extend_from_slice(&[flag, f]);
        }
        args.extend_from_slice(extra);
        trueaxis(&args)
    };
    let [a1, a2, c1, c2] = ["A1", "A2", "C1", "C2"].map(|s| format!("examples/ballbar/{s}.csv"));
    let steps = |first: &str| identify([first, &a2, &c1, &c2], &[]);
    refused(&steps(arg(&three)), 2, &["a1_3.csv", "step A1", "3 readings over 20.0 deg", "at least 8 readings over at least 45 deg"]);
    refused(&steps(&c1), 2, &["C1.csv", "step A1", "over 0.0 deg"]);
    refused(&steps(arg(&empty)), 2, &["empty.csv", "the file is empty"]);
    refused(&identify([&a1, &a2, &c1, &c2], &["--pivot-offset-a", "0,100"]), 2, &["--pivot-offset-a", "100.000 mm", "below 10 mm"]);
    refused(&identify([&a1, &a2, &c1, &c2], &["--method", "two-pivot"]), 2, &["--outer-offset"]);
    // swapped C files: accepted (each is a full circle) but warned about, with the residual
    let swapped = identify([&a1, &a2, &c2, &c1], &["--json"]);
    let doc = json(&swapped);
    let warnings = doc["warnings"].as_array().unwrap();
    assert!(warnings.iter().any(|w| w.as_str().unwrap().contains("step C1 (examples/ballbar/C2.csv)")), "{warnings:?}");
    assert!(String::from_utf8_lossy(&swapped.stderr).contains("warning"));
}

#[test]
fn simulate_bounds_its_inputs() {
    let circle = |extra: &[&str]| {
        let mut a = vec!["ballbar", "simulate", "--machine", "examples/machines/vmc3.toml", "--test", "circle", "--centre", "0,0,-200"];
        a.extend_from_slice(extra);
        trueaxis(&a)
    };
    refused(&circle(&["--step", "1e-9"]), 2, &["--step", "at most 1000000"]);
    refused(&circle(&["--noise", "inf"]), 2, &["--noise"]);
    refused(&circle(&["--radius", "0"]), 2, &["--radius"]);
    refused(&trueaxis(&vmc3(&["ballbar", "simulate"], &["--test", "a1"])), 2, &["rotary axes", "need exactly two"]);
}

fn iso(file: &str) -> serde_json::Value {
    json(&trueaxis(&[
        "ballbar",
        "iso230-4",
        file,
        "--machine",
        "examples/machines/vmc3.toml",
        "--radius",
        "100",
        "--centre",
        "0,0,-200",
        "--json",
    ]))
}

#[test]
fn iso230_4_reports_only_significant_resolved_terms() {
    let dir = tempfile::tempdir().unwrap();
    let sim = |extra: &[&str], name: &str| {
        let path = dir.path().join(name).to_str().unwrap().to_string();
        let mut a = vec!["ballbar", "simulate", "--machine", "examples/machines/vmc3.toml", "--test", "circle", "--centre", "0,0,-200"];
        a.extend_from_slice(extra);
        a.extend_from_slice(&["--out", &path]);
        assert!(trueaxis(&a).status.success());
        path
    };
    // A perfect circle: every effect is rounding (< 0.1 um, the bar resolution): no shares.
    let perfect = iso(&sim(&["--dir", "both", "--start", "0.5"], "perfect.csv"));
    for d in perfect["diagnostics"].as_array().unwrap() {
        assert_eq!(d["share_percent"].as_f64().unwrap(), 0.0, "{d}");
    }
    // A 10-80 deg arc with 0.1 um noise and a 25 urad squareness: what remains has |value| >= u,
    // the rest is listed as not significant.
    let errors = dir.path().join("sq.toml");
    std::fs::write(&errors, "[constant]\nEC0X = 25.0\n").unwrap();
    let arc = sim(&["--errors", arg(&errors), "--dir", "ccw", "--start", "10", "--noise", "0.1", "--seed", "5"], "full.csv");
    let text = std::fs::read_to_string(&arc).unwrap();
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| l.split(',').nth(3).and_then(|a| a.parse::<f64>().ok()).is_none_or(|a| (10.0..=80.0).contains(&a)))
        .collect();
    let partial = dir.path().join("arc.csv");
    std::fs::write(&partial, kept.join("\n")).unwrap();
    let doc = iso(arg(&partial));
    for d in doc["diagnostics"].as_array().unwrap() {
        if d["effect_um"].as_f64().unwrap() > 0.0 {
            assert!(d["value"].as_f64().unwrap().abs() >= d["std_uncertainty"].as_f64().unwrap(), "{d}");
        }
    }
    let omitted: Vec<&str> = doc["omitted"].as_array().unwrap().iter().map(|o| o.as_str().unwrap()).collect();
    assert!(omitted.iter().any(|o| o.contains("not significant")), "{omitted:?}");
    let total: f64 = doc["diagnostics"].as_array().unwrap().iter().map(|d| d["share_percent"].as_f64().unwrap()).sum();
    assert!(total == 0.0 || (total - 100.0).abs() < 0.1, "shares sum to {total}");
}
