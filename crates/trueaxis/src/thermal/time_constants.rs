//! Multi-exponential fit of temperature records with shared time constants (Zhu 2008 §3.5,
//! eq. 3.17): `T(t) = b + sum_j A_j (1 - exp(-t / tau_j))`, the time constants `tau_j` shared by
//! every series (sensor and test), the amplitudes `A_j` (and the offset `b`, optional) per series.
//!
//! Variable projection: for given `tau` the amplitudes are a linear least-squares problem per
//! series; Levenberg-Marquardt on `ln tau` minimises the projected residual. The start is the best
//! point of a log-spaced grid of time constants between the sampling step and three times the
//! longest record.

use super::levenberg_marquardt::{levenberg_marquardt, LmOptions};
use crate::error::Error;
use nalgebra::{DMatrix, DVector};

/// One temperature record: times since the start of the step (s) and temperatures (degC or K).
#[derive(Clone, Debug)]
pub struct Series {
    pub times_s: Vec<f64>,
    pub values: Vec<f64>,
}

/// The fitted time constants and amplitudes.
#[derive(Clone, Debug)]
pub struct TimeConstantFit {
    /// Shared time constants (s), decreasing.
    pub tau_s: Vec<f64>,
    /// Per series: `[A_1, .., A_m]` in the order of `tau_s`.
    pub amplitudes: Vec<Vec<f64>>,
    /// Per series: the offset `b` (0 without offsets).
    pub offsets: Vec<f64>,
    /// RMS of the residuals over all samples.
    pub residual_rms: f64,
}

impl TimeConstantFit {
    /// Eq. 3.17 for series `k` at time `t` (s from the step): `b + sum_j A_j (1 - exp(-t / tau_j))`.
    pub fn evaluate(&self, k: usize, t: f64) -> f64 {
        self.offsets[k] + self.amplitudes[k].iter().zip(&self.tau_s).map(|(a, tau)| a * (1.0 - (-t / tau).exp())).sum::<f64>()
    }
}

/// Fits `count` shared time constants to `series` (eq. 3.17); `offset` adds a constant per series
/// (the temperature at t = 0 when the records are not rises from zero).
pub fn fit_time_constants(series: &[Series], count: usize, offset: bool) -> Result<TimeConstantFit, Error> {
    if count == 0 || count > 6 {
        return Err(Error::input(format!("the number of time constants must be 1 to 6 (got {count})")));
    }
    let mut samples = 0;
    let mut t_min = f64::INFINITY;
    let mut t_max = 0.0f64;
    for (k, s) in series.iter().enumerate() {
        if s.times_s.len() != s.values.len() || s.values.len() < count + 2 {
            return Err(Error::input(format!("series {}: needs as many times as values and more than {} samples", k + 1, count + 1)));
        }
        if s.times_s.iter().chain(&s.values).any(|v| !v.is_finite()) || s.times_s.iter().any(|t| *t < 0.0) {
            return Err(Error::input(format!("series {}: times must be finite and >= 0, values finite", k + 1)));
        }
        samples += s.values.len();
        for w in s.times_s.windows(2) {
            if w[1] > w[0] {
                t_min = t_min.min(w[1] - w[0]);
            }
        }
        t_max = t_max.max(s.times_s.iter().copied().fold(0.0, f64::max));
    }
    if series.is_empty() || !t_min.is_finite() || t_max <= 0.0 {
        return Err(Error::input("no usable series: each needs increasing times"));
    }
    let residuals = |log_tau: &[f64], r: &mut [f64]| -> bool {
        if log_tau.iter().any(|v| !v.is_finite() || *v > 50.0 || *v < -20.0) {
            return false;
        }
        let tau: Vec<f64> = log_tau.iter().map(|v| v.exp()).collect();
        let mut at = 0;
        for s in series {
            match project(s, &tau, offset) {
                Some((_, res)) => {
                    r[at..at + res.len()].copy_from_slice(&res);
                    at += res.len();
                }
                None => return false,
            }
        }
        true
    };
    // start: the best point of a log-spaced grid of distinct time constants
    let grid: Vec<f64> = (0..16).map(|i| (t_min.max(1e-3) * (3.0 * t_max / t_min.max(1e-3)).powf(i as f64 / 15.0)).ln()).collect();
    let mut best = (f64::INFINITY, Vec::new());
    let mut r = vec![0.0; samples];
    let mut choose = vec![0usize; count];
    let mut combo = |idx: &[usize]| {
        let x: Vec<f64> = idx.iter().map(|&i| grid[i]).collect();
        if residuals(&x, &mut r) {
            let c: f64 = r.iter().map(|v| v * v).sum();
            if c < best.0 {
                best = (c, x);
            }
        }
    };
    combinations(grid.len(), count, 0, 0, &mut choose, &mut combo);
    if best.1.is_empty() {
        return Err(Error::computation("no start point for the time-constant fit: the records are degenerate"));
    }
    let lm = levenberg_marquardt(residuals, &best.1, samples, &LmOptions::default());
    let mut tau: Vec<f64> = lm.x.iter().map(|v| v.exp()).collect();
    tau.sort_by(|a, b| b.total_cmp(a));
    let mut amplitudes = Vec::new();
    let mut offsets = Vec::new();
    for s in series {
        let (coef, _) = project(s, &tau, offset).ok_or_else(|| Error::computation("the fitted time constants are not separable"))?;
        offsets.push(if offset { coef[0] } else { 0.0 });
        amplitudes.push(coef[usize::from(offset)..].to_vec());
    }
    if tau.iter().any(|t| !t.is_finite()) || tau.windows(2).any(|w| w[1] > 0.99 * w[0]) {
        return Err(Error::computation(format!(
            "the {count} time constants are not separable in these records (the fit merges them); fit fewer, or only the response to a step"
        )));
    }
    Ok(TimeConstantFit { tau_s: tau, amplitudes, offsets, residual_rms: (lm.cost / samples as f64).sqrt() })
}

/// Linear least squares of one series for given time constants: coefficients `[b?, A_1..A_m]` and
/// residuals; `None` when the columns are dependent.
fn project(s: &Series, tau: &[f64], offset: bool) -> Option<(Vec<f64>, Vec<f64>)> {
    let n = s.values.len();
    let p = tau.len() + usize::from(offset);
    let x = DMatrix::from_fn(n, p, |i, j| if offset && j == 0 { 1.0 } else { 1.0 - (-s.times_s[i] / tau[j - usize::from(offset)]).exp() });
    let y = DVector::from_column_slice(&s.values);
    let svd = x.clone().svd(true, true);
    let smax = svd.singular_values.max();
    if svd.singular_values.min() < 1e-13 * smax {
        return None;
    }
    let coef = svd.solve(&y, 0.0).ok()?;
    let res = &y - &x * &coef;
    Some((coef.iter().copied().collect(), res.iter().copied().collect()))
}

/// Calls `f` with every strictly increasing index tuple of length `k` from `0..n`.
pub(crate) fn combinations(n: usize, k: usize, start: usize, depth: usize, idx: &mut Vec<usize>, f: &mut impl FnMut(&[usize])) {
    if depth == k {
        f(idx);
        return;
    }
    for i in start..n {
        idx[depth] = i;
        combinations(n, k, i + 1, depth + 1, idx, f);
    }
}
