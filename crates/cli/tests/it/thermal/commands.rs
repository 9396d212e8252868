//! `trueaxis thermal` end to end: the JSON contract of `modes` (docs/design.md, Command line), placement,
//! fit -> model file -> predict, error terms read by `trueaxis predict`, and bad input.

use crate::support::thermal::fit_dz;
use crate::support::{arg, failed, json, read, refused, trueaxis, vmc3, ROOT};

#[test]
fn modes_json_is_sorted_by_decreasing_time_constant() {
    let doc = json(&trueaxis(&["thermal", "modes", "--model", "examples/thermal/fin.toml", "--count", "5", "--json"]));
    let modes = doc["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 5);
    let taus: Vec<f64> = modes.iter().map(|m| m["tau_min"].as_f64().unwrap()).collect();
    assert!(taus.windows(2).all(|w| w[0] > w[1]));
    // tau_1 of the fin with insulated ends: 1 / (h P / (rho c_p A)) = 140.98 min
    assert!((taus[0] - 140.978).abs() < 0.01, "{}", taus[0]);
    let shares: f64 = modes.iter().map(|m| m["share"].as_f64().unwrap()).sum();
    assert!((shares - 1.0).abs() < 1e-12 && modes.iter().all(|m| m["weight"].as_f64().unwrap() > 0.0));
    // the sparse solver gives the same numbers
    let sparse =
        json(&trueaxis(&["thermal", "modes", "--model", "examples/thermal/plate.toml", "--count", "4", "--method", "lanczos", "--json"]));
    let dense =
        json(&trueaxis(&["thermal", "modes", "--model", "examples/thermal/plate.toml", "--count", "4", "--method", "dense", "--json"]));
    for (a, b) in sparse["modes"].as_array().unwrap().iter().zip(dense["modes"].as_array().unwrap()) {
        let (a, b) = (a["tau_min"].as_f64().unwrap(), b["tau_min"].as_f64().unwrap());
        assert!((a - b).abs() < 1e-8 * b);
    }
}

#[test]
fn place_reproduces_the_thesis_positions() {
    let doc =
        json(&trueaxis(&["thermal", "place", "--model", "examples/thermal/elongation.toml", "--count", "3", "--share", "1", "--json"]));
    let sensors = doc["sensors"].as_array().unwrap();
    // Position 5 (the middle, node 12) serves modes I and III, Position 1 (node 0) mode II
    assert_eq!(sensors[0]["node"], 12);
    assert_eq!(sensors[0]["modes"], serde_json::json!([1, 3]));
    assert_eq!(sensors[1]["node"], 0);
    assert_eq!(sensors[1]["modes"], serde_json::json!([2]));
}

#[test]
fn fit_writes_a_model_that_predict_and_the_chain_evaluate() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("dz.toml");
    let terms = dir.path().join("terms.toml");
    let doc = json(&fit_dz(
        "warmup",
        &["--out", arg(&model), "--parameter", "EZZ", "--terms-out", arg(&terms), "--machine", "examples/machines/vmc3.toml", "--json"],
    ));
    // validated on the three other runs, RMS below 4 % of the 63 um peak
    for run in ["short", "long", "cycle"] {
        assert!(doc["validation"][run]["rms"].as_f64().unwrap() < 2.5, "{run}");
    }
    let c = doc["model"]["coefficients"][0].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect::<Vec<_>>();
    let pred = json(&trueaxis(&["thermal", "predict", "--model", arg(&model), "--data", "examples/thermal/campaign.csv", "--json"]));
    let first_cycle = pred["samples"].as_array().unwrap().iter().find(|s| s["run"] == "cycle" && s["t"] == 3600.0).unwrap();
    assert!((pred["residuals"]["short"]["rms"].as_f64().unwrap() - doc["validation"]["short"]["rms"].as_f64().unwrap()).abs() < 1e-12);
    // the error terms give the same dz through the kinematic chain (Z carries the tool: dz = EZZ)
    let poses = dir.path().join("poses.csv");
    std::fs::write(&poses, "X,Y,Z,T:p1,T:p5\n10,20,-100,31.5,24.25\n").unwrap();
    let out = trueaxis(&vmc3(&["predict"], &["--errors", arg(&terms), "--poses", arg(&poses), "--json"]));
    let dz = json(&out)["poses"][0]["dz"].as_f64().unwrap();
    let want = c[0] + c[1] * 31.5 + c[2] * 24.25;
    assert!((dz - want).abs() < 1e-4, "{dz} vs {want}");
    assert!(first_cycle["predicted"].as_f64().is_some());
}

#[test]
fn bad_input_is_reported_with_exit_status_2() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "kind = \"bar1d\"\nlength_m = 1.0\n").unwrap();
    let out = trueaxis(&["thermal", "modes", "--model", arg(&bad)]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.toml") && err.contains("missing key `conductivity_w_mk`"), "{err}");
    // a model without heat loss has an infinite time constant
    std::fs::write(
        &bad,
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/thermal/fin.toml"))
            .unwrap()
            .replace("convection_w_m2k = 20.0", "convection_w_m2k = 0.0"),
    )
    .unwrap();
    let out = trueaxis(&["thermal", "modes", "--model", arg(&bad)]);
    failed(&out, 2, &["loses no heat"]);
    let out = trueaxis(&["thermal", "fit", "--data", "examples/thermal/campaign.csv", "--error", "dq"]);
    failed(&out, 2, &["missing column `dq`"]);
}

#[test]
fn out_of_range_options_are_refused_naming_the_option() {
    let place = |reuse: &str| trueaxis(&["thermal", "place", "--model", "examples/thermal/fin.toml", &format!("--reuse={reuse}")]);
    for reuse in ["nan", "5", "0", "-0.5"] {
        refused(&place(reuse), 2, &["--reuse", "(0, 1]"]);
    }
    let fit = |more: &[&str]| trueaxis(&[&["thermal", "fit", "--data", "examples/thermal/campaign.csv"][..], more].concat());
    refused(&fit(&["--time-constants", "2", "--until", "nan"]), 2, &["--until NaN"]);
    refused(&fit(&["--error", "dz", "--select", "correlation:0"]), 2, &["--select correlation:0", "N >= 1"]);
    // the descriptions of place and predict options are all there
    let help = String::from_utf8_lossy(&trueaxis(&["thermal", "place", "--help"]).stdout).to_string();
    for text in ["Placement method", "Cumulative weight share", "candidates", "Print one JSON document"] {
        assert!(help.contains(text), "place --help lacks `{text}`");
    }
    let help = String::from_utf8_lossy(&trueaxis(&["thermal", "predict", "--help"]).stdout).to_string();
    for text in ["Campaign (CSV)", "Print one JSON document"] {
        assert!(help.contains(text), "predict --help lacks `{text}`");
    }
}

#[test]
fn one_sensor_for_five_modes_has_an_infinite_condition_number() {
    // the fin with insulated ends: every mode has its extreme at the heat source, one sensor serves
    // the 5 dominant modes; Phi_s is 1 x 5 of rank 1
    let doc = json(&trueaxis(&["thermal", "place", "--model", "examples/thermal/fin.toml", "--method", "modal", "--json"]));
    assert_eq!(doc["sensors"].as_array().unwrap().len(), 1);
    assert_eq!(doc["dominant_modes"].as_array().unwrap().len(), 5);
    assert!(doc["condition_number"].is_null());
    assert_eq!(doc["rank"], 1);
    assert!(doc["conditioning"].as_str().unwrap().contains("infinite, rank 1 < 5 modes"));
    // five sensors by effective independence separate the five modes: a finite condition number
    let doc = json(&trueaxis(&["thermal", "place", "--model", "examples/thermal/fin.toml", "--method", "efi", "--json"]));
    assert_eq!(doc["rank"], 5);
    let k = doc["condition_number"].as_f64().unwrap();
    assert!(k.is_finite() && k >= 1.0, "{k}");
}

#[test]
fn non_finite_predictions_and_rank_deficient_fits_are_failed_computations() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("huge.toml");
    std::fs::write(
        &model,
        "kind = \"regression\"\nerror = \"dz\"\nsensors = [\"T:p1\", \"T:p5\"]\nintercept = true\ncoefficients = [[1e308, 1e308, 1e308]]\n",
    )
    .unwrap();
    let out_file = dir.path().join("dz.csv");
    let out = trueaxis(&["thermal", "predict", "--model", arg(&model), "--data", "examples/thermal/campaign.csv", "--out", arg(&out_file)]);
    refused(&out, 1, &["not a finite number", "data row 1 in warmup"]);
    assert!(!out_file.exists() && out.stdout.is_empty());
    // a sensor that reads a constant cannot be separated from the intercept: exit 1, as identify
    let text = read("examples/thermal/campaign.csv");
    let constant: String = text
        .lines()
        .map(|l| {
            if l.starts_with('#') {
                l.to_string()
            } else if l.starts_with("run") {
                format!("{l},T:c")
            } else {
                format!("{l},21.5")
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let data = dir.path().join("constant.csv");
    std::fs::write(&data, constant).unwrap();
    refused(&trueaxis(&["thermal", "fit", "--data", arg(&data), "--error", "dz"]), 1, &["rank deficient", "T:c"]);
}

/// Screening (docs/screening.md): a blank cell (a logger dropout) refuses the file naming its
/// line; `--skip-missing` leaves the row out and lists it under `data_quality`.
#[test]
fn a_blank_cell_is_refused_or_skipped_on_request() {
    let root = std::path::Path::new(ROOT);
    let text = std::fs::read_to_string(root.join("examples/thermal/campaign.csv")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    // line 103: a row of the warm-up with T:p5 missing
    let cells: Vec<&str> = lines[102].split(',').collect();
    lines[102] = format!("{},{},{},,{}", cells[0], cells[1], cells[2], cells[4]);
    let dir = std::env::temp_dir().join(format!("trueaxis-thermal-screening-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("dropout.csv");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let p = arg(&path);
    let refused = trueaxis(&["thermal", "fit", "--data", p, "--error", "dz", "--train-runs", "warmup"]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("line 103"), "{}", String::from_utf8_lossy(&refused.stderr));
    let doc = json(&trueaxis(&["thermal", "fit", "--data", p, "--error", "dz", "--train-runs", "warmup", "--skip-missing", "--json"]));
    assert_eq!(doc["data_quality"][0]["kind"], "missing cells");
    assert_eq!(doc["data_quality"][0]["lines"], serde_json::json!([103]));
    let clean = json(&fit_dz("warmup", &["--json"]));
    assert_eq!(clean["data_quality"], serde_json::json!([]));
    let _ = std::fs::remove_dir_all(&dir);
}
