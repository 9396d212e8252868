//! Error terms of inputs from the command line: a workpiece-load error (Soons 1993 eq. 3.20) through
//! `predict --input` against the same error written out by hand, a drift model interpolated between
//! two axis positions (Soons 1993 §3.4.4) through `predict` against `thermal predict` of the fitted
//! model, and `compensate --poses` with load and spindle-speed columns against `predict`.

use crate::support::thermal::fit_dz;
use crate::support::{arg, failed, json, ok, read, trueaxis, vmc3};

fn poses_json(errors: &str, poses: &str, extra: &[&str]) -> Vec<serde_json::Value> {
    let mut args = vec!["predict", "--machine", "examples/machines/vmc3.toml", "--errors", errors, "--poses", poses, "--json"];
    args.extend_from_slice(extra);
    json(&trueaxis(&args))["poses"].as_array().unwrap().clone()
}

#[test]
fn load_error_from_the_command_line_equals_the_scaled_table() {
    let dir = tempfile::tempdir().unwrap();
    let load = dir.path().join("load.toml");
    std::fs::write(
        &load,
        "[load.EAX]\nreference_n = 4900.0\nposition = [-400, 0, 400]\nvalue = [12.0, 0.0, 13.0]\nlever_mm = 375.0\nlever_at = \"P:workpiece_z\"\n",
    )
    .unwrap();
    // 2600 N at 208 mm: the 4900 N table times 2600/4900 * (375 - 208)/375
    let f = 2600.0 / 4900.0 * (375.0 - 208.0) / 375.0;
    let scaled = dir.path().join("scaled.toml");
    std::fs::write(&scaled, format!("[table.EAX]\nposition = [-400, 0, 400]\nvalue = [{}, 0.0, {}]\n", 12.0 * f, 13.0 * f)).unwrap();
    let a = poses_json(arg(&load), "examples/poses/vmc3.csv", &["--input", "F:workpiece=2600", "--input", "P:workpiece_z=208"]);
    let b = poses_json(arg(&scaled), "examples/poses/vmc3.csv", &[]);
    let mut largest = 0.0f64;
    for (p, q) in a.iter().zip(&b) {
        for k in ["dx", "dy", "dz", "drx", "dry", "drz"] {
            let (x, y) = (p[k].as_f64().unwrap(), q[k].as_f64().unwrap());
            assert!((x - y).abs() < 1.1e-4, "{k}: {x} vs {y} (4 decimals)");
            largest = largest.max(x.abs());
        }
    }
    assert!(largest > 1.0, "the load error is seen: {largest}");
    // a load column in the poses file takes precedence over nothing given; a missing one is named
    let out = trueaxis(&vmc3(&["predict"], &["--errors", arg(&load), "--poses", "examples/poses/vmc3.csv"]));
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("missing column `F:workpiece` (N) needed by the error model; add it or give --input F:workpiece=N"),
        "{stderr}"
    );
    let out = trueaxis(&vmc3(&["predict"], &["--errors", arg(&load), "--poses", "examples/poses/vmc3.csv", "--input", "F:other=1"]));
    failed(&out, 2, &["the error model has no input `F:other` (inputs: F:workpiece, P:workpiece_z)"]);
}

#[test]
fn interpolated_drift_through_predict_equals_thermal_predict_of_the_models() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("dz_drift.toml");
    ok(&fit_dz("warmup", &["--model", "state-space", "--rates", "1", "--out", arg(&model)]));
    let fitted = std::fs::read_to_string(&model).unwrap();
    let body: String = fitted.lines().filter(|l| !l.starts_with('#')).map(|l| format!("{l}\n")).collect();
    // the model tested at Z = -400 and, with its gains doubled, at Z = 0
    let doubled: String = body
        .lines()
        .map(|l| match l.strip_prefix("gains_um_per_degc = ") {
            Some(g) => {
                let v: Vec<Vec<f64>> = serde_json::from_str(g).unwrap();
                format!("gains_um_per_degc = {:?}\n", v.iter().map(|r| r.iter().map(|x| 2.0 * x).collect::<Vec<_>>()).collect::<Vec<_>>())
            }
            None => format!("{l}\n"),
        })
        .collect();
    let errors = dir.path().join("drift.toml");
    std::fs::write(
        &errors,
        format!("[[drift.TZ]]\naxis = \"Z\"\nposition = -400\n{body}\n[[drift.TZ]]\naxis = \"Z\"\nposition = 0\n{doubled}"),
    )
    .unwrap();
    // poses: the campaign's rows at Z = -300 (a quarter of the way: 1.25 times the drift of Z = -400)
    let campaign = read("examples/thermal/campaign.csv");
    let mut lines = campaign.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let mut poses = String::from("X,Y,Z,run,t,T:p1,T:p5\n");
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        poses += &format!("0,0,-300,{},{},{},{}\n", f[col("run")], f[col("t")], f[col("T:p1")], f[col("T:p5")]);
    }
    let poses_path = dir.path().join("poses.csv");
    std::fs::write(&poses_path, poses).unwrap();
    let predicted = poses_json(arg(&errors), arg(&poses_path), &[]);
    let thermal = json(&trueaxis(&["thermal", "predict", "--model", arg(&model), "--data", "examples/thermal/campaign.csv", "--json"]));
    let samples = thermal["samples"].as_array().unwrap();
    assert_eq!(samples.len(), predicted.len());
    let mut largest = 0.0f64;
    for (p, s) in predicted.iter().zip(samples) {
        let want = 1.25 * s["predicted"].as_f64().unwrap();
        let got = p["dz"].as_f64().unwrap();
        assert!((got - want).abs() < 6e-5, "{got} vs {want} (predict prints 4 decimals)");
        largest = largest.max(got.abs());
    }
    assert!(largest > 5.0, "the drift is seen: {largest} um");
}

#[test]
fn compensate_poses_use_load_and_spindle_columns() {
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("e.toml");
    std::fs::write(
        &errors,
        "[load.EZX]\nreference_n = 1000.0\ncoefficients = [5.0, 0.01]\n[[term.EXX]]\ncoefficient = 1e-3\nfactors = { \"S:spindle\" = 1 }\n",
    )
    .unwrap();
    let poses = dir.path().join("p.csv");
    std::fs::write(&poses, "X,Y,Z,F:workpiece,S:spindle\n100,0,-100,3000,6000\n-200,50,-300,500,1000\n").unwrap();
    let predicted = poses_json(arg(&errors), arg(&poses), &[]);
    let out_dir = dir.path().join("comp");
    ok(&trueaxis(&vmc3(
        &["compensate"],
        &["--errors", arg(&errors), "--format", "csv", "--poses", arg(&poses), "--out", arg(&out_dir), "--input", "S:spindle=0"],
    )));
    let corrections = std::fs::read_to_string(out_dir.join("corrections.csv")).unwrap();
    let mut rows = corrections.lines();
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let e = header.iter().position(|h| *h == "error_um").unwrap();
    for (row, p) in rows.zip(&predicted) {
        let f: Vec<f64> = row.split(',').map(|v| v.parse().unwrap()).collect();
        let norm = ["dx", "dy", "dz"].iter().map(|k| p[k].as_f64().unwrap().powi(2)).sum::<f64>().sqrt();
        assert!((f[e] - norm).abs() < 1e-3, "{} vs {norm}", f[e]);
        assert!(norm > 1.0);
    }
    // first pose by hand: EZX = (5 + 0.01 * 100) * 3 = 18 um, EXX = 6 um
    assert!((predicted[0]["dz"].as_f64().unwrap().abs() - 18.0).abs() < 1e-4);
    assert!((predicted[0]["dx"].as_f64().unwrap().abs() - 6.0).abs() < 1e-4);
}
