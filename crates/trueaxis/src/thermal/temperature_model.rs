//! The empirical state-space model of the temperature distribution (Soons 1993 §3.4.2, eqs.
//! 3.41-3.55; ch. 5: "two temperature sensors to predict the temperature elevation of all other
//! sensors ... three time constants"): the rises of a few input sensors near the heat sources since
//! the start of each run pass through m first-order lags with time constants shared by every input
//! and output; each output sensor's rise is a weighted sum of the lagged inputs:
//!
//! `tau_j dz_ij/dt = -z_ij + (T_i(t) - T_i(t_0))`, `T_o(t) = T_o(t_0) + sum_ij g_oij z_ij(t)`,
//!
//! (`dx/dt = -gamma x + B u`, `T = C x` with `C = g gamma`), identified by
//! [`super::state_space::identify_state_space`] (Levenberg-Marquardt on the rates, the gains by
//! least squares). Each run starts from its reference state.

use super::drift_model::{identify_lags, rises};
use super::state_space::{states, Record};
use super::thermal_campaign::Campaign;
use super::validation::{residual_stats, ResidualStats};
use crate::error::Error;
use serde::{Deserialize, Serialize};

/// A fitted temperature model; its TOML form (`kind = "temperature_state_space"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemperatureModel {
    /// Input sensors `T:<name>` (near the heat sources).
    pub inputs: Vec<String>,
    /// Output sensors `T:<name>` whose temperatures the model predicts.
    pub outputs: Vec<String>,
    /// Shared time constants tau_j (s), decreasing.
    pub time_constants_s: Vec<f64>,
    /// Row o: the gains (degC per degC) of output o, input by input, each time constant in turn:
    /// `[g_o,1,1, .., g_o,1,m, g_o,2,1, ..]`.
    pub gains: Vec<Vec<f64>>,
}

impl TemperatureModel {
    pub fn validate(&self) -> Result<(), Error> {
        if self.inputs.is_empty() || self.outputs.is_empty() || self.time_constants_s.is_empty() {
            return Err(Error::input("a temperature model needs at least one input, one output and one time constant"));
        }
        if self.time_constants_s.iter().any(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(Error::input("`time_constants_s` must be positive finite numbers of seconds"));
        }
        let width = self.inputs.len() * self.time_constants_s.len();
        if self.gains.len() != self.outputs.len() || self.gains.iter().any(|g| g.len() != width || g.iter().any(|v| !v.is_finite())) {
            return Err(Error::input(format!(
                "`gains` needs one row per output ({}) of {width} finite gains (inputs x time constants)",
                self.outputs.len()
            )));
        }
        if let Some(s) = self.inputs.iter().chain(&self.outputs).find(|s| !s.starts_with("T:") || s.len() < 3) {
            return Err(Error::input(format!("sensor `{s}` must be named `T:<name>`")));
        }
        Ok(())
    }

    /// Reads the TOML form; `origin` names it in messages.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<TemperatureModel, Error> {
        let one_line = |e: &dyn std::fmt::Display| e.to_string().split_whitespace().collect::<Vec<_>>().join(" ");
        crate::io::toml_numbers::refuse_underflow(text).map_err(|e| e.in_file(origin))?;
        let mut table: toml::Table = toml::from_str(text).map_err(|e| Error::input(format!("{origin}: {}", one_line(&e))))?;
        match table.remove("kind").as_ref().and_then(|k| k.as_str()) {
            Some("temperature_state_space") => {}
            other => {
                return Err(Error::input(format!(
                    "{origin}: kind `{}` is not a temperature model (kind = \"temperature_state_space\")",
                    other.unwrap_or("")
                )))
            }
        }
        let model: TemperatureModel =
            toml::Value::Table(table).try_into().map_err(|e: toml::de::Error| Error::input(format!("{origin}: {}", one_line(&e))))?;
        model.validate().map_err(|m| Error::input(format!("{origin}: {m}")))?;
        Ok(model)
    }

    pub fn to_toml(&self) -> String {
        let body = toml::to_string(self).expect("a temperature model serialises");
        format!(
            "# temperature model (Soons (1993) §3.4.2): tau_j dz_ij/dt = -z_ij + (T_i - T_i(start of run)), T_o = T_o(start) + sum g_oij z_ij (degC)\nkind = \"temperature_state_space\"\n{body}"
        )
    }

    /// Output temperatures `[sample][output]` (degC) at `times_s` for input readings
    /// `inputs[sample][input]` (degC), starting at `start[output]` (the outputs at the first time).
    pub fn simulate(&self, times_s: &[f64], inputs: &[Vec<f64>], start: &[f64]) -> Vec<Vec<f64>> {
        let rises = rises(inputs);
        let gammas: Vec<f64> = self.time_constants_s.iter().map(|t| 1.0 / t).collect();
        let x = states(&gammas, times_s, &rises);
        let m = gammas.len();
        (0..times_s.len())
            .map(|k| {
                self.gains
                    .iter()
                    .zip(start)
                    .map(|(g, s)| s + (0..g.len()).map(|state| g[state] * gammas[state % m] * x[(k, state)]).sum::<f64>())
                    .collect()
            })
            .collect()
    }
}

/// The rows of one run of a campaign: times, input readings and output readings.
fn run_record(campaign: &Campaign, inputs: &[String], outputs: &[String], rows: &[usize]) -> Result<Record, Error> {
    let t = campaign.column("t")?;
    let times: Vec<f64> = rows.iter().map(|&i| t[i]).collect();
    if times.windows(2).any(|w| w[1] <= w[0]) {
        return Err(Error::input(format!("{}: the times of a run must increase from row to row (column t)", campaign.origin)));
    }
    let by_row = |names: &[String]| -> Result<Vec<Vec<f64>>, Error> {
        let columns = campaign.select(names, rows)?;
        Ok((0..rows.len()).map(|k| columns.iter().map(|c| c[k]).collect()).collect())
    };
    Ok((times, by_row(inputs)?, by_row(outputs)?))
}

/// Fits `rates` shared time constants and the gains to the runs `runs` (row indices of each run in
/// time order, each from its reference state).
pub fn fit_temperature_model(
    campaign: &Campaign,
    runs: &[Vec<usize>],
    inputs: &[String],
    outputs: &[String],
    rates: usize,
) -> Result<(TemperatureModel, f64), Error> {
    if let Some(s) = outputs.iter().find(|o| inputs.contains(o)) {
        return Err(Error::input(format!("`{s}` is both an input and an output")));
    }
    let records: Vec<Record> = runs
        .iter()
        .map(|rows| {
            let (t, u, y) = run_record(campaign, inputs, outputs, rows)?;
            Ok((t, rises(&u), rises(&y)))
        })
        .collect::<Result<_, Error>>()?;
    let (model, rms) = identify_lags(&records, rates)?;
    let m = model.gammas.len();
    let gains = (0..outputs.len()).map(|o| (0..inputs.len() * m).map(|s| model.c[(o, s)] / model.gammas[s % m]).collect()).collect();
    let fitted = TemperatureModel { inputs: inputs.to_vec(), outputs: outputs.to_vec(), time_constants_s: model.time_constants_s(), gains };
    Ok((fitted, rms))
}

/// The prediction of one run: temperatures `[sample][output]` (degC) and the residual statistics
/// per output.
pub type RunPrediction = (Vec<Vec<f64>>, Vec<Option<ResidualStats>>);

/// The predicted output temperatures at `rows` (one run, in time order) and, per output, the
/// residual statistics `measured - predicted` (degC) when the campaign has the output columns.
pub fn predict_run(campaign: &Campaign, model: &TemperatureModel, rows: &[usize]) -> Result<RunPrediction, Error> {
    let t = campaign.column("t")?;
    let times: Vec<f64> = rows.iter().map(|&i| t[i]).collect();
    let inputs = campaign.select(&model.inputs, rows)?;
    let inputs: Vec<Vec<f64>> = (0..rows.len()).map(|k| inputs.iter().map(|c| c[k]).collect()).collect();
    let measured: Vec<Option<Vec<f64>>> =
        model.outputs.iter().map(|o| campaign.select(std::slice::from_ref(o), rows).ok().map(|mut c| c.remove(0))).collect();
    let start: Vec<f64> = measured.iter().map(|m| m.as_ref().map_or(0.0, |m| m[0])).collect();
    if measured.iter().any(Option::is_none) {
        return Err(Error::input(format!(
            "{}: the output columns {} are needed for the temperatures at the start of each run (the reference state)",
            campaign.origin,
            model.outputs.join(", ")
        )));
    }
    let predicted = model.simulate(&times, &inputs, &start);
    if predicted.iter().flatten().any(|v| !v.is_finite()) {
        return Err(Error::computation(format!("{}: the predicted temperatures are not finite numbers", campaign.origin)));
    }
    let stats = measured
        .iter()
        .enumerate()
        .map(|(o, m)| m.as_ref().and_then(|m| residual_stats(m, &predicted.iter().map(|p| p[o]).collect::<Vec<_>>())))
        .collect();
    Ok((predicted, stats))
}
