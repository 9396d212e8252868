//! A fitted thermal error model of either form, as read from and written to a model file: the
//! static regression of Zhu 2008 eqs. 3.12-3.15 (`kind = "regression"`) or the state-space drift
//! model of Soons 1993 §3.4.4 (`kind = "state_space"`).

use super::drift_model::{record, DriftModel};
use super::regression::RegressionModel;
use super::segmented::SegmentedModel;
use super::thermal_campaign::Campaign;
use crate::error::Error;
use serde::{Deserialize, Serialize};

/// A thermal error model (um) of sensor readings (degC).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ThermalErrorModel {
    Regression(RegressionModel),
    #[serde(rename = "state_space")]
    Drift(DriftModel),
    /// The G-T model by segment of NISTIR 5236 §3.6.
    Segmented(SegmentedModel),
}

impl From<RegressionModel> for ThermalErrorModel {
    fn from(m: RegressionModel) -> Self {
        ThermalErrorModel::Regression(m)
    }
}

impl ThermalErrorModel {
    /// Reads a model file's text; `origin` names it in messages.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<ThermalErrorModel, Error> {
        #[derive(Deserialize)]
        struct Kind {
            kind: Option<String>,
        }
        let one_line = |e: &dyn std::fmt::Display| e.to_string().split_whitespace().collect::<Vec<_>>().join(" ");
        crate::io::toml_numbers::refuse_underflow(text).map_err(|e| e.in_file(origin))?;
        let kind: Kind =
            toml::from_str::<toml::Table>(text).map_err(|e| Error::input(format!("{origin}: {}", one_line(&e)))).and_then(|t| {
                toml::Value::Table(t).try_into().map_err(|e: toml::de::Error| Error::input(format!("{origin}: {}", one_line(&e))))
            })?;
        match kind.kind.as_deref() {
            Some("segmented") => {
                let mut table: toml::Table = toml::from_str(text).map_err(|e| Error::input(format!("{origin}: {}", one_line(&e))))?;
                table.remove("kind");
                let model: SegmentedModel = toml::Value::Table(table)
                    .try_into()
                    .map_err(|e: toml::de::Error| Error::input(format!("{origin}: {}", one_line(&e))))?;
                model.validate().map_err(|m| Error::input(format!("{origin}: {m}")))?;
                Ok(ThermalErrorModel::Segmented(model))
            }
            Some("state_space") => {
                let mut table: toml::Table = toml::from_str(text).map_err(|e| Error::input(format!("{origin}: {}", one_line(&e))))?;
                table.remove("kind");
                let model: DriftModel = toml::Value::Table(table)
                    .try_into()
                    .map_err(|e: toml::de::Error| Error::input(format!("{origin}: {}", one_line(&e))))?;
                model.validate().map_err(|m| Error::input(format!("{origin}: {m}")))?;
                Ok(ThermalErrorModel::Drift(model))
            }
            _ => RegressionModel::from_toml_str(text, origin).map(ThermalErrorModel::Regression),
        }
    }

    /// The model file text.
    pub fn to_toml(&self) -> String {
        match self {
            ThermalErrorModel::Regression(m) => m.to_toml(),
            ThermalErrorModel::Drift(m) => m.to_toml(),
            ThermalErrorModel::Segmented(m) => m.to_toml(),
        }
    }

    /// The modelled error column.
    pub fn error(&self) -> &str {
        match self {
            ThermalErrorModel::Regression(m) => &m.error,
            ThermalErrorModel::Drift(m) => &m.error,
            ThermalErrorModel::Segmented(m) => &m.error,
        }
    }

    /// The prediction (um) at `rows` of a campaign. The regression is evaluated row by row; the
    /// drift model simulates each run from its first row in `rows` (its reference state), so `rows`
    /// should hold whole runs, in time order.
    pub fn predict(&self, campaign: &Campaign, rows: &[usize]) -> Result<Vec<f64>, Error> {
        match self {
            ThermalErrorModel::Regression(model) => {
                let temps = campaign.select(&model.sensors, rows)?;
                let positions = match &model.position {
                    Some(p) => Some(campaign.select(std::slice::from_ref(p), rows)?.remove(0)),
                    None => None,
                };
                let mut t = vec![0.0; model.sensors.len()];
                Ok((0..rows.len())
                    .map(|i| {
                        t.iter_mut().zip(&temps).for_each(|(x, col)| *x = col[i]);
                        model.evaluate(positions.as_ref().map_or(0.0, |p| p[i]), &t)
                    })
                    .collect())
            }
            ThermalErrorModel::Segmented(model) => model.predict(campaign, rows),
            ThermalErrorModel::Drift(model) => {
                let mut out = vec![0.0; rows.len()];
                for run in campaign.run_names() {
                    let at: Vec<usize> = (0..rows.len()).filter(|&k| campaign.runs[rows[k]] == run).collect();
                    if at.is_empty() {
                        continue;
                    }
                    let run_rows: Vec<usize> = at.iter().map(|&k| rows[k]).collect();
                    let (times, temperatures, _) = record(campaign, &model.sensors, None, &run_rows)?;
                    for (k, e) in at.iter().zip(model.simulate(&times, &temperatures)?) {
                        out[*k] = e;
                    }
                }
                Ok(out)
            }
        }
    }
}
