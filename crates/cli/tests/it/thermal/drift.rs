//! The state-space drift model (Soons 1993 §3.4.4) and the time-split validation (Zhu 2008 §3.4.3)
//! from the library and through `thermal fit --model state-space`, `--validate time-split:F` and
//! `thermal predict`: known time constants and gains recovered from simulated drift, a lag model
//! that predicts the 20-min duty cycle of the shipped campaign better than the static regression,
//! the model file read back, and bad input.

use crate::support::thermal::fit_dz;
use crate::support::{arg, json, root, trueaxis};
use trueaxis::thermal::drift_model::{fit_drift_model, record, DriftModel};
use trueaxis::thermal::error_model::ThermalErrorModel;
use trueaxis::thermal::thermal_campaign::Campaign;
use trueaxis::thermal::validation::{evaluate_segments, segments, Role};

fn campaign() -> Campaign {
    Campaign::read(root().join("examples/thermal/campaign.csv")).unwrap()
}

fn sensors() -> Vec<String> {
    vec!["T:p1".into(), "T:p5".into()]
}

#[test]
fn known_time_constants_and_gains_are_recovered_from_simulated_drift() {
    // the drift of a known model driven by the shipped sensor records (noise-free output)
    let truth = DriftModel {
        error: "dz".into(),
        sensors: sensors(),
        time_constants_s: vec![3000.0, 400.0],
        gains_um_per_degc: vec![vec![1.5, 0.4], vec![6.0, -0.8]],
    };
    let c = campaign();
    let run_rows = |run: &str| c.rows_of(&[run.to_string()]).unwrap();
    let simulated = |run: &str| {
        let (t, temps, _) = record(&c, &sensors(), None, &run_rows(run)).unwrap();
        let e = truth.simulate(&t, &temps).unwrap();
        (t, temps, e.into_iter().map(|v| vec![v]).collect::<Vec<_>>())
    };
    let records = vec![simulated("warmup"), simulated("cycle")];
    let (fitted, rms) = fit_drift_model("dz", &sensors(), &records, 2).unwrap();
    assert!(rms < 1e-8, "{rms}");
    for (got, want) in fitted.time_constants_s.iter().zip(&truth.time_constants_s) {
        assert!((got - want).abs() < 1e-6 * want, "tau {got} vs {want}");
    }
    for (g, w) in fitted.gains_um_per_degc.iter().flatten().zip(truth.gains_um_per_degc.iter().flatten()) {
        assert!((g - w).abs() < 1e-6 * (1.0 + w.abs()), "gain {g} vs {w}");
    }
    // a held-out run is predicted; the model file reads back to the same model
    let (t, temps, e) = simulated("long");
    for (p, m) in fitted.simulate(&t, &temps).unwrap().iter().zip(&e) {
        assert!((p - m[0]).abs() < 1e-6, "{p} vs {}", m[0]);
    }
    let back = ThermalErrorModel::from_toml_str(&ThermalErrorModel::Drift(fitted.clone()).to_toml(), "drift.toml").unwrap();
    assert_eq!(back, ThermalErrorModel::Drift(fitted));
    // a step of 1 degC on sensor 1 alone: after many time constants the drift is the sum of its gains
    let steps: Vec<Vec<f64>> = (0..200).map(|k| vec![20.0 + f64::from(u8::from(k > 0)), 20.0]).collect();
    let times: Vec<f64> = (0..200).map(|k| 300.0 * k as f64).collect();
    let end = *truth.simulate(&times, &steps).unwrap().last().unwrap();
    assert!((end - 1.9).abs() < 1e-6, "{end}");
}

#[test]
fn time_split_segments_train_on_the_first_part_of_each_training_run() {
    let c = campaign();
    let s = segments(&c, Some(&["long".to_string()]), Some(0.5)).unwrap();
    let names: Vec<(&str, Role, usize)> = s.iter().map(|g| (g.name.as_str(), g.role, g.rows.len())).collect();
    // 241 samples every 120 s over 8 h: t < 4 h trains (120 samples), the rest verifies (121)
    assert_eq!(
        names,
        vec![
            ("warmup", Role::Validation, 241),
            ("short", Role::Validation, 241),
            ("long (first 50 %)", Role::Training, 120),
            ("long (last 50 %)", Role::Validation, 121),
            ("cycle", Role::Validation, 241),
        ]
    );
    assert!(segments(&c, None, Some(1.0)).is_err() && segments(&c, None, Some(f64::NAN)).is_err());
    // the verification part of a drift model is simulated from the start of its run: the same
    // numbers as evaluating the whole run
    let model = ThermalErrorModel::Drift(DriftModel {
        error: "dz".into(),
        sensors: sensors(),
        time_constants_s: vec![360.0],
        gains_um_per_degc: vec![vec![1.8], vec![7.7]],
    });
    let parts = evaluate_segments(&c, &model, &s).unwrap();
    let whole = model.predict(&c, &s[2].run_rows).unwrap();
    assert_eq!(parts[3].predicted, whole[120..].to_vec());
    assert_eq!(parts[2].predicted, whole[..120].to_vec());
}

#[test]
fn a_lag_model_predicts_the_duty_cycle_better_than_the_static_regression() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("drift.toml");
    let fit = |extra: &[&str]| {
        let mut args =
            vec!["thermal", "fit", "--data", "examples/thermal/campaign.csv", "--error", "dz", "--train-runs", "warmup", "--json"];
        args.extend_from_slice(extra);
        json(&trueaxis(&args))
    };
    let regression = fit(&[]);
    let drift = fit(&["--model", "state-space", "--rates", "1", "--out", arg(&model)]);
    assert_eq!(drift["model"]["kind"], "state_space");
    let tau = drift["model"]["time_constants_s"][0].as_f64().unwrap();
    assert!(tau > 120.0 && tau < 1800.0, "{tau}");
    let rms = |doc: &serde_json::Value, run: &str| doc["validation"][run]["rms"].as_f64().unwrap();
    // the static model lags the 20-min cycle (2.2 um RMS); the lag model halves that at least
    assert!(rms(&regression, "cycle") > 2.0 && rms(&drift, "cycle") < 0.5 * rms(&regression, "cycle"));
    for run in ["short", "long"] {
        assert!(rms(&drift, run) < rms(&regression, run), "{run}");
    }
    // predict reads the state-space model file back: the same residuals
    let predicted = json(&trueaxis(&["thermal", "predict", "--model", arg(&model), "--data", "examples/thermal/campaign.csv", "--json"]));
    for run in ["short", "long", "cycle"] {
        let a = predicted["residuals"][run]["rms"].as_f64().unwrap();
        assert!((a - rms(&drift, run)).abs() < 1e-12, "{run}: {a} vs {}", rms(&drift, run));
    }
    // time split through the command line: trained on the first half of `long`
    let split = json(&fit_dz("long", &["--validate", "time-split:0.5", "--json"]));
    assert_eq!(split["training"]["samples"], 120);
    assert_eq!(split["validation"]["long (last 50 %)"]["samples"], 121);
}

#[test]
fn bad_drift_input_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let check = |args: &[&str], code: i32, text: &str| {
        let out = trueaxis(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{err}");
        assert!(err.contains(text) && err.trim_end().lines().count() == 1, "{err}");
    };
    let fit = ["thermal", "fit", "--data", "examples/thermal/campaign.csv", "--error", "dz"];
    check(&[&fit[..], &["--validate", "time-split:1.5"]].concat(), 2, "--validate time-split:1.5");
    check(&[&fit[..], &["--validate", "runs:2"]].concat(), 2, "expected time-split:F");
    check(&[&fit[..], &["--model", "state-space", "--select", "stepwise"]].concat(), 2, "apply to regression models");
    check(&[&fit[..], &["--model", "state-space", "--rates", "5"]].concat(), 2, "1 to 4");
    // two time constants are not determined by the warm-up alone: one runs away (exit 1)
    check(&[&fit[..], &["--model", "state-space", "--rates", "2", "--train-runs", "warmup"]].concat(), 1, "use fewer --rates");
    let model = dir.path().join("bad.toml");
    std::fs::write(
        &model,
        "kind = \"state_space\"\nerror = \"dz\"\nsensors = [\"T:p1\"]\ntime_constants_s = [600.0, 60.0]\ngains_um_per_degc = [[1.0]]\n",
    )
    .unwrap();
    check(&["thermal", "predict", "--model", arg(&model), "--data", "examples/thermal/campaign.csv"], 2, "bad.toml");
}
