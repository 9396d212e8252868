//! The correction of a pose: the axis set-point changes that cancel the predicted error of the tool
//! point relative to the workpiece (Soons 1993 §2.3.5; NISTIR 5236 section 4).
//!
//! Soons 1993 §2.3.5 adds an unknown correction to each joint and chooses the corrections by linear
//! least squares on the kinematic model. Here the linear solve ([`super::solve`]) is iterated on the
//! exact chain until the position residual is below [`CorrectionOptions::tolerance_mm`] (default
//! 0.01 um), so that the result holds for errors of any size the exact chain can represent:
//!
//! ```text
//! dq_{k+1} = S( J dq_k - r(dq_k) )
//! ```
//!
//! with `r(dq)` the exact residual at the set-points `q + dq` (actual chain minus the nominal target at
//! `q`), `J` the joint Jacobian of the nominal chain at `q` (taken once per call: a chord method that
//! contracts by the size of the errors, ~1e-4, per step) and `S` the linear solve. Written for the
//! total correction rather than the step, the iteration has a fixed point also where the solve damps
//! an ill-conditioned orientation direction (near a 5-axis singularity), and there the fixed point is
//! the damped least-squares solution, continuous in the pose.
//!
//! Cost per call: one nominal chain pass with the Jacobian, and the exact chain (error values plus
//! the actual chains) once per iterate: 2 evaluations for a cold start (the error, then the check of
//! the first-order correction), typically 1 along a path with [`Corrector::correct_along`], which
//! starts from the previous correction and reuses the previous linearisation nearby.
//!
//! Priorities: the position of the tool point is corrected first (a least-squares solve over all
//! joints); the orientation is corrected in the null space of the position task, as far as the
//! machine's joints allow. By default only the direction of the tool axis counts (a spin about the
//! spindle axis does not change the cut); what no joint can correct (orientation on a 3-axis machine,
//! the tilt near a 5-axis singularity, where the correction fades out) stays in the residual and is
//! reported.

pub use super::solve::MAX_AXES;
use super::solve::{Block, Joints, OrientationRows, Solver, CHARACTERISTIC_LENGTH_MM};
use crate::error_model::{Direction, ErrorModel, MachineState};
use crate::geometry::{rotation_log, Mat3, Pose, Twist, Vec3};
use crate::machine::{AxisKind, Component, Machine, SetupSide};
use crate::model::{actual_chain, nominal_chain, Setup};

/// A linearisation taken at one pose is reused for another (by [`Corrector::correct_along`]) while
/// no rotary axis moved more than this (rad) ...
const RELINEARISE_RAD: f64 = 1e-2;
/// ... and no linear axis more than this (mm), and only where it is well conditioned
/// ([`Solver::reusable`]): the fixed point of the iteration is then the same, the older Jacobian
/// only slows the contraction of a step that is itself tiny along a path.
const RELINEARISE_MM: f64 = 10.0;

/// Which part of the orientation error the correction cancels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OrientationTarget {
    /// Position only.
    None,
    /// The direction of the tool axis; `axis` is its unit direction at home in M (a spindle along
    /// +z: `[0, 0, 1]`). The spin about the tool axis is left alone.
    ToolAxis(Vec3),
    /// All three orientation components.
    Full,
}

/// Options of the correction solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CorrectionOptions {
    /// Stop when the position residual is below this (mm; default 1e-5 mm = 0.01 um) and the next
    /// step would move no linear axis by more than it ...
    pub tolerance_mm: f64,
    /// ... and no rotary axis by more than this (rad; default 1e-7 rad = 0.1 urad, a fifth of the
    /// resolution of a fine rotary encoder; its effect on the position is in the position residual).
    pub rotary_tolerance_rad: f64,
    /// Most linear steps on the exact chain.
    pub max_iterations: usize,
    /// Orientation part to correct (default: the tool axis along +z).
    pub orientation: OrientationTarget,
    /// Singular values of the scaled position Jacobian below this (mm per mm; for a rotary joint the
    /// lever arm divided by 1000 mm) count as zero: such directions are not corrected.
    pub singular_threshold: f64,
    /// Fade-out of the orientation task (`eps`, default 0.1, must be > 0): an orientation direction
    /// whose singular value `sigma` (rad of tool tilt per rad of rotary correction: `sin A` for the C
    /// axis of a table-tilting machine, zero at the singularity) is below it is corrected with the
    /// gain `2 sigma / (sigma^2 + eps^2)` instead of `1 / sigma`: near a 5-axis singularity the
    /// rotary correction never exceeds `1 / eps` times the tilt, falls continuously to zero at the
    /// singularity, and the fraction `(eps^2 - sigma^2) / (eps^2 + sigma^2)` of the tilt in that
    /// direction is left and reported as uncorrectable ([`super::solve`]).
    pub orientation_threshold: f64,
    /// Keep the rotary axes where they are and correct with the linear axes alone (what an
    /// axis-indexed table of a five-axis controller can do: a rotary correction that cancels a
    /// tilt depends on where both rotary axes stand).
    pub rotary_fixed: bool,
}

impl Default for CorrectionOptions {
    fn default() -> Self {
        CorrectionOptions {
            tolerance_mm: 1e-5,
            rotary_tolerance_rad: 1e-7,
            max_iterations: 20,
            orientation: OrientationTarget::ToolAxis(Vec3::z()),
            singular_threshold: 1e-3,
            orientation_threshold: 0.1,
            rotary_fixed: false,
        }
    }
}

/// The correction of one pose (internal units: mm, rad). Plain data, no allocation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Correction {
    /// Axis set-point changes in canonical axis order (mm, rad); entries beyond `axis_count` are 0.
    pub dq: [f64; MAX_AXES],
    pub axis_count: usize,
    /// Error before correction: tool point relative to the workpiece point, actual minus nominal,
    /// in the workpiece frame (mm), and the orientation error (rad). Exact for a cold start; with a
    /// warm start ([`Corrector::correct_along`]) extrapolated to first order from the first
    /// evaluated set-points (relative error of the order of the error gradients, ~1e-4).
    pub original_position: Vec3,
    pub original_orientation: Vec3,
    /// What remains after correction, on the exact chain (mm, rad).
    pub residual_position: Vec3,
    pub residual_orientation: Vec3,
    /// The part of `residual_orientation` that the correction targets but does not remove (rad), as
    /// the linear model predicts it: with [`OrientationTarget::ToolAxis`] the tilt of the tool axis
    /// that no joint can correct (3-axis machines) or that fades out near a singularity; with
    /// `Full`, all three components.
    pub uncorrectable_orientation: Vec3,
    /// Linear steps taken (exact-chain evaluations minus one).
    pub iterations: usize,
    /// Exact-chain evaluations (error values plus actual chains) used.
    pub evaluations: usize,
    /// Whether the position residual reached the tolerance.
    pub converged: bool,
}

impl Correction {
    /// The corrections in user units (mm, deg), one per axis.
    pub fn dq_user(&self, machine: &Machine) -> Vec<f64> {
        machine.axes().iter().zip(&self.dq).map(|(a, &d)| a.position_to_user(d)).collect()
    }

    /// What could not be corrected, as readable sentences (empty when everything was).
    /// `position_tolerance_mm` is the reporting threshold for position, `orientation_tolerance_rad` for
    /// orientation.
    pub fn uncorrectable(&self, position_tolerance_mm: f64, orientation_tolerance_rad: f64) -> Vec<String> {
        let mut out = Vec::new();
        if self.residual_position.norm() > position_tolerance_mm {
            let p = self.residual_position * 1e3;
            out.push(format!(
                "position: {:.4} um remain (dx {:.4}, dy {:.4}, dz {:.4} um); the joints cannot move the tool point that way here",
                p.norm(),
                p.x,
                p.y,
                p.z
            ));
        }
        if self.uncorrectable_orientation.norm() > orientation_tolerance_rad {
            let o = self.uncorrectable_orientation * 1e6;
            out.push(format!(
                "orientation: {:.3} urad remain (drx {:.3}, dry {:.3}, drz {:.3} urad); the machine has no joint to turn the tool that way",
                o.norm(),
                o.x,
                o.y,
                o.z
            ));
        }
        out
    }
}

/// Reusable buffers of the correction solve (allocated once; no allocation per pose afterwards).
#[derive(Clone, Debug)]
pub struct CorrectionWorkspace {
    values: Vec<f64>,
    tool_parents: Vec<Pose>,
    work_parents: Vec<Pose>,
}

impl CorrectionWorkspace {
    pub fn new(machine: &Machine) -> CorrectionWorkspace {
        CorrectionWorkspace {
            values: vec![0.0; machine.parameter_count()],
            tool_parents: Vec::with_capacity(MAX_AXES),
            work_parents: Vec::with_capacity(MAX_AXES),
        }
    }
}

/// What a call along a path carries to the next one ([`Corrector::correct_along`]): the last two
/// converged corrections, from which the next solve starts (extrapolated along the path), and the
/// last linearisation, reused while the pose stays close to where it was taken. Results agree with
/// a cold solve to within the tolerance.
#[derive(Clone, Copy, Debug, Default)]
pub struct WarmStart {
    /// The last and the one before: pose in scaled joint units (mm; rotary rad x L) and the
    /// converged correction (scaled joint units).
    last: Option<(Joints, Joints)>,
    before: Option<(Joints, Joints)>,
    /// Pose (mm, rad) and solver of the last linearisation.
    linearisation: Option<(Joints, Solver)>,
}

impl WarmStart {
    /// Forgets the last corrections and linearisation (the next call starts cold).
    pub fn reset(&mut self) {
        *self = WarmStart::default();
    }

    /// The start of the solve at the scaled pose `x`: the last correction, moved on by the last
    /// change of correction times the projection `s` of this pose step on the last one, clamped to
    /// [-2, 2] (`s = 1` for a servo loop at constant speed, 0 at rest); `None` without history.
    fn start(&self, x: &Joints) -> Option<Joints> {
        let (x1, u1) = self.last?;
        let Some((x0, u0)) = self.before else { return Some(u1) };
        let (d_now, d_last) = (x - x1, x1 - x0);
        let squared = d_last.norm_squared();
        let s = if squared > 0.0 { (d_now.dot(&d_last) / squared).clamp(-2.0, 2.0) } else { 0.0 };
        Some(u1 + (u1 - u0) * s)
    }

    fn remember(&mut self, x: Joints, u: Joints) {
        self.before = self.last;
        self.last = Some((x, u));
    }
}

/// Corrects poses of one machine with one error model and setup (the tool point relative to the
/// workpiece point, as in [`crate::model::Predictor`]).
#[derive(Clone, Copy)]
pub struct Corrector<'a> {
    pub machine: &'a Machine,
    pub errors: &'a ErrorModel,
    pub setup: Setup,
    pub options: CorrectionOptions,
    /// The workpiece datum `D`: a constant rigid transform of the workpiece frame (mm, rad) that
    /// the correction aims in, `D r_actual = r_nominal` (identity: the workpiece frame itself).
    /// A kinematic description stated in another gauge than the machine's chain (the frame of the
    /// linear axes, [`super::kinematic`]) differs from it by one.
    pub datum: Pose,
}

/// The nominal relative position (workpiece frame) and orientation at a pose.
pub(super) struct Target {
    pub position: Vec3,
    pub rotation: Mat3,
}

impl Target {
    /// The part of an orientation residual (rad) that the correction targets, with the tool axis of
    /// this pose: the tilt (the residual minus its spin about the tool axis), all of it, or none.
    fn targeted(&self, orientation: &Vec3, target: OrientationTarget) -> Vec3 {
        match target {
            OrientationTarget::None => Vec3::zeros(),
            OrientationTarget::ToolAxis(a) => {
                let t = self.rotation * a.normalize();
                orientation - t * t.dot(orientation)
            }
            OrientationTarget::Full => *orientation,
        }
    }
}

impl<'a> Corrector<'a> {
    /// The machine's tool point relative to the workpiece origin, default options.
    pub fn new(machine: &'a Machine, errors: &'a ErrorModel) -> Corrector<'a> {
        Corrector { machine, errors, setup: Setup::of_machine(machine), options: CorrectionOptions::default(), datum: Pose::IDENTITY }
    }

    /// The correction of pose `q` (mm, rad, canonical order), at rest and at 20 degC.
    pub fn correct(&self, q: &[f64], ws: &mut CorrectionWorkspace) -> Correction {
        self.correct_state(q, &MachineState::default(), ws)
    }

    /// The correction of pose `q` (mm, rad) in machine state `state` (directions of motion,
    /// temperatures): finds `dq` such that the actual chain at `q + dq` puts the tool point where the
    /// nominal chain at `q` puts it, relative to the workpiece (Soons 1993 §2.3.5, iterated on the exact
    /// chain). The error model is evaluated at the corrected set-points `q + dq`. A cold start
    /// (`dq = 0`): the result depends on `q` and `state` only. Allocation-free.
    pub fn correct_state(&self, q: &[f64], state: &MachineState, ws: &mut CorrectionWorkspace) -> Correction {
        self.solve(q, state, ws, None)
    }

    /// The same along a path (a servo loop, the points of an NC program): starts from the corrections
    /// of the previous calls extrapolated along the path ([`WarmStart`]) and reuses the linearisation
    /// while the pose is within 1e-3 rad / 1 mm of where it was taken, so that a call along a smooth
    /// path typically costs one exact-chain evaluation. The residual is
    /// still checked on the exact chain; the result differs from [`Self::correct_state`] by less than
    /// the tolerance. `warm` is updated (reset when the solve does not converge). Allocation-free.
    pub fn correct_along(&self, q: &[f64], state: &MachineState, ws: &mut CorrectionWorkspace, warm: &mut WarmStart) -> Correction {
        let c = self.solve(q, state, ws, Some(warm));
        if !c.converged {
            warm.reset();
        }
        c
    }

    fn solve(&self, q: &[f64], state: &MachineState, ws: &mut CorrectionWorkspace, warm: Option<&mut WarmStart>) -> Correction {
        let n = self.machine.axis_count();
        assert!(n <= MAX_AXES && q.len() >= n, "pose of {} positions for {n} axes", q.len());
        let q_joints = Joints::from_fn(|k, _| if k < n { q[k] } else { 0.0 });
        let along = warm.is_some();
        let mut cold = WarmStart::default();
        let warm = warm.unwrap_or(&mut cold);
        let target = match &warm.linearisation {
            Some((at, solver)) if solver.reusable && self.is_near(at, &q_joints) => self.target(q),
            _ => {
                let (target, solver) = self.linearise(q, ws);
                warm.linearisation = Some((q_joints, solver));
                target
            }
        };
        let solver = &warm.linearisation.as_ref().expect("linearised above").1;
        let x = Joints::from_fn(|k, _| if k < n { q[k] / self.weight(k) } else { 0.0 });
        let start = if along { warm.start(&x) } else { None };
        let u = start.unwrap_or_else(Joints::zeros);
        let mut qc = [0.0; MAX_AXES];
        let mut evaluate = |u: &Joints, ws: &mut CorrectionWorkspace| {
            for k in 0..n {
                qc[k] = q[k] + u[k] * self.weight(k);
            }
            self.residual(&qc[..n], &target, state, ws)
        };
        let mut iteration = Iteration::start(u, evaluate(&u, ws), start.is_some());
        let (uncorrectable, next) = loop {
            match iteration.step(self, solver, &target) {
                Next::Evaluate(u) => {
                    let residual = evaluate(&u, ws);
                    iteration.checked(u, residual);
                }
                Next::Done { uncorrectable, next } => break (uncorrectable, next),
            }
        };
        let correction = iteration.correction(self, uncorrectable);
        if along && correction.converged {
            warm.remember(x, next);
        }
        correction
    }

    /// The exact error left at pose `q` (mm, rad, canonical order) when the set-points are `q + dq`
    /// (mm, rad): the tool point relative to the workpiece point, actual chain at `q + dq` (error
    /// functions evaluated there, in `state`) minus the nominal chain at `q`, in the workpiece frame
    /// (mm), and the orientation (rotation vector, rad). `dq = 0` gives the error before correction;
    /// the `dq` of [`Self::correct_state`] gives its `residual_position`. Used to judge corrections
    /// that a controller format approximates ([`super::export::residual`]). One exact-chain
    /// evaluation; allocation-free.
    pub fn residual_at(&self, q: &[f64], dq: &[f64], state: &MachineState, ws: &mut CorrectionWorkspace) -> (Vec3, Vec3) {
        let n = self.machine.axis_count();
        assert!(n <= MAX_AXES && q.len() >= n && dq.len() >= n, "pose of {} positions and {} corrections for {n} axes", q.len(), dq.len());
        let mut qc = [0.0; MAX_AXES];
        for k in 0..n {
            qc[k] = q[k] + dq[k];
        }
        let target = self.target(&q[..n]);
        self.residual(&qc[..n], &target, state, ws)
    }

    /// Whether a step (scaled joint units) moves the linear axes by less than the tolerance (mm) and
    /// the rotary axes by less than the rotary tolerance (rad).
    fn is_small(&self, step: &Joints) -> bool {
        let (mut linear, mut rotary) = (0.0, 0.0);
        for (k, axis) in self.machine.axes().iter().enumerate() {
            let d = step[k] * self.weight(k);
            match axis.kind {
                AxisKind::Linear => linear += d * d,
                AxisKind::Rotary => rotary += d * d,
            }
        }
        linear < self.options.tolerance_mm.powi(2) && rotary < self.options.rotary_tolerance_rad.powi(2)
    }

    /// Whether a linearisation taken at `at` serves pose `q` (see [`RELINEARISE_RAD`]).
    fn is_near(&self, at: &Joints, q: &Joints) -> bool {
        self.machine.axes().iter().enumerate().all(|(k, axis)| {
            let limit = if axis.kind == AxisKind::Rotary { RELINEARISE_RAD } else { RELINEARISE_MM };
            (at[k] - q[k]).abs() <= limit
        })
    }

    /// Nominal tool point relative to the workpiece point at pose `q` (mm, rad), in the workpiece
    /// frame (mm): what a correction aims at.
    pub fn nominal_relative_position(&self, q: &[f64]) -> Vec3 {
        self.target(q).position
    }

    /// Nominal tool point relative to the workpiece point (workpiece frame) and relative rotation.
    fn target(&self, q: &[f64]) -> Target {
        let m = self.machine;
        let tool = nominal_chain(m, m.tool_chain(), q, None);
        let work = nominal_chain(m, m.work_chain(), q, None);
        self.relative(&tool, &work)
    }

    fn relative(&self, tool: &Pose, work: &Pose) -> Target {
        let rt = work.rotation.transpose();
        let (position, rotation) =
            (rt * (tool.transform_point(&self.setup.tool_point) - work.transform_point(&self.setup.work_point)), rt * tool.rotation);
        // in the datum: D r_actual = r_nominal, so the actual relative pose aims at D^-1 of the nominal one
        let d = self.datum.rotation.transpose();
        Target { position: d * (position - self.datum.translation), rotation: d * rotation }
    }

    /// Actual relative position and rotation at the set-points `qc`, minus the target: position
    /// (mm, workpiece frame) and rotation vector (rad). One exact-chain evaluation.
    fn residual(&self, qc: &[f64], target: &Target, state: &MachineState, ws: &mut CorrectionWorkspace) -> (Vec3, Vec3) {
        let m = self.machine;
        self.errors.values_at_state(m, qc, state, &mut ws.values);
        let p = &ws.values;
        let offset = |side| {
            let i = m.setup_index(side, Component::X);
            Vec3::new(p[i], p[i + 1], p[i + 2])
        };
        let tool = actual_chain(m, m.tool_chain(), qc, p);
        let work = actual_chain(m, m.work_chain(), qc, p);
        let rt = work.rotation.transpose();
        let tool_point = tool.transform_point(&(self.setup.tool_point + offset(SetupSide::Tool)));
        let work_point = work.transform_point(&(self.setup.work_point + offset(SetupSide::Workpiece)));
        let position = rt * (tool_point - work_point) - target.position;
        let orientation = rotation_log(&(rt * tool.rotation * target.rotation.transpose()));
        (position, orientation)
    }

    /// One pass of the nominal chains at `q`: the target, and the solver of the joint Jacobian.
    /// Derivatives of the relative tool position (mm per mm or rad) and orientation (rad per mm or
    /// rad) with respect to each joint, in the workpiece frame: tool-side joints move the tool point,
    /// workpiece-side joints move the workpiece, so their effect on the relative position has the
    /// opposite sign. Columns are scaled to joint units `u` ([`super::solve`]).
    pub(super) fn linearise(&self, q: &[f64], ws: &mut CorrectionWorkspace) -> (Target, Solver) {
        let m = self.machine;
        let tool = nominal_chain(m, m.tool_chain(), q, Some(&mut ws.tool_parents));
        let work = nominal_chain(m, m.work_chain(), q, Some(&mut ws.work_parents));
        let rt = work.rotation.transpose();
        let tool_point = tool.transform_point(&self.setup.tool_point);
        let mut jp = Block::zeros();
        let mut jo = Block::zeros();
        for (chain, parents, sign) in [(m.tool_chain(), &ws.tool_parents, 1.0), (m.work_chain(), &ws.work_parents, -1.0)] {
            for (&k, parent) in chain.iter().zip(parents.iter()) {
                let axis = &m.axes()[k];
                let twist = match axis.kind {
                    AxisKind::Linear => Twist::of_small_transform(parent, &Vec3::zeros(), &axis.direction, &Vec3::zeros()),
                    AxisKind::Rotary => Twist::of_small_transform(parent, &axis.direction, &Vec3::zeros(), &axis.point),
                };
                let locked = self.options.rotary_fixed && axis.kind == AxisKind::Rotary;
                let w = if locked { 0.0 } else { sign * self.weight(k) };
                jp.set_column(k, &(rt * twist.displacement_of(&tool_point) * w));
                jo.set_column(k, &(rt * twist.omega * w));
            }
        }
        let rows = match self.options.orientation {
            OrientationTarget::None => OrientationRows::none(),
            OrientationTarget::ToolAxis(a) => OrientationRows::tilt_of(&(rt * tool.rotation * a.normalize())),
            OrientationTarget::Full => OrientationRows::full(),
        };
        let solver = Solver::new(&jp, &jo, rows, self.options.singular_threshold, self.options.orientation_threshold.max(1e-9));
        (self.relative(&tool, &work), solver)
    }

    /// Weight of each joint in the scaled solve: 1 (linear), 1/L (rotary).
    pub(super) fn weight(&self, k: usize) -> f64 {
        match self.machine.axes().get(k).map(|a| a.kind) {
            Some(AxisKind::Rotary) => 1.0 / CHARACTERISTIC_LENGTH_MM,
            Some(AxisKind::Linear) => 1.0,
            None => 0.0,
        }
    }
}

/// One pose's solve in progress (the iteration of the module documentation): the last iterate
/// checked on the exact chain and its residual. The caller evaluates the residuals the iteration
/// asks for, so that one pose (a scalar chain, [`Corrector::correct_state`]) and many at once (the
/// batch kernel, [`super::batch_correction`]) run the same solve.
pub(super) struct Iteration {
    /// The last checked correction (scaled joint units) and its exact residual (mm, rad).
    u: Joints,
    position: Vec3,
    orientation: Vec3,
    /// The error before correction (mm, rad): the first residual, corrected to first order for a
    /// warm start.
    original_position: Vec3,
    original_orientation: Vec3,
    warm: bool,
    iterations: usize,
}

/// What an [`Iteration`] needs next.
pub(super) enum Next {
    /// The exact residual at the correction `u` (scaled joint units).
    Evaluate(Joints),
    /// The solve has ended at the last checked iterate: the targeted orientation that the linear
    /// model leaves (rad), and the solve from that iterate (the better estimate of the fixed point,
    /// for a warm start).
    Done { uncorrectable: Vec3, next: Joints },
}

impl Iteration {
    /// Starts at the correction `u` (scaled joint units) with its exact `residual` (position mm,
    /// orientation rad); `warm` when `u` is a warm start rather than zero.
    pub(super) fn start(u: Joints, residual: (Vec3, Vec3), warm: bool) -> Iteration {
        let (position, orientation) = residual;
        Iteration { u, position, orientation, original_position: position, original_orientation: orientation, warm, iterations: 0 }
    }

    /// One linear solve from the last checked iterate (`dq_{k+1} = S(J dq_k - r(dq_k))`): the next
    /// iterate to check, or the end (the residual is within the tolerance and the step is small, or
    /// the iterations are used up).
    pub(super) fn step(&mut self, corrector: &Corrector, solver: &Solver, target: &Target) -> Next {
        let options = &corrector.options;
        // the spin is removed with this pose's tool axis, so that a linearisation reused from a
        // nearby pose does not see it
        let step = solver.solve(&self.u, &self.position, &target.targeted(&self.orientation, options.orientation));
        if self.iterations == 0 && self.warm {
            // the error at q, to first order from the warm start
            self.original_position -= step.position_change;
            self.original_orientation -= step.orientation_change;
        }
        let small_step = corrector.is_small(&(step.u - self.u));
        if (self.position.norm() < options.tolerance_mm && small_step) || self.iterations >= options.max_iterations {
            Next::Done { uncorrectable: step.left, next: step.u }
        } else {
            Next::Evaluate(step.u)
        }
    }

    /// The exact residual (position mm, orientation rad) at the iterate `u` that [`Self::step`]
    /// asked for.
    pub(super) fn checked(&mut self, u: Joints, residual: (Vec3, Vec3)) {
        self.u = u;
        (self.position, self.orientation) = residual;
        self.iterations += 1;
    }

    /// The correction at the last checked iterate, once [`Self::step`] returned [`Next::Done`].
    pub(super) fn correction(&self, corrector: &Corrector, uncorrectable: Vec3) -> Correction {
        let n = corrector.machine.axis_count();
        let mut dq = [0.0; MAX_AXES];
        for (k, d) in dq.iter_mut().enumerate().take(n) {
            *d = self.u[k] * corrector.weight(k);
        }
        Correction {
            dq,
            axis_count: n,
            original_position: self.original_position,
            original_orientation: self.original_orientation,
            residual_position: self.position,
            residual_orientation: self.orientation,
            uncorrectable_orientation: uncorrectable,
            iterations: self.iterations,
            evaluations: self.iterations + 1,
            converged: self.position.norm() < corrector.options.tolerance_mm,
        }
    }
}

/// Direction of motion from a signed increment (`None` when the axis does not move).
pub fn direction_of(increment: f64) -> Option<Direction> {
    if increment > 0.0 {
        Some(Direction::Positive)
    } else if increment < 0.0 {
        Some(Direction::Negative)
    } else {
        None
    }
}
