//! A small Levenberg-Marquardt solver for nonlinear least squares `min sum r_i(x)^2` (Marquardt
//! 1963, with the diagonal scaling of JTJ; forward-difference Jacobian). Used for the few nonlinear
//! parameters (time constants) of variable-projection problems, where the linear parameters are
//! eliminated inside the residual function (Golub & Pereyra 1973).
//!
//! Why not a crate: `identify` has no LM, and the problems here have 1 to 10 parameters; this
//! file is about 100 lines on nalgebra, which the project already uses, whereas the
//! `levenberg-marquardt` crate pins its own nalgebra version and a trait-object problem API.

use nalgebra::{DMatrix, DVector};

/// Options of [`levenberg_marquardt`].
#[derive(Clone, Copy, Debug)]
pub struct LmOptions {
    pub max_iterations: usize,
    /// Stop when the relative decrease of the cost or the relative step is below this.
    pub tolerance: f64,
}

impl Default for LmOptions {
    fn default() -> Self {
        LmOptions { max_iterations: 200, tolerance: 1e-13 }
    }
}

/// The solution.
#[derive(Clone, Debug)]
pub struct LmResult {
    pub x: Vec<f64>,
    /// `sum r_i^2` at `x`.
    pub cost: f64,
    pub iterations: usize,
    pub converged: bool,
}

/// Minimises `sum r_i(x)^2` from `x0`. `residuals(x, r)` fills the `m` residuals and returns
/// `false` where `x` is outside the model's domain (the step is then rejected).
pub fn levenberg_marquardt(mut residuals: impl FnMut(&[f64], &mut [f64]) -> bool, x0: &[f64], m: usize, options: &LmOptions) -> LmResult {
    let p = x0.len();
    let mut x = x0.to_vec();
    let mut r = vec![0.0; m];
    if !residuals(&x, &mut r) {
        return LmResult { x, cost: f64::INFINITY, iterations: 0, converged: false };
    }
    let mut cost: f64 = r.iter().map(|v| v * v).sum();
    let mut mu = 1e-3;
    let mut jac = DMatrix::zeros(m, p);
    let mut trial = vec![0.0; m];
    for iteration in 1..=options.max_iterations {
        // forward-difference Jacobian
        for j in 0..p {
            let h = 1e-7 * x[j].abs().max(1.0);
            let mut xh = x.clone();
            xh[j] += h;
            if !residuals(&xh, &mut trial) {
                xh[j] = x[j] - h;
                residuals(&xh, &mut trial);
                for i in 0..m {
                    jac[(i, j)] = (r[i] - trial[i]) / h;
                }
            } else {
                for i in 0..m {
                    jac[(i, j)] = (trial[i] - r[i]) / h;
                }
            }
        }
        let jtj = jac.transpose() * &jac;
        let jtr = jac.transpose() * DVector::from_column_slice(&r);
        let mut improved = false;
        for _ in 0..30 {
            let mut a = jtj.clone();
            for j in 0..p {
                a[(j, j)] += mu * jtj[(j, j)].max(1e-300);
            }
            let Some(step) = a.cholesky().map(|c| c.solve(&(-&jtr))) else {
                mu *= 10.0;
                continue;
            };
            let candidate: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            if residuals(&candidate, &mut trial) {
                let new_cost: f64 = trial.iter().map(|v| v * v).sum();
                if new_cost < cost {
                    let rel_cost = (cost - new_cost) / cost.max(f64::MIN_POSITIVE);
                    let rel_step = step.norm() / (x.iter().map(|v| v * v).sum::<f64>().sqrt() + options.tolerance);
                    x = candidate;
                    r.copy_from_slice(&trial);
                    cost = new_cost;
                    mu = (mu / 3.0).max(1e-12);
                    improved = true;
                    if rel_cost < options.tolerance || rel_step < options.tolerance || cost == 0.0 {
                        return LmResult { x, cost, iterations: iteration, converged: true };
                    }
                    break;
                }
            }
            mu *= 10.0;
        }
        if !improved {
            // no descent direction left: a (local) minimum at working precision
            return LmResult { x, cost, iterations: iteration, converged: true };
        }
    }
    LmResult { x, cost, iterations: options.max_iterations, converged: false }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rosenbrock_minimum_is_found() {
        // r = (10 (y - x^2), 1 - x): minimum 0 at (1, 1)
        let result = levenberg_marquardt(
            |x, r| {
                r[0] = 10.0 * (x[1] - x[0] * x[0]);
                r[1] = 1.0 - x[0];
                true
            },
            &[-1.2, 1.0],
            2,
            &LmOptions::default(),
        );
        assert!(result.converged);
        assert!((result.x[0] - 1.0).abs() < 1e-6 && (result.x[1] - 1.0).abs() < 1e-6, "{:?}", result.x);
    }
}
