//! A compensation plan: the kinematic part a controller's description carries, then tables for
//! what remains, and what the controller applies with both.
//!
//! The controller computes joint positions with its kinematic description (the corrected one):
//! for a programmed tool pose it commands the set-points at which *that* description puts the tool
//! there, `q + dq_K(q)` with `dq_K` the correction of the description's location errors
//! ([`KinematicCorrection::errors`]) on the exact chain. Its axis tables then add, at the commanded
//! axis positions, what the full correction needs beyond the kinematic one: the tables hold
//! `dq(q) - dq_K(q)` along the axis lines through the reference pose (own-axis and cross-axis,
//! `crate::compensate::tables`).

use super::description::KinematicDescription;
use crate::compensate::correction::{CorrectionOptions, CorrectionWorkspace, Corrector, OrientationTarget};
use crate::compensate::export::residual::Applied;
use crate::compensate::tables::{axis_tables, TableSet, TableSpec};
use crate::compensate::CompensateError;
use crate::error_model::{Direction, ErrorModel, MachineState};
use crate::geometry::{Pose, Vec3};
use crate::machine::{AxisKind, Component, Machine, ParameterId};

/// What a controller's kinematic description can hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Carried {
    /// Where the rotary axis lines pass (their position in the two directions across the axis).
    pub rotary_positions: bool,
    /// Which way the rotary axes point (their tilts).
    pub rotary_directions: bool,
    /// The zero offsets of the rotary axes.
    pub zero_offsets: bool,
    /// Which way the linear axes move (squareness, the tilt of a linear axis).
    pub linear_directions: bool,
    /// The tool end: where the tool point sits on the last tool-side body.
    pub tool_end: bool,
}

impl Carried {
    /// Everything (a generated kinematics module).
    pub const ALL: Carried =
        Carried { rotary_positions: true, rotary_directions: true, zero_offsets: true, linear_directions: true, tool_end: true };
    /// The rotary axes' lines and zero offsets, and where the tool point sits on a rotary head
    /// (Heidenhain kinematics, Siemens swivel data): see [`Carried::for_machine`].
    pub const ROTARY_AXES: Carried =
        Carried { rotary_positions: true, rotary_directions: true, zero_offsets: true, linear_directions: false, tool_end: true };

    /// What `self` carries on `machine`: the tool end only where a rotary axis carries the tool (the
    /// controllers' head offset vectors hold it; on a machine whose tool side is linear it is a
    /// constant offset of the linear axes, which their tables hold).
    pub fn for_machine(self, machine: &Machine) -> Carried {
        let head = machine.tool_chain().iter().any(|&k| machine.axes()[k].kind == AxisKind::Rotary);
        Carried { tool_end: self.tool_end && head, ..self }
    }
}

/// The kinematic part of a compensation plan.
#[derive(Clone, Debug)]
pub struct KinematicCorrection {
    /// The actual description (every location error folded in), in the frame of the linear axes
    /// ([`KinematicDescription::in_frame_of_linear_axes`]).
    pub actual: KinematicDescription,
    /// The description the controller is given (the carried parts of `actual`, nominal elsewhere).
    pub written: KinematicDescription,
    /// Location errors of the machine whose chain is `written` (the controller's kinematics as an
    /// error model of the nominal machine).
    pub errors: ErrorModel,
    /// The same as a parameter vector (mm, rad): location errors and the tool setup.
    pub params: Vec<f64>,
    /// The workpiece datums ([`Corrector::datum`]) in which a correction on the machine's own errors
    /// (`actual`) and one on [`Self::errors`] (`written`) aim at the same relative positions: both
    /// map to the frame of the linear axes.
    pub datum_actual: Pose,
    pub datum_written: Pose,
    pub carried: Carried,
}

impl KinematicCorrection {
    /// The kinematic correction of `machine` whose location errors are those of `errors` at pose
    /// `reference` (mm, rad) and sensor values `temperatures` (a location error may depend on
    /// temperatures; it is taken at these), for a description that carries `carried`.
    pub fn new(machine: &Machine, errors: &ErrorModel, reference: &[f64], temperatures: &[f64], carried: Carried) -> KinematicCorrection {
        let carried = carried.for_machine(machine);
        let mut params = vec![0.0; machine.parameter_count()];
        let state = crate::error_model::MachineState { directions: None, temperatures };
        errors.values_at_state(machine, reference, &state, &mut params);
        let raw = KinematicDescription::actual(machine, &params);
        let (actual, turn) = raw.in_frame_of_linear_axes(machine);
        let datum_actual = Pose { rotation: turn, translation: Vec3::zeros() }.then(&raw.work_end);
        let nominal = KinematicDescription::nominal(machine);
        let mut written = nominal.clone();
        for (k, axis) in machine.axes().iter().enumerate() {
            let (a, w) = (&actual.axes[k], &mut written.axes[k]);
            match axis.kind {
                AxisKind::Linear if carried.linear_directions => w.direction = a.direction,
                AxisKind::Linear => {}
                AxisKind::Rotary => {
                    if carried.rotary_directions {
                        w.direction = a.direction;
                    }
                    if carried.rotary_positions {
                        // the image of the nominal axis point: the body the axis carries moves
                        // with it, so that a description with every line carried ends as the actual
                        w.point = a.point;
                    }
                    if carried.zero_offsets {
                        w.zero_offset = a.zero_offset;
                    }
                }
            }
        }
        if carried.tool_end {
            written.tool_end = actual.tool_end;
        }
        let (params, [_, datum_written]) = written.to_parameters_and_ends(machine, carried.tool_end);
        KinematicCorrection {
            errors: ErrorModel::from_parameter_vector(machine, &params),
            params,
            actual,
            written,
            datum_actual,
            datum_written,
            carried,
        }
    }
}

/// What a controller applies with a kinematic description and tables: the joint positions its
/// kinematics commands, then the tables' corrections at those positions.
pub struct PlanApplied<'m> {
    pub machine: &'m Machine,
    /// The controller's kinematics as location errors ([`KinematicCorrection::errors`]) and the
    /// datum its corrections aim in.
    pub kinematics: ErrorModel,
    pub datum: Pose,
    /// The tables (or grid) on top; `None`: the description alone.
    pub tables: Option<Box<dyn Applied + 'm>>,
}

impl Applied for PlanApplied<'_> {
    fn applied(&self, q_user: &[f64], directions: &[Option<Direction>], out: &mut [f64]) {
        let m = self.machine;
        let corrector = Corrector { datum: self.datum, ..Corrector::new(m, &self.kinematics) };
        let mut q = vec![0.0; m.axis_count()];
        m.pose_to_internal(q_user, &mut q);
        let c = corrector.correct(&q, &mut CorrectionWorkspace::new(m));
        for (k, o) in out.iter_mut().enumerate() {
            *o = m.axes()[k].position_to_user(c.dq[k]);
        }
        if let Some(tables) = &self.tables {
            let commanded: Vec<f64> = q_user.iter().zip(out.iter()).map(|(q, d)| q + d).collect();
            let mut extra = vec![0.0; out.len()];
            tables.applied(&commanded, directions, &mut extra);
            out.iter_mut().zip(&extra).for_each(|(o, e)| *o += e);
        }
    }
}

/// The own rotation of rotary axis `k` (its angular positioning error: `ECC` for a C axis along
/// z): the motion-error component about the axis, when the axis lies along x, y or z.
fn own_rotation(machine: &Machine, k: usize) -> Option<Component> {
    let d = machine.axes()[k].direction;
    (0..3).find(|&i| (d[i].abs() - 1.0).abs() < 1e-12).map(|i| Component::from_index(3 + i))
}

/// The tables of a compensation plan: what they must add, at the axis positions the corrected
/// kinematics commands, so that the machine reaches the programmed points.
///
/// - Linear corrections along each axis line through the reference pose: the position of the
///   tool point corrected with the linear axes alone (a table cannot hold a rotary correction that
///   cancels a tilt, which depends on where both rotary axes stand), for the machine's errors minus
///   that of the kinematic description.
/// - The own-axis table of a rotary axis along x, y or z: minus its angular positioning error
///   (`-ECC(C)`), read from the error model (both directions); that error is left out of the linear
///   corrections, so it is corrected once.
pub fn plan_tables(corrector: &Corrector, kinematics: &KinematicCorrection, spec: &TableSpec) -> Result<TableSet, CompensateError> {
    let m = corrector.machine;
    let own: Vec<(usize, Component)> =
        (0..m.axis_count()).filter(|&k| m.axes()[k].kind == AxisKind::Rotary).filter_map(|k| own_rotation(m, k).map(|c| (k, c))).collect();
    let is_own = |id: &ParameterId| {
        own.iter().any(|&(k, c)| matches!(id, ParameterId::Motion { axis, component } if *axis == m.axes()[k].letter && *component == c))
    };
    let rest = corrector.errors.without(is_own);
    let options = CorrectionOptions { orientation: OrientationTarget::None, rotary_fixed: true, ..corrector.options };
    let full = axis_tables(&Corrector { errors: &rest, options, datum: kinematics.datum_actual, ..*corrector }, spec)?;
    let written = Corrector { errors: &kinematics.errors, options, datum: kinematics.datum_written, ..*corrector };
    let mut tables = full.minus(&axis_tables(&written, spec)?);
    let mut values = vec![0.0; m.parameter_count()];
    let mut q = vec![0.0; m.axis_count()];
    m.pose_to_internal(&tables.reference, &mut q);
    for (k, component) in own {
        let index = m.motion_index(k, component);
        let table = tables.tables.iter_mut().find(|t| t.driver == k && t.corrected == k).expect("own-axis table of every axis");
        for (direction, column) in [(Direction::Positive, &mut table.forward), (Direction::Negative, &mut table.reverse)] {
            let mut directions = vec![None; m.axis_count()];
            directions[k] = Some(direction);
            let state = MachineState { directions: Some(&directions), temperatures: &spec.temperatures };
            for (value, &position) in column.iter_mut().zip(&table.positions) {
                q[k] = m.axes()[k].position_to_internal(position);
                corrector.errors.values_at_state(m, &q, &state, &mut values);
                *value = -values[index].to_degrees();
            }
        }
    }
    Ok(tables)
}
