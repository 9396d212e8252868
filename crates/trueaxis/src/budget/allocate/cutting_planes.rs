//! The local stage of an allocation (Zhu 2008 eq. B.8 solved as a convex program): from the
//! global stage's best point, the interior-point method ([`super::super::barrier`]) on the
//! constraints known so far, then the constraints still violated at its optimum (up to 20, the
//! most violated first) added as cutting planes, until none is violated (at most 200 rounds). A
//! 3D worst-case constraint is refreshed at each new point even for a pose already known, its
//! supporting half-space having moved.

use super::super::barrier::{solve, ConvexProblem};
use super::constraints::{Constraints, Key};
use super::Stack;
use crate::error::Error;

/// Most rounds of the cutting-plane loop.
const MAX_ROUNDS: usize = 200;
/// Most constraints added in one round.
const CUTS_PER_ROUND: usize = 20;

/// The optimum of the local stage and what it took.
pub(super) struct LocalStage {
    pub z: Vec<f64>,
    /// Cost of the global stage's best point made strictly feasible.
    pub global_cost: Option<f64>,
    pub rounds: usize,
    pub newton_steps: usize,
    pub duality_gap: f64,
}

/// Solves `problem` from `z` (the global stage's best point), adding the violated constraints of
/// `c` as rows (and their keys to `row_keys`) until every constraint holds.
pub(super) fn cutting_planes(
    c: &Constraints<'_>,
    problem: &mut ConvexProblem,
    row_keys: &mut Vec<Key>,
    mut z: Vec<f64>,
    total: bool,
) -> Result<LocalStage, Error> {
    let mut working: Vec<Key> = row_keys.clone();
    let mut global_cost = None;
    let mut rounds = 0;
    let mut newton_steps = 0;
    loop {
        rounds += 1;
        let start = problem.interior(&z).ok_or_else(|| Error::computation("no strictly feasible start for the local stage"))?;
        if global_cost.is_none() {
            global_cost = Some(problem.objective(&start));
        }
        let result = solve(problem, &start, 1e-11)?;
        z = result.z;
        newton_steps += result.newton_steps;
        let duality_gap = result.duality_gap;
        let refresh = c.stack == Stack::WorstCase && total;
        let mut violated: Vec<(f64, Key)> =
            c.keys.iter().map(|&k| (c.value(k, &z), k)).filter(|(v, k)| *v > 1.0 + 1e-9 && (refresh || !working.contains(k))).collect();
        if violated.is_empty() {
            return Ok(LocalStage { z, global_cost, rounds, newton_steps, duality_gap });
        }
        if rounds > MAX_ROUNDS {
            return Err(Error::computation("the cutting-plane loop of the allocation did not converge in 200 rounds"));
        }
        violated.sort_by(|a, b| b.0.total_cmp(&a.0));
        for &(_, key) in violated.iter().take(CUTS_PER_ROUND) {
            if !working.contains(&key) {
                working.push(key);
            }
            row_keys.push(key);
            problem.rows.push(c.row(key, &z));
        }
    }
}
