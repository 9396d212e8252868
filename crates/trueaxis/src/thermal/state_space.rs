//! State-space thermal models (Soons 1993 §3.4.2, eqs. 3.41-3.55, and the empirical drift model of
//! §3.4.4, eqs. 3.65-3.66): inputs `u_i(t)` (temperature rises of sensors near the heat sources,
//! ambient), states `x_ij` with `dx_ij/dt = -gamma_j x_ij + u_i` (A block diagonal with the same m
//! decay rates for every input, B = 1), outputs `y = C x` (temperatures at other sensors, or the
//! drift components of the tool relative to the workpiece).
//!
//! Discrete time with the input held over each sample interval (zero-order hold):
//! `x[k+1] = e^(-gamma dt) x[k] + (1 - e^(-gamma dt)) / gamma u[k]`, from the zero state (the
//! experiment starts in the reference state). Identification: C enters linearly and is eliminated
//! by least squares (variable projection); Levenberg-Marquardt on `ln gamma`.

use super::levenberg_marquardt::{levenberg_marquardt, LmOptions};
use super::time_constants::combinations;
use crate::error::Error;
use nalgebra::DMatrix;

/// `m` decay rates shared by every input, and the output matrix.
#[derive(Clone, Debug)]
pub struct StateSpaceModel {
    /// Decay rates gamma_j (1/s); time constants `1/gamma_j`.
    pub gammas: Vec<f64>,
    pub inputs: usize,
    /// Outputs x states; state `i * m + j` is input i, rate j.
    pub c: DMatrix<f64>,
}

/// The states at every sample for inputs `u[k][i]` held on `[t_k, t_k+1)`: rows = samples.
pub fn states(gammas: &[f64], times_s: &[f64], u: &[Vec<f64>]) -> DMatrix<f64> {
    let m = gammas.len();
    let inputs = u.first().map_or(0, Vec::len);
    let mut x = vec![0.0; inputs * m];
    let mut out = DMatrix::zeros(times_s.len(), inputs * m);
    for k in 0..times_s.len() {
        if k > 0 {
            advance(gammas, times_s[k] - times_s[k - 1], &u[k - 1], &mut x);
        }
        for (s, v) in x.iter().enumerate() {
            out[(k, s)] = *v;
        }
    }
    out
}

/// One sample interval of `dt` seconds with the inputs `u_held[i]` held (zero-order hold):
/// `x_ij <- e^(-gamma_j dt) x_ij + (1 - e^(-gamma_j dt)) / gamma_j u_i` (state `i * m + j`). The
/// batch [`states`] and the sample-by-sample drift model (`super::stepping`) both advance by it.
pub fn advance(gammas: &[f64], dt: f64, u_held: &[f64], x: &mut [f64]) {
    let m = gammas.len();
    for (j, g) in gammas.iter().enumerate() {
        let decay = (-g * dt).exp();
        let gain = if *g * dt > 1e-12 { (1.0 - decay) / g } else { dt };
        for (i, u) in u_held.iter().enumerate() {
            x[i * m + j] = decay * x[i * m + j] + gain * u;
        }
    }
}

impl StateSpaceModel {
    /// Outputs `[sample][output]` for an input history.
    pub fn simulate(&self, times_s: &[f64], u: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let x = states(&self.gammas, times_s, u);
        let y = &x * self.c.transpose();
        (0..y.nrows()).map(|k| y.row(k).iter().copied().collect()).collect()
    }

    /// Time constants `1/gamma` (s), in the order of `gammas`.
    pub fn time_constants_s(&self) -> Vec<f64> {
        self.gammas.iter().map(|g| 1.0 / g).collect()
    }
}

/// One experiment: times (s), inputs `u[sample][input]`, outputs `y[sample][output]`.
pub type Record = (Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>);

/// Identifies `m` shared decay rates and C from records `(times_s, u[k][i], y[k][o])` (several
/// experiments, each from the zero state). `initial_tau_s` gives the start (m values), or `None`
/// for a log-spaced grid search.
pub fn identify_state_space(records: &[Record], m: usize, initial_tau_s: Option<&[f64]>) -> Result<(StateSpaceModel, f64), Error> {
    let first = records.first().ok_or_else(|| Error::input("no records to identify a state-space model"))?;
    let inputs = first.1.first().map_or(0, Vec::len);
    let outputs = first.2.first().map_or(0, Vec::len);
    if m == 0 || inputs == 0 || outputs == 0 {
        return Err(Error::input("a state-space model needs at least one rate, one input and one output"));
    }
    let mut samples = 0;
    for (t, u, y) in records {
        if t.len() != u.len() || t.len() != y.len() || u.iter().any(|r| r.len() != inputs) || y.iter().any(|r| r.len() != outputs) {
            return Err(Error::input("every record needs one input row and one output row per time, all of the same widths"));
        }
        if t.windows(2).any(|w| w[1].is_nan() || w[1] <= w[0]) {
            return Err(Error::input("times must increase strictly within a record"));
        }
        samples += t.len();
    }
    if samples <= inputs * m + m {
        return Err(Error::input(format!("{samples} samples cannot determine {} parameters per output", inputs * m)));
    }
    let y_all = DMatrix::from_fn(samples, outputs, |r, o| {
        let mut r = r;
        for (_, _, y) in records {
            if r < y.len() {
                return y[r][o];
            }
            r -= y.len();
        }
        unreachable!()
    });
    let design = |gammas: &[f64]| -> DMatrix<f64> {
        let mut x = DMatrix::zeros(samples, inputs * m);
        let mut at = 0;
        for (t, u, _) in records {
            let s = states(gammas, t, u);
            x.view_mut((at, 0), (t.len(), inputs * m)).copy_from(&s);
            at += t.len();
        }
        x
    };
    let solve = |gammas: &[f64]| -> Option<(DMatrix<f64>, DMatrix<f64>)> {
        let x = design(gammas);
        let svd = x.clone().svd(true, true);
        if svd.singular_values.min() < 1e-12 * svd.singular_values.max() {
            return None;
        }
        let ct = svd.solve(&y_all, 0.0).ok()?;
        let res = &y_all - &x * &ct;
        Some((ct, res))
    };
    let residuals = |log_g: &[f64], r: &mut [f64]| -> bool {
        if log_g.iter().any(|v| !v.is_finite() || v.abs() > 40.0) {
            return false;
        }
        let g: Vec<f64> = log_g.iter().map(|v| v.exp()).collect();
        match solve(&g) {
            Some((_, res)) => {
                r.copy_from_slice(res.as_slice());
                true
            }
            None => false,
        }
    };
    let start: Vec<f64> = match initial_tau_s {
        Some(t) if t.len() == m && t.iter().all(|v| *v > 0.0) => t.iter().map(|v| -(v.ln())).collect(),
        Some(_) => return Err(Error::input(format!("give {m} positive initial time constants"))),
        None => {
            let (dt, span) = records.iter().fold((f64::INFINITY, 0.0f64), |(d, s), (t, _, _)| {
                (t.windows(2).map(|w| w[1] - w[0]).fold(d, f64::min), s.max(t[t.len() - 1] - t[0]))
            });
            let grid: Vec<f64> = (0..12).map(|i| -(dt * (3.0 * span / dt).powf(i as f64 / 11.0)).ln()).collect();
            let mut best = (f64::INFINITY, Vec::new());
            let mut r = vec![0.0; samples * outputs];
            let mut idx = vec![0usize; m];
            let mut visit = |idx: &[usize]| {
                let x: Vec<f64> = idx.iter().map(|&i| grid[i]).collect();
                if residuals(&x, &mut r) {
                    let c: f64 = r.iter().map(|v| v * v).sum();
                    if c < best.0 {
                        best = (c, x);
                    }
                }
            };
            combinations(grid.len(), m, 0, 0, &mut idx, &mut visit);
            if best.1.is_empty() {
                return Err(Error::computation("no start point for the state-space identification: the inputs do not excite the model"));
            }
            best.1
        }
    };
    let lm = levenberg_marquardt(residuals, &start, samples * outputs, &LmOptions::default());
    let mut gammas: Vec<f64> = lm.x.iter().map(|v| v.exp()).collect();
    gammas.sort_by(|a, b| a.total_cmp(b));
    let (ct, _) = solve(&gammas).ok_or_else(|| Error::computation("the identified decay rates are not separable"))?;
    let rms = (lm.cost / (samples * outputs) as f64).sqrt();
    Ok((StateSpaceModel { gammas, inputs, c: ct.transpose() }, rms))
}

/// The rows of `u` as a column vector (helper for single-input use).
pub fn column(values: &[f64]) -> Vec<Vec<f64>> {
    values.iter().map(|v| vec![*v]).collect()
}
