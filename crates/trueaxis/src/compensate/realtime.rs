//! The real-time corrector: from axis positions (and temperatures, directions of motion) to axis
//! corrections, for a controller's servo cycle (NISTIR 5236 section 4, "way of the future": the model
//! computed by an open-architecture controller and passed to the position loop; Soons 1993 §2.3.5,
//! real-time use). Owns its machine, error model and buffers; a call allocates nothing. The C ABI
//! is in [`super::ffi`].
//!
//! Consecutive calls of a servo loop are close together, so each call starts from the previous
//! correction and reuses the previous linearisation nearby ([`Corrector::correct_along`]): typically
//! one exact-chain evaluation per call; the residual is checked on the exact chain every call.

use super::correction::{Correction, CorrectionOptions, CorrectionWorkspace, Corrector, WarmStart, MAX_AXES};
use super::export::Limits;
use super::CompensateError;
use crate::error_model::{Direction, ErrorModel, MachineState};
use crate::machine::Machine;
use crate::model::Setup;

/// Outcome of one real-time call (also the C return codes). Every status but `Ok` leaves the output
/// all zeros (no correction), never stale values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(i32)]
pub enum RealtimeStatus {
    /// Corrections written.
    Ok = 0,
    /// A slice has the wrong length (positions, temperatures, directions or output).
    BadLength = -1,
    /// A position or temperature is not a finite number.
    NotFinite = -2,
    /// The solve did not reach the position tolerance.
    NotConverged = -3,
    /// A null pointer was passed (C ABI only).
    NullPointer = -4,
    /// A correction exceeds the machine's correction limit (`[limits]` of the machine file, else
    /// 1000 um / 10000 urad; docs/limits.md): refused, never clipped.
    BeyondLimit = -5,
}

/// A corrector bound to one machine and error model, with its own buffers.
#[derive(Clone, Debug)]
pub struct RealtimeCorrector {
    machine: Machine,
    errors: ErrorModel,
    setup: Setup,
    options: CorrectionOptions,
    limits: Limits,
    workspace: CorrectionWorkspace,
    warm: WarmStart,
    last: Option<Correction>,
}

impl RealtimeCorrector {
    /// Binds a machine and error model (the tool point of the machine, the workpiece origin); the
    /// correction limits are the machine's ([`Limits::of_machine`]).
    pub fn new(machine: Machine, errors: ErrorModel) -> Result<RealtimeCorrector, CompensateError> {
        if machine.axis_count() > MAX_AXES {
            return Err(CompensateError::Input(format!("machine `{}` has more than {MAX_AXES} axes", machine.name)));
        }
        let workspace = CorrectionWorkspace::new(&machine);
        Ok(RealtimeCorrector {
            setup: Setup::of_machine(&machine),
            limits: Limits::of_machine(&machine),
            machine,
            errors,
            options: CorrectionOptions::default(),
            workspace,
            warm: WarmStart::default(),
            last: None,
        })
    }

    /// Changes the solve options (tolerance, iterations, orientation target).
    pub fn with_options(mut self, options: CorrectionOptions) -> RealtimeCorrector {
        self.options = options;
        self
    }

    /// Replaces the correction limits (um, urad).
    pub fn with_limits(mut self, limits: Limits) -> RealtimeCorrector {
        self.limits = limits;
        self
    }

    pub fn machine(&self) -> &Machine {
        &self.machine
    }

    pub fn axis_count(&self) -> usize {
        self.machine.axis_count()
    }

    /// Number of temperatures a call expects (the error model's sensors, in its order).
    pub fn sensor_count(&self) -> usize {
        self.errors.sensors().len()
    }

    /// Forgets the previous call: the next one starts cold (e.g. after a jump of the axes).
    pub fn reset(&mut self) {
        self.warm.reset();
        self.last = None;
    }

    /// The full result of the last successful call (residuals, iterations, evaluations).
    pub fn last(&self) -> Option<&Correction> {
        self.last.as_ref()
    }

    /// Corrections (mm, deg; added to the set-points) of the axis positions `positions` (mm, deg,
    /// canonical axis order). `temperatures`: one per sensor (degC), or empty for 20 degC;
    /// `directions`: one per axis (+1, -1, 0 at rest), or empty for all at rest. Any status but
    /// `Ok` zeroes `out`. Allocation-free.
    pub fn correct(&mut self, positions: &[f64], temperatures: &[f64], directions: &[i8], out: &mut [f64]) -> RealtimeStatus {
        let status = self.correct_into(positions, temperatures, directions, out);
        if status != RealtimeStatus::Ok {
            out.iter_mut().for_each(|o| *o = 0.0);
        }
        status
    }

    fn correct_into(&mut self, positions: &[f64], temperatures: &[f64], directions: &[i8], out: &mut [f64]) -> RealtimeStatus {
        let n = self.machine.axis_count();
        if positions.len() != n || out.len() != n || (!temperatures.is_empty() && temperatures.len() != self.sensor_count()) {
            return RealtimeStatus::BadLength;
        }
        if !directions.is_empty() && directions.len() != n {
            return RealtimeStatus::BadLength;
        }
        if positions.iter().chain(temperatures).any(|v| !v.is_finite()) {
            return RealtimeStatus::NotFinite;
        }
        let mut q = [0.0; MAX_AXES];
        self.machine.pose_to_internal(positions, &mut q[..n]);
        let mut dirs = [None; MAX_AXES];
        for (d, &s) in dirs.iter_mut().zip(directions) {
            *d = match s {
                1.. => Some(Direction::Positive),
                ..=-1 => Some(Direction::Negative),
                0 => None,
            };
        }
        let state = MachineState { directions: (!directions.is_empty()).then_some(&dirs[..n]), temperatures };
        let corrector = Corrector {
            machine: &self.machine,
            errors: &self.errors,
            setup: self.setup,
            options: self.options,
            datum: crate::geometry::Pose::IDENTITY,
        };
        let c = corrector.correct_along(&q[..n], &state, &mut self.workspace, &mut self.warm);
        if !c.converged || c.dq[..n].iter().any(|v| !v.is_finite()) {
            self.warm.reset();
            return RealtimeStatus::NotConverged;
        }
        for (axis, d) in self.machine.axes().iter().zip(&c.dq) {
            let micro = *d * if axis.kind == crate::machine::AxisKind::Rotary { 1e6 } else { 1e3 };
            if !self.limits.allows(axis.kind, micro) {
                return RealtimeStatus::BeyondLimit;
            }
        }
        for ((o, axis), d) in out.iter_mut().zip(self.machine.axes()).zip(&c.dq) {
            *o = axis.position_to_user(*d);
        }
        self.last = Some(c);
        RealtimeStatus::Ok
    }
}
