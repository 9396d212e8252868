//! The correction of a pose: the axis set-point changes that cancel the predicted error of the tool
//! point relative to the workpiece (seed 000 §2.3.5; seed 003 section 4).
//!
//! Seed 000 §2.3.5 adds an unknown correction to each joint and chooses the corrections by linear
//! least squares on the kinematic model. Here the linear step is iterated on the exact chain
//! (Gauss-Newton with the nominal joint Jacobian) until the position residual is below
//! [`CorrectionOptions::tolerance_mm`] (default 0.01 um), so that the result holds for errors of any
//! size the exact chain can represent.
//!
//! Priorities: the position of the tool point is corrected first (a least-squares solve over all
//! joints); the orientation is corrected in the null space of the position task, as far as the
//! machine's joints allow. By default only the direction of the tool axis counts (a spin about the
//! spindle axis does not change the cut); what no joint can correct (orientation on a 3-axis machine,
//! a tool point on the axis of the only rotary joint) stays in the residual and is reported.

use crate::errors::{Direction, ErrorModel, MachineState};
use crate::geometry::{rotation_log, Mat3, Pose, Twist, Vec3};
use crate::machine::{AxisKind, Component, Machine, SetupSide};
use crate::model::{actual_chain, nominal_chain, Setup};
use nalgebra::{SMatrix, SVector};

/// Most axes a machine can have (X Y Z U V W A B C).
pub const MAX_AXES: usize = 9;

/// A 3 x `MAX_AXES` block of the joint Jacobian (unused columns zero).
type Block = SMatrix<f64, 3, MAX_AXES>;
/// Joint-space vector (unused entries zero).
type Joints = SVector<f64, MAX_AXES>;

/// Characteristic length (mm) that makes rotary joints and orientation errors comparable with
/// linear ones in the least-squares solve: 1 rad of a rotary joint costs as much as 1000 mm of a
/// linear one, and 1 urad of orientation error weighs as 1 um of position error.
const CHARACTERISTIC_LENGTH_MM: f64 = 1000.0;

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
    /// Stop when the position residual is below this (mm); default 1e-5 mm = 0.01 um.
    pub tolerance_mm: f64,
    /// Most Gauss-Newton iterations on the exact chain.
    pub max_iterations: usize,
    /// Orientation part to correct (default: the tool axis along +z).
    pub orientation: OrientationTarget,
    /// Singular values of the scaled joint Jacobian below this (mm per mm; for a rotary joint the
    /// lever arm divided by 1000 mm) count as zero: such directions are not corrected.
    pub singular_threshold: f64,
    /// The same for the orientation task (default 0.1): near a 5-axis singularity (a rotary axis
    /// nearly parallel to the tool axis) a tilt of the tool would need a rotary correction more
    /// than ten times its size; it is left uncorrected and reported instead.
    pub orientation_threshold: f64,
}

impl Default for CorrectionOptions {
    fn default() -> Self {
        CorrectionOptions {
            tolerance_mm: 1e-5,
            max_iterations: 20,
            orientation: OrientationTarget::ToolAxis(Vec3::z()),
            singular_threshold: 1e-3,
            orientation_threshold: 0.1,
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
    /// in the workpiece frame (mm), and the orientation error (rad).
    pub original_position: Vec3,
    pub original_orientation: Vec3,
    /// What remains after correction, on the exact chain (mm, rad).
    pub residual_position: Vec3,
    pub residual_orientation: Vec3,
    /// The part of `residual_orientation` that the correction targets but the joints cannot reach
    /// (rad): with [`OrientationTarget::ToolAxis`], the tilt of the tool axis; with `Full`, all of it.
    pub uncorrectable_orientation: Vec3,
    /// Gauss-Newton iterations used.
    pub iterations: usize,
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

/// Corrects poses of one machine with one error model and setup (the tool point relative to the
/// workpiece point, as in [`crate::model::Predictor`]).
#[derive(Clone, Copy)]
pub struct Corrector<'a> {
    pub machine: &'a Machine,
    pub errors: &'a ErrorModel,
    pub setup: Setup,
    pub options: CorrectionOptions,
}

/// The nominal relative position (workpiece frame) and orientation at a pose.
struct Target {
    position: Vec3,
    rotation: Mat3,
}

impl<'a> Corrector<'a> {
    /// The machine's tool point relative to the workpiece origin, default options.
    pub fn new(machine: &'a Machine, errors: &'a ErrorModel) -> Corrector<'a> {
        Corrector { machine, errors, setup: Setup::of_machine(machine), options: CorrectionOptions::default() }
    }

    /// The correction of pose `q` (mm, rad, canonical order), at rest and at 20 degC.
    pub fn correct(&self, q: &[f64], ws: &mut CorrectionWorkspace) -> Correction {
        self.correct_state(q, &MachineState::default(), ws)
    }

    /// The correction of pose `q` (mm, rad) in machine state `state` (directions of motion,
    /// temperatures): finds `dq` such that the actual chain at `q + dq` puts the tool point where the
    /// nominal chain at `q` puts it, relative to the workpiece (seed 000 §2.3.5, iterated on the exact
    /// chain). The error model is evaluated at the corrected set-points `q + dq`. Allocation-free.
    pub fn correct_state(&self, q: &[f64], state: &MachineState, ws: &mut CorrectionWorkspace) -> Correction {
        let n = self.machine.axis_count();
        assert!(n <= MAX_AXES && q.len() >= n, "pose of {} positions for {n} axes", q.len());
        let target = self.target(q);
        let mut qc = [0.0; MAX_AXES];
        qc[..n].copy_from_slice(&q[..n]);
        let mut dq = Joints::zeros();
        let (mut position, mut orientation) = self.residual(&qc[..n], &target, state, ws);
        let (original_position, original_orientation) = (position, orientation);
        // the joint Jacobian of the nominal chain at q serves every iteration (chord method): it
        // differs from the actual one by the size of the errors (~1e-4), so the iteration contracts
        // by that factor per step
        let (jp, jo, tool_axis) = self.joint_jacobian(&qc[..n], ws);
        let solver = self.prepare(&jp, &jo, &tool_axis);
        let mut iterations = 0;
        let mut uncorrectable;
        loop {
            let (step, unreached) = solver.step(&position, &orientation);
            uncorrectable = unreached;
            let small_step = step.norm() < self.options.tolerance_mm;
            if (position.norm() < self.options.tolerance_mm && small_step) || iterations >= self.options.max_iterations {
                break;
            }
            dq += self.unscale(&step);
            for k in 0..n {
                qc[k] = q[k] + dq[k];
            }
            (position, orientation) = self.residual(&qc[..n], &target, state, ws);
            iterations += 1;
        }
        let mut out = [0.0; MAX_AXES];
        out[..n].copy_from_slice(&dq.as_slice()[..n]);
        Correction {
            dq: out,
            axis_count: n,
            original_position,
            original_orientation,
            residual_position: position,
            residual_orientation: orientation,
            uncorrectable_orientation: uncorrectable,
            iterations,
            converged: position.norm() < self.options.tolerance_mm,
        }
    }

    /// Nominal tool point relative to the workpiece point (workpiece frame) and relative rotation.
    fn target(&self, q: &[f64]) -> Target {
        let m = self.machine;
        let tool = nominal_chain(m, m.tool_chain(), q, None);
        let work = nominal_chain(m, m.work_chain(), q, None);
        let rt = work.rotation.transpose();
        Target {
            position: rt * (tool.transform_point(&self.setup.tool_point) - work.transform_point(&self.setup.work_point)),
            rotation: rt * tool.rotation,
        }
    }

    /// Actual relative position and rotation at the set-points `qc`, minus the target: position
    /// (mm, workpiece frame) and rotation vector (rad).
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

    /// Derivatives of the relative tool position (mm per mm or rad) and orientation (rad per mm or
    /// rad) with respect to each joint, in the workpiece frame, on the nominal chain at `q`; and the
    /// tool axis in the workpiece frame. Tool-side joints move the tool point, workpiece-side joints
    /// move the workpiece, so their effect on the relative position has the opposite sign.
    fn joint_jacobian(&self, q: &[f64], ws: &mut CorrectionWorkspace) -> (Block, Block, Vec3) {
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
                jp.set_column(k, &(rt * twist.displacement_of(&tool_point) * sign));
                jo.set_column(k, &(rt * twist.omega * sign));
            }
        }
        let tool_axis = match self.options.orientation {
            OrientationTarget::ToolAxis(a) => rt * tool.rotation * a.normalize(),
            _ => Vec3::zeros(),
        };
        (jp, jo, tool_axis)
    }

    /// Weight of each joint in the scaled solve: 1 (linear), 1/L (rotary).
    fn weight(&self, k: usize) -> f64 {
        match self.machine.axes().get(k).map(|a| a.kind) {
            Some(AxisKind::Rotary) => 1.0 / CHARACTERISTIC_LENGTH_MM,
            Some(AxisKind::Linear) => 1.0,
            None => 0.0,
        }
    }

    fn unscale(&self, u: &Joints) -> Joints {
        Joints::from_fn(|k, _| u[k] * self.weight(k))
    }

    /// The prioritised least-squares solve for one Jacobian, in scaled joint units: position first
    /// (minimum-norm solution over all joints), then the targeted orientation in the null space of
    /// the position task.
    fn prepare(&self, jp: &Block, jo: &Block, tool_axis: &Vec3) -> Solver {
        let w = Joints::from_fn(|k, _| self.weight(k));
        let scale = |b: &Block| Block::from_fn(|i, k| b[(i, k)] * w[k]);
        let jp = scale(jp);
        let projector = match self.options.orientation {
            OrientationTarget::None => Mat3::zeros(),
            OrientationTarget::ToolAxis(_) => Mat3::identity() - tool_axis * tool_axis.transpose(),
            OrientationTarget::Full => Mat3::identity(),
        };
        let a = projector * scale(jo) * CHARACTERISTIC_LENGTH_MM;
        let jp_pinv = pseudo_inverse(&jp, self.options.singular_threshold);
        let a_null = a - (a * jp_pinv) * jp;
        let a_null_pinv = pseudo_inverse(&a_null, self.options.orientation_threshold);
        Solver { jp_pinv, a, a_null, a_null_pinv, projector }
    }
}

/// The linear operators of one prioritised least-squares solve.
struct Solver {
    jp_pinv: SMatrix<f64, MAX_AXES, 3>,
    a: Block,
    a_null: Block,
    a_null_pinv: SMatrix<f64, MAX_AXES, 3>,
    projector: Mat3,
}

impl Solver {
    /// The step (scaled joint units) that cancels the residual, and the part of the targeted
    /// orientation residual it cannot reach (rad).
    fn step(&self, position: &Vec3, orientation: &Vec3) -> (Joints, Vec3) {
        let step1 = self.jp_pinv * (-position);
        let b = -(self.projector * orientation) * CHARACTERISTIC_LENGTH_MM - self.a * step1;
        let step2 = self.a_null_pinv * b;
        let unreached = (b - self.a_null * step2) / CHARACTERISTIC_LENGTH_MM;
        (step1 + step2, -unreached)
    }
}

/// Moore-Penrose pseudo-inverse `M^T (M M^T)^+` of a 3 x n block, singular values of `M` below
/// `threshold` treated as zero. Allocation-free (3 x 3 symmetric eigenproblem).
fn pseudo_inverse(m: &Block, threshold: f64) -> SMatrix<f64, MAX_AXES, 3> {
    let gram = m * m.transpose();
    // fast path: the smallest eigenvalue of the Gram matrix is at least det / (trace / 2)^2 (the
    // product of the two largest is at most (trace / 2)^2); when det > threshold^2 trace^2 / 3
    // it clears threshold^2, and the plain inverse is the pseudo-inverse
    let trace = gram.trace();
    if gram.determinant() > threshold * threshold * trace * trace / 3.0 {
        if let Some(inverse) = gram.try_inverse() {
            return m.transpose() * inverse;
        }
    }
    let eigen = gram.symmetric_eigen();
    let mut gram_pinv = Mat3::zeros();
    for i in 0..3 {
        let lambda = eigen.eigenvalues[i];
        if lambda > threshold * threshold {
            let v = eigen.eigenvectors.column(i);
            gram_pinv += v * v.transpose() / lambda;
        }
    }
    m.transpose() * gram_pinv
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
