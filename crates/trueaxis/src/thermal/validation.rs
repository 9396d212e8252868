//! Validation of thermal error models (Zhu 2008 §3.4.3, §3.5, Table 4.3, ch. 5): residual
//! `e = measured - predicted`, its band (min, max), RMS, max |e|, range, mean and standard
//! deviation; the time split of one record into training and verification parts.

use super::error_model::ThermalErrorModel;
use super::thermal_campaign::Campaign;
use crate::error::Error;
use serde::Serialize;

/// Statistics of the residuals `measured - predicted` (units of the error, um).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ResidualStats {
    pub samples: usize,
    pub rms: f64,
    pub max_abs: f64,
    pub range: f64,
    pub min: f64,
    pub max: f64,
    pub mean: f64,
    /// Sample standard deviation (n - 1).
    pub sd: f64,
}

/// Residual statistics of `measured - predicted`; `None` without samples.
pub fn residual_stats(measured: &[f64], predicted: &[f64]) -> Option<ResidualStats> {
    let e: Vec<f64> = measured.iter().zip(predicted).map(|(m, p)| m - p).collect();
    let n = e.len();
    if n == 0 {
        return None;
    }
    let mean = e.iter().sum::<f64>() / n as f64;
    let min = e.iter().copied().fold(f64::INFINITY, f64::min);
    let max = e.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let ss: f64 = e.iter().map(|v| (v - mean).powi(2)).sum();
    Some(ResidualStats {
        samples: n,
        rms: (e.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt(),
        max_abs: min.abs().max(max.abs()),
        range: max - min,
        min,
        max,
        mean,
        sd: if n > 1 { (ss / (n - 1) as f64).sqrt() } else { 0.0 },
    })
}

/// Index splitting samples at `fraction` of the time span (Zhu 2008 §3.4.3: the first hour trains,
/// the second verifies): rows with `t < t0 + fraction (t1 - t0)` train.
pub fn time_split(times: &[f64], fraction: f64) -> usize {
    let (t0, t1) = (times.iter().copied().fold(f64::INFINITY, f64::min), times.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    let cut = t0 + fraction * (t1 - t0);
    times.iter().take_while(|t| **t < cut).count()
}

/// What a stretch of a campaign is used for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    Training,
    Validation,
    /// Evaluated with a given model.
    Prediction,
}

/// A stretch of a campaign: a whole run, or the first part (training) or the rest (verification)
/// of a run split in time. `run_rows` are all rows of its run, `rows` the stretch's.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    pub name: String,
    pub role: Role,
    pub run_rows: Vec<usize>,
    pub rows: Vec<usize>,
}

/// One prediction segment per run (all rows when the campaign names no runs), each predicted from
/// its own start (the reference state of a state-space model): what `thermal predict` evaluates.
pub fn prediction_segments(campaign: &Campaign) -> Vec<Segment> {
    campaign
        .run_names()
        .into_iter()
        .map(|run| {
            let rows: Vec<usize> = (0..campaign.len()).filter(|&i| campaign.runs[i] == run).collect();
            Segment { name: if run.is_empty() { "all rows".into() } else { run }, role: Role::Prediction, run_rows: rows.clone(), rows }
        })
        .collect()
}

/// The segments of a fit: the runs in `train_runs` (every run when `None`) train and the others
/// validate (other duty cycles, altered warm-up; Zhu 2008 §3.5); with `split = Some(f)`, each
/// training run trains on the samples before `t0 + f (t1 - t0)` and validates on the rest (Zhu 2008
/// §3.4.3: the first hour trains, the second verifies).
pub fn segments(campaign: &Campaign, train_runs: Option<&[String]>, split: Option<f64>) -> Result<Vec<Segment>, Error> {
    if let Some(f) = split.filter(|f| !(*f > 0.0 && *f < 1.0)) {
        return Err(Error::input(format!("time-split:{f}: the training fraction must lie strictly between 0 and 1")));
    }
    if let Some(runs) = train_runs {
        campaign.rows_of(runs)?;
    }
    let t = campaign.column("t").ok();
    let mut out = Vec::new();
    for run in campaign.run_names() {
        // exactly this run's rows (a segment after a gap is a run of its own)
        let run_rows: Vec<usize> = (0..campaign.len()).filter(|&i| campaign.runs[i] == run).collect();
        let name = if run.is_empty() { "all rows".to_string() } else { run.clone() };
        let training = train_runs.is_none_or(|r| r.iter().any(|name| Campaign::is_of_run(&run, name)));
        match (training, split) {
            (true, Some(f)) => {
                let t = t.ok_or_else(|| Error::input(format!("{}: a time split needs the column t", campaign.origin)))?;
                let times: Vec<f64> = run_rows.iter().map(|&i| t[i]).collect();
                let cut = time_split(&times, f);
                if cut < 2 || cut + 1 > run_rows.len() {
                    return Err(Error::input(format!("time-split:{f}: run `{name}` has no samples on one side of the split")));
                }
                let percent = 100.0 * f;
                out.push(Segment {
                    name: format!("{name} (first {percent:.0} %)"),
                    role: Role::Training,
                    run_rows: run_rows.clone(),
                    rows: run_rows[..cut].to_vec(),
                });
                out.push(Segment {
                    name: format!("{name} (last {:.0} %)", 100.0 - percent),
                    role: Role::Validation,
                    run_rows: run_rows.clone(),
                    rows: run_rows[cut..].to_vec(),
                });
            }
            _ => {
                let role = if training { Role::Training } else { Role::Validation };
                out.push(Segment { name, role, run_rows: run_rows.clone(), rows: run_rows });
            }
        }
    }
    Ok(out)
}

/// A segment with its times (s), measured error (when the campaign has the column) and prediction.
#[derive(Clone, Debug)]
pub struct Evaluated {
    pub segment: Segment,
    pub times_s: Vec<f64>,
    pub measured: Option<Vec<f64>>,
    pub predicted: Vec<f64>,
}

impl Evaluated {
    /// Residual statistics of the segment, if measured.
    pub fn stats(&self) -> Option<ResidualStats> {
        self.measured.as_ref().and_then(|m| residual_stats(m, &self.predicted))
    }
}

/// Evaluates `model` on each segment: on its whole run (the drift model needs the run from its
/// start), kept at the segment's rows. A prediction that is not a finite number (coefficients too
/// large for the temperatures) is a failed computation.
pub fn evaluate_segments(campaign: &Campaign, model: &ThermalErrorModel, segments: &[Segment]) -> Result<Vec<Evaluated>, Error> {
    let t = campaign.column("t").ok();
    let measured_column = campaign.names.iter().any(|n| n == model.error());
    segments
        .iter()
        .map(|segment| {
            let run_prediction = model.predict(campaign, &segment.run_rows)?;
            let at = |row: usize| segment.run_rows.iter().position(|&r| r == row).expect("a segment's rows are rows of its run");
            let predicted: Vec<f64> = segment.rows.iter().map(|&r| run_prediction[at(r)]).collect();
            if let Some(k) = predicted.iter().position(|v| !v.is_finite()) {
                return Err(Error::computation(format!(
                    "{}: the prediction of `{}` at data row {} in {} is not a finite number: the model's coefficients are too large for these temperatures",
                    campaign.origin,
                    model.error(),
                    segment.rows[k] + 1,
                    segment.name
                )));
            }
            let measured = if measured_column { Some(campaign.select(&[model.error().to_string()], &segment.rows)?.remove(0)) } else { None };
            let times_s = segment.rows.iter().map(|&r| t.map_or(r as f64, |t| t[r])).collect();
            Ok(Evaluated { segment: segment.clone(), times_s, measured, predicted })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_of_a_known_residual() {
        let s = residual_stats(&[1.0, 2.0, 3.0, 4.0], &[0.5, 2.5, 3.0, 3.0]).unwrap();
        // e = 0.5, -0.5, 0, 1
        assert_eq!((s.min, s.max, s.range, s.max_abs), (-0.5, 1.0, 1.5, 1.0));
        assert!((s.rms - (1.5f64 / 4.0).sqrt()).abs() < 1e-15);
        assert!((s.mean - 0.25).abs() < 1e-15);
        assert!((s.sd - ((0.0625 + 0.5625 + 0.0625 + 0.5625) / 3.0f64).sqrt()).abs() < 1e-15);
        assert_eq!(time_split(&[0.0, 1.0, 2.0, 3.0, 4.0], 0.5), 2);
    }
}
