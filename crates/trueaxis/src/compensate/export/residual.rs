//! What a controller format carries, and the error it leaves on the exact chain.
//!
//! Every exporter describes the corrections its files make the controller apply ([`Applied`]): a
//! sum of one-dimensional tables as the controller interpolates them ([`TableSum`]: LinuxCNC joint
//! compensation, Heidenhain `.COM`, Siemens LEC/CEC, Fanuc pitch-error compensation), a volumetric
//! grid with rotary-axis tables ([`GridSum`]: the LinuxCNC HAL component, the lattice), or the
//! correction the controller computes itself from written error parameters ([`ModelCorrection`]:
//! ISG). [`residual_of_format`] applies those corrections at poses spread over the whole travel and
//! evaluates what is left on the exact chain (the same chain as `trueaxis predict`): the error the
//! chosen format cannot remove, in um, at the worst pose and as an RMS over the poses. A calibration
//! report shows this as "after compensation" with that table.

use super::rigid_fit::RigidFit;
use crate::compensate::correction::{CorrectionOptions, CorrectionWorkspace, Corrector, OrientationTarget};
use crate::compensate::tables::{table_range, AxisTable, VolumetricGrid};
use crate::compensate::CompensateError;
use crate::error_model::{Direction, ErrorModel, MachineState};
use crate::geometry::Vec3;
use crate::machine::{AxisKind, Machine};
use rayon::prelude::*;

/// The corrections a controller applies with the data of one format.
pub trait Applied: Sync {
    /// Corrections (user units: mm, deg; one per axis, canonical order) applied at the pose `q_user`
    /// (mm, deg) while the axes move in `directions` (`None`: at rest), written into `out`.
    fn applied(&self, q_user: &[f64], directions: &[Option<Direction>], out: &mut [f64]);
}

/// Which column of a bidirectional table the controller applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Branch {
    /// The forward column whatever the direction.
    Forward,
    /// The mean of both columns whatever the direction (a format without direction).
    Mean,
    /// Forward while the driving axis moves up, reverse while it moves down, the mean at rest.
    Directional,
}

/// How the controller takes a value between two table points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Linearly, the end values held outside the table (LinuxCNC, Heidenhain, Siemens).
    Linear,
    /// The value of the last point at or below the position (a compensation output at each point,
    /// not interpolated: Fanuc pitch-error compensation).
    Held,
}

/// A table's value at `x` (mm or deg of its driver) on `branch`, with the driver moving in
/// `direction`. A table over exactly one turn of a rotary axis wraps `x` into it.
pub fn table_value(
    machine: &Machine,
    t: &AxisTable,
    x: f64,
    direction: Option<Direction>,
    branch: Branch,
    interpolation: Interpolation,
) -> f64 {
    let n = t.positions.len();
    let (first, last) = (t.positions[0], t.positions[n - 1]);
    let x = if machine.axes()[t.driver].kind == AxisKind::Rotary && ((last - first) - 360.0).abs() < 1e-9 {
        first + (x - first).rem_euclid(360.0)
    } else {
        x
    };
    let column = |k: usize| match (branch, direction) {
        (Branch::Forward, _) | (Branch::Directional, Some(Direction::Positive)) => t.forward[k],
        (Branch::Directional, Some(Direction::Negative)) => t.reverse[k],
        (Branch::Mean, _) | (Branch::Directional, None) => 0.5 * (t.forward[k] + t.reverse[k]),
    };
    let i = t.positions.partition_point(|&p| p <= x).clamp(1, n - 1) - 1;
    match interpolation {
        Interpolation::Held => column(if x >= t.positions[i + 1] { i + 1 } else { i }),
        Interpolation::Linear => {
            let s = ((x - t.positions[i]) / (t.positions[i + 1] - t.positions[i])).clamp(0.0, 1.0);
            column(i) + s * (column(i + 1) - column(i))
        }
    }
}

/// The sum of one-dimensional tables, each of the correction of its `corrected` axis as a function
/// of its `driver`: what controllers with own-axis and cross-axis tables apply.
pub struct TableSum<'m> {
    pub machine: &'m Machine,
    pub tables: Vec<(AxisTable, Branch)>,
    pub interpolation: Interpolation,
}

impl Applied for TableSum<'_> {
    fn applied(&self, q_user: &[f64], directions: &[Option<Direction>], out: &mut [f64]) {
        out.fill(0.0);
        for (t, branch) in &self.tables {
            out[t.corrected] += table_value(self.machine, t, q_user[t.driver], directions[t.driver], *branch, self.interpolation);
        }
    }
}

/// A volumetric grid over X, Y, Z (trilinear) plus tables of other axes, each the change from its
/// value at the grid's reference pose: exact at the grid nodes with the other axes at the reference,
/// and along each other axis through the reference.
pub struct GridSum<'m> {
    pub grid: &'m VolumetricGrid,
    /// The axes whose grid values the format carries (canonical indices).
    pub grid_columns: Vec<usize>,
    pub tables: TableSum<'m>,
}

impl Applied for GridSum<'_> {
    fn applied(&self, q_user: &[f64], directions: &[Option<Direction>], out: &mut [f64]) {
        self.tables.applied(q_user, directions, out);
        let p = self.grid.axes.map(|a| q_user[a]);
        for &axis in &self.grid_columns {
            out[axis] += self.grid.interpolate(p, axis);
        }
    }
}

/// The correction a controller computes itself from written error parameters (ISG volumetric
/// compensation): the position of the tool point only, at rest and at 20 degC.
pub struct ModelCorrection<'m> {
    pub machine: &'m Machine,
    /// The error parameters as written (tables as the controller interpolates them).
    pub errors: ErrorModel,
}

impl Applied for ModelCorrection<'_> {
    fn applied(&self, q_user: &[f64], _directions: &[Option<Direction>], out: &mut [f64]) {
        let m = self.machine;
        let options = CorrectionOptions { orientation: OrientationTarget::None, ..CorrectionOptions::default() };
        let corrector = Corrector { options, ..Corrector::new(m, &self.errors) };
        let mut q = vec![0.0; m.axis_count()];
        m.pose_to_internal(q_user, &mut q);
        let c = corrector.correct(&q, &mut CorrectionWorkspace::new(m));
        for (k, o) in out.iter_mut().enumerate() {
            *o = m.axes()[k].position_to_user(c.dq[k]);
        }
    }
}

/// The error a format leaves over the travel (exact chain, position of the tool point relative to
/// the workpiece), judged up to the placement of the workpiece: before and after compensation, the
/// reached points are aligned to the programmed ones by the least-squares rigid motion of the
/// workpiece frame ([`RigidFit`]; a table frame that is shifted or tilted as a whole is where the
/// workpiece datum puts it when the workpiece is probed, not an error of the machine).
#[derive(Clone, Debug, PartialEq)]
pub struct FormatResidual {
    /// Largest position error left (um) ...
    pub worst_um: f64,
    /// ... at this pose (mm, deg, canonical order) ...
    pub worst_pose: Vec<f64>,
    /// ... in this state of motion: `at rest`, `all axes moving +`, `all axes moving -`.
    pub worst_state: &'static str,
    /// The error there before correction (um).
    pub error_there_um: f64,
    /// Root mean square of the error left over all evaluated poses and states (um).
    pub rms_um: f64,
    /// Largest error before correction over the same poses (um).
    pub worst_error_um: f64,
    /// Root mean square of the error before correction over the same poses (um).
    pub rms_error_um: f64,
    /// Poses times states evaluated.
    pub samples: usize,
    /// The workpiece frame's best placement before and after (the datum a workpiece probe would
    /// set; rotation vector in rad, shift in mm, in the workpiece frame).
    pub placement_before: RigidFit,
    pub placement_after: RigidFit,
}

impl FormatResidual {
    /// Whether the files leave more error than they remove: the worst error left is more than half
    /// the worst error before (what is removed, `before - left`, is then less than what is left).
    /// What is left within [`NEGLIGIBLE_LEFT_UM`] is never more: a machine without errors gets
    /// tables of zeros, which change nothing.
    pub fn leaves_more_than_it_removes(&self) -> bool {
        leaves_more_than_it_removes(self.worst_error_um, self.worst_um)
    }
}

/// Whether a compensation that leaves `worst_left_um` of `worst_before_um` (largest errors over
/// the same poses, um) leaves more than it removes, by the rule of
/// [`FormatResidual::leaves_more_than_it_removes`].
pub fn leaves_more_than_it_removes(worst_before_um: f64, worst_left_um: f64) -> bool {
    worst_left_um > 0.5 * worst_before_um && worst_left_um > NEGLIGIBLE_LEFT_UM
}

/// An error left that no controller can show or act on: half the 0.1 um resolution of the
/// controllers' compensation tables (Heidenhain, Siemens and LinuxCNC write 0.0001 mm).
pub const NEGLIGIBLE_LEFT_UM: f64 = 0.05;

#[cfg(test)]
mod never_worse {
    use super::*;

    fn judged(before: f64, left: f64) -> bool {
        let placement = RigidFit::identity();
        FormatResidual {
            worst_um: left,
            worst_pose: vec![0.0; 3],
            worst_state: "at rest",
            error_there_um: before,
            rms_um: left,
            worst_error_um: before,
            rms_error_um: before,
            samples: 1,
            placement_before: placement,
            placement_after: placement,
        }
        .leaves_more_than_it_removes()
    }

    #[test]
    fn half_the_error_before_is_the_limit_above_the_resolution() {
        assert!(!judged(10.0, 5.0));
        assert!(judged(10.0, 5.001));
        assert!(!judged(0.0, 1e-9), "a machine without errors is not made worse by tables of zeros");
        assert!(!judged(0.04, 0.049));
        assert!(judged(0.04, 0.051));
    }
}

/// Poses spread over the travel: a full factorial of `levels` equally spaced positions per axis over
/// its range (0..360 deg for an unlimited rotary axis), about 4000 poses (at most 17 levels, at
/// least 3).
pub fn sample_poses(machine: &Machine) -> Result<Vec<f64>, CompensateError> {
    let n = machine.axis_count();
    // the most levels whose full factorial stays within 4096 poses (integer arithmetic: a floating
    // root such as 4096^(1/3) may round either way between builds)
    let within = |l: usize| (0..n).try_fold(1usize, |acc, _| acc.checked_mul(l).filter(|v| *v <= 4096)).is_some();
    let levels = (3..=17).take_while(|&l| within(l)).last().unwrap_or(3);
    let values: Vec<Vec<f64>> = (0..n)
        .map(|k| {
            let [lo, hi] = table_range(machine, k)?;
            Ok((0..levels).map(|i| lo + (hi - lo) * i as f64 / (levels - 1) as f64).collect())
        })
        .collect::<Result<_, CompensateError>>()?;
    let count = levels.pow(n as u32);
    let mut poses = Vec::with_capacity(count * n);
    for mut index in 0..count {
        for v in &values {
            poses.push(v[index % levels]);
            index /= levels;
        }
    }
    Ok(poses)
}

/// The error left when the controller applies `applied` instead of the exact correction, over
/// [`sample_poses`] at the sensor temperatures `temperatures` (degC; empty: 20 degC), at rest and,
/// when the error model depends on the direction of motion, with all axes moving up and all moving
/// down; before and after, each up to the best placement of the workpiece frame ([`RigidFit`]).
/// Each pose costs one exact-chain evaluation for the error before and one after.
pub fn residual_of_format(corrector: &Corrector, temperatures: &[f64], applied: &dyn Applied) -> Result<FormatResidual, CompensateError> {
    let m = corrector.machine;
    let n = m.axis_count();
    let poses = sample_poses(m)?;
    let directional = corrector.errors.directional_entries().any(|(_, d, _)| d.is_some());
    let states: &[(&'static str, Option<Direction>)] = if directional {
        &[("at rest", None), ("all axes moving +", Some(Direction::Positive)), ("all axes moving -", Some(Direction::Negative))]
    } else {
        &[("at rest", None)]
    };
    // per sample: (nominal relative position, error before, error after, pose index, state index)
    let samples: Vec<(Vec3, Vec3, Vec3, usize, usize)> = (0..poses.len() / n)
        .into_par_iter()
        .map_init(
            || (CorrectionWorkspace::new(m), vec![0.0; n], vec![0.0; n], vec![0.0; n]),
            |(ws, q, dq_user, dq), i| {
                let user = &poses[i * n..(i + 1) * n];
                m.pose_to_internal(user, q);
                let nominal = corrector.nominal_relative_position(q);
                states
                    .iter()
                    .enumerate()
                    .map(|(s, &(_, direction))| {
                        let directions = vec![direction; n];
                        let state = MachineState { directions: Some(&directions), temperatures };
                        applied.applied(user, &directions, dq_user);
                        for k in 0..n {
                            dq[k] = m.axes()[k].position_to_internal(dq_user[k]);
                        }
                        let before = corrector.residual_at(q, &vec![0.0; n], &state, ws).0;
                        let after = corrector.residual_at(q, dq, &state, ws).0;
                        (nominal, before, after, i, s)
                    })
                    .collect::<Vec<_>>()
            },
        )
        .flatten()
        .collect();
    if let Some(&(_, _, _, i, _)) = samples.iter().find(|r| !(r.1.iter().chain(r.2.iter()).all(|v| v.is_finite()))) {
        return Err(CompensateError::Computation(format!(
            "the residual of the format is not finite at pose {:?}",
            &poses[i * n..(i + 1) * n]
        )));
    }
    let nominal: Vec<Vec3> = samples.iter().map(|s| s.0).collect();
    // the points reached before and after: nominal plus the error before (`.1`) or left (`.2`)
    let reached_before: Vec<Vec3> = samples.iter().map(|s| s.0 + s.1).collect();
    let reached_after: Vec<Vec3> = samples.iter().map(|s| s.0 + s.2).collect();
    let (placement_before, placement_after) = (RigidFit::of(&nominal, &reached_before), RigidFit::of(&nominal, &reached_after));
    // errors in um after the placement
    let left =
        |fit: &RigidFit, reached: &[Vec3]| -> Vec<f64> { nominal.iter().zip(reached).map(|(n, a)| fit.left(n, a).norm() * 1e3).collect() };
    let (before, after) = (left(&placement_before, &reached_before), left(&placement_after, &reached_after));
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
    let worst = (0..after.len()).max_by(|&a, &b| after[a].total_cmp(&after[b])).expect("at least one pose");
    let (_, _, _, pose, state) = samples[worst];
    Ok(FormatResidual {
        worst_um: after[worst],
        worst_pose: poses[pose * n..(pose + 1) * n].to_vec(),
        worst_state: states[state].0,
        error_there_um: before[worst],
        rms_um: rms(&after),
        worst_error_um: before.iter().copied().fold(0.0, f64::max),
        rms_error_um: rms(&before),
        samples: samples.len(),
        placement_before,
        placement_after,
    })
}

/// What the uncertainty of the error values means for the error a compensation leaves: the files
/// correct the values as stated; if a value is off by its standard uncertainty, its effect is left.
#[derive(Clone, Debug, PartialEq)]
pub struct LeftUncertainty {
    /// Expanded uncertainty (k = 2, um) of the error left, the largest over the poses ...
    pub expanded_um: f64,
    /// ... and its root mean square over them (um, k = 2).
    pub rms_expanded_um: f64,
    /// The parameters with a stated uncertainty that took part.
    pub parameters: usize,
}

/// The uncertainty of the error left that follows from the standard uncertainties the error model
/// states (`[uncertainty]`, e.g. of an identification): for each such parameter, its effect on the
/// tool point relative to the workpiece over [`sample_poses`] (exact chain, a change of one standard
/// uncertainty), up to the best placement of the workpiece frame ([`RigidFit`]), as the error before
/// and after are judged; the parameters taken as independent (their effects added in quadrature);
/// `None` when the model states none.
pub fn uncertainty_of_error_left(corrector: &Corrector, temperatures: &[f64]) -> Result<Option<LeftUncertainty>, CompensateError> {
    let m = corrector.machine;
    let uncertain: Vec<(usize, f64)> = corrector
        .errors
        .uncertainties()
        .iter()
        .filter(|(_, u)| *u > 0.0)
        .map(|(id, u)| {
            m.parameter_index(id).map(|i| (i, u * id.component().to_internal())).map_err(|e| CompensateError::Input(e.to_string()))
        })
        .collect::<Result<_, _>>()?;
    if uncertain.is_empty() {
        return Ok(None);
    }
    let n = m.axis_count();
    let poses = sample_poses(m)?;
    let state = MachineState { directions: None, temperatures };
    let count = poses.len() / n;
    // per pose: the nominal relative position and the effect of each parameter's uncertainty (mm)
    let effects: Vec<(Vec3, Vec<Vec3>)> = (0..count)
        .into_par_iter()
        .map(|i| {
            let mut q = vec![0.0; n];
            m.pose_to_internal(&poses[i * n..(i + 1) * n], &mut q);
            let mut params = vec![0.0; m.parameter_count()];
            corrector.errors.values_at_state(m, &q, &state, &mut params);
            let at = |p: &[f64]| crate::model::volumetric_error(m, &q, p, &corrector.setup, crate::model::Frame::Workpiece).position;
            let base = at(&params);
            let effects = uncertain
                .iter()
                .map(|&(index, u)| {
                    let mut changed = params.clone();
                    changed[index] += u;
                    at(&changed) - base
                })
                .collect();
            (corrector.nominal_relative_position(&q), effects)
        })
        .collect();
    let nominal: Vec<Vec3> = effects.iter().map(|e| e.0).collect();
    let mut variance = vec![0.0; count];
    for j in 0..uncertain.len() {
        let moved: Vec<Vec3> = effects.iter().map(|(n, e)| n + e[j]).collect();
        let fit = RigidFit::of(&nominal, &moved);
        for (v, (n, a)) in variance.iter_mut().zip(nominal.iter().zip(&moved)) {
            *v += fit.left(n, a).norm_squared();
        }
    }
    if variance.iter().any(|v| !v.is_finite()) {
        return Err(CompensateError::Computation("the uncertainty of the error left is not finite".into()));
    }
    let expanded: Vec<f64> = variance.iter().map(|v| 2.0 * v.sqrt() * 1e3).collect();
    Ok(Some(LeftUncertainty {
        expanded_um: expanded.iter().copied().fold(0.0, f64::max),
        rms_expanded_um: (expanded.iter().map(|x| x * x).sum::<f64>() / count as f64).sqrt(),
        parameters: uncertain.len(),
    }))
}
