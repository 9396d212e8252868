//! The update step of live compensation without any server: against `thermal predict`'s library
//! evaluation of the same campaign (bit for bit), the hold / ramp / resume timing, the refusals
//! (physical range, a 200 degC jump, the correction limit), the state file saved and continued,
//! and the offsets of the closed form on the shipped machines.

use std::path::PathBuf;
use std::time::Duration;
use trueaxis::machine::Machine;
use trueaxis::thermal::campaign_predict::{predict_campaign, read_model_file};
use trueaxis::thermal::error_model::ThermalErrorModel;
use trueaxis::thermal::regression::RegressionModel;
use trueaxis::thermal::thermal_campaign::Campaign;
use trueaxis_live::engine::{Engine, Sample};
use trueaxis_live::mapping::Mapping;
use trueaxis_live::source::{CsvReplay, Event, Source};
use trueaxis_live::state::{EngineState, Phase};

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn vmc3() -> Machine {
    Machine::load(root().join("examples/machines/vmc3.toml")).unwrap()
}

fn drift_model() -> ThermalErrorModel {
    read_model_file(&root().join("examples/live/dz_drift.toml")).unwrap()
}

/// The regression of docs/thermal.md §5 (trained on `warmup`).
fn regression_model() -> ThermalErrorModel {
    ThermalErrorModel::Regression(RegressionModel {
        error: "dz".into(),
        sensors: vec!["T:p1".into(), "T:p5".into()],
        position: None,
        intercept: true,
        coefficients: vec![vec![-210.2691485973841, 1.5290372189618289, 8.961787989083792]],
    })
}

fn engine(model: ThermalErrorModel) -> Engine {
    Engine::new(&vmc3(), vec![model], &Mapping::default(), 600.0, 600.0).unwrap()
}

/// Every sample of the shipped campaign through the CSV replay.
fn replay() -> Vec<Sample> {
    let inputs = vec!["T:p1".to_string(), "T:p5".to_string()];
    let mut src =
        CsvReplay::open(&root().join("examples/thermal/campaign.csv"), &inputs, &Mapping::default(), f64::INFINITY, None).unwrap();
    let mut out = Vec::new();
    while let Some(Event::Sample(s)) = src.next(Duration::ZERO).unwrap() {
        out.push(s);
    }
    out
}

#[test]
fn the_engine_equals_thermal_predict_on_the_whole_campaign() {
    let campaign = Campaign::read(root().join("examples/thermal/campaign.csv")).unwrap();
    let samples = replay();
    assert_eq!(samples.len(), 964);
    for model in [drift_model(), regression_model()] {
        let predicted = predict_campaign(&model, &campaign).unwrap().predicted;
        let mut e = engine(model);
        for (s, p) in samples.iter().zip(&predicted) {
            let step = e.update(s).unwrap();
            // the same code evaluates both: equal bit for bit
            assert_eq!(step.drift_um.as_ref().unwrap()[0].to_bits(), p.to_bits(), "{s:?}");
            // vmc3: Z carries the tool along +z, X and Y the workpiece: offsets (0, 0, -dz)
            assert_eq!(step.offsets_um, vec![0.0, 0.0, -p], "{s:?}");
            assert!(step.write && step.phase == Phase::Compensating);
        }
        // runs start from their reference state: the drift model is zero at each run's first row
        if matches!(e.models().next().unwrap().0, ThermalErrorModel::Drift(_)) {
            assert_eq!(predicted[241], 0.0);
        }
    }
}

#[test]
fn a_gap_holds_then_ramps_then_resumes() {
    let samples = replay();
    let mut e = Engine::new(&vmc3(), vec![drift_model()], &Mapping::default(), 300.0, 600.0).unwrap();
    for s in &samples[..20] {
        e.update(s).unwrap();
    }
    let last = samples[19].time_s;
    let held = e.state.written_um.clone();
    assert!(held[2] < -1.0, "a warm machine: {held:?}");
    // within 1.5 sample intervals (120 s): nothing to say
    assert!(e.tick(last + 170.0).is_none());
    let step = e.tick(last + 200.0).unwrap();
    assert_eq!(step.phase, Phase::Held);
    assert!(step.message.unwrap().contains("held"));
    assert_eq!(step.offsets_um, held);
    // after the hold, linear to zero over the ramp: at 300 + 150 s, 3/4 of the offsets
    let step = e.tick(last + 450.0).unwrap();
    assert_eq!(step.phase, Phase::Ramping);
    assert!((step.offsets_um[2] - 0.75 * held[2]).abs() < 1e-12, "{:?}", step.offsets_um);
    let step = e.tick(last + 600.0).unwrap();
    assert!((step.offsets_um[2] - 0.5 * held[2]).abs() < 1e-12);
    let step = e.tick(last + 901.0).unwrap();
    assert_eq!((step.phase, step.offsets_um.clone()), (Phase::Zero, vec![0.0; 3]));
    assert!(e.tick(last + 1000.0).is_none());
    // resumed: the model went on over the gap (inputs held) and its offsets are written again
    let mut back = samples[30].clone();
    back.run = samples[19].run.clone();
    let step = e.update(&back).unwrap();
    assert!(step.message.unwrap().starts_with("resumed after"));
    assert_eq!(step.phase, Phase::Compensating);
    assert_eq!(step.offsets_um[2], -step.drift_um.unwrap()[0]);
}

#[test]
fn a_200_degc_jump_and_a_reading_outside_the_range_are_refused_and_change_nothing() {
    let samples = replay();
    let mut e = engine(drift_model());
    for s in &samples[..10] {
        e.update(s).unwrap();
    }
    let before = e.state.clone();
    let mut jump = samples[10].clone();
    jump.readings[0] += 200.0;
    let step = e.update(&jump).unwrap();
    let why = step.message.unwrap();
    assert!(why.starts_with("refused: T:p1: a jump of +2"), "{why}");
    assert!(!step.write && step.readings.is_none());
    assert_eq!(e.state, before);
    let mut hot = samples[10].clone();
    hot.readings[1] = 400.0;
    assert!(e.update(&hot).unwrap().message.unwrap().contains("T:p5: 400 is outside the physical range [-100, 300]"));
    assert_eq!(e.state, before);
    // the refused row is as if it had not come: the next one equals predict without it
    let mut text = String::from("run,t,T:p1,T:p5\n");
    for (_, s) in samples[..12].iter().enumerate().filter(|(k, _)| *k != 10) {
        text += &format!("{},{},{},{}\n", s.run.clone().unwrap(), s.time_s, s.readings[0], s.readings[1]);
    }
    let without = Campaign::parse(&text, "without row 10").unwrap();
    let predicted = predict_campaign(&drift_model(), &without).unwrap().predicted;
    let step = e.update(&samples[11]).unwrap();
    assert_eq!(step.drift_um.unwrap()[0].to_bits(), predicted[10].to_bits());
}

#[test]
fn an_offset_beyond_the_correction_limit_is_refused_and_held() {
    let text = std::fs::read_to_string(root().join("examples/machines/vmc3.toml")).unwrap() + "\n[limits]\ncorrection_um = 5\n";
    let m = Machine::from_toml_str(&text, "vmc3_limited").unwrap();
    let mut e = Engine::new(&m, vec![drift_model()], &Mapping::default(), 600.0, 600.0).unwrap();
    let mut refused = 0;
    for s in &replay()[..60] {
        let step = e.update(s).unwrap();
        if !step.write {
            refused += 1;
            assert!(step.message.unwrap().contains("beyond the correction limit of 5 um"));
        }
        assert!(step.offsets_um[2].abs() <= 5.0, "{:?}", step.offsets_um);
    }
    assert!(refused > 10, "{refused}");
}

#[test]
fn the_saved_state_continues_exactly() {
    let samples = replay();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("state.json");
    let mut whole = engine(drift_model());
    let mut first = engine(drift_model());
    for s in &samples[..300] {
        whole.update(s).unwrap();
        first.update(s).unwrap();
        first.state.save(&path, true).unwrap();
    }
    let mut second = engine(drift_model());
    second.resume(EngineState::load(&path).unwrap().unwrap(), "state.json").unwrap();
    for s in &samples[300..] {
        assert_eq!(whole.update(s).unwrap(), second.update(s).unwrap());
    }
    // a state of other models is refused
    let mut other = engine(regression_model());
    let err = other.resume(EngineState::load(&path).unwrap().unwrap(), "state.json").unwrap_err().to_string();
    assert!(err.contains("other thermal models"), "{err}");
    // the replay skips what the state already took
    let inputs = vec!["T:p1".to_string(), "T:p5".to_string()];
    let saved = EngineState::load(&path).unwrap().unwrap();
    let mut src =
        CsvReplay::open(&root().join("examples/thermal/campaign.csv"), &inputs, &Mapping::default(), f64::INFINITY, Some(&saved)).unwrap();
    match src.next(Duration::ZERO).unwrap() {
        Some(Event::Sample(s)) => assert_eq!(s, samples[300]),
        other => panic!("{other:?}"),
    }
}

#[test]
fn drifts_become_offsets_of_the_axes_that_move_them() {
    use trueaxis_live::axes::OffsetMap;
    // vmc3: X (direction -x) and Y (-y) carry the workpiece, Z (+z) the tool
    let map = OffsetMap::new(&vmc3(), &[0, 1, 2]).unwrap();
    assert_eq!(map.offsets([1.0, 2.0, 3.0]), vec![-1.0, -2.0, -3.0]);
    // c600u (wCAbYXZt): X, Y, Z on the tool side along +x, +y, +z
    let c600u = Machine::load(root().join("examples/machines/c600u.toml")).unwrap();
    assert_eq!(OffsetMap::new(&c600u, &[0, 1, 2]).unwrap().offsets([1.0, 2.0, 3.0]), vec![-1.0, -2.0, -3.0]);
    // a lathe has no Y: a drift dy cannot be compensated, dz can
    let lathe = Machine::load(root().join("examples/machines/lathe2.toml")).unwrap();
    let err = OffsetMap::new(&lathe, &[1]).unwrap_err().to_string();
    assert!(err.contains("no linear axis moves the tool along y"), "{err}");
    assert!(OffsetMap::new(&lathe, &[2]).is_ok());
    // a model of something else than dx, dy, dz is refused, and so is a position-dependent one
    let mut m = regression_model();
    if let ThermalErrorModel::Regression(r) = &mut m {
        r.error = "EZZ".into();
    }
    let err = Engine::new(&vmc3(), vec![m], &Mapping::default(), 1.0, 1.0).unwrap_err().to_string();
    assert!(err.contains("dx, dy or dz"), "{err}");
}
