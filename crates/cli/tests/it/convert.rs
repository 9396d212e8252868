//! Instrument files through the command line: `iso230-2`, `fit` and `reversal` on a Renishaw `.rtl`
//! give the results of the CSV it was written from (with and without the file's material
//! temperature); `convert` writes canonical CSV and error-values files that the other commands read
//! to the same numbers; ballbar exports through `ballbar iso230-4`; `inspect`; refusals (exit 2, one
//! line naming the file, the column and the fix) and warnings (exit 0, stderr) of the plausibility
//! checks; a `fit` range error names the file, line and column.

use crate::support::{arg, failed, json_of, read, trueaxis, vmc3};
use serde_json::Value;

fn close(name: &str, a: &Value, b: &Value, tol: f64) {
    let (x, y) = (a.as_f64().unwrap_or_else(|| panic!("{name}: {a}")), b.as_f64().unwrap_or_else(|| panic!("{name}: {b}")));
    assert!((x - y).abs() <= tol, "{name}: {x} vs {y} (tolerance {tol})");
}

const KEYS: [&str; 12] = ["A", "A_plus", "A_minus", "B", "B_mean", "E", "E_plus", "E_minus", "M", "R", "R_plus", "R_minus"];

#[test]
fn iso230_2_of_the_rtl_equals_its_csv_with_and_without_the_file_temperature() {
    let csv = json_of(&["iso230-2", "examples/data/laser_x.csv", "--json"]);
    let raw = json_of(&["iso230-2", "examples/data/laser_x.rtl", "--json", "--no-file-temperature"]);
    for k in KEYS {
        close(k, &raw[k], &csv[k], 1e-9);
    }
    assert_eq!(raw["metadata"]["machine"], "VMC3 example machine (examples/machines/vmc3.toml)");
    assert_eq!(raw["metadata"]["operator"], "A. Example");
    assert!(raw["temperature_correction"].is_null());
    // by default the file's material temperature (mean 21.2 degC) and coefficient (11.5 um/m/K)
    // correct the readings: the same as the options on the CSV
    let file = trueaxis(&["iso230-2", "examples/data/laser_x.rtl", "--json"]);
    assert!(file.status.success());
    let note = String::from_utf8_lossy(&file.stderr);
    assert!(note.contains("material temperature 21.200 degC") && note.contains("11.5 um/m/K"), "{note}");
    let file: Value = serde_json::from_slice(&file.stdout).unwrap();
    let options = json_of(&["iso230-2", "examples/data/laser_x.csv", "--json", "--scale-temperature", "21.2", "--scale-expansion", "11.5"]);
    for k in KEYS {
        close(k, &file[k], &options[k], 1e-9);
    }
    assert_eq!(file["temperature_correction"]["source"], "file");
    close("material temperature", &file["temperature_correction"]["material_temperature_degc"], &Value::from(21.2), 1e-12);
    // the correction is 11.5e-3 um/mm/K * 1.2 K * 400 mm = 5.52 um at the end: E changes by it
    assert!((file["E"].as_f64().unwrap() - raw["E"].as_f64().unwrap()).abs() > 1.0);
}

#[test]
fn convert_writes_canonical_csv_that_reads_to_the_same_results() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("laser_x_from_rtl.csv");
    let status = trueaxis(&["convert", "examples/data/laser_x.rtl", "--to", "csv", "--out", arg(&out)]);
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("# Machine: VMC3 example machine") && text.contains("target [mm],dev [um],dir,run\n"), "{text}");
    let a = json_of(&["iso230-2", arg(&out), "--json"]);
    let b = json_of(&["iso230-2", "examples/data/laser_x.rtl", "--json"]);
    for k in KEYS {
        close(k, &a[k], &b[k], 1e-9);
    }
    assert_eq!(a["metadata"], b["metadata"], "the metadata survive the conversion");
    // an Etalon file is refused as readings and converted as errors
    let bad = trueaxis(&["convert", "examples/data/vmc3_etalon.exc", "--to", "csv"]);
    failed(&bad, 2, &["use --to errors --machine"]);
}

#[test]
fn fit_and_reversal_read_rtl_files() {
    let args = |data: &str| {
        vec![
            "fit",
            "--data",
            data,
            "--parameter",
            "EXX",
            "--machine",
            "examples/machines/vmc3.toml",
            "--knot-spacing",
            "200",
            "--direction",
            "both",
            "--json",
            "--no-file-temperature",
        ]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>()
    };
    let run = |data: &str| {
        let a = args(data);
        json_of(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let (rtl, csv) = (run("examples/data/laser_x.rtl"), run("examples/data/laser_x.csv"));
    for side in ["plus", "minus"] {
        let (x, y) = (rtl[side]["terms"].as_array().unwrap(), csv[side]["terms"].as_array().unwrap());
        assert_eq!(x.len(), y.len());
        for (p, q) in x.iter().zip(y) {
            close("coefficient", &p["coefficient"], &q["coefficient"], 1e-7);
        }
        close("residual", &rtl[side]["residual_rms"], &csv[side]["residual_rms"], 1e-9);
    }
    assert_eq!(rtl["metadata"]["axis"], "X");
    // a reversal from a laser file of two runs: run 1 is m1, run 2 is m2
    let dir = tempfile::tempdir().unwrap();
    let arbor = read("examples/data/reversal_arbor.csv");
    let rows: Vec<Vec<f64>> = arbor
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("position"))
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let mut rtl = format!("TARGET DATA::\r\nTarget-count: {}\r\nTargets :\r\n", rows.len());
    for r in &rows {
        rtl.push_str(&format!("{:.6}\r\n", r[0]));
    }
    rtl.push_str("RUNS::\r\nRun-count: 2\r\nDEVIATIONS::\r\nRun Target Data:\r\n");
    for (run, col) in [(1, 1), (2, 2)] {
        for (i, r) in rows.iter().enumerate() {
            rtl.push_str(&format!("{run}   {}      {:.7}\r\n", i + 1, r[col] / 1000.0));
        }
    }
    rtl.push_str("EOF::\r\n");
    // the second scan listed in the same order: both runs + (a straightness scan, not a positioning run)
    let path = dir.path().join("arbor.rtl");
    std::fs::write(&path, rtl).unwrap();
    let a = json_of(&["reversal", "arbor", arg(&path), "--json"]);
    let b = json_of(&["reversal", "arbor", "examples/data/reversal_arbor.csv", "--json"]);
    for (x, y) in a["straightness_um"].as_array().unwrap().iter().zip(b["straightness_um"].as_array().unwrap()) {
        close("straightness", x, y, 1e-9);
    }
}

#[test]
fn ballbar_exports_and_inspect() {
    let export = json_of(&vmc3(&["ballbar", "iso230-4", "examples/ballbar/export_xy.txt"], &["--centre", "0,0,-200", "--json"]));
    assert_eq!(export["radius_mm"], 100.0);
    assert_eq!(export["plane"], "xy");
    assert_eq!(export["metadata"]["operator"], "A. Example");
    assert_eq!(export["runs"].as_array().unwrap().len(), 2);
    // the simulation the export was written from (its first line), through the CSV path
    let dir = tempfile::tempdir().unwrap();
    let sim = dir.path().join("sim.csv");
    let out = trueaxis(&vmc3(
        &["ballbar", "simulate"],
        &[
            "--errors",
            "examples/ballbar/vmc3_circle.toml",
            "--test",
            "circle",
            "--plane",
            "xy",
            "--radius",
            "100",
            "--centre",
            "0,0,-200",
            "--dir",
            "both",
            "--step",
            "0.954929658551372",
            "--noise",
            "0.15",
            "--seed",
            "7",
            "--out",
            arg(&sim),
        ],
    ));
    assert!(out.status.success());
    let csv = json_of(&[
        "ballbar",
        "iso230-4",
        arg(&sim),
        "--radius",
        "100",
        "--machine",
        "examples/machines/vmc3.toml",
        "--centre",
        "0,0,-200",
        "--json",
    ]);
    for (r, s) in export["runs"].as_array().unwrap().iter().zip(csv["runs"].as_array().unwrap()) {
        for k in ["G_um", "F_max_um", "F_min_um", "arc_deg"] {
            close(k, &r[k], &s[k], 1e-9);
        }
    }
    close("H", &export["H_um"], &csv["H_um"], 1e-9);
    // inspect says what it found
    let i = json_of(&["inspect", "examples/ballbar/export_xy.txt", "--json"]);
    assert_eq!(i["separator"], ";");
    assert_eq!(i["readings"]["header"]["radius_mm"], 100.0);
    assert_eq!(i["readings"]["angles_from"], "sample numbers, radius, feed rate and sample rate");
    let i = json_of(&["inspect", "examples/data/laser_x.rtl", "--json"]);
    assert_eq!(i["format"], "Renishaw laser file (.rtl)");
    assert_eq!(i["readings"]["targets"], 41);
    assert_eq!(i["readings"]["runs"].as_array().unwrap().len(), 10);
    assert!(i["commands"].as_array().unwrap().iter().any(|c| c["command"] == "iso230-2"));
    let i = json_of(&["inspect", "examples/data/vmc3_etalon.exc", "--json"]);
    assert_eq!(i["parameters"].as_array().unwrap().len(), 22);
    let text = trueaxis(&["inspect", "examples/data/iso230_2_x.csv"]);
    assert!(String::from_utf8_lossy(&text.stdout).contains("iso230-2"));
}

#[test]
fn etalon_files_convert_to_errors_that_predict_reads() {
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("vmc3_etalon.toml");
    let out = trueaxis(&vmc3(&["convert", "examples/data/vmc3_etalon.exc", "--to", "errors"], &["--out", arg(&errors)]));
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("[P0Z]"), "the skipped ISG parameter is named");
    // at poses on the 50 mm grid the converted tables equal the example's polynomials
    let poses = dir.path().join("grid.csv");
    std::fs::write(&poses, "X,Y,Z\n-400,-250,-400\n-150,100,-200\n200,-50,-50\n400,250,0\n").unwrap();
    let run = |e: &str| json_of(&vmc3(&["predict"], &["--errors", e, "--poses", arg(&poses), "--json"]));
    let (a, b) = (run(arg(&errors)), run("examples/errors/vmc3.toml"));
    for (p, q) in a["poses"].as_array().unwrap().iter().zip(b["poses"].as_array().unwrap()) {
        for k in ["dx", "dy", "dz", "drx", "dry", "drz"] {
            close(k, &p[k], &q[k], 2e-4);
        }
    }
    let out = trueaxis(&["convert", "examples/data/vmc3_etalon.exc", "--to", "errors", "--machine", "examples/machines/lathe2.toml"]);
    failed(&out, 2, &["refers to axis"]);
}

/// Exit 2, one line, naming the file and every fragment.
fn refused(args: &[&str], fragments: &[&str]) {
    let out = trueaxis(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(out.stdout.is_empty(), "nothing printed: {}", String::from_utf8_lossy(&out.stdout));
    for f in fragments {
        assert!(err.contains(f), "`{f}` not in: {err}");
    }
}

#[test]
fn implausible_files_are_refused_and_suspicious_ones_warned() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        arg(&p).to_string()
    };
    let mut mm = String::from("target,dev,dir,run\n");
    let mut um = String::from("target,dev,dir,run\n");
    for run in 1..=3 {
        for (t, d) in [(0.0, 1.2), (100.0, 2.5), (200.0, 3.1)] {
            for (dir, b) in [("+", 0.5), ("-", -0.5)] {
                mm.push_str(&format!("{t},{},{dir},{run}\n", (d + b) / 1000.0));
                um.push_str(&format!("{t},{},{dir},{run}\n", d + b));
            }
        }
    }
    let mm = write("mm.csv", &mm);
    refused(&["iso230-2", &mm], &["mm.csv", "column `dev`", "most likely mm", "label the header `dev [mm]`"]);
    refused(&["fit", "--data", &mm, "--parameter", "EXX"], &["mm.csv", "column `dev`", "`dev [mm]`"]);
    assert!(trueaxis(&["iso230-2", &write("um.csv", &um)]).status.success());
    // the fix works: the same file with its unit in the header
    let labelled = std::fs::read_to_string(&mm).unwrap().replacen("dev", "dev [mm]", 1);
    let fixed = json_of(&["iso230-2", &write("labelled.csv", &labelled), "--json"]);
    let plain = json_of(&["iso230-2", &dir.path().join("um.csv").to_string_lossy(), "--json"]);
    close("A", &fixed["A"], &plain["A"], 1e-9);
    // a target written with other digits in one run
    let near = std::fs::read_to_string(dir.path().join("um.csv")).unwrap().replacen("100,3,+,2", "100.0004,3,+,2", 1);
    refused(&["iso230-2", &write("near.csv", &near)], &["near.csv", "column `target`", "100.0004 mm", "one value"]);
    // a target missing from a run: a warning, the evaluation goes on
    let lines: Vec<&str> = std::fs::read_to_string(dir.path().join("um.csv")).unwrap().leak().lines().collect();
    let missing: String = lines.iter().filter(|l| **l != "200,2.6,-,2").map(|l| format!("{l}\n")).collect();
    let out = trueaxis(&["iso230-2", &write("missing.csv", &missing)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("warning") && err.contains("200 mm from run 2 (-)"), "{err}");
    // ballbar angles in radians
    let mut rad = String::from("angle,dL\n");
    for k in 0..72 {
        rad.push_str(&format!("{},{}\n", (5.0 * k as f64).to_radians(), (k as f64 * 0.3).sin()));
    }
    refused(
        &["ballbar", "iso230-4", &write("rad.csv", &rad), "--radius", "100"],
        &["rad.csv", "column `angle`", "radians", "`angle [rad]`"],
    );
    // a radius that disagrees with the file's
    refused(
        &vmc3(&["ballbar", "iso230-4", "examples/ballbar/export_xy.txt", "--radius", "150"], &["--centre", "0,0,-200"]),
        &["export_xy.txt", "radius 100 mm", "150 mm"],
    );
    // an axis-position circle of another radius
    refused(
        &vmc3(&["ballbar", "iso230-4", "examples/ballbar/vmc3_xy.csv", "--radius", "150"], &["--centre", "0,0,-200"]),
        &["vmc3_xy.csv", "column `X, Y`", "radius 100.000 mm", "150 mm"],
    );
}

#[test]
fn a_fit_range_error_names_the_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("long.csv");
    std::fs::write(&data, "# beyond the X range of vmc3\ntarget,dev\n0,1.5\n200,2.5\n450,3.5\n").unwrap();
    refused(
        &["fit", "--data", arg(&data), "--parameter", "EXX", "--machine", "examples/machines/vmc3.toml"],
        &["long.csv: line 5: column target", "450", "outside its range"],
    );
}
