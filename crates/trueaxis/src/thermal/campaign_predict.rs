//! A fitted thermal error model evaluated on a campaign, as `trueaxis thermal predict` and the Python
//! package run it: the prediction of every row (each run from its start, for the drift model), and,
//! with the measured error column present, the residuals and their statistics per run. The
//! document of `trueaxis thermal predict --json` and its CSV.
//!
//! Units: times in s, errors in um.

use super::error_model::ThermalErrorModel;
use super::thermal_campaign::Campaign;
use super::validation::{evaluate_segments, prediction_segments, Evaluated, ResidualStats};
use crate::error::Error;
use serde_json::{json, Value};

/// The prediction of a model on every row of a campaign, in file order.
#[derive(Clone, Debug)]
pub struct CampaignPrediction {
    /// The modelled error column.
    pub error: String,
    /// The run of each row.
    pub runs: Vec<String>,
    /// The time of each row (s), when the campaign has a `t` column.
    pub times: Option<Vec<f64>>,
    pub predicted: Vec<f64>,
    /// The measured error of each row, when every run has the column.
    pub measured: Option<Vec<f64>>,
    /// Residual statistics per run, for the runs with a measured error.
    pub per_run: Vec<(String, ResidualStats)>,
    /// The runs evaluated (for plots).
    pub evaluated: Vec<Evaluated>,
}

/// Reads a model file (TOML, `kind = "regression"` or `"state_space"`, as `thermal fit --out`
/// writes it).
pub fn read_model_file(path: &std::path::Path) -> Result<ThermalErrorModel, Error> {
    let text = crate::files::inputs::read_to_string(path).map_err(|e| Error::input(format!("{}: cannot read: {e}", path.display())))?;
    ThermalErrorModel::from_toml_str(&text, &path.display().to_string())
}

/// Evaluates `model` on every run of `campaign`.
pub fn predict_campaign(model: &ThermalErrorModel, campaign: &Campaign) -> Result<CampaignPrediction, Error> {
    let evaluated = evaluate_segments(campaign, model, &prediction_segments(campaign))?;
    // back in file order
    let mut predicted = vec![0.0; campaign.len()];
    let mut measured = evaluated.iter().all(|e| e.measured.is_some()).then(|| vec![0.0; campaign.len()]);
    for e in &evaluated {
        for (k, &r) in e.segment.rows.iter().enumerate() {
            predicted[r] = e.predicted[k];
            if let (Some(m), Some(em)) = (measured.as_mut(), &e.measured) {
                m[r] = em[k];
            }
        }
    }
    let error = model.error().to_string();
    let times = campaign.column("t").ok().map(<[f64]>::to_vec);
    let per_run: Vec<(String, ResidualStats)> = evaluated.iter().filter_map(|e| e.stats().map(|s| (e.segment.name.clone(), s))).collect();
    Ok(CampaignPrediction { error, runs: campaign.runs.clone(), times, predicted, measured, per_run, evaluated })
}

impl CampaignPrediction {
    /// `{"error", "unit": "um", "samples": [{"run", "t", "predicted", "measured", "residual"}],
    /// "residuals": {run: statistics}}`.
    pub fn to_json(&self) -> Value {
        let (predicted, measured, times) = (&self.predicted, &self.measured, &self.times);
        let samples: Vec<Value> = (0..self.runs.len())
            .map(|i| {
                let mut s = json!({"run": self.runs[i], "predicted": predicted[i]});
                if let Some(t) = times {
                    s["t"] = json!(t[i]);
                }
                if let Some(m) = measured {
                    s["measured"] = json!(m[i]);
                    s["residual"] = json!(m[i] - predicted[i]);
                }
                s
            })
            .collect();
        let stats: serde_json::Map<String, Value> = self.per_run.iter().map(|(r, s)| (r.clone(), json!(s))).collect();
        json!({"error": self.error, "unit": "um", "samples": samples, "residuals": stats})
    }

    /// The CSV of `trueaxis thermal predict`: run, t, the prediction (and the measured error and
    /// the residual), um to 1e-4; a comment line of residual statistics per run.
    pub fn to_csv(&self) -> String {
        let (error, predicted, measured) = (&self.error, &self.predicted, &self.measured);
        let mut out =
            format!("run,t,{}_predicted{}\n", error, if measured.is_some() { format!(",{0},{0}_residual", error) } else { String::new() });
        for i in 0..self.runs.len() {
            let t = self.times.as_ref().map_or(String::new(), |t| t[i].to_string());
            out += &format!("{},{t},{:.4}", self.runs[i], predicted[i]);
            if let Some(m) = measured {
                out += &format!(",{},{:.4}", m[i], m[i] - predicted[i]);
            }
            out.push('\n');
        }
        for (run, s) in &self.per_run {
            out += &format!(
                "# {run}: residual RMS {:.3} max {:.3} range {:.3} band [{:.3}, {:.3}] um\n",
                s.rms, s.max_abs, s.range, s.min, s.max
            );
        }
        out
    }
}
