//! The check of an allocation's optimum by the Karush-Kuhn-Tucker conditions solved afresh:
//! `grad f + C_A^T lambda - nu_B = 0` with `C_A` the constraints within 1e-6 of their bound and `B`
//! the components within 1e-6 (relative) of their lower limit, the multipliers `lambda, nu` by
//! least squares (SVD); the relative residual `|grad f + C_A^T lambda - nu_B| / |grad f|` and the
//! smallest multiplier (non-negative at a true optimum). Each binding constraint's multiplier
//! gives the change of the optimal cost per um of relaxed target, `-lambda p / VE` (p the power
//! of the variables, VE the target in um).

use super::super::barrier::ConvexProblem;
use super::constraints::{Constraints, Key};
use super::ActiveConstraint;
use crate::error::Error;
use nalgebra::{DMatrix, DVector};

/// What the KKT solve finds at the optimum.
pub(super) struct KktCheck {
    pub kkt_residual: f64,
    pub smallest_multiplier: f64,
    /// The binding constraints, one per pose and direction, the largest multiplier first.
    pub active: Vec<ActiveConstraint>,
    /// The free components (indices among them) held at their lower limit.
    pub at_lower: Vec<usize>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The KKT conditions of `problem` at `z` (`row_keys[r]` the constraint of row r).
pub(super) fn kkt_check(
    c: &Constraints<'_>,
    problem: &ConvexProblem,
    row_keys: &[Key],
    z: &[f64],
    lower: &[f64],
) -> Result<KktCheck, Error> {
    let n = c.len();
    let grad = problem.gradient(z);
    let active_rows: Vec<usize> = (0..problem.rows.len()).filter(|&r| dot(&problem.rows[r], z) >= 1.0 - 1e-6).collect();
    let at_lower: Vec<usize> = (0..n).filter(|&j| z[j] - lower[j] <= 1e-6 * z[j]).collect();
    let unknowns = active_rows.len() + at_lower.len();
    let mut m = DMatrix::zeros(n, unknowns);
    for (col, &r) in active_rows.iter().enumerate() {
        for j in 0..n {
            m[(j, col)] = problem.rows[r][j];
        }
    }
    for (col, &j) in at_lower.iter().enumerate() {
        m[(j, active_rows.len() + col)] = -1.0;
    }
    let rhs = -DVector::from_vec(grad);
    let multipliers = if unknowns > 0 {
        m.clone().svd(true, true).solve(&rhs, 1e-12).map_err(|e| Error::computation(format!("KKT solve: {e}")))?
    } else {
        DVector::zeros(0)
    };
    let residual = if unknowns > 0 { (&m * &multipliers - &rhs).norm() } else { rhs.norm() };
    let kkt_residual = residual / rhs.norm().max(f64::MIN_POSITIVE);
    let smallest_multiplier = multipliers.iter().copied().fold(f64::INFINITY, f64::min);
    let active = active_constraints(c, &active_rows, row_keys, multipliers.as_slice());
    Ok(KktCheck { kkt_residual, smallest_multiplier, active, at_lower })
}

/// The binding constraints with their multipliers, rows of one pose and direction summed, the
/// largest multiplier first.
fn active_constraints(c: &Constraints<'_>, active_rows: &[usize], row_keys: &[Key], multipliers: &[f64]) -> Vec<ActiveConstraint> {
    let mut active: Vec<ActiveConstraint> = Vec::new();
    for (col, &r) in active_rows.iter().enumerate() {
        let key = row_keys[r];
        let target = c.targets[key.direction.unwrap_or(0)];
        let multiplier = multipliers[col];
        match active.iter_mut().find(|a| a.pose == key.pose && a.direction == key.direction) {
            Some(a) => {
                a.multiplier += multiplier;
                a.marginal_cost_per_um -= multiplier * c.power / target;
            }
            None => active.push(ActiveConstraint {
                pose: key.pose,
                direction: key.direction,
                multiplier,
                marginal_cost_per_um: -multiplier * c.power / target,
            }),
        }
    }
    active.sort_by(|a, b| b.multiplier.total_cmp(&a.multiplier));
    active
}
