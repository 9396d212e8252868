//! The stack-up constraints of an allocation (Zhu 2008 eq. B.7) in the variables of the convex
//! program: one per pose and direction (or per pose for the 3D error), each a row `c` with
//! `c . z <= 1` on the target. Root-sum-square: `z_j = e_j^2` and `c_j = SE_dj^2 / VE_d^2` (3D:
//! `|SE_:j|^2 / VE^2`); worst case: `z_j = e_j` and `c_j = |SE_dj| / VE_d` (3D: the supporting
//! half-space `|u . SE_:j| / VE` at the farthest vertex `u` of the zonotope at z). `SE` are the
//! homogenised gains (um per um/m or per urad), `VE` the targets (um).

use super::super::barrier::ConvexProblem;
use super::super::sensitivity::Sensitivity;
use super::super::spec::BudgetSpec;
use super::super::stackup::worst_case;
use super::{AllocationOptions, Stack, Target};
use crate::error::Error;
use crate::geometry::Vec3;

/// One stack-up constraint: a pose and a direction (`None`: the 3D error).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Key {
    pub pose: usize,
    pub direction: Option<usize>,
}

/// The constraints of the free components (those that move the tool point at some pose).
pub(super) struct Constraints<'a> {
    spec: &'a BudgetSpec,
    s: &'a Sensitivity,
    pub stack: Stack,
    /// The target of each direction (um; the 3D target three times).
    pub targets: [f64; 3],
    /// 2 for the root-sum-square stack-up (`z = e^2`), 1 for the worst case (`z = e`).
    pub power: f64,
    /// The components allocated, in the budget's order.
    pub free: Vec<usize>,
    /// The directions constrained: x, y, z, or the 3D error.
    pub directions: Vec<Option<usize>>,
    /// Every constraint, pose by pose.
    pub keys: Vec<Key>,
}

impl<'a> Constraints<'a> {
    /// The constraints of `options` on the components of `spec` that move the tool point; a
    /// target that is not positive, or no such component, is bad input.
    pub fn new(
        spec: &'a BudgetSpec,
        s: &'a Sensitivity,
        options: &AllocationOptions,
        allocated: &[bool],
    ) -> Result<Constraints<'a>, Error> {
        let targets = match options.target {
            Target::Total(v) => [v; 3],
            Target::PerDirection(v) => v,
        };
        if targets.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(Error::input(format!("target {targets:?} um: a target volumetric error must be positive")));
        }
        let free: Vec<usize> = (0..allocated.len()).filter(|&j| allocated[j]).collect();
        if free.is_empty() {
            return Err(Error::input("no component of the budget moves the tool point at these poses"));
        }
        let power = match options.stack {
            Stack::Rss => 2.0,
            Stack::WorstCase => 1.0,
        };
        let directions: Vec<Option<usize>> = match options.target {
            Target::Total(_) => vec![None],
            Target::PerDirection(_) => vec![Some(0), Some(1), Some(2)],
        };
        let keys: Vec<Key> = (0..s.poses()).flat_map(|pose| directions.iter().map(move |&direction| Key { pose, direction })).collect();
        Ok(Constraints { spec, s, stack: options.stack, targets, power, free, directions, keys })
    }

    /// The number of free components.
    pub fn len(&self) -> usize {
        self.free.len()
    }

    /// The homogenised gain (um per um/m or urad) of free component `j` at pose `p`.
    fn gain(&self, p: usize, j: usize) -> Vec3 {
        self.s.column(p, self.free[j]) * self.spec.components[self.free[j]].scale()
    }

    /// The row of a constraint (for the 3D worst case, the supporting half-space at `z`).
    pub fn row(&self, key: Key, z: &[f64]) -> Vec<f64> {
        let (p, n, targets) = (key.pose, self.len(), self.targets);
        match (self.stack, key.direction) {
            (Stack::Rss, Some(d)) => (0..n).map(|j| self.gain(p, j)[d].powi(2) / targets[d].powi(2)).collect(),
            (Stack::Rss, None) => (0..n).map(|j| self.gain(p, j).norm_squared() / targets[0].powi(2)).collect(),
            (Stack::WorstCase, Some(d)) => (0..n).map(|j| self.gain(p, j)[d].abs() / targets[d]).collect(),
            (Stack::WorstCase, None) => {
                // the supporting half-space at the farthest vertex of the zonotope at z
                let generators: Vec<Vec3> = (0..n).map(|j| self.gain(p, j) * z[j]).collect();
                let (_, signs) = worst_case(&generators);
                let vertex: Vec3 = generators.iter().zip(&signs).map(|(g, s)| g * *s).sum();
                let u = if vertex.norm() > 0.0 { vertex.normalize() } else { Vec3::x() };
                (0..n).map(|j| u.dot(&self.gain(p, j)).abs() / targets[0]).collect()
            }
        }
    }

    /// The value of a constraint at `z` (1 = on the target).
    pub fn value(&self, key: Key, z: &[f64]) -> f64 {
        match (self.stack, key.direction) {
            (Stack::WorstCase, None) => {
                let generators: Vec<Vec3> = (0..self.len()).map(|j| self.gain(key.pose, j) * z[j]).collect();
                worst_case(&generators).0 / self.targets[0]
            }
            _ => self.row(key, z).iter().zip(z).map(|(c, z)| c * z).sum(),
        }
    }

    /// The lower limits of the free components in the program's variables.
    pub fn lower(&self) -> Vec<f64> {
        let spec = self.spec;
        self.free.iter().map(|&j| (spec.cost.terms[j].lower / spec.components[j].scale()).powf(self.power)).collect()
    }

    /// Refuses lower limits that alone reach the target at some pose (a failed computation).
    pub fn check_lower(&self, lower: &[f64]) -> Result<(), Error> {
        for &key in &self.keys {
            let v = self.value(key, lower);
            if v >= 1.0 {
                let target = self.targets[key.direction.unwrap_or(0)];
                return Err(Error::computation(format!(
                    "the lower limits alone give {:.4} um {} at pose {}, not less than the target {target} um: raise the target or lower the limits",
                    v.powf(1.0 / self.power) * target,
                    direction_text(key.direction),
                    key.pose + 1
                )));
            }
        }
        Ok(())
    }

    /// The program with the most demanding constraint of each direction at the upper corner, and
    /// the constraint of each of its rows.
    pub fn starting_problem(&self, lower: &[f64]) -> (ConvexProblem, Vec<Key>) {
        let terms: Vec<_> = self.free.iter().map(|&j| self.spec.cost.terms[j]).collect();
        let mut problem = ConvexProblem {
            a: terms.iter().map(|t| t.a).collect(),
            beta: terms.iter().map(|t| t.k / self.power).collect(),
            lower: lower.to_vec(),
            rows: Vec::new(),
        };
        let probe: Vec<f64> = vec![1.0; self.len()];
        let mut row_keys: Vec<Key> = Vec::new();
        for &d in &self.directions {
            let best = self
                .keys
                .iter()
                .filter(|k| k.direction == d)
                .max_by(|a, b| self.value(**a, &probe).total_cmp(&self.value(**b, &probe)))
                .copied()
                .expect("poses exist");
            row_keys.push(best);
            problem.rows.push(self.row(best, &probe));
        }
        (problem, row_keys)
    }

    /// The largest stack-up over the poses at `z`, in the sense of the target (um; the 3D value
    /// three times for a 3D target).
    pub fn achieved(&self, z: &[f64], total: bool) -> [f64; 3] {
        let mut achieved = [0.0; 3];
        for &key in &self.keys {
            let d = key.direction.unwrap_or(0);
            achieved[d] = f64::max(achieved[d], self.value(key, z).powf(1.0 / self.power) * self.targets[d]);
        }
        if total {
            achieved = [achieved[0]; 3];
        }
        achieved
    }
}

fn direction_text(d: Option<usize>) -> &'static str {
    match d {
        Some(0) => "along x",
        Some(1) => "along y",
        Some(2) => "along z",
        _ => "(3D)",
    }
}
