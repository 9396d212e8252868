//! A budget problem as `trueaxis budget analyse` and `allocate` (and the Python package) state it:
//! a machine, the budget (components, tolerances in um and urad, costs), the tool and workpiece
//! points (mm), the frame of the volumetric error, and one or more pose sets (a pose file, parts of
//! a given size in mm, or a grid over the travel), with the rotary axes at given positions (deg).
//! Each set holds its poses in user units (mm, deg) and internal units (mm, rad). The forward
//! analysis and the allocation of Zhu (2008) appendix B run on it; [`super::documents`] writes it.

use super::allocate::{allocate, Allocation, AllocationOptions};
use super::poses::{part_grid, to_internal, volume_grid};
use super::sensitivity::{sensitivity, Sensitivity};
use super::spec::{BudgetSpec, KindValues};
use super::{analyse, Analysis};
use crate::error::Error;
use crate::machine::{AxisKind, Machine};
use crate::model::{Frame, Setup};
use crate::poses::read_poses;
use std::path::Path;

/// Where the poses of a budget come from.
#[derive(Clone, Debug)]
pub enum PoseSource<'a> {
    /// A pose CSV, one column per axis (mm, deg).
    File(&'a Path),
    /// The tool point on a grid of `nodes` points per edge over each part (x, y, z in mm).
    Parts { sizes: &'a [[f64; 3]], nodes: usize },
    /// A grid of `nodes` points per linear axis over the travel.
    Grid(usize),
    /// Poses given in user units (mm, deg; `machine.axis_count()` per pose), named `label`.
    Given { label: &'a str, user: &'a [f64] },
}

/// One pose set: a label (the part size or the source), the part size, poses in user and internal
/// units (`machine.axis_count()` values per pose).
#[derive(Clone, Debug)]
pub struct PoseSet {
    pub label: String,
    pub part: Option<[f64; 3]>,
    pub user: Vec<f64>,
    pub internal: Vec<f64>,
}

/// A machine, its budget, the points, the frame and the pose sets.
#[derive(Clone, Debug)]
pub struct BudgetProblem {
    pub machine: Machine,
    pub spec: BudgetSpec,
    pub setup: Setup,
    pub frame: Frame,
    pub sets: Vec<PoseSet>,
}

/// The budget of a machine: the budget file if given (its defaults `defaults`), else the standard
/// components with the tolerances `defaults` (linear um, angular urad, squareness urad).
pub fn budget_spec(machine: &Machine, budget: Option<&Path>, defaults: KindValues) -> Result<BudgetSpec, Error> {
    let names = ["--linear-um", "--angular-urad", "--squareness-urad"];
    for (name, v) in names.iter().zip(defaults.0) {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::input(format!("{name} {v}: a tolerance must be a positive number")));
        }
    }
    match budget {
        Some(path) => BudgetSpec::load(path, machine, defaults),
        None => Ok(BudgetSpec::standard(machine, defaults)),
    }
}

/// The positions (deg) of the machine's rotary axes in canonical order from `(letter, deg)` pairs;
/// an axis not named is at 0, a letter that is not a rotary axis of the machine is an error.
pub fn rotary_positions(machine: &Machine, given: &[(char, f64)]) -> Result<Vec<f64>, Error> {
    for (c, v) in given {
        if !machine.axes().iter().any(|a| a.letter == *c && a.kind == AxisKind::Rotary) {
            return Err(Error::input(format!(
                "--rotary {c}=...: machine `{}` has no rotary axis {c} (axes: {})",
                machine.name,
                machine.axis_letters()
            )));
        }
        if !v.is_finite() {
            return Err(Error::input(format!("--rotary {c}={v}: a position must be a finite number of deg")));
        }
    }
    let rotary = machine.axes().iter().filter(|a| a.kind == AxisKind::Rotary);
    Ok(rotary.map(|axis| given.iter().find(|(c, _)| *c == axis.letter).map_or(0.0, |r| r.1)).collect())
}

/// The pose sets of `source`, the rotary axes at `rotary` (deg, canonical order) for parts and
/// grids; every pose of a file within the travel.
pub fn pose_sets(machine: &Machine, setup: &Setup, source: &PoseSource<'_>, rotary: &[f64]) -> Result<Vec<PoseSet>, Error> {
    let set = |label: String, part: Option<[f64; 3]>, user: Vec<f64>| PoseSet { label, part, internal: to_internal(machine, &user), user };
    match source {
        PoseSource::File(path) => {
            let table = read_poses(path, machine)?;
            if table.is_empty() {
                return Err(Error::input(format!("{}: no poses", path.display())));
            }
            for (i, pose) in table.user.chunks(machine.axis_count()).enumerate() {
                machine.check_range(pose).map_err(|e| e.in_file(path.display().to_string()).at_line(table.lines[i] as usize))?;
            }
            Ok(vec![set(path.display().to_string(), None, table.user)])
        }
        PoseSource::Parts { sizes, nodes } => {
            if *nodes < 2 {
                return Err(Error::input(format!("--part-nodes {nodes}: at least 2 points per edge")));
            }
            let label = |s: &[f64; 3]| format!("{}x{}x{}", s[0], s[1], s[2]);
            sizes.iter().map(|s| Ok(set(label(s), Some(*s), part_grid(machine, setup, *s, *nodes, rotary)?))).collect()
        }
        PoseSource::Given { label, user } => {
            let n = machine.axis_count();
            if user.is_empty() || user.len() % n != 0 {
                return Err(Error::input(format!(
                    "{label}: expected poses of {n} axis positions ({}), got {} values",
                    machine.axis_letters(),
                    user.len()
                )));
            }
            for (i, pose) in user.chunks(n).enumerate() {
                machine.check_range(pose).map_err(|e| e.context(format!("{label}: pose {}", i + 1)))?;
            }
            Ok(vec![set(label.to_string(), None, user.to_vec())])
        }
        PoseSource::Grid(nodes) => {
            if *nodes < 2 {
                return Err(Error::input(format!("--grid {nodes}: at least 2 points per axis")));
            }
            Ok(vec![set("work volume".into(), None, volume_grid(machine, *nodes, rotary)?)])
        }
    }
}

impl BudgetProblem {
    /// The forward analysis of every pose set; a stack-up that is not finite is a failed
    /// computation naming the set.
    pub fn analyse(&self) -> Result<Vec<Analysis>, Error> {
        let mut out = Vec::with_capacity(self.sets.len());
        for set in &self.sets {
            let a = analyse(&self.machine, &self.spec, &set.internal, &self.setup, self.frame)?;
            let finite = a.poses.iter().all(|p| p.stack.rss_total.is_finite() && p.stack.worst_total.is_finite()) && a.rss_rms.is_finite();
            if !finite {
                return Err(Error::computation(format!("{}: the stack-up is not finite (check the machine and tolerances)", set.label)));
            }
            out.push(a);
        }
        Ok(out)
    }

    /// The root-sum-square 3D error (um) at each of `poses_user` (mm, deg; `machine.axis_count()`
    /// per pose) with every rotary axis where the first pose set has it: the map of `trueaxis
    /// budget analyse --plots` over the mid-planes of the travel.
    pub fn rss_at(&self, poses_user: &[f64]) -> Result<Vec<f64>, Error> {
        let n = self.machine.axis_count();
        let mut poses = poses_user.to_vec();
        if let Some(base) = self.sets.first().and_then(|set| set.user.get(..n)) {
            for (k, axis) in self.machine.axes().iter().enumerate() {
                if axis.kind == AxisKind::Rotary {
                    poses.chunks_mut(n).for_each(|pose| pose[k] = base[k]);
                }
            }
        }
        let a = analyse(&self.machine, &self.spec, &to_internal(&self.machine, &poses), &self.setup, self.frame)?;
        Ok(a.poses.iter().map(|p| p.stack.rss_total).collect())
    }

    /// The cost-optimal allocation on the (single) pose set, with the sensitivity it used.
    pub fn allocate(&self, options: &AllocationOptions) -> Result<(Allocation, Sensitivity), Error> {
        let [set] = &self.sets[..] else {
            return Err(Error::input("allocate takes one pose set: give one --part (or --poses, --grid)"));
        };
        let s = sensitivity(&self.machine, &self.spec.components, &set.internal, &self.setup, self.frame);
        let a = allocate(&self.spec, &s, options)?;
        if !(a.cost.is_finite() && a.tolerances.iter().all(|t| t.is_finite())) {
            return Err(Error::computation("the allocation is not finite"));
        }
        Ok((a, s))
    }
}
