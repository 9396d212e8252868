//! The update step of a live compensation, free of any source or sink: a sample (source time s,
//! readings) is screened ([`crate::screen`]), passed through each thermal model one step
//! ([`ThermalErrorModel::step`], the evaluation of `trueaxis thermal predict`), turned into axis
//! offsets ([`crate::axes`]) and checked against the correction limit; between samples
//! [`Engine::tick`] holds the offsets, then ramps them to zero, and says so:
//!
//! - an accepted sample: offsets `q = -A^+ e` (um) written, phase `compensating`;
//! - no accepted sample for more than 1.5 sample intervals: phase `held`, offsets unchanged;
//! - no accepted sample for more than `hold_s`: phase `ramping`, offsets
//!   `q (1 - (age - hold_s) / ramp_s)`, then `zero`;
//! - a refused sample (not a number, outside the range, a jump, a drift beyond the correction
//!   limit) is reported with its reason and changes nothing that is written; the model's state
//!   does not take a refused reading;
//! - the first accepted sample after a gap says `resumed` and writes the model's offsets.
//!
//! A run (the value of the run signal) starts from its reference state, as each run of a campaign
//! does in `thermal predict`; the log's time `t` is the source time since the run's first sample.

use crate::axes::{drift_component, OffsetMap};
use crate::mapping::Mapping;
use crate::screen::InputLimits;
use crate::state::{digest, Accepted, EngineState, Phase, FORMAT};
use crate::{input, LiveError};
use trueaxis::machine::Machine;
use trueaxis::thermal::error_model::ThermalErrorModel;
use trueaxis::thermal::stepping::StepState;

/// A sample from a source.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Source time (s).
    pub time_s: f64,
    /// The run signal's value, if the source has one.
    pub run: Option<String>,
    /// One reading per engine input (degC for temperatures), in the order of [`Engine::inputs`].
    pub readings: Vec<f64>,
}

/// What one step did, for sinks, logs and the status.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// Source time (s).
    pub time_s: f64,
    /// Time since the run's first sample (s): the `t` of the log.
    pub run_time_s: f64,
    pub run: Option<String>,
    /// The readings, when the step is an accepted sample.
    pub readings: Option<Vec<f64>>,
    /// The predicted drift of each model (um), when the step is an accepted sample.
    pub drift_um: Option<Vec<f64>>,
    /// The offsets at the controller after this step (um, per axis of [`OffsetMap::letters`]).
    pub offsets_um: Vec<f64>,
    /// Whether this step changes what is written.
    pub write: bool,
    pub phase: Phase,
    /// What happened, when it is worth a log line (refusal, hold, ramp, resume, new run).
    pub message: Option<String>,
    /// The lag states of each model after the step (degC s).
    pub lags: Vec<Vec<f64>>,
}

/// One model and where its drift goes.
#[derive(Clone, Debug)]
struct Channel {
    model: ThermalErrorModel,
    /// 0, 1, 2: dx, dy, dz.
    component: usize,
    /// Indices of its inputs in the engine's inputs.
    inputs: Vec<usize>,
}

/// The live compensation of one machine.
#[derive(Clone, Debug)]
pub struct Engine {
    /// Every input of the models, in order of first use.
    pub inputs: Vec<String>,
    limits: Vec<InputLimits>,
    channels: Vec<Channel>,
    pub offsets: OffsetMap,
    /// Time the offsets are held without an accepted sample (s).
    pub hold_s: f64,
    /// Time of the ramp to zero after the hold (s).
    pub ramp_s: f64,
    pub state: EngineState,
}

impl Engine {
    /// An engine for `models` on `machine`, from a fresh state.
    pub fn new(
        machine: &Machine,
        models: Vec<ThermalErrorModel>,
        mapping: &Mapping,
        hold_s: f64,
        ramp_s: f64,
    ) -> Result<Engine, LiveError> {
        if models.is_empty() {
            return Err(input("no thermal model (--thermal-model)"));
        }
        if !(hold_s.is_finite() && hold_s >= 0.0 && ramp_s.is_finite() && ramp_s >= 0.0) {
            return Err(input(format!("--hold {hold_s} and --ramp {ramp_s} must be non-negative numbers of seconds")));
        }
        let mut inputs: Vec<String> = Vec::new();
        let mut channels = Vec::new();
        for model in models {
            model.check_steppable()?;
            let component = drift_component(model.error())?;
            if channels.iter().any(|c: &Channel| c.component == component) {
                return Err(input(format!("two models of `{}`: give one model per drift component", model.error())));
            }
            let mut at = Vec::new();
            for name in model.inputs() {
                if !inputs.contains(name) {
                    inputs.push(name.clone());
                }
                at.push(inputs.iter().position(|n| n == name).expect("just added"));
            }
            channels.push(Channel { model, component, inputs: at });
        }
        let used: Vec<usize> = channels.iter().map(|c| c.component).collect();
        let offsets = OffsetMap::new(machine, &used)?;
        let limits = inputs.iter().map(|n| InputLimits::of(n, mapping)).collect();
        let state = EngineState {
            format: FORMAT.into(),
            models: channels.iter().map(|c| format!("{}:{}", c.model.error(), digest(&c.model.to_toml()))).collect(),
            steps: vec![StepState::default(); channels.len()],
            written_um: vec![0.0; offsets.letters.len()],
            held_um: vec![0.0; offsets.letters.len()],
            ..EngineState::default()
        };
        Ok(Engine { inputs, limits, channels, offsets, hold_s, ramp_s, state })
    }

    /// Continues from a saved state, refusing one written for other models.
    pub fn resume(&mut self, saved: EngineState, origin: &str) -> Result<(), LiveError> {
        if saved.models != self.state.models
            || saved.written_um.len() != self.offsets.letters.len()
            || saved.steps.iter().zip(&self.channels).any(|(s, c)| !s.fits(&c.model))
        {
            return Err(input(format!(
                "{origin}: the state was saved for other thermal models or another machine ({}); start a new run with --reset",
                saved.models.join(", ")
            )));
        }
        self.state = saved;
        Ok(())
    }

    /// The model of each channel with its drift component (for logs).
    pub fn models(&self) -> impl Iterator<Item = (&ThermalErrorModel, usize)> {
        self.channels.iter().map(|c| (&c.model, c.component))
    }

    /// Takes a sample; `None` for a repeat of the last accepted sample (a re-delivery).
    pub fn update(&mut self, sample: &Sample) -> Option<Step> {
        let mut notes: Vec<String> = Vec::new();
        if sample.run.is_some() && sample.run != self.state.run {
            notes.push(format!("run `{}` starts: its first sample is the reference state", sample.run.as_deref().unwrap_or("")));
            self.state.run = sample.run.clone();
            self.state.run_start_s = None;
            self.state.steps = vec![StepState::default(); self.channels.len()];
            self.state.accepted = None;
        }
        let last = self.state.accepted.as_ref().map(|a| (a.time_s, a.readings.clone()));
        if let Some((t0, _)) = &last {
            if sample.time_s == *t0 {
                return None;
            }
            if sample.time_s < *t0 {
                return Some(self.refused(sample, format!("sample at {} s is older than the last accepted one at {t0} s", sample.time_s)));
            }
        }
        if sample.readings.len() != self.inputs.len() {
            return Some(self.refused(sample, format!("{} readings for {} inputs", sample.readings.len(), self.inputs.len())));
        }
        for (k, l) in self.limits.iter().enumerate() {
            if let Some(why) = l.refusal(sample.readings[k], sample.time_s, last.as_ref().map(|(t, r)| (*t, r[k]))) {
                return Some(self.refused(sample, format!("refused: {why}")));
            }
        }
        // the models, on copies of their states: a failure changes nothing
        let mut steps = self.state.steps.clone();
        let mut drift = Vec::with_capacity(self.channels.len());
        let mut e = [0.0; 3];
        let mut readings = Vec::new();
        for (c, st) in self.channels.iter().zip(steps.iter_mut()) {
            readings.clear();
            readings.extend(c.inputs.iter().map(|&k| sample.readings[k]));
            let d = match c.model.step(st, sample.time_s, &readings) {
                Ok(d) if d.is_finite() => d,
                Ok(d) => {
                    return Some(self.refused(sample, format!("refused: the drift {} of `{}` is not a finite number", d, c.model.error())))
                }
                Err(err) => return Some(self.refused(sample, format!("refused: {err}"))),
            };
            e[c.component] += d;
            drift.push(d);
        }
        let offsets = self.offsets.offsets(e);
        let interval_s = last.as_ref().map(|(t, _)| sample.time_s - t);
        self.state.steps = steps;
        self.state.run_start_s.get_or_insert(sample.time_s);
        self.state.accepted =
            Some(Accepted { time_s: sample.time_s, readings: sample.readings.clone(), drift_um: drift.clone(), interval_s });
        self.state.samples += 1;
        let write = match self.offsets.beyond_limit(&offsets) {
            Some(why) => {
                notes.push(format!("refused: {why}; the offsets are held"));
                false
            }
            None => {
                if matches!(self.state.phase, Phase::Held | Phase::Ramping | Phase::Zero) {
                    let since = self.state.written_time_s.map_or(0.0, |t| sample.time_s - t);
                    notes.push(format!("resumed after {since:.0} s without an accepted sample"));
                }
                self.state.written_um = offsets.clone();
                self.state.held_um = offsets;
                self.state.written_time_s = Some(sample.time_s);
                self.state.phase = Phase::Compensating;
                true
            }
        };
        let mut step = self.step_now(sample.time_s, write, (!notes.is_empty()).then(|| notes.join("; ")));
        step.readings = Some(sample.readings.clone());
        step.drift_um = Some(drift);
        Some(step)
    }

    /// Advances the hold / ramp at source time `now_s` without a sample; a step when the phase or
    /// the offsets change.
    pub fn tick(&mut self, now_s: f64) -> Option<Step> {
        let since = now_s - self.state.written_time_s?;
        let interval = self.state.accepted.as_ref().and_then(|a| a.interval_s).unwrap_or(0.0);
        let (phase, factor) = if since > self.hold_s + self.ramp_s {
            (Phase::Zero, 0.0)
        } else if since > self.hold_s {
            (Phase::Ramping, 1.0 - (since - self.hold_s) / self.ramp_s)
        } else if since > 1.5 * interval && interval > 0.0 {
            (Phase::Held, 1.0)
        } else {
            return None;
        };
        let previous = self.state.phase;
        let written: Vec<f64> = self.state.held_um.iter().map(|q| q * factor).collect();
        let changed = written != self.state.written_um;
        if phase == previous && !changed {
            return None;
        }
        let message = (phase != previous).then(|| match phase {
            Phase::Held => format!("no accepted sample for {since:.0} s: the offsets are held for up to {} s", self.hold_s),
            Phase::Ramping => format!("no accepted sample for {since:.0} s: the offsets ramp to zero over {} s", self.ramp_s),
            _ => format!("no accepted sample for {since:.0} s: the offsets are zero until a sample is accepted"),
        });
        self.state.phase = phase;
        self.state.written_um = written;
        Some(self.step_now(now_s, changed, message))
    }

    /// The step of the last accepted sample, rebuilt from the state (after a restart).
    pub fn last_step(&self) -> Option<Step> {
        let a = self.state.accepted.as_ref()?;
        let mut step = self.step_now(a.time_s, false, None);
        step.readings = Some(a.readings.clone());
        step.drift_um = Some(a.drift_um.clone());
        step.offsets_um = self.state.held_um.clone();
        Some(step)
    }

    /// A step that only reports (refusals, repeats).
    fn refused(&mut self, sample: &Sample, why: String) -> Step {
        self.step_now(sample.time_s, false, Some(why))
    }

    fn step_now(&self, time_s: f64, write: bool, message: Option<String>) -> Step {
        Step {
            time_s,
            run_time_s: time_s - self.state.run_start_s.unwrap_or(time_s),
            run: self.state.run.clone(),
            readings: None,
            drift_um: None,
            offsets_um: self.state.written_um.clone(),
            write,
            phase: self.state.phase,
            message,
            lags: self.state.steps.iter().map(|s| s.lags.clone()).collect(),
        }
    }
}
