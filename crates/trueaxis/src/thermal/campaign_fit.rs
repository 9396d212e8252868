//! A thermal error model fitted to a campaign, end to end, as `trueaxis thermal fit` and the Python
//! package run it: the training and validation segments (other runs, or a time split of each
//! training run), the sensor selection, the PITE/PDTE regression (Zhu 2008 eqs. 3.12-3.15 with
//! intercepts as eqs. 4.3-4.5) or the state-space drift model (Soons 1993 §3.4.4), the residuals of
//! every segment, the model file and its error terms; or the eq. 3.17 fit of shared time constants
//! to the temperature records of every run. The document of `trueaxis thermal fit --json`.
//!
//! Units: times in s (time constants reported in min), temperatures in degC, errors in um.

use super::drift_model::{fit_drift_model, record};
use super::error_model::ThermalErrorModel;
use super::links::{add_terms, model_terms, terms_toml};
use super::regression::{fit_regression, fit_regression_robust, fit_split, fit_stepwise, select_by_correlation, RegressionModel};
use super::segmented::{fit_segmented, Segmentation};
use super::thermal_campaign::Campaign;
use super::time_constants::{fit_time_constants, Series, TimeConstantFit};
use super::validation::{evaluate_segments, residual_stats, segments, Evaluated, ResidualStats, Role, Segment};
use crate::error::Error;
use crate::error_model::ErrorModel;
use crate::machine::Machine;
use crate::screen::irls::{RobustWeights, Weighting};
use serde_json::{json, Value};

/// The form of a thermal error model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelForm {
    /// Static regression (Zhu 2008 eqs. 3.12-3.15).
    Regression,
    /// State space (Soons 1993 §3.4.4): the drift as a sum of first-order lags of the sensors' rises
    /// since the start of each run.
    StateSpace,
}

/// What to fit (the options of `trueaxis thermal fit`).
#[derive(Clone, Debug, PartialEq)]
pub struct FitRequest {
    /// Error column (um) to model; needed unless `time_constants`.
    pub error: Option<String>,
    pub model: ModelForm,
    /// State-space model: number of time constants shared by the sensors (1 to 4).
    pub rates: usize,
    /// Validation: none (the runs not in `train_runs`), or `time-split:F`.
    pub validate: Option<String>,
    /// Fit this many shared time constants (eq. 3.17) to the temperature columns instead.
    pub time_constants: Option<usize>,
    /// With `time_constants`: only the first seconds of each run.
    pub until: Option<f64>,
    /// Sensor columns (default: every `T:<sensor>` column).
    pub sensors: Option<Vec<String>>,
    /// Sensor selection: `correlation:N` or `stepwise`.
    pub select: Option<String>,
    /// Axis column whose position enters the model (PDTE).
    pub position: Option<String>,
    /// Highest power of the position (PDTE).
    pub degree: usize,
    /// Drop the intercept terms (eqs. 3.12-3.13 as printed).
    pub no_intercept: bool,
    /// Geometric/thermal split: the degree of the geometric polynomial in the position (the
    /// intercepts), `degree` then being the degree of the position multiplying the temperatures.
    pub geometric_degree: Option<usize>,
    /// G-T model (NISTIR 5236): one model per direction of motion (column `dir`, + or -).
    pub by_direction: bool,
    /// G-T model: one model per range of the position between these breakpoints (mm or deg).
    pub ranges: Option<Vec<f64>>,
    /// Runs to train on (default: every row); the others validate.
    pub train_runs: Option<Vec<String>>,
    /// Robust weights (Huber or Tukey) for a regression model (`regression::fit_regression_robust`).
    pub robust: Option<Weighting>,
    /// Whether the model is wanted as error terms (`--terms-out`; regression models only).
    pub terms: bool,
}

impl Default for FitRequest {
    fn default() -> Self {
        FitRequest {
            error: None,
            model: ModelForm::Regression,
            rates: 2,
            validate: None,
            time_constants: None,
            until: None,
            sensors: None,
            select: None,
            position: None,
            degree: 0,
            no_intercept: false,
            geometric_degree: None,
            by_direction: false,
            ranges: None,
            train_runs: None,
            robust: None,
            terms: false,
        }
    }
}

/// A fitted thermal error model with its residuals.
#[derive(Clone, Debug)]
pub struct ModelFit {
    pub error: String,
    pub model: ThermalErrorModel,
    /// The sensors or terms kept by a selection.
    pub kept: Option<Vec<String>>,
    /// Number of training rows.
    pub rows: usize,
    /// Every segment evaluated (training and validation).
    pub evaluated: Vec<Evaluated>,
    pub training: Option<ResidualStats>,
    /// Per validation segment, its residual statistics.
    pub validation: Vec<(String, Option<ResidualStats>)>,
    /// What a robust regression did (`--robust`).
    pub robust: Option<Box<RobustSummary>>,
}

/// A robust regression's method, coefficients with their standard uncertainties (M-estimator
/// covariance, `screen::irls`) and the training samples it as good as left out (weight under 0.1).
#[derive(Clone, Debug)]
pub struct RobustSummary {
    pub weights: RobustWeights,
    pub names: Vec<String>,
    pub coefficients: Vec<f64>,
    pub uncertainties: Vec<f64>,
    /// (run, file line, residual um, weight) of each sample left with a weight under 0.1.
    pub downweighted: Vec<(String, u64, f64, f64)>,
}

impl RobustSummary {
    fn new(campaign: &Campaign, rows: &[usize], names: Vec<String>, fit: &crate::identify::LinearFit, weights: RobustWeights) -> Self {
        let downweighted = weights
            .listed()
            .into_iter()
            .map(|i| (campaign.runs[rows[i]].clone(), campaign.lines[rows[i]], fit.residuals[i], weights.weights[i]))
            .collect();
        RobustSummary { names, coefficients: fit.coefficients.clone(), uncertainties: fit.standard_uncertainties(), downweighted, weights }
    }

    /// When most downweighted samples come in runs of successive samples, the model misses a
    /// systematic part of the error (a transient, a missing sensor): robust weights are meant for
    /// isolated gross readings, and leaving such runs out hides the misfit instead.
    pub fn systematic_note(&self) -> Option<String> {
        let listed: Vec<usize> = self.weights.listed();
        let neighboured = listed.iter().filter(|&&i| listed.contains(&(i + 1)) || (i > 0 && listed.contains(&(i - 1)))).count();
        (listed.len() >= 4 && 2 * neighboured > listed.len()).then(|| {
            format!(
                "{neighboured} of the {} downweighted samples come in runs of successive samples: the model misses a systematic part \
                 of the error there (a transient, a sensor it lacks), not isolated gross readings; the robust fit leaves that part out \
                 instead of modelling it",
                listed.len()
            )
        })
    }

    /// `robust` of `thermal fit --json`.
    pub fn to_json(&self) -> Value {
        let w = &self.weights;
        json!({
            "weighting": w.weighting.name(), "tuning_constant": w.weighting.constant(), "scale_um": w.scale,
            "iterations": w.iterations, "converged": w.converged, "effective_samples": w.effective_readings(),
            "coefficients": self.names.iter().zip(self.coefficients.iter().zip(&self.uncertainties))
                .map(|(n, (c, u))| json!({"term": n, "value": c, "u": u})).collect::<Vec<_>>(),
            "downweighted": self.downweighted.iter()
                .map(|(r, l, e, w)| json!({"run": r, "line": l, "residual_um": e, "weight": w})).collect::<Vec<_>>(),
            "note": self.systematic_note(),
        })
    }
}

/// Shared time constants fitted to temperature records.
#[derive(Clone, Debug)]
pub struct TimeConstantsFit {
    /// (run, sensor) of each record.
    pub labels: Vec<(String, String)>,
    pub series: Vec<Series>,
    pub fit: TimeConstantFit,
}

/// The outcome of a fit: a model, or time constants.
#[derive(Clone, Debug)]
pub enum CampaignFit {
    Model(ModelFit),
    TimeConstants(TimeConstantsFit),
}

impl CampaignFit {
    /// The document of `trueaxis thermal fit --json`.
    pub fn to_json(&self) -> Value {
        match self {
            CampaignFit::Model(m) => m.to_json(),
            CampaignFit::TimeConstants(t) => t.to_json(),
        }
    }
}

impl ModelFit {
    /// `{"model", "kept", "training", "validation": {segment: statistics}}`.
    pub fn to_json(&self) -> Value {
        let mut doc = json!({"model": self.model, "kept": self.kept, "training": self.training,
               "validation": self.validation.iter().map(|(r, s)| (r.clone(), json!(s))).collect::<serde_json::Map<_, _>>()});
        if let Some(r) = &self.robust {
            doc["robust"] = r.to_json();
        }
        doc
    }

    /// The model as `[[term.NAME]]` error terms (factors T - 20 degC) of ISO parameter `parameter`
    /// for `trueaxis predict`, checked against `machine` when given; none for a state-space model.
    pub fn terms_text(&self, parameter: &str, machine: Option<&Machine>) -> Result<Option<String>, Error> {
        let terms = match &self.model {
            ThermalErrorModel::Regression(regression) => model_terms(parameter, regression, 1.0)?,
            ThermalErrorModel::Segmented(segmented) => segmented.terms(parameter)?,
            ThermalErrorModel::Drift(_) => return Ok(None),
        };
        if let Some(machine) = machine {
            add_terms(&mut ErrorModel::zero(machine), machine, &terms)?;
        }
        Ok(Some(format!(
            "# thermal error model of `{}` as error terms (factors T - 20 degC), from trueaxis thermal fit\n{}",
            self.error,
            terms_toml(&terms)
        )))
    }
}

impl TimeConstantsFit {
    /// `{"tau_min", "residual_rms", "amplitudes": [{"run", "sensor", "A", "offset"}]}`.
    pub fn to_json(&self) -> Value {
        let fit = &self.fit;
        let amplitudes: Vec<Value> = self
            .labels
            .iter()
            .zip(fit.amplitudes.iter().zip(&fit.offsets))
            .map(|((r, s), (a, b))| json!({"run": r, "sensor": s, "A": a, "offset": b}))
            .collect();
        json!({"tau_min": fit.tau_s.iter().map(|t| t / 60.0).collect::<Vec<_>>(), "residual_rms": fit.residual_rms, "amplitudes": amplitudes})
    }
}

/// Fits `request` to `campaign`; `data` names the campaign in messages.
pub fn fit_campaign(campaign: &Campaign, data: &str, request: &FitRequest) -> Result<CampaignFit, Error> {
    let rows: Vec<usize> = match &request.train_runs {
        Some(runs) => campaign.rows_of(runs)?,
        None => (0..campaign.len()).collect(),
    };
    let sensors = request.sensors.clone().unwrap_or_else(|| campaign.sensors());
    if sensors.is_empty() {
        return Err(Error::input(format!("{data}: no temperature columns T:<sensor>")));
    }
    if let Some(n) = request.time_constants {
        return Ok(CampaignFit::TimeConstants(fit_taus(request, campaign, &rows, &sensors, n)?));
    }
    let error = request.error.clone().ok_or_else(|| Error::input("--error: name the error column (um) to model"))?;
    let split = match request.validate.as_deref() {
        None => None,
        Some(v) => match v.strip_prefix("time-split:").map(str::parse::<f64>) {
            Some(Ok(f)) if f > 0.0 && f < 1.0 => Some(f),
            _ => return Err(Error::input(format!("--validate {v}: expected time-split:F with 0 < F < 1"))),
        },
    };
    let segments = segments(campaign, request.train_runs.as_deref(), split)?;
    let training: Vec<&Segment> = segments.iter().filter(|s| s.role == Role::Training).collect();
    let rows: Vec<usize> = training.iter().flat_map(|s| s.rows.iter().copied()).collect();
    let segmented = request.by_direction || request.ranges.is_some();
    let plain_regression = matches!(request.model, ModelForm::Regression) && request.select.is_none() && request.geometric_degree.is_none();
    if request.robust.is_some() && (segmented || !plain_regression) {
        return Err(Error::input(
            "--robust applies to a regression model without --select, --geometric-degree, --by-direction or --ranges",
        ));
    }
    let mut robust = None;
    let (model, kept) = match request.model {
        ModelForm::Regression if segmented => {
            if request.select.is_some() || request.no_intercept {
                return Err(Error::input("--select and --no-intercept do not apply to a segmented G-T model (--by-direction, --ranges)"));
            }
            let segmentation = Segmentation {
                by_direction: request.by_direction,
                breakpoints: request.ranges.clone().unwrap_or_default(),
                geometric_degree: request.geometric_degree.unwrap_or(request.degree),
                thermal_degree: request.degree,
            };
            let position =
                request.position.as_deref().ok_or_else(|| Error::input("--by-direction and --ranges need --position (the axis column)"))?;
            (ThermalErrorModel::Segmented(fit_segmented(campaign, &rows, &error, &sensors, position, &segmentation)?), None)
        }
        ModelForm::Regression => {
            let (model, kept, summary) = fit_regression_model(request, campaign, &rows, &sensors, &error)?;
            robust = summary;
            (ThermalErrorModel::Regression(model), kept)
        }
        ModelForm::StateSpace => {
            if request.select.is_some() || request.position.is_some() || request.no_intercept || request.terms || segmented {
                return Err(Error::input(
                    "--select, --position, --no-intercept, --by-direction, --ranges and --terms-out apply to regression models, not to --model state-space",
                ));
            }
            // a state-space record starts from the state at the start of its run; after a gap
            // (`thermal::thermal_screening::split_at_gaps`) that state is unknown, so such segments are not
            // fitted (they are still evaluated, from a zero state)
            let known_start = |s: &&&Segment| !s.name.contains(crate::thermal::thermal_screening::AFTER_GAP);
            let records = training
                .iter()
                .filter(known_start)
                .map(|s| record(campaign, &sensors, Some(&error), &s.rows))
                .collect::<Result<Vec<_>, _>>()?;
            (ThermalErrorModel::Drift(fit_drift_model(&error, &sensors, &records, request.rates)?.0), None)
        }
    };
    let evaluated = evaluate_segments(campaign, &model, &segments)?;
    if evaluated.iter().any(|e| e.predicted.iter().any(|v| !v.is_finite())) {
        return Err(Error::computation(format!("{data}: the fitted model predicts numbers that are not finite; nothing was written")));
    }
    let (measured, predicted): (Vec<f64>, Vec<f64>) = evaluated
        .iter()
        .filter(|e| e.segment.role == Role::Training)
        .flat_map(|e| e.measured.clone().unwrap_or_default().into_iter().zip(e.predicted.clone()))
        .unzip();
    let training_stats = residual_stats(&measured, &predicted);
    let validation: Vec<(String, Option<ResidualStats>)> =
        evaluated.iter().filter(|e| e.segment.role == Role::Validation).map(|e| (e.segment.name.clone(), e.stats())).collect();
    Ok(CampaignFit::Model(ModelFit { error, model, kept, rows: rows.len(), evaluated, training: training_stats, validation, robust }))
}

/// A regression model, the sensors or terms a selection kept, what a robust fit did.
type RegressionFit = (RegressionModel, Option<Vec<String>>, Option<Box<RobustSummary>>);

/// The PITE/PDTE regression on the training rows, with the sensor selection of `select`; the
/// names of the kept terms or sensors when selected; what a robust fit did.
fn fit_regression_model(
    request: &FitRequest,
    campaign: &Campaign,
    rows: &[usize],
    sensors: &[String],
    error: &str,
) -> Result<RegressionFit, Error> {
    let temps = campaign.select(sensors, rows)?;
    let measured = campaign.select(&[error.to_string()], rows)?.remove(0);
    let positions = match &request.position {
        Some(p) => Some(campaign.select(std::slice::from_ref(p), rows)?.remove(0)),
        None => None,
    };
    let position = request.position.as_deref().zip(positions.as_deref());
    let intercept = !request.no_intercept;
    if let Some(g) = request.geometric_degree {
        let position = position.ok_or_else(|| Error::input("--geometric-degree needs --position (the axis column)"))?;
        if request.select.is_some() || !intercept {
            return Err(Error::input("--geometric-degree does not combine with --select or --no-intercept"));
        }
        return Ok((fit_split(error, sensors, &temps, position, g, request.degree, &measured)?.0, None, None));
    }
    match request.select.as_deref() {
        None => match request.robust {
            Some(w) => {
                let (m, fit, weights) = fit_regression_robust(error, sensors, &temps, position, request.degree, intercept, &measured, w)?;
                let names = super::regression::column_names(sensors, position.map(|p| p.0), request.degree, intercept);
                Ok((m, None, Some(Box::new(RobustSummary::new(campaign, rows, names, &fit, weights)))))
            }
            None => Ok((fit_regression(error, sensors, &temps, position, request.degree, intercept, &measured)?.0, None, None)),
        },
        Some("stepwise") => {
            let (m, _, k) = fit_stepwise(error, sensors, &temps, position, request.degree, intercept, &measured, 0.9999)?;
            Ok((m, Some(k), None))
        }
        Some(s) if s.starts_with("correlation:") => {
            let n = match s["correlation:".len()..].parse::<usize>() {
                Ok(n) if n >= 1 => n,
                _ => {
                    return Err(Error::input(format!(
                        "--select {s}: expected correlation:N with N >= 1, the number of sensors to keep (of {})",
                        sensors.len()
                    )))
                }
            };
            let chosen = select_by_correlation(&temps, &measured, n, 0.0);
            let names: Vec<String> = chosen.iter().map(|&i| sensors[i].clone()).collect();
            let t: Vec<Vec<f64>> = chosen.iter().map(|&i| temps[i].clone()).collect();
            let (m, _) = fit_regression(error, &names, &t, position, request.degree, intercept, &measured)?;
            Ok((m, Some(names), None))
        }
        Some(other) => Err(Error::input(format!("--select {other}: expected correlation:N or stepwise"))),
    }
}

/// Shared time constants (eq. 3.17) of the temperature records of each run and sensor, each from
/// the start of its run (up to `until` seconds).
fn fit_taus(request: &FitRequest, campaign: &Campaign, rows: &[usize], sensors: &[String], n: usize) -> Result<TimeConstantsFit, Error> {
    if let Some(u) = request.until.filter(|u| !(u.is_finite() && *u > 0.0)) {
        return Err(Error::input(format!("--until {u}: expected a positive number of seconds from the start of each run")));
    }
    let t = campaign.column("t")?;
    let mut series = Vec::new();
    let mut labels = Vec::new();
    let runs: Vec<String> = campaign.run_names().into_iter().filter(|r| rows.iter().any(|&i| &campaign.runs[i] == r)).collect();
    for run in &runs {
        let run_rows: Vec<usize> = rows.iter().copied().filter(|&i| &campaign.runs[i] == run).collect();
        let t0 = run_rows.iter().map(|&i| t[i]).fold(f64::INFINITY, f64::min);
        let run_rows: Vec<usize> = run_rows.into_iter().filter(|&i| request.until.is_none_or(|u| t[i] - t0 <= u)).collect();
        for s in sensors {
            let v = campaign.column(s)?;
            series
                .push(Series { times_s: run_rows.iter().map(|&i| t[i] - t0).collect(), values: run_rows.iter().map(|&i| v[i]).collect() });
            labels.push((run.clone(), s.clone()));
        }
    }
    let fit = fit_time_constants(&series, n, true)?;
    Ok(TimeConstantsFit { labels, series, fit })
}
