//! The state-space model of the temperature distribution (Soons 1993 §3.4.2): a known two-input,
//! two-output, two-rate model simulated on irregular duty cycles and recovered (time constants
//! and gains to 1e-6) from the command line; on the shipped campaign (the bar heated at one end,
//! sensor noise 0.02 K) the far sensor predicted from the near one within the noise on the runs not
//! trained on; the model file evaluated again equals the fit.

use crate::support::{arg, failed, json, trueaxis};
use std::fmt::Write;
use trueaxis::thermal::temperature_model::TemperatureModel;

fn truth() -> TemperatureModel {
    TemperatureModel {
        inputs: vec!["T:spindle".into(), "T:ram".into()],
        outputs: vec!["T:column".into(), "T:table".into()],
        time_constants_s: vec![5400.0, 900.0],
        // row o: [input 1 tau 1, input 1 tau 2, input 2 tau 1, input 2 tau 2]
        gains: vec![vec![0.45, 0.10, 0.20, -0.05], vec![0.05, 0.30, -0.10, 0.15]],
    }
}

#[test]
fn known_model_is_recovered() {
    let model = truth();
    let mut text = String::from("run,t,T:spindle,T:ram,T:column,T:table\n");
    for (run, period, hours) in [("train1", 3600.0, 8.0), ("train2", 1500.0, 6.0), ("check", 2400.0, 5.0)] {
        let times: Vec<f64> = (0..((hours * 60.0) as usize)).map(|k| 60.0 * k as f64 + 13.0 * ((k * 7919) % 5) as f64).collect();
        let inputs: Vec<Vec<f64>> = times
            .iter()
            .map(|t| {
                let on = (t / period) as usize % 2 == 0;
                vec![21.0 + if on { 6.0 * (1.0 - (-t / 1200.0).exp()) } else { 2.0 }, 20.5 + 1.5 * (t / 3000.0).sin().abs()]
            })
            .collect();
        let outputs = model.simulate(&times, &inputs, &[20.8, 20.2]);
        for k in 0..times.len() {
            let _ =
                writeln!(text, "{run},{},{:.12},{:.12},{:.12},{:.12}", times[k], inputs[k][0], inputs[k][1], outputs[k][0], outputs[k][1]);
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("temps.csv");
    std::fs::write(&data, text).unwrap();
    let out = dir.path().join("model.toml");
    let doc = json(&trueaxis(&[
        "thermal",
        "temperatures",
        "--data",
        arg(&data),
        "--inputs",
        "T:spindle,T:ram",
        "--outputs",
        "T:column,T:table",
        "--rates",
        "2",
        "--train-runs",
        "train1,train2",
        "--out",
        arg(&out),
        "--json",
    ]));
    let taus: Vec<f64> = serde_json::from_value(doc["model"]["time_constants_s"].clone()).unwrap();
    for (got, want) in taus.iter().zip(&truth().time_constants_s) {
        assert!((got / want - 1.0).abs() < 1e-6, "tau {got} vs {want}");
    }
    let gains: Vec<Vec<f64>> = serde_json::from_value(doc["model"]["gains"].clone()).unwrap();
    for (g, w) in gains.iter().flatten().zip(truth().gains.iter().flatten()) {
        assert!((g - w).abs() < 1e-6, "gain {g} vs {w}");
    }
    assert_eq!(doc["residuals"]["check"]["training"], false);
    assert!(doc["residuals"]["check"]["outputs"]["T:table"]["max_abs"].as_f64().unwrap() < 1e-6);
    // the written model evaluated again
    let back = json(&trueaxis(&["thermal", "temperatures", "--model", arg(&out), "--data", arg(&data), "--json"]));
    assert!(back["residuals"]["check"]["outputs"]["T:column"]["max_abs"].as_f64().unwrap() < 1e-6);
}

#[test]
fn far_sensor_from_the_near_one_on_the_shipped_campaign() {
    let doc = json(&trueaxis(&[
        "thermal",
        "temperatures",
        "--data",
        "examples/thermal/campaign.csv",
        "--inputs",
        "T:p1",
        "--outputs",
        "T:p5",
        "--rates",
        "2",
        "--train-runs",
        "warmup",
        "--json",
    ]));
    // sensor noise 0.02 K on both: the residual RMS is of that order on every run, trained or not
    for run in ["warmup", "short", "long", "cycle"] {
        let rms = doc["residuals"][run]["outputs"]["T:p5"]["rms"].as_f64().unwrap();
        assert!(rms < 0.05, "{run}: {rms} degC");
    }
    // bad input: an output that is an input, a model file of another kind
    let out = trueaxis(&["thermal", "temperatures", "--data", "examples/thermal/campaign.csv", "--inputs", "T:p1", "--outputs", "T:p1"]);
    failed(&out, 2, &["`T:p1` is both an input and an output"]);
    let out = trueaxis(&["thermal", "temperatures", "--model", "examples/thermal/fin.toml", "--data", "examples/thermal/campaign.csv"]);
    failed(&out, 2, &["is not a temperature model"]);
}
