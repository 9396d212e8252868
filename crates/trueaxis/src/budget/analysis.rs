//! The forward analysis of a budget over a pose set (Zhu 2008 appendix B, "error budget analysis"):
//! the stack-up at each pose and over the set, the sensitivity measures, and the share of every
//! component, axis and kind of error; with a check of the linear stack-up on the exact chain.

use super::components::ErrorKind;
use super::measures::{condition_number, homogenised_norm, mean_square_gains, singular_values};
use super::sensitivity::{sensitivity, Sensitivity};
use super::spec::BudgetSpec;
use super::stackup::{stack_up, worst_case, StackUp};
use crate::error::Error;
use crate::geometry::Vec3;
use crate::machine::{AxisKind, Machine};
use crate::model::{volumetric_error, Frame, Setup};
use rayon::prelude::*;

/// Label of the group of squareness errors between linear axes in [`Analysis::by_axis`].
pub const BETWEEN_AXES: &str = "between axes";

/// Results at one pose.
#[derive(Clone, Debug)]
pub struct PoseResult {
    pub stack: StackUp,
    /// Singular values of the homogenised sensitivity matrix (mm, descending).
    pub singular_values: [f64; 3],
    pub condition: Option<f64>,
}

/// The share of a group of components (an axis or a kind) in the volumetric error.
#[derive(Clone, Debug)]
pub struct GroupShare {
    /// An axis letter or a kind (`linear`, `angular`, `squareness`).
    pub label: String,
    /// Indices of the components.
    pub members: Vec<usize>,
    /// Share (%) of the mean square root-sum-square error: the shares of a partition add up to 100.
    pub share: f64,
    /// Root mean square over poses of the root-sum-square 3D error of the group alone (um).
    pub rss_um: f64,
    /// Machine sensitivity `SM` (Zhu 2008 eqs. B.14-B.19): `rss_um` per unit norm of the group's
    /// homogenised tolerances (mm). The printed ratio has the total error above every group; the
    /// group's own error is read here, which is what separates the groups.
    pub sensitivity_mm: f64,
}

/// One component's part of the volumetric error.
#[derive(Clone, Debug)]
pub struct ComponentShare {
    /// Root mean square over poses of `|SE_:j| e_j` (um): the error the tolerance alone causes.
    pub rss_um: f64,
    /// Share (%) of the mean square root-sum-square error.
    pub share: f64,
    /// Root mean square over poses of `|SE_:j|`: um per um for linear errors; for angular and
    /// squareness errors um per urad, i.e. the lever arm in m (Abbe effect): `lever_mm` = 1000 x.
    pub gain: f64,
}

/// The linear worst case at one pose checked on the exact chain.
#[derive(Clone, Debug)]
pub struct ExactCheck {
    pub pose: usize,
    /// Worst-case 3D error of the linear stack-up (um).
    pub linear_um: f64,
    /// Length of the exact volumetric error with every component at its limit with those signs (um).
    pub exact_um: f64,
}

/// The forward analysis of a budget over poses.
#[derive(Clone, Debug)]
pub struct Analysis {
    pub sensitivity: Sensitivity,
    pub poses: Vec<PoseResult>,
    /// Of the pose-averaged homogenised sensitivity (mm).
    pub singular_values: [f64; 3],
    /// Robustness index `RI_1` (eq. B.12); `RI_2` (eq. B.13) is `singular_values[0]`.
    pub condition: Option<f64>,
    /// Part sensitivity `SP_x, SP_y, SP_z` (eqs. B.9-B.11, mm): the root mean square root-sum-square
    /// error along each direction per unit norm of all homogenised tolerances.
    pub part_sensitivity: [f64; 3],
    pub components: Vec<ComponentShare>,
    /// By axis (motion errors, and location errors of a rotary axis), then the squareness errors
    /// between linear axes as the group [`BETWEEN_AXES`].
    pub by_axis: Vec<GroupShare>,
    pub by_kind: Vec<GroupShare>,
    /// Components that move the tool point at none of the poses (all-zero columns).
    pub no_effect: Vec<usize>,
    /// Root mean square over poses of the root-sum-square 3D error (um).
    pub rss_rms: f64,
    pub exact_check: ExactCheck,
}

impl Analysis {
    /// `(pose, value)` of the largest root-sum-square 3D error.
    pub fn rss_max(&self) -> (usize, f64) {
        largest(self.poses.iter().map(|p| p.stack.rss_total))
    }

    /// `(pose, value)` of the largest worst-case 3D error.
    pub fn worst_max(&self) -> (usize, f64) {
        largest(self.poses.iter().map(|p| p.stack.worst_total))
    }

    /// `(pose, value)` of the largest error along direction `d` by root-sum-square or worst case.
    pub fn direction_max(&self, d: usize, worst: bool) -> (usize, f64) {
        largest(self.poses.iter().map(|p| if worst { p.stack.worst[d] } else { p.stack.rss[d] }))
    }
}

fn largest(values: impl Iterator<Item = f64>) -> (usize, f64) {
    values.enumerate().fold((0, f64::NEG_INFINITY), |a, (i, v)| if v > a.1 { (i, v) } else { a })
}

/// Analyses `spec` at `poses` (internal units, `machine.axis_count()` per pose).
pub fn analyse(machine: &Machine, spec: &BudgetSpec, poses: &[f64], setup: &Setup, frame: Frame) -> Result<Analysis, Error> {
    let count = poses.len() / machine.axis_count().max(1);
    if count == 0 {
        return Err(Error::input("no poses to analyse"));
    }
    let s = sensitivity(machine, &spec.components, poses, setup, frame);
    Ok(analyse_sensitivity(machine, spec, s, poses, setup, frame))
}

/// [`analyse`] from sensitivity matrices already computed at `poses`.
pub fn analyse_sensitivity(machine: &Machine, spec: &BudgetSpec, s: Sensitivity, poses: &[f64], setup: &Setup, frame: Frame) -> Analysis {
    let t = &spec.tolerances;
    let components = &spec.components;
    let n = components.len();
    let count = s.poses();
    let results: Vec<PoseResult> = (0..count)
        .into_par_iter()
        .map(|p| {
            let sigma = singular_values(&s, components, [p]);
            PoseResult { stack: stack_up(s.pose(p), t), singular_values: sigma, condition: condition_number(&sigma) }
        })
        .collect();
    let sigma = singular_values(&s, components, 0..count);
    let mean_square = mean_square_gains(&s);
    let variance: Vec<f64> = mean_square.iter().zip(t).map(|(g, e)| g * e * e).collect();
    let total: f64 = variance.iter().sum();
    let share = |v: f64| if total > 0.0 { 100.0 * v / total } else { 0.0 };
    let everything: Vec<usize> = (0..n).collect();
    let norm_all = homogenised_norm(components, t, &everything);
    let mut part_sensitivity = [0.0; 3];
    for (d, sp) in part_sensitivity.iter_mut().enumerate() {
        let mean: f64 = results.iter().map(|r| r.stack.rss[d].powi(2)).sum::<f64>() / count as f64;
        *sp = 1000.0 * mean.sqrt() / norm_all;
    }
    let group = |label: String, members: Vec<usize>| {
        let v: f64 = members.iter().map(|&j| variance[j]).sum();
        let norm = homogenised_norm(components, t, &members);
        GroupShare {
            label,
            share: share(v),
            rss_um: v.sqrt(),
            sensitivity_mm: if norm > 0.0 { 1000.0 * v.sqrt() / norm } else { 0.0 },
            members,
        }
    };
    // squareness errors of the linear axes are between two axes (Zhu 2008 B.2: "three squareness
    // errors between each axes"): a group of their own; every other error belongs to its axis
    let between = |j: usize| {
        components[j].kind == ErrorKind::Squareness
            && machine.axis_index(components[j].axis).is_some_and(|k| machine.axes()[k].kind == AxisKind::Linear)
    };
    let mut by_axis: Vec<GroupShare> = machine
        .axes()
        .iter()
        .map(|a| (a.letter, (0..n).filter(|&j| components[j].axis == a.letter && !between(j)).collect::<Vec<_>>()))
        .filter(|(_, m)| !m.is_empty())
        .map(|(letter, m)| group(letter.to_string(), m))
        .collect();
    let squareness: Vec<usize> = (0..n).filter(|&j| between(j)).collect();
    if !squareness.is_empty() {
        by_axis.push(group(BETWEEN_AXES.to_string(), squareness));
    }
    let by_kind = ErrorKind::ALL
        .iter()
        .map(|k| (k.name().to_string(), (0..n).filter(|&j| components[j].kind == *k).collect::<Vec<_>>()))
        .filter(|(_, m)| !m.is_empty())
        .map(|(label, m)| group(label, m))
        .collect();
    let component_shares =
        (0..n).map(|j| ComponentShare { rss_um: variance[j].sqrt(), share: share(variance[j]), gain: mean_square[j].sqrt() }).collect();
    let no_effect = (0..n).filter(|&j| (0..count).all(|p| s.column(p, j).norm() <= 1e-12)).collect();
    let rss_rms = (results.iter().map(|r| r.stack.rss_total.powi(2)).sum::<f64>() / count as f64).sqrt();
    let (worst_pose, worst_value) = largest(results.iter().map(|r| r.stack.worst_total));
    let exact_check = exact_worst_case(machine, spec, &s, &poses[worst_pose * machine.axis_count()..], worst_pose, setup, frame);
    debug_assert!((exact_check.linear_um - worst_value).abs() <= 1e-9 * worst_value.max(1.0));
    Analysis {
        sensitivity: s,
        poses: results,
        singular_values: sigma,
        condition: condition_number(&sigma),
        part_sensitivity,
        components: component_shares,
        by_axis,
        by_kind,
        no_effect,
        rss_rms,
        exact_check,
    }
}

/// Every component at its tolerance with the signs of the worst case at pose `p`, put through the
/// exact chain: the difference from the linear stack-up is of second order in the tolerances.
fn exact_worst_case(machine: &Machine, spec: &BudgetSpec, s: &Sensitivity, q: &[f64], p: usize, setup: &Setup, frame: Frame) -> ExactCheck {
    let t = &spec.tolerances;
    let generators: Vec<Vec3> = (0..t.len()).map(|j| s.column(p, j) * t[j]).collect();
    let (linear_um, signs) = worst_case(&generators);
    let mut params = vec![0.0; machine.parameter_count()];
    for ((c, e), sign) in spec.components.iter().zip(t).zip(&signs) {
        params[c.index] = sign * e * c.id.component().to_internal();
    }
    let exact = volumetric_error(machine, &q[..machine.axis_count()], &params, setup, frame);
    ExactCheck { pose: p, linear_um, exact_um: exact.position.norm() * 1e3 }
}
