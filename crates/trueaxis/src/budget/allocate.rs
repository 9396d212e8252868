//! Cost-optimal tolerance allocation (Zhu 2008 eqs. B.5-B.8): the tolerances of the components that
//! minimise `sum_j A_j / e_j^k_j` (homogenised tolerances `e_j`) subject to the stack-up staying
//! within the target at every pose, and `e_j >= e_j^l`.
//!
//! Structure: with the root-sum-square stack-up the constraints are linear in the squared
//! tolerances `z_j = e_j^2` (`sum_j SE_ij^2 z_j <= VE_R^2`), with the worst case linear in `z_j = e_j`
//! (per direction), or an intersection of such half-spaces (the 3D length: one per direction `u`,
//! `sum_j |u . SE_:j| z_j <= VE_R`), and the cost `A z^(-k/2)` or `A z^(-k)` is convex: a convex
//! program, whose local optimum is the global one. So the two stages of the appendix are kept (a
//! seeded genetic global stage, [`super::global`], then an interior-point local stage,
//! [`super::barrier`], from its best point), and the result is checked by the KKT conditions solved
//! afresh at the optimum. The constraints of all poses are handled by cutting planes: solve with the
//! binding ones, add those still violated, repeat. The steps: the constraints (`allocate/constraints.rs`), the
//! local stage (`allocate/cutting_planes.rs`) and the optimality check (`allocate/kkt.rs`).

mod constraints;
mod cutting_planes;
mod kkt;

use super::barrier::ConvexProblem;
use super::global::{genetic, GeneticOptions};
use super::sensitivity::Sensitivity;
use super::spec::BudgetSpec;
use crate::error::Error;
use constraints::Constraints;
use cutting_planes::cutting_planes;
use kkt::kkt_check;

/// The stack-up the target applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stack {
    Rss,
    WorstCase,
}

/// The target volumetric error (um): of the 3D error, or one per direction x, y, z (eq. B.7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    Total(f64),
    PerDirection([f64; 3]),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AllocationOptions {
    pub stack: Stack,
    pub target: Target,
    pub genetic: GeneticOptions,
}

/// A constraint binding at the optimum.
#[derive(Clone, Debug, PartialEq)]
pub struct ActiveConstraint {
    pub pose: usize,
    /// 0, 1, 2 for x, y, z; `None` for the 3D error.
    pub direction: Option<usize>,
    /// Lagrange multiplier of the normalised constraint (cost units), from the KKT solve.
    pub multiplier: f64,
    /// Change of the optimal cost per um of relaxed target: `-multiplier * p / target`.
    pub marginal_cost_per_um: f64,
}

/// The optimal allocation and its checks.
#[derive(Clone, Debug)]
pub struct Allocation {
    /// Tolerances (um, urad) in the component order of the budget; components with no effect keep
    /// their tolerance of the budget.
    pub tolerances: Vec<f64>,
    /// Whether each component was allocated (false: it moves the tool point at no pose).
    pub allocated: Vec<bool>,
    pub cost: f64,
    /// Cost of the global stage's best point made feasible (never below `cost`).
    pub global_cost: f64,
    /// Largest stack-up over the poses, in the sense of the target (um; per direction if so).
    pub achieved: [f64; 3],
    /// `|grad f + C_A^T lambda - nu_B| / |grad f|` at the optimum, with the multipliers solved by least
    /// squares on the binding constraints and lower limits.
    pub kkt_residual: f64,
    /// Smallest multiplier of the KKT solve (non-negative at a true optimum).
    pub smallest_multiplier: f64,
    pub active: Vec<ActiveConstraint>,
    /// Components held at their lower limit.
    pub at_lower: Vec<usize>,
    pub duality_gap: f64,
    pub newton_steps: usize,
    pub cutting_rounds: usize,
}

/// Allocates tolerances to `spec`'s components for the sensitivity `s` (poses of the budget):
/// the constraints of the components that move the tool point, the genetic global stage on the
/// most demanding ones, the local stage with cutting planes, the KKT check.
pub fn allocate(spec: &BudgetSpec, s: &Sensitivity, options: &AllocationOptions) -> Result<Allocation, Error> {
    let poses = s.poses();
    let allocated: Vec<bool> = (0..spec.components.len()).map(|j| (0..poses).any(|p| s.column(p, j).norm() > 1e-12)).collect();
    let c = Constraints::new(spec, s, options, &allocated)?;
    let lower = c.lower();
    c.check_lower(&lower)?;
    let (mut problem, mut row_keys) = c.starting_problem(&lower);
    let (global_z, _) = genetic(&problem, &upper_bounds(&problem, &lower), &options.genetic);
    let total = matches!(options.target, Target::Total(_));
    let local = cutting_planes(&c, &mut problem, &mut row_keys, global_z, total)?;
    let z = local.z;
    let cost = problem.objective(&z);
    let kkt = kkt_check(&c, &problem, &row_keys, &z, &lower)?;
    let mut tolerances = spec.tolerances.clone();
    for (i, &j) in c.free.iter().enumerate() {
        tolerances[j] = z[i].powf(1.0 / c.power) * spec.components[j].scale();
    }
    Ok(Allocation {
        tolerances,
        allocated,
        cost,
        global_cost: local.global_cost.unwrap_or(cost).max(cost),
        achieved: c.achieved(&z, total),
        kkt_residual: kkt.kkt_residual,
        smallest_multiplier: kkt.smallest_multiplier,
        active: kkt.active,
        at_lower: kkt.at_lower.iter().map(|&i| c.free[i]).collect(),
        duality_gap: local.duality_gap,
        newton_steps: local.newton_steps,
        cutting_rounds: local.rounds,
    })
}

/// The box of the global stage: each variable up to its value alone on the starting constraints
/// (a million times its lower limit, at least 1, where no constraint bounds it).
fn upper_bounds(problem: &ConvexProblem, lower: &[f64]) -> Vec<f64> {
    (0..lower.len())
        .map(|j| {
            let limit = problem.rows.iter().filter(|c| c[j] > 0.0).map(|c| 1.0 / c[j]).fold(f64::INFINITY, f64::min);
            if limit.is_finite() {
                limit
            } else {
                lower[j].max(1.0) * 1e6
            }
        })
        .collect()
}
