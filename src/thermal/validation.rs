//! Validation of thermal error models (seed 002 §3.4.3, §3.5, Table 4.3, ch. 5): residual
//! `e = measured - predicted`, its band (min, max), RMS, max |e|, range, mean and standard
//! deviation; the time split of one record into training and verification parts.

use super::campaign::Campaign;
use super::regression::RegressionModel;
use super::{computation, ThermalError};
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

/// Index splitting samples at `fraction` of the time span (seed 002 §3.4.3: the first hour trains,
/// the second verifies): rows with `t < t0 + fraction (t1 - t0)` train.
pub fn time_split(times: &[f64], fraction: f64) -> usize {
    let (t0, t1) = (times.iter().copied().fold(f64::INFINITY, f64::min), times.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    let cut = t0 + fraction * (t1 - t0);
    times.iter().take_while(|t| **t < cut).count()
}

/// The model's prediction (um) at `rows` of a campaign, and the measured error column when the
/// campaign has it (the regression of seed 002 eqs. 3.12-3.15 evaluated on the sensor columns and,
/// for PDTE, the position column). A prediction that is not a finite number (coefficients too large
/// for the temperatures) is a failed computation.
pub fn evaluate_rows(campaign: &Campaign, model: &RegressionModel, rows: &[usize]) -> Result<(Option<Vec<f64>>, Vec<f64>), ThermalError> {
    let temps = campaign.select(&model.sensors, rows)?;
    let positions = match &model.position {
        Some(p) => Some(campaign.select(std::slice::from_ref(p), rows)?.remove(0)),
        None => None,
    };
    let mut t = vec![0.0; model.sensors.len()];
    let predicted = (0..rows.len())
        .map(|i| {
            t.iter_mut().zip(&temps).for_each(|(x, col)| *x = col[i]);
            model.evaluate(positions.as_ref().map_or(0.0, |p| p[i]), &t)
        })
        .collect::<Vec<f64>>();
    if let Some(i) = predicted.iter().position(|v| !v.is_finite()) {
        let run = &campaign.runs[rows[i]];
        return Err(computation(format!(
            "{}: the prediction of `{}` at data row {}{} is not a finite number: the model's coefficients are too large for these temperatures",
            campaign.origin,
            model.error,
            rows[i] + 1,
            if run.is_empty() { String::new() } else { format!(" (run {run})") }
        )));
    }
    let measured = if campaign.names.contains(&model.error) {
        Some(campaign.select(std::slice::from_ref(&model.error), rows)?.remove(0))
    } else {
        None
    };
    Ok((measured, predicted))
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
