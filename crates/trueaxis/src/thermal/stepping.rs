//! A fitted thermal error model evaluated one sample at a time, as a live compensation runs it
//! (trueaxis-live) and as `trueaxis thermal predict` runs it over a campaign: both go through
//! [`ThermalErrorModel::step`], so the two give the same numbers bit for bit.
//!
//! - Static regression without position (PITE, Zhu (2008) eq. 3.12): `E = c_0 + sum_i c_i T_i`
//!   (um) of the current readings (degC); no state.
//! - State-space drift model (Soons (1993) §3.4.4): the first sample of a run is its reference
//!   state (`T_i(t_0)`, all lags zero, `E = 0`); each later sample at time `t_k` advances the lags
//!   over `t_k - t_(k-1)` with the rises of the previous sample held (zero-order hold,
//!   [`super::state_space::advance`]) and sums `E = sum_ij g_ij gamma_j x_ij` (um).
//!
//! The state is plain numbers (readings in degC, times in s, lag states in degC s) so that it can
//! be saved after every sample and a run can continue after a restart.

use super::drift_model::DriftModel;
use super::error_model::ThermalErrorModel;
use super::state_space::advance;
use crate::error::Error;
use serde::{Deserialize, Serialize};

/// What a model remembers between samples of one run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepState {
    /// Time of the last sample (s); `None` before the first sample of a run.
    pub time_s: Option<f64>,
    /// Readings at the start of the run (degC), in the order of the model's inputs.
    pub reference: Vec<f64>,
    /// Rises over the reference at the last sample (degC): the inputs held over the next interval.
    pub rises: Vec<f64>,
    /// Lag states `x_ij` (degC s), state `i * m + j` for input i and time constant j.
    pub lags: Vec<f64>,
}

impl StepState {
    /// Whether the state fits `model` (after a reload: the same numbers of inputs and lags).
    pub fn fits(&self, model: &ThermalErrorModel) -> bool {
        match model {
            ThermalErrorModel::Drift(d) => {
                let (n, m) = (d.sensors.len(), d.time_constants_s.len());
                self.time_s.is_none() || (self.reference.len() == n && self.rises.len() == n && self.lags.len() == n * m)
            }
            _ => true,
        }
    }
}

impl ThermalErrorModel {
    /// The inputs the model reads, in the order `step` takes them.
    pub fn inputs(&self) -> &[String] {
        match self {
            ThermalErrorModel::Regression(m) => &m.sensors,
            ThermalErrorModel::Drift(m) => &m.sensors,
            ThermalErrorModel::Segmented(m) => &m.sensors,
        }
    }

    /// Refuses models that need more than readings at a time: position-dependent (PDTE) and
    /// segmented G-T models depend on where the axis is, which only the controller knows at its
    /// servo rate; they belong in the error terms of the chain (`thermal fit --terms-out`).
    pub fn check_steppable(&self) -> Result<(), Error> {
        let position = match self {
            ThermalErrorModel::Regression(m) => m.position.clone(),
            ThermalErrorModel::Segmented(m) => Some(m.position.clone()),
            ThermalErrorModel::Drift(_) => None,
        };
        match position {
            Some(p) => Err(Error::input(format!(
                "the model of `{}` depends on the position of axis {p}: a live offset cannot follow the axis; write it as error terms (thermal fit --terms-out) for compensate",
                self.error()
            ))),
            None => Ok(()),
        }
    }

    /// The error (um) at time `t_s` (s) for `readings` in the order of [`Self::inputs`], advancing
    /// `state` to this sample. Times within a run must increase.
    pub fn step(&self, state: &mut StepState, t_s: f64, readings: &[f64]) -> Result<f64, Error> {
        self.check_steppable()?;
        match self {
            ThermalErrorModel::Regression(m) => Ok(m.evaluate(0.0, readings)),
            ThermalErrorModel::Drift(m) => m.step(state, t_s, readings),
            ThermalErrorModel::Segmented(_) => unreachable!("refused by check_steppable"),
        }
    }
}

impl DriftModel {
    /// One sample of the drift model: see the module documentation.
    pub fn step(&self, state: &mut StepState, t_s: f64, readings: &[f64]) -> Result<f64, Error> {
        let gammas: Vec<f64> = self.time_constants_s.iter().map(|t| 1.0 / t).collect();
        match state.time_s {
            None => {
                *state = StepState {
                    time_s: Some(t_s),
                    reference: readings.to_vec(),
                    rises: vec![0.0; readings.len()],
                    lags: vec![0.0; readings.len() * gammas.len()],
                };
            }
            Some(previous) => {
                if t_s.is_nan() || t_s <= previous {
                    return Err(Error::input(format!("sample time {t_s} s does not follow the previous sample at {previous} s")));
                }
                advance(&gammas, t_s - previous, &state.rises, &mut state.lags);
                state.time_s = Some(t_s);
                for ((r, t), t0) in state.rises.iter_mut().zip(readings).zip(&state.reference) {
                    *r = t - t0;
                }
            }
        }
        Ok(self.output(&gammas, &state.lags))
    }

    /// `E = sum_i sum_j g_ij gamma_j x_ij` (um).
    fn output(&self, gammas: &[f64], lags: &[f64]) -> f64 {
        let m = gammas.len();
        let mut e = 0.0;
        for (i, g) in self.gains_um_per_degc.iter().enumerate() {
            for j in 0..m {
                e += g[j] * gammas[j] * lags[i * m + j];
            }
        }
        e
    }
}
