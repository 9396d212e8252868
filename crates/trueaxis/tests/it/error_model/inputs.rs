//! Error terms of inputs other than the axis positions: workpiece-load errors (Soons 1993 eq. 3.20),
//! drift models interpolated between tested axis positions (Soons 1993 §3.4.4), product terms of one
//! direction of motion or one position range with a spindle-speed input (the geometric-thermal
//! model of NISTIR 5236 §3.6). Each against its closed form or an independent implementation.

use trueaxis::error_model::{input_values, Direction, ErrorModel, InputSource, MachineState};
use trueaxis::machine::{Machine, ParameterId};
use trueaxis::thermal::drift_model::DriftModel;

const MACHINE: &str = r#"
name = "milling machine of Soons 1993 ch. 5, X table on Y, Z ram"
structure = "wXYbZt"
[axes]
X = { kind = "linear", direction = [1, 0, 0], range = [0, 700] }
Y = { kind = "linear", direction = [0, 1, 0], range = [0, 600] }
Z = { kind = "linear", direction = [0, 0, 1], range = [0, 600] }
[tool]
point = [0, 0, 300]
"#;

fn machine() -> Machine {
    Machine::from_toml_str(MACHINE, "m.toml").unwrap()
}

/// The value (um or urad) of parameter `name` at pose `q` (mm) with the model's inputs `inputs`.
fn value(model: &ErrorModel, m: &Machine, name: &str, q: [f64; 3], directions: Option<&[Option<Direction>]>, inputs: &[f64]) -> f64 {
    let id = ParameterId::parse(name).unwrap();
    let mut v = vec![0.0; m.parameter_count()];
    model.values_at_state(m, &q, &MachineState { directions, temperatures: inputs }, &mut v);
    v[m.parameter_index(&id).unwrap()] / id.component().to_internal()
}

#[test]
fn workpiece_load_roll_scales_with_load_and_lever_as_eq_3_20() {
    // x_rx(X, F_w, p) = x_rx(X, 4900, 0) F_w / 4900 (375 - p) / 375; x_rx(X, 4900, 0) measured as a
    // table that grows away from the guideway support at X = 350 mm
    let m = machine();
    let text = r#"
[load.EAX]
reference_n = 4900.0
position = [0, 175, 350, 525, 700]
value = [12.0, 3.0, 0.0, 3.5, 13.0]
lever_mm = 375.0
lever_at = "P:workpiece_z"
"#;
    let model = ErrorModel::from_toml_str(text, "load.toml", &m).unwrap();
    assert_eq!(model.sensors(), &["F:workpiece".to_string(), "P:workpiece_z".to_string()]);
    assert_eq!(model.input_references(), &[0.0, 0.0]);
    // not given: the unloaded machine
    assert_eq!(value(&model, &m, "EAX", [100.0, 0.0, 0.0], None, &[]), 0.0);
    // 4900 N at the table centre reproduces the measured curve; between table points it interpolates
    assert!((value(&model, &m, "EAX", [175.0, 0.0, 0.0], None, &[4900.0, 0.0]) - 3.0).abs() < 1e-12);
    assert!((value(&model, &m, "EAX", [612.5, 0.0, 0.0], None, &[4900.0, 0.0]) - 8.25).abs() < 1e-12);
    // Fig. 3.21: 2600 N at Z = +208 mm and -208 mm relative to the table centre
    for p in [208.0, 0.0, -208.0] {
        let want = 12.0 * 2600.0 / 4900.0 * (375.0 - p) / 375.0;
        let got = value(&model, &m, "EAX", [0.0, 0.0, 0.0], None, &[2600.0, p]);
        assert!((got - want).abs() < 1e-12, "p = {p}: {got} vs {want}");
    }
    // 2600 N at +208 mm: 0.2363 of the 4900 N curve
    let ratio = value(&model, &m, "EAX", [0.0, 0.0, 0.0], None, &[2600.0, 208.0]) / 12.0;
    assert!((ratio - 2600.0 / 4900.0 * 167.0 / 375.0).abs() < 1e-15);
    assert!((ratio - 0.236299).abs() < 1e-6);
    // a location error under load: B/Y parallelism offset proportional to the load, no lever
    let text = "[load.EA0Y]\nreference_n = 4900.0\nconstant = 9.8\n";
    let model = ErrorModel::from_toml_str(text, "load.toml", &m).unwrap();
    assert!((value(&model, &m, "EA0Y", [0.0, 0.0, 0.0], None, &[1750.0]) - 3.5).abs() < 1e-12);
}

fn drift_model(gains: [f64; 2]) -> DriftModel {
    DriftModel {
        error: "dz".into(),
        sensors: vec!["T:34".into(), "T:52".into()],
        time_constants_s: vec![1800.0],
        gains_um_per_degc: vec![vec![gains[0]], vec![gains[1]]],
    }
}

#[test]
fn drift_between_tested_positions_is_the_linear_interpolation_of_the_two_models() {
    // Soons 1993 §3.4.4: models at Z = 0 (ram extended) and Z = 600 (retracted), interpolated
    let m = machine();
    let (near, far) = (drift_model([4.0, -1.5]), drift_model([7.0, 0.5]));
    let entry = |z: f64, d: &DriftModel| {
        format!(
            "[[drift.TZ]]\naxis = \"Z\"\nposition = {z}\n{}",
            d.to_toml().lines().filter(|l| !l.starts_with('#')).collect::<Vec<_>>().join("\n")
        )
    };
    let text = format!("{}\n{}\n", entry(0.0, &near), entry(600.0, &far));
    let model = ErrorModel::from_toml_str(&text, "drift.toml", &m).unwrap();
    assert_eq!(model.sensors().len(), 2, "one lag input per sensor and time constant: {:?}", model.sensors());
    // a warm-up and a cool-down of the two sensors, 10-minute samples, two runs
    let times: Vec<f64> = (0..60).map(|k| 600.0 * (k % 30) as f64).collect();
    let runs: Vec<String> = (0..60).map(|k| if k < 30 { "warmup" } else { "cycle" }.to_string()).collect();
    let t34: Vec<f64> = (0..60).map(|k| 21.0 + if k < 30 { 0.2 * (k as f64).min(18.0) } else { 1.5 * ((k % 4) as f64) }).collect();
    let t52: Vec<f64> = (0..60).map(|k| 20.5 + if k < 30 { 0.1 * (k as f64) } else { 0.7 * ((k % 3) as f64) }).collect();
    let column = |name: &str| match name {
        "T:34" => Some(t34.clone()),
        "T:52" => Some(t52.clone()),
        _ => None,
    };
    let source = InputSource { rows: 60, column: &column, given: &|_| None, times: Some(&times), runs: Some(&runs), origin: "poses.csv" };
    let inputs = input_values(model.sensors(), &source).unwrap();
    let n = model.sensors().len();
    for (run, rows) in [("warmup", 0..30), ("cycle", 30..60)] {
        let temps: Vec<Vec<f64>> = rows.clone().map(|k| vec![t34[k], t52[k]]).collect();
        let (d0, d600) = (near.simulate(&times[rows.clone()], &temps).unwrap(), far.simulate(&times[rows.clone()], &temps).unwrap());
        for (i, k) in rows.enumerate() {
            for (z, w) in [(0.0, 0.0), (150.0, 0.25), (450.0, 0.75), (600.0, 1.0)] {
                let want = (1.0 - w) * d0[i] + w * d600[i];
                let got = value(&model, &m, "TZ", [0.0, 0.0, z], None, &inputs[k * n..(k + 1) * n]);
                assert!((got - want).abs() < 1e-9, "{run} row {i} Z {z}: {got} vs {want}");
            }
        }
    }
    // the drift is not zero: the models differ and the temperatures move
    let late = &inputs[29 * n..30 * n];
    assert!(value(&model, &m, "TZ", [0.0, 0.0, 300.0], None, late).abs() > 1.0);
    // a lag needs the time column
    let source = InputSource { rows: 60, column: &column, given: &|_| None, times: None, runs: None, origin: "poses.csv" };
    assert!(input_values(model.sensors(), &source).unwrap_err().to_string().contains("time column `t`"));
}

#[test]
fn gt_segments_follow_the_direction_and_position_range_and_spindle_speed() {
    // EXX: +2 um backlash-like offset moving +, -2 moving -; a thermal slope only for X >= 350
    // driven by the spindle speed (um per 1000 rpm per 100 mm)
    let m = machine();
    let text = r#"
[[term."EXX+"]]
coefficient = 2.0
factors = {}
[[term."EXX-"]]
coefficient = -2.0
factors = {}
[[term.EXX]]
coefficient = 1e-5
factors = { X = 1, "S:spindle" = 1 }
range = [350, inf]
[[term.EXX]]
coefficient = 0.5
factors = { "T:bed" = 1 }
range = [-inf, 350]
"#;
    let model = ErrorModel::from_toml_str(text, "gt.toml", &m).unwrap();
    assert_eq!(model.sensors(), &["S:spindle".to_string(), "T:bed".to_string()]);
    assert_eq!(model.input_references(), &[0.0, 20.0]);
    let plus = [Some(Direction::Positive), None, None];
    let minus = [Some(Direction::Negative), None, None];
    let inputs = [4000.0, 23.0];
    // X = 500 moving +: 2 + 1e-5 * 500 * 4000 = 22 um; moving -: 18; at rest: the mean, 20
    assert!((value(&model, &m, "EXX", [500.0, 0.0, 0.0], Some(&plus), &inputs) - 22.0).abs() < 1e-12);
    assert!((value(&model, &m, "EXX", [500.0, 0.0, 0.0], Some(&minus), &inputs) - 18.0).abs() < 1e-12);
    assert!((value(&model, &m, "EXX", [500.0, 0.0, 0.0], None, &inputs) - 20.0).abs() < 1e-12);
    // X = 349.9 is in the other range: 0.5 * (23 - 20) = 1.5 um at rest; X = 350 starts the upper one
    assert!((value(&model, &m, "EXX", [349.9, 0.0, 0.0], None, &inputs) - 1.5).abs() < 1e-12);
    assert!((value(&model, &m, "EXX", [350.0, 0.0, 0.0], None, &inputs) - 14.0).abs() < 1e-12);
    // the reference state (no inputs given): only the directional offsets remain
    assert!((value(&model, &m, "EXX", [500.0, 0.0, 0.0], Some(&plus), &[]) - 2.0).abs() < 1e-12);
}
