//! The local stage of the allocation: a primal log-barrier interior-point method (Newton steps on
//! the barrier function, backtracking line search, barrier parameter raised tenfold per round;
//! Boyd & Vandenberghe, Convex Optimization, section 11.3) for
//!
//! ```text
//! minimise  sum_j a_j z_j^(-beta_j)   subject to  c_r . z <= 1 (r = 1..m),  z_j >= l_j >= 0
//! ```
//!
//! Every `z^(-beta)` with `beta > 0` is convex and the constraints are linear, so the problem is
//! convex and the point it converges to is the global optimum; the duality gap `(m + n) / t` bounds
//! how far its cost is from the optimum.

use crate::error::Error;
use nalgebra::{DMatrix, DVector};

/// The convex allocation problem in the variables `z` (squared or plain homogenised tolerances).
#[derive(Clone, Debug)]
pub struct ConvexProblem {
    pub a: Vec<f64>,
    pub beta: Vec<f64>,
    pub lower: Vec<f64>,
    /// Constraint rows, each `c . z <= 1`.
    pub rows: Vec<Vec<f64>>,
}

impl ConvexProblem {
    pub fn objective(&self, z: &[f64]) -> f64 {
        self.a.iter().zip(&self.beta).zip(z).map(|((a, b), z)| a * z.powf(-b)).sum()
    }

    /// Gradient of the objective.
    pub fn gradient(&self, z: &[f64]) -> Vec<f64> {
        self.a.iter().zip(&self.beta).zip(z).map(|((a, b), z)| -b * a * z.powf(-b - 1.0)).collect()
    }

    /// The largest `c_r . z` over the rows (1 at the boundary).
    pub fn largest_row(&self, z: &[f64]) -> f64 {
        self.rows.iter().map(|c| dot(c, z)).fold(f64::NEG_INFINITY, f64::max)
    }

    /// A strictly feasible point on the segment from the lower limits to `z`: `l + tau (z - l)` with
    /// the largest `tau <= 1` that keeps every row at most halfway between its value at `l` and 1.
    /// `None` if the lower limits themselves reach a row.
    pub fn interior(&self, z: &[f64]) -> Option<Vec<f64>> {
        let mut tau: f64 = 1.0;
        for c in &self.rows {
            let at_lower = dot(c, &self.lower);
            if at_lower >= 1.0 {
                return None;
            }
            let rise: f64 = c.iter().zip(z).zip(&self.lower).map(|((c, z), l)| c * (z - l)).sum();
            let room = 0.5 * (1.0 - at_lower);
            if rise > room {
                tau = tau.min(room / rise);
            }
        }
        let point: Vec<f64> = z.iter().zip(&self.lower).map(|(z, l)| l + tau * (z - l)).collect();
        point.iter().zip(&self.lower).all(|(p, l)| p > l).then_some(point)
    }
}

/// The converged point of the barrier method.
#[derive(Clone, Debug)]
pub struct BarrierResult {
    pub z: Vec<f64>,
    pub objective: f64,
    pub newton_steps: usize,
    /// Bound on the objective's distance from the optimum, `(m + n) / t`, in objective units.
    pub duality_gap: f64,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves `problem` from a strictly feasible `start`; stops when the duality gap is below
/// `relative_gap` times the objective.
pub fn solve(problem: &ConvexProblem, start: &[f64], relative_gap: f64) -> Result<BarrierResult, Error> {
    let n = start.len();
    let m = problem.rows.len();
    let slack = |z: &[f64]| -> Option<(Vec<f64>, Vec<f64>)> {
        let s: Vec<f64> = problem.rows.iter().map(|c| 1.0 - dot(c, z)).collect();
        let d: Vec<f64> = z.iter().zip(&problem.lower).map(|(z, l)| z - l).collect();
        (s.iter().all(|v| *v > 0.0) && d.iter().all(|v| *v > 0.0)).then_some((s, d))
    };
    let barrier = |z: &[f64], t: f64| -> Option<f64> {
        let (s, d) = slack(z)?;
        Some(t * problem.objective(z) - s.iter().map(|v| v.ln()).sum::<f64>() - d.iter().map(|v| v.ln()).sum::<f64>())
    };
    let mut z = start.to_vec();
    if slack(&z).is_none() {
        return Err(Error::computation("the start of the interior-point method is not strictly feasible"));
    }
    let f0 = problem.objective(&z).max(f64::MIN_POSITIVE);
    let mut t = (m + n) as f64 / f0;
    let mut steps = 0;
    loop {
        for _ in 0..200 {
            let (s, d) = slack(&z).expect("the line search keeps the point interior");
            let grad_f = problem.gradient(&z);
            let mut g = DVector::from_fn(n, |j, _| t * grad_f[j] - 1.0 / d[j]);
            let mut h = DMatrix::from_fn(n, n, |i, j| {
                if i == j {
                    let (a, b) = (problem.a[j], problem.beta[j]);
                    t * b * (b + 1.0) * a * z[j].powf(-b - 2.0) + 1.0 / (d[j] * d[j])
                } else {
                    0.0
                }
            });
            for (c, s) in problem.rows.iter().zip(&s) {
                let cv = DVector::from_column_slice(c);
                g += &cv / *s;
                h.syger(1.0 / (s * s), &cv, &cv, 1.0);
            }
            let Some(chol) = h.clone().cholesky() else {
                return Err(Error::computation("the Newton system of the interior-point method is not positive definite"));
            };
            let delta = -chol.solve(&g);
            let decrement = -g.dot(&delta);
            steps += 1;
            if decrement / 2.0 <= 1e-12 {
                break;
            }
            let phi = barrier(&z, t).expect("interior");
            let mut alpha = 1.0;
            let mut accepted = false;
            for _ in 0..80 {
                let trial: Vec<f64> = z.iter().zip(delta.iter()).map(|(z, d)| z + alpha * d).collect();
                if let Some(value) = barrier(&trial, t) {
                    if value <= phi - 0.25 * alpha * decrement {
                        z = trial;
                        accepted = true;
                        break;
                    }
                }
                alpha *= 0.5;
            }
            if !accepted {
                break; // no further decrease representable: centred to machine precision
            }
        }
        let objective = problem.objective(&z);
        let gap = (m + n) as f64 / t;
        if gap <= relative_gap * objective {
            return Ok(BarrierResult { z, objective, newton_steps: steps, duality_gap: gap });
        }
        if steps > 5000 {
            return Err(Error::computation(format!(
                "the interior-point method did not converge (duality gap {gap:.3e} after {steps} Newton steps)"
            )));
        }
        t *= 10.0;
    }
}
