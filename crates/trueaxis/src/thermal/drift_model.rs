//! The state-space thermal drift model of Soons 1993 §3.4.4 (eqs. 3.65-3.66, the states of §3.4.2)
//! as a fitted-model file: inputs are the temperature rises of the sensors since the start of each
//! run (the reference state), each passed through m first-order lags with time constants shared by
//! every sensor; the drift is their weighted sum:
//!
//! `tau_j dz_ij/dt = -z_ij + (T_i(t) - T_i(t_0))`, `E(t) = sum_i sum_j g_ij z_ij(t)` (um),
//!
//! with `z_ij(t_0) = 0`, T in degC, gains g in um/degC. This is `dx/dt = -gamma x + u`, `y = C x` of
//! [`super::state_space`] with `gamma_j = 1/tau_j`, `z = gamma x` and `C = g gamma`. Unlike the static
//! regression (Zhu 2008 eq. 3.12), it reproduces the lag between a sensor and the drift.

use super::state_space::{identify_state_space, Record, StateSpaceModel};
use super::thermal_campaign::Campaign;
use crate::error::Error;
use serde::{Deserialize, Serialize};

/// A fitted state-space drift model; its TOML form (`kind = "state_space"`) is written by
/// `trueaxis thermal fit --model state-space`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriftModel {
    /// Name of the modelled error column (um).
    pub error: String,
    /// Sensor columns `T:<name>` (inputs: rises since the start of the run, degC).
    pub sensors: Vec<String>,
    /// Shared time constants tau_j (s), decreasing.
    pub time_constants_s: Vec<f64>,
    /// `gains[i][j]`: um per degC of sensor i through lag j (steady-state gain of that path).
    pub gains_um_per_degc: Vec<Vec<f64>>,
}

impl DriftModel {
    /// Checks shapes and numbers.
    pub fn validate(&self) -> Result<(), Error> {
        if self.sensors.is_empty() || self.time_constants_s.is_empty() {
            return Err(Error::input("a drift model needs at least one sensor and one time constant"));
        }
        if self.time_constants_s.iter().any(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(Error::input("`time_constants_s` must be positive finite numbers of seconds"));
        }
        if self.gains_um_per_degc.len() != self.sensors.len()
            || self.gains_um_per_degc.iter().any(|g| g.len() != self.time_constants_s.len() || g.iter().any(|v| !v.is_finite()))
        {
            return Err(Error::input(format!(
                "`gains_um_per_degc` needs one row per sensor ({}) of one finite gain per time constant ({})",
                self.sensors.len(),
                self.time_constants_s.len()
            )));
        }
        if let Some(s) = self.sensors.iter().find(|s| !s.starts_with("T:") || s.len() < 3) {
            return Err(Error::input(format!("sensor `{s}` must be named `T:<name>`")));
        }
        Ok(())
    }

    /// The drift (um) at `times_s` (increasing, from the reference state at the first time) for
    /// sensor readings `temperatures[sample][sensor]` (degC): the samples one by one through
    /// [`DriftModel::step`], as a live compensation takes them.
    pub fn simulate(&self, times_s: &[f64], temperatures: &[Vec<f64>]) -> Result<Vec<f64>, Error> {
        let mut state = super::stepping::StepState::default();
        times_s.iter().zip(temperatures).map(|(t, readings)| self.step(&mut state, *t, readings)).collect()
    }

    /// The TOML form.
    pub fn to_toml(&self) -> String {
        let body = toml::to_string(self).expect("a drift model serialises");
        format!(
            "# thermal drift model (Soons (1993) §3.4.4): tau_j dz_ij/dt = -z_ij + (T_i - T_i(start of run)), E = sum g_ij z_ij (um)\nkind = \"state_space\"\n{body}"
        )
    }
}

/// Rises since the first sample: `u[k][i] = T[k][i] - T[0][i]`.
pub(crate) fn rises(temperatures: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let first = temperatures.first().cloned().unwrap_or_default();
    temperatures.iter().map(|row| row.iter().zip(&first).map(|(t, t0)| t - t0).collect()).collect()
}

/// One record of a campaign for the drift model: the rows of one run (or the first part of it), in
/// time order.
pub fn record(campaign: &Campaign, sensors: &[String], error: Option<&str>, rows: &[usize]) -> Result<Record, Error> {
    let t = campaign.column("t")?;
    let times: Vec<f64> = rows.iter().map(|&i| t[i]).collect();
    if times.windows(2).any(|w| w[1] <= w[0]) {
        return Err(Error::input(format!("{}: the times of a run must increase from row to row (column t)", campaign.origin)));
    }
    let columns = campaign.select(sensors, rows)?;
    let temperatures: Vec<Vec<f64>> = (0..rows.len()).map(|k| columns.iter().map(|c| c[k]).collect()).collect();
    let outputs = match error {
        Some(e) => campaign.select(&[e.to_string()], rows)?.remove(0).into_iter().map(|v| vec![v]).collect(),
        None => Vec::new(),
    };
    Ok((times, temperatures, outputs))
}

/// Fits `rates` shared time constants and the gains to records (each a run from its reference
/// state, where the error is zero), by [`identify_state_space`].
pub fn fit_drift_model(error: &str, sensors: &[String], records: &[Record], rates: usize) -> Result<(DriftModel, f64), Error> {
    let prepared: Vec<Record> = records.iter().map(|(t, temps, y)| (t.clone(), rises(temps), y.clone())).collect();
    let (model, rms) = identify_lags(&prepared, rates)?;
    let m = model.gammas.len();
    // decreasing time constants: gammas are increasing
    let gains = (0..sensors.len()).map(|i| (0..m).map(|j| model.c[(0, i * m + j)] / model.gammas[j]).collect()).collect();
    let drift =
        DriftModel { error: error.into(), sensors: sensors.to_vec(), time_constants_s: model.time_constants_s(), gains_um_per_degc: gains };
    Ok((drift, rms))
}

/// [`identify_state_space`] of `rates` (1 to 4) shared time constants from records of rises, each
/// from its reference state, refusing time constants the data do not determine.
pub(crate) fn identify_lags(records: &[Record], rates: usize) -> Result<(StateSpaceModel, f64), Error> {
    if !(1..=4).contains(&rates) {
        return Err(Error::input(format!("the number of time constants must be 1 to 4 (got {rates})")));
    }
    let (model, rms) = identify_state_space(records, rates, None)?;
    // a time constant far beyond the records acts as an integrator, one far below the sampling
    // step as a gain: neither is identified by the data
    let step = records.iter().flat_map(|r| r.0.windows(2).map(|w| w[1] - w[0])).fold(f64::INFINITY, f64::min);
    let span = records.iter().map(|r| r.0.last().unwrap_or(&0.0) - r.0.first().unwrap_or(&0.0)).fold(0.0, f64::max);
    if let Some(tau) = model.time_constants_s().into_iter().find(|t| *t > 10.0 * span || *t < 0.1 * step) {
        return Err(Error::computation(format!(
            "the fitted time constant {tau:.4e} s lies outside [0.1 x sampling step, 10 x longest record] = [{:.1}, {:.1}] s: the data do not determine {rates} time constants; use fewer --rates",
            0.1 * step,
            10.0 * span
        )));
    }
    Ok((model, rms))
}
