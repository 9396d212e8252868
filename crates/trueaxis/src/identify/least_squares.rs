//! Linear least squares by QR with unit-length column scaling (Soons 1993 §3.2.2), with the
//! statistics of Soons 1993 §3.2.2 and §4.3: covariance `sigma^2 (X^T X)^-1` (eq. 4.11), leverage,
//! Cook's distance, and prediction intervals for single measurements (eq. 4.12 plus the noise).

use super::IdentifyError;
use nalgebra::{DMatrix, DVector};
use statrs::distribution::{ContinuousCDF, StudentsT};

/// Relative size below which a diagonal entry of R marks a column as linearly dependent.
pub const RANK_TOLERANCE: f64 = 1e-10;

/// The result of `y = X beta + noise`.
#[derive(Clone, Debug)]
pub struct LinearFit {
    /// Estimated coefficients, in the units of `y` per unit of each column.
    pub coefficients: Vec<f64>,
    /// `sigma^2 (X^T X)^-1` (Soons 1993 eq. 4.11).
    pub covariance: DMatrix<f64>,
    /// `(X^T X)^-1` without `sigma^2`, for prediction variances.
    pub unscaled_covariance: DMatrix<f64>,
    /// Residual standard deviation `sqrt(RSS / (n - p))` (units of `y`).
    pub sigma: f64,
    /// `y - X beta`.
    pub residuals: Vec<f64>,
    /// Residual sum of squares.
    pub rss: f64,
    /// Degrees of freedom `n - p`.
    pub dof: usize,
    /// Leverages `h_ii`, the diagonal of the hat matrix.
    pub leverage: Vec<f64>,
}

impl LinearFit {
    /// Standard uncertainty of each coefficient.
    pub fn standard_uncertainties(&self) -> Vec<f64> {
        (0..self.coefficients.len()).map(|i| self.covariance[(i, i)].sqrt()).collect()
    }

    /// Cook's distance of each observation: `D_i = e_i^2 h_ii / (p s^2 (1 - h_ii)^2)`.
    pub fn cooks_distance(&self) -> Vec<f64> {
        let p = self.coefficients.len() as f64;
        let s2 = self.sigma * self.sigma;
        self.residuals
            .iter()
            .zip(&self.leverage)
            .map(|(e, h)| if s2 > 0.0 && *h < 1.0 { e * e * h / (p * s2 * (1.0 - h) * (1.0 - h)) } else { 0.0 })
            .collect()
    }

    /// Prediction `g^T beta` at regressor row `g` with the half-width of the two-sided prediction
    /// interval of a single new measurement at confidence `level` (e.g. 0.95):
    /// `t_{(1+level)/2, n-p} s sqrt(1 + g^T (X^T X)^-1 g)`.
    pub fn prediction(&self, g: &[f64], level: f64) -> (f64, f64) {
        let value: f64 = g.iter().zip(&self.coefficients).map(|(a, b)| a * b).sum();
        let gv = DVector::from_column_slice(g);
        let var = (gv.transpose() * &self.unscaled_covariance * &gv)[(0, 0)];
        (value, t_quantile(level, self.dof) * self.sigma * (1.0 + var).sqrt())
    }
}

/// Two-sided Student-t quantile `t_{(1+level)/2, dof}`; the normal quantile for large `dof`.
pub fn t_quantile(level: f64, dof: usize) -> f64 {
    let dof = dof.max(1) as f64;
    StudentsT::new(0.0, 1.0, dof).map(|t| t.inverse_cdf(0.5 * (1.0 + level))).unwrap_or(f64::NAN)
}

/// Solves `min |W^(1/2) (y - X beta)|` by QR of the unit-length-scaled design matrix.
/// `names` name the columns for the rank-deficiency message. `weights` (optional) are `1/sigma_i^2`.
pub fn fit_linear(design: &DMatrix<f64>, y: &[f64], weights: Option<&[f64]>, names: &[String]) -> Result<LinearFit, IdentifyError> {
    let (n, p) = design.shape();
    if y.len() != n {
        return Err(IdentifyError::Input(format!("{} observations for a design matrix of {n} rows", y.len())));
    }
    if n <= p {
        return Err(IdentifyError::Input(format!("{n} observations cannot determine {p} coefficients and a residual variance")));
    }
    if design.iter().chain(y).any(|v| !v.is_finite()) {
        return Err(IdentifyError::Input("the data or the design matrix contain numbers that are not finite".into()));
    }
    let sqrt_w: Vec<f64> = match weights {
        Some(w) if w.len() == n && w.iter().all(|v| v.is_finite() && *v > 0.0) => w.iter().map(|v| v.sqrt()).collect(),
        Some(_) => return Err(IdentifyError::Input("weights must be positive finite numbers, one per observation".into())),
        None => vec![1.0; n],
    };
    let mut x = design.clone();
    let mut b = DVector::from_iterator(n, y.iter().zip(&sqrt_w).map(|(v, w)| v * w));
    for (i, w) in sqrt_w.iter().enumerate() {
        x.row_mut(i).scale_mut(*w);
    }
    // unit-length scaling: every column to norm 1
    let scale: Vec<f64> = (0..p).map(|j| column_norm(x.column(j))).collect();
    for (j, s) in scale.iter().enumerate() {
        if *s == 0.0 {
            return Err(IdentifyError::RankDeficient { message: format!("{} is zero at every observation", name(names, j)) });
        }
        if !s.is_finite() {
            return Err(IdentifyError::Input(format!("{}: the weighted sensitivities are too large to scale", name(names, j))));
        }
        x.column_mut(j).unscale_mut(*s);
    }
    let qr = x.clone().qr();
    let r = qr.r();
    let rmax = (0..p).map(|i| r[(i, i)].abs()).fold(0.0, f64::max);
    // a NaN diagonal (from non-finite input) counts as dependent too
    if let Some(j) = (0..p).find(|&i| r[(i, i)].abs() < RANK_TOLERANCE * rmax || r[(i, i)].is_nan()) {
        return Err(IdentifyError::RankDeficient { message: dependent_message(&x, j, names) });
    }
    let q = qr.q();
    let qtb = q.transpose() * &b;
    let singular = || IdentifyError::RankDeficient { message: "the scaled design matrix is singular".into() };
    let beta_scaled = r.solve_upper_triangular(&qtb).ok_or_else(singular)?;
    let r_inv = r.solve_upper_triangular(&DMatrix::identity(p, p)).ok_or_else(singular)?;
    let mut unscaled = &r_inv * r_inv.transpose();
    for i in 0..p {
        for j in 0..p {
            unscaled[(i, j)] /= scale[i] * scale[j];
        }
    }
    let coefficients: Vec<f64> = beta_scaled.iter().zip(&scale).map(|(c, s)| c / s).collect();
    let fitted = &x * &beta_scaled;
    b -= &fitted;
    let residuals: Vec<f64> = b.iter().zip(&sqrt_w).map(|(e, w)| e / w).collect();
    let rss = b.norm_squared();
    let dof = n - p;
    let sigma = (rss / dof as f64).sqrt();
    let leverage = (0..n).map(|i| q.row(i).norm_squared()).collect();
    Ok(LinearFit {
        covariance: &unscaled * (sigma * sigma),
        unscaled_covariance: unscaled,
        coefficients,
        sigma,
        residuals,
        rss,
        dof,
        leverage,
    })
}

/// Euclidean norm of a column without overflow or underflow of the squares: `m |x / m|` with
/// `m = max |x_i|` (a column of sensitivities of 1e200 has a norm, not infinity).
pub(crate) fn column_norm(x: nalgebra::DVectorView<f64>) -> f64 {
    weighted_column_norm(x.as_slice(), &[])
}

/// [`column_norm`] of every column of `x`; the columns in parallel from 2^20 entries (each norm a
/// memory-bound pass, the same value on any number of threads).
pub(crate) fn column_norms(x: &DMatrix<f64>) -> Vec<f64> {
    use rayon::prelude::*;
    let norm = |j: usize| column_norm(x.column(j));
    match x.len() < PARALLEL_ENTRIES {
        true => (0..x.ncols()).map(norm).collect(),
        false => (0..x.ncols()).into_par_iter().map(norm).collect(),
    }
}

/// `X beta` (rows of `X` in parallel chunks from 2^20 entries: a memory-bound pass over `X`; each
/// row summed in the order of the columns, the same value on any number of threads).
pub(crate) fn design_times(x: &DMatrix<f64>, beta: &[f64]) -> Vec<f64> {
    use rayon::prelude::*;
    const CHUNK: usize = 4096;
    let (n, p) = x.shape();
    let mut out = vec![0.0; n];
    let chunk = |(c, rows): (usize, &mut [f64])| {
        for (j, b) in beta.iter().enumerate().take(p) {
            let column = &x.as_slice()[j * n + c * CHUNK..j * n + c * CHUNK + rows.len()];
            rows.iter_mut().zip(column).for_each(|(o, v)| *o += v * b);
        }
    };
    match x.len() < PARALLEL_ENTRIES {
        true => out.chunks_mut(CHUNK).enumerate().for_each(chunk),
        false => out.par_chunks_mut(CHUNK).enumerate().for_each(chunk),
    }
    out
}

/// Matrices with at least this many entries are worth a second thread for one pass over them.
const PARALLEL_ENTRIES: usize = 1 << 20;

/// `|diag(w) x|` as [`column_norm`], `w` the row factors (`sqrt` of the weights; empty: all 1).
pub(crate) fn weighted_column_norm(x: &[f64], w: &[f64]) -> f64 {
    if w.is_empty() {
        scaled_norm(x.iter().copied())
    } else {
        scaled_norm(x.iter().zip(w).map(|(v, w)| v * w))
    }
}

fn scaled_norm(values: impl Iterator<Item = f64> + Clone) -> f64 {
    let m = values.clone().fold(0.0, |m: f64, v| m.max(v.abs()));
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    let inverse = 1.0 / m;
    m * values.map(|v| (v * inverse) * (v * inverse)).sum::<f64>().sqrt()
}

fn name(names: &[String], j: usize) -> String {
    names.get(j).cloned().unwrap_or_else(|| format!("column {}", j + 1))
}

/// Names the columns that column `j` depends on: the least-squares combination of the columns
/// before it that reproduces it.
fn dependent_message(x: &DMatrix<f64>, j: usize, names: &[String]) -> String {
    let before = x.columns(0, j).into_owned();
    let target = x.column(j).into_owned();
    let mut parts = Vec::new();
    if j > 0 {
        if let Ok(sol) = before.clone().svd(true, true).solve(&target, 1e-12) {
            for (k, c) in sol.iter().enumerate() {
                if c.abs() > 1e-6 {
                    parts.push(name(names, k));
                }
            }
        }
    }
    if parts.is_empty() {
        format!("{} cannot be separated from the other terms with these data", name(names, j))
    } else {
        format!("{} cannot be separated from {} with these data", name(names, j), parts.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_line_matches_the_closed_form() {
        // y = 2 + 3x at x = 0..4 with residuals +-0.1: slope = Sxy/Sxx, s^2 = RSS/(n-2)
        let xs = [0.0, 1.0, 2.0, 3.0, 4.0];
        let noise = [0.1, -0.1, 0.0, 0.1, -0.1];
        let y: Vec<f64> = xs.iter().zip(noise).map(|(x, e)| 2.0 + 3.0 * x + e).collect();
        let design = DMatrix::from_fn(5, 2, |i, j| if j == 0 { 1.0 } else { xs[i] });
        let fit = fit_linear(&design, &y, None, &[]).unwrap();
        let (xm, ym) = (2.0, y.iter().sum::<f64>() / 5.0);
        let sxx: f64 = xs.iter().map(|x| (x - xm) * (x - xm)).sum();
        let sxy: f64 = xs.iter().zip(&y).map(|(x, v)| (x - xm) * (v - ym)).sum();
        let slope = sxy / sxx;
        assert!((fit.coefficients[1] - slope).abs() < 1e-12);
        assert!((fit.coefficients[0] - (ym - slope * xm)).abs() < 1e-12);
        let rss: f64 = fit.residuals.iter().map(|e| e * e).sum();
        assert!((fit.sigma - (rss / 3.0).sqrt()).abs() < 1e-12);
        // Var(slope) = s^2 / Sxx
        assert!((fit.covariance[(1, 1)] - fit.sigma * fit.sigma / sxx).abs() < 1e-12);
        // leverages of a straight line: 1/n + (x - xm)^2 / Sxx
        for (h, x) in fit.leverage.iter().zip(xs) {
            assert!((h - (0.2 + (x - xm) * (x - xm) / sxx)).abs() < 1e-12);
        }
        // t_{0.975, 3} = 3.182446
        assert!((t_quantile(0.95, 3) - 3.182446305).abs() < 1e-6);
    }

    #[test]
    fn dependent_columns_are_named() {
        let design = DMatrix::from_fn(6, 3, |i, j| match j {
            0 => i as f64,
            1 => 1.0,
            _ => 2.0 * i as f64 + 3.0,
        });
        let names: Vec<String> = ["slope", "offset", "combo"].iter().map(|s| s.to_string()).collect();
        let e = fit_linear(&design, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.5], None, &names).unwrap_err().to_string();
        assert!(e.contains("combo cannot be separated from slope, offset"), "{e}");
    }

    #[test]
    fn huge_sensitivities_are_scaled_without_overflow() {
        // a column of 1e200 (its square overflows): the rank check must not see infinity, and the
        // fit of y = beta x through (1e200, 0), (1, 1), (1, 1) is beta = 2 / (1e400 + 2) ~ 0
        let design = DMatrix::from_column_slice(3, 1, &[1e200, 1.0, 1.0]);
        let fit = fit_linear(&design, &[0.0, 1.0, 1.0], None, &[]).unwrap();
        assert!(fit.coefficients[0].abs() < 1e-300 && fit.covariance.iter().all(|v| v.is_finite()), "{fit:?}");
        let col = DMatrix::from_column_slice(3, 1, &[3e200, 4e200, 0.0]);
        assert!((column_norm(col.column(0)) - 5e200).abs() < 1e186);
        let tiny = DMatrix::from_column_slice(2, 1, &[3e-200, 4e-200]);
        assert!((column_norm(tiny.column(0)) - 5e-200).abs() < 1e-214);
    }

    #[test]
    fn the_parallel_passes_equal_the_serial_formulas() {
        // 10001 x 120 (above the parallel size, a partial last chunk)
        let (n, p) = (10_001, 120);
        let x = DMatrix::from_fn(n, p, |i, j| ((i * (j + 3)) as f64 * 0.0171).sin() * 10f64.powi(j as i32 % 9 - 4));
        let beta: Vec<f64> = (0..p).map(|j| (j as f64 * 0.31).cos()).collect();
        let reference = &x * DVector::from_column_slice(&beta);
        let fitted = design_times(&x, &beta);
        for (i, (a, b)) in fitted.iter().zip(reference.iter()).enumerate() {
            // each row to 1e-14 of the sum of the magnitudes of its terms
            let size: f64 = (0..p).map(|j| (x[(i, j)] * beta[j]).abs()).sum();
            assert!((a - b).abs() <= 1e-14 * size, "row {i}: {a} vs {b}");
        }
        let norms = column_norms(&x);
        assert!((0..p).all(|j| norms[j] == column_norm(x.column(j))));
    }
}
