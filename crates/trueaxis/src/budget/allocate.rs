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
//! binding ones, add those still violated, repeat.

use super::barrier::{solve, ConvexProblem};
use super::global::{genetic, GeneticOptions};
use super::sensitivity::Sensitivity;
use super::spec::BudgetSpec;
use super::stackup::worst_case;
use crate::error::Error;
use crate::geometry::Vec3;
use nalgebra::{DMatrix, DVector};

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

/// One stack-up constraint: a pose and a direction (`None`: the 3D error).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Key {
    pose: usize,
    direction: Option<usize>,
}

/// Allocates tolerances to `spec`'s components for the sensitivity `s` (poses of the budget).
pub fn allocate(spec: &BudgetSpec, s: &Sensitivity, options: &AllocationOptions) -> Result<Allocation, Error> {
    let targets = match options.target {
        Target::Total(v) => [v; 3],
        Target::PerDirection(v) => v,
    };
    if targets.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return Err(Error::input(format!("target {targets:?} um: a target volumetric error must be positive")));
    }
    let n_all = spec.components.len();
    let poses = s.poses();
    let allocated: Vec<bool> = (0..n_all).map(|j| (0..poses).any(|p| s.column(p, j).norm() > 1e-12)).collect();
    let free: Vec<usize> = (0..n_all).filter(|&j| allocated[j]).collect();
    if free.is_empty() {
        return Err(Error::input("no component of the budget moves the tool point at these poses"));
    }
    let n = free.len();
    // homogenised gains (um per um/m or urad) of the free components, per pose
    let gain = |p: usize, j: usize| -> Vec3 { s.column(p, free[j]) * spec.components[free[j]].scale() };
    let power = match options.stack {
        Stack::Rss => 2.0,
        Stack::WorstCase => 1.0,
    };
    let row_of = |key: Key, z: &[f64]| -> Vec<f64> {
        let p = key.pose;
        match (options.stack, key.direction) {
            (Stack::Rss, Some(d)) => (0..n).map(|j| gain(p, j)[d].powi(2) / targets[d].powi(2)).collect(),
            (Stack::Rss, None) => (0..n).map(|j| gain(p, j).norm_squared() / targets[0].powi(2)).collect(),
            (Stack::WorstCase, Some(d)) => (0..n).map(|j| gain(p, j)[d].abs() / targets[d]).collect(),
            (Stack::WorstCase, None) => {
                // the supporting half-space at the farthest vertex of the zonotope at z
                let generators: Vec<Vec3> = (0..n).map(|j| gain(p, j) * z[j]).collect();
                let (_, signs) = worst_case(&generators);
                let vertex: Vec3 = generators.iter().zip(&signs).map(|(g, s)| g * *s).sum();
                let u = if vertex.norm() > 0.0 { vertex.normalize() } else { Vec3::x() };
                (0..n).map(|j| u.dot(&gain(p, j)).abs() / targets[0]).collect()
            }
        }
    };
    // value of a constraint (1 = on the target) at z
    let value_of = |key: Key, z: &[f64]| -> f64 {
        match (options.stack, key.direction) {
            (Stack::WorstCase, None) => {
                let generators: Vec<Vec3> = (0..n).map(|j| gain(key.pose, j) * z[j]).collect();
                worst_case(&generators).0 / targets[0]
            }
            _ => row_of(key, z).iter().zip(z).map(|(c, z)| c * z).sum(),
        }
    };
    let directions: Vec<Option<usize>> = match options.target {
        Target::Total(_) => vec![None],
        Target::PerDirection(_) => vec![Some(0), Some(1), Some(2)],
    };
    let keys: Vec<Key> = (0..poses).flat_map(|pose| directions.iter().map(move |&direction| Key { pose, direction })).collect();

    let terms: Vec<_> = free.iter().map(|&j| spec.cost.terms[j]).collect();
    let lower: Vec<f64> = free.iter().map(|&j| (spec.cost.terms[j].lower / spec.components[j].scale()).powf(power)).collect();
    for &key in &keys {
        let v = value_of(key, &lower);
        if v >= 1.0 {
            let target = targets[key.direction.unwrap_or(0)];
            return Err(Error::computation(format!(
                "the lower limits alone give {:.4} um {} at pose {}, not less than the target {target} um: raise the target or lower the limits",
                v.powf(1.0 / power) * target,
                direction_text(key.direction),
                key.pose + 1
            )));
        }
    }
    let mut problem = ConvexProblem {
        a: terms.iter().map(|t| t.a).collect(),
        beta: terms.iter().map(|t| t.k / power).collect(),
        lower: lower.clone(),
        rows: Vec::new(),
    };
    // start with the most demanding constraint of each direction at the upper corner
    let probe: Vec<f64> = vec![1.0; n];
    let mut working: Vec<Key> = Vec::new();
    // the constraint of each row of `problem`
    let mut row_keys: Vec<Key> = Vec::new();
    for &d in &directions {
        let best = keys
            .iter()
            .filter(|k| k.direction == d)
            .max_by(|a, b| value_of(**a, &probe).total_cmp(&value_of(**b, &probe)))
            .copied()
            .expect("poses exist");
        working.push(best);
        row_keys.push(best);
        problem.rows.push(row_of(best, &probe));
    }
    // the global stage on the starting constraints; each z_j searched up to its value alone on them
    let upper: Vec<f64> = (0..n)
        .map(|j| {
            let limit = problem.rows.iter().filter(|c| c[j] > 0.0).map(|c| 1.0 / c[j]).fold(f64::INFINITY, f64::min);
            if limit.is_finite() {
                limit
            } else {
                lower[j].max(1.0) * 1e6
            }
        })
        .collect();
    let (global_z, _) = genetic(&problem, &upper, &options.genetic);
    let mut z = global_z.clone();
    let mut global_cost = None;
    let mut rounds = 0;
    let mut steps = 0;
    let mut gap;
    loop {
        rounds += 1;
        let start = problem.interior(&z).ok_or_else(|| Error::computation("no strictly feasible start for the local stage"))?;
        if global_cost.is_none() {
            global_cost = Some(problem.objective(&start));
        }
        let result = solve(&problem, &start, 1e-11)?;
        z = result.z;
        steps += result.newton_steps;
        gap = result.duality_gap;
        let mut violated: Vec<(f64, Key)> =
            keys.iter().map(|&k| (value_of(k, &z), k)).filter(|(v, k)| *v > 1.0 + 1e-9 && !working.contains(k)).collect();
        // a cutting plane of the 3D worst case is refreshed at the new point even for a known pose
        if options.stack == Stack::WorstCase && options.target == Target::Total(targets[0]) {
            violated = keys.iter().map(|&k| (value_of(k, &z), k)).filter(|(v, _)| *v > 1.0 + 1e-9).collect();
        }
        if violated.is_empty() {
            break;
        }
        if rounds > 200 {
            return Err(Error::computation("the cutting-plane loop of the allocation did not converge in 200 rounds"));
        }
        violated.sort_by(|a, b| b.0.total_cmp(&a.0));
        for &(_, key) in violated.iter().take(20) {
            if !working.contains(&key) {
                working.push(key);
            }
            row_keys.push(key);
            problem.rows.push(row_of(key, &z));
        }
    }
    let cost = problem.objective(&z);

    // KKT conditions solved afresh: constraints within 1e-6 of their bound are active
    let grad = problem.gradient(&z);
    let active_rows: Vec<usize> = (0..problem.rows.len()).filter(|&r| dot(&problem.rows[r], &z) >= 1.0 - 1e-6).collect();
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
    let rhs = -DVector::from_vec(grad.clone());
    let multipliers = if unknowns > 0 {
        m.clone().svd(true, true).solve(&rhs, 1e-12).map_err(|e| Error::computation(format!("KKT solve: {e}")))?
    } else {
        DVector::zeros(0)
    };
    let residual = if unknowns > 0 { (&m * &multipliers - &rhs).norm() } else { rhs.norm() };
    let kkt_residual = residual / rhs.norm().max(f64::MIN_POSITIVE);
    let smallest_multiplier = multipliers.iter().copied().fold(f64::INFINITY, f64::min);
    let mut active: Vec<ActiveConstraint> = Vec::new();
    for (col, &r) in active_rows.iter().enumerate() {
        let key = row_keys[r];
        let target = targets[key.direction.unwrap_or(0)];
        let multiplier = multipliers[col];
        match active.iter_mut().find(|a| a.pose == key.pose && a.direction == key.direction) {
            Some(a) => {
                a.multiplier += multiplier;
                a.marginal_cost_per_um -= multiplier * power / target;
            }
            None => active.push(ActiveConstraint {
                pose: key.pose,
                direction: key.direction,
                multiplier,
                marginal_cost_per_um: -multiplier * power / target,
            }),
        }
    }
    active.sort_by(|a, b| b.multiplier.total_cmp(&a.multiplier));

    let mut tolerances = spec.tolerances.clone();
    for (i, &j) in free.iter().enumerate() {
        tolerances[j] = z[i].powf(1.0 / power) * spec.components[j].scale();
    }
    let mut achieved = [0.0; 3];
    for &key in &keys {
        let d = key.direction.unwrap_or(0);
        achieved[d] = f64::max(achieved[d], value_of(key, &z).powf(1.0 / power) * targets[d]);
    }
    if key_is_total(options.target) {
        achieved = [achieved[0]; 3];
    }
    Ok(Allocation {
        tolerances,
        allocated,
        cost,
        global_cost: global_cost.unwrap_or(cost).max(cost),
        achieved,
        kkt_residual,
        smallest_multiplier,
        active,
        at_lower: at_lower.iter().map(|&i| free[i]).collect(),
        duality_gap: gap,
        newton_steps: steps,
        cutting_rounds: rounds,
    })
}

fn key_is_total(target: Target) -> bool {
    matches!(target, Target::Total(_))
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn direction_text(d: Option<usize>) -> &'static str {
    match d {
        Some(0) => "along x",
        Some(1) => "along y",
        Some(2) => "along z",
        _ => "(3D)",
    }
}
