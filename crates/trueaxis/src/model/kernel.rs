//! The batch volumetric error kernel: the exact volumetric error of [`super::volumetric_error`] with the
//! error values of [`ErrorModel::values_at_state`], evaluated over blocks of [`LANES`] poses laid
//! out as structure of arrays ([`super::lanes`]).
//!
//! A [`VolumetricKernel`] is prepared once from a machine, its error model, the setup and the
//! frame (immutable, shared by the threads); a [`KernelWorkspace`] holds one block's buffers (one
//! per thread). Preparation decides, once, what the scalar path decides at every pose:
//! - which location and motion errors are zero at every pose (skipped) and which are constant
//!   (their small transform computed once, not per pose);
//! - which parameters come from functions of their own axis alone (`PositionFunction::add_lanes`:
//!   tables by index arithmetic and polynomials by Horner's rule over the lanes, bases lane by
//!   lane) and which from directional functions and terms (evaluated pose by pose by the scalar
//!   code, so the two paths cannot diverge);
//! - which axis is a linear translation, a rotary motion (one sine and cosine per pose) or a
//!   translation along a coordinate direction.
//!
//! The block function is compiled for the baseline target (SSE2 on x86-64: separate products and
//! sums, as the scalar path), with AVX2 and with AVX-512F (both with fused
//! multiply-add, one rounding per `a b + c`), and chosen at run time by CPU feature detection
//! (stable Rust `#[target_feature]`, no dependency).

use super::lanes::{
    add, dot, mat_mul_t, mat_t_mul, mat_t_vec, mat_vec, norm, rotation_about_axis, rotation_log_lanes, small_transform, splat, splat_vec,
    sub, Fused, LaneMat, LanePose, LaneVec, Lanes, MulAdd, Separate, LANES,
};
use super::volumetric::{Frame, Setup, VolumetricError};
use crate::error_model::{Direction, ErrorModel, MachineState};
use crate::geometry::{rotation_exp, Pose, Vec3};
use crate::machine::{AxisKind, Component, Machine, SetupSide};

/// A location or motion error `[e; eps]` of one axis, as the kernel applies it.
#[derive(Clone)]
enum Displacement {
    /// The six values at `start` of the parameter vector change from pose to pose: the small
    /// transform is computed per pose about `centre`.
    Varying { start: usize, centre: Centre },
    /// Constant values about a constant centre: the transform, computed once.
    Fixed(Box<LanePose>),
    /// Constant values about the centre of a linear axis's motion errors, `r + q d`: the rotation
    /// and `e` computed once, the translation `c + e - R c` per pose.
    FixedAlong { rotation: Box<[[Lanes; 3]; 3]>, e: LaneVec, centre: Centre },
}

/// The centre of a small transform: constant, or `point + q direction` for axis `axis`.
#[derive(Clone)]
enum Centre {
    Constant(Vec3),
    Along { axis: usize, point: Vec3, direction: Vec3 },
}

/// One factor of a chain, base outward.
#[derive(Clone)]
enum Step {
    /// The actual chain only.
    Error(Displacement),
    /// `Trans(d q)` of linear axis `axis`, both chains.
    Translate { axis: usize, direction: Vec3 },
    /// `Trans(p) Rot(d, q) Trans(-p)` of rotary axis `axis`, both chains.
    Rotate { axis: usize, direction: LaneVec, point: LaneVec },
}

/// The prepared kernel (see the module documentation).
pub struct VolumetricKernel<'a> {
    machine: &'a Machine,
    errors: &'a ErrorModel,
    setup: Setup,
    frame: Frame,
    tool_steps: Vec<Step>,
    work_steps: Vec<Step>,
    /// Parameters evaluated per block: `(index, constant)`, then the tables added.
    live: Vec<(usize, f64)>,
    /// Parameters the state-dependent part of the model may change.
    state_dependent: Vec<usize>,
    /// Setup-error parameter indices of the tool and the workpiece side (X Y Z), if any is not zero.
    tool_offset: Option<usize>,
    work_offset: Option<usize>,
    block: BlockFn,
    /// The instruction set the block function was compiled for.
    pub instruction_set: &'static str,
}

type BlockFn = fn(&VolumetricKernel, &mut KernelWorkspace, &[f64], &BlockState, Option<&RelativeTargets>, &mut [VolumetricError]);

/// Relative poses, one per lane, that a block's actual relative pose is compared with instead of
/// the nominal one at the same set-points ([`VolumetricKernel::residual_block`]): the position of
/// the tool point relative to the workpiece point in the workpiece frame (mm) and the rotation of
/// the tool relative to the workpiece.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RelativeTargets {
    pub position: LaneVec,
    pub rotation: LaneMat,
}

impl Default for RelativeTargets {
    fn default() -> Self {
        RelativeTargets { position: splat_vec(&Vec3::zeros()), rotation: LanePose::IDENTITY.rotation }
    }
}

/// The per-pose state of one block: directions of motion and input values (temperatures, ...),
/// `axis_count` and `sensors().len()` per pose, as in [`super::Predictor::predict_states`].
pub(crate) struct BlockState<'s> {
    pub directions: Option<&'s [Option<Direction>]>,
    pub temperatures: &'s [f64],
}

/// The buffers of one block (one per thread).
pub struct KernelWorkspace {
    /// Parameter values, `values[parameter][lane]` (mm, rad).
    values: Vec<Lanes>,
    /// Axis positions, `q[axis][lane]` (mm, rad).
    q: Vec<Lanes>,
    /// One pose's parameter vector, for the state-dependent part.
    row: Vec<f64>,
}

impl<'a> VolumetricKernel<'a> {
    /// Prepares the kernel for `machine` with `errors`, evaluated between the points of `setup`
    /// and expressed in `frame`.
    pub fn new(machine: &'a Machine, errors: &'a ErrorModel, setup: &Setup, frame: Frame) -> Self {
        let (constants, positional) = errors.position_plan();
        let state_dependent = errors.state_dependent_parameters();
        // a parameter is zero at every pose unless a constant, a function of position or a
        // state-dependent part gives it a value; constant unless a function or a state-dependent
        // part does
        let mut varies = vec![false; machine.parameter_count()];
        for &i in positional.iter().map(|(i, _, _)| i).chain(&state_dependent) {
            varies[i] = true;
        }
        let live: Vec<(usize, f64)> =
            (0..machine.parameter_count()).filter(|&i| varies[i] || constants[i] != 0.0).map(|i| (i, constants[i])).collect();
        let steps = |chain: &[usize]| -> Vec<Step> {
            let mut steps = Vec::new();
            for &k in chain {
                let axis = &machine.axes()[k];
                let linear = axis.kind == AxisKind::Linear;
                for (start, centre) in [
                    (machine.location_index(k, Component::X), Centre::Constant(axis.location_error_centre())),
                    (
                        machine.motion_index(k, Component::X),
                        if linear {
                            Centre::Along { axis: k, point: axis.point, direction: axis.direction }
                        } else {
                            Centre::Constant(axis.motion_error_centre(0.0))
                        },
                    ),
                ] {
                    let group = start..start + 6;
                    if group.clone().any(|i| varies[i]) {
                        steps.push(Step::Error(Displacement::Varying { start, centre }));
                    } else if group.clone().any(|i| constants[i] != 0.0) {
                        let eps = Vec3::new(constants[start + 3], constants[start + 4], constants[start + 5]);
                        let e = Vec3::new(constants[start], constants[start + 1], constants[start + 2]);
                        steps.push(Step::Error(match centre {
                            Centre::Constant(c) => Displacement::Fixed(Box::new(LanePose::splat(&Pose::small_transform(&eps, &e, &c)))),
                            along => Displacement::FixedAlong {
                                rotation: Box::new(LanePose::splat(&Pose { rotation: rotation_exp(&eps), translation: e }).rotation),
                                e: splat_vec(&e),
                                centre: along,
                            },
                        }));
                    }
                }
                steps.push(match axis.kind {
                    AxisKind::Linear => Step::Translate { axis: k, direction: axis.direction },
                    AxisKind::Rotary => Step::Rotate { axis: k, direction: splat_vec(&axis.direction), point: splat_vec(&axis.point) },
                });
            }
            steps
        };
        let offset = |side: SetupSide| {
            let i = machine.setup_index(side, Component::X);
            (i..i + 3).any(|p| varies[p] || constants[p] != 0.0).then_some(i)
        };
        let (block, instruction_set) = dispatch();
        VolumetricKernel {
            machine,
            errors,
            setup: *setup,
            frame,
            tool_steps: steps(machine.tool_chain()),
            work_steps: steps(machine.work_chain()),
            live,
            state_dependent,
            tool_offset: offset(SetupSide::Tool),
            work_offset: offset(SetupSide::Workpiece),
            block,
            instruction_set,
        }
    }

    /// The same kernel evaluated with `instruction_set` (one of [`INSTRUCTION_SETS`]) instead of
    /// the best one, or `None` when this CPU does not have it: to compare the compiled variants.
    pub fn with_instruction_set(mut self, instruction_set: &'static str) -> Option<Self> {
        self.block = block_for(instruction_set)?;
        self.instruction_set = instruction_set;
        Some(self)
    }

    /// A workspace for this kernel.
    pub fn workspace(&self) -> KernelWorkspace {
        KernelWorkspace {
            values: vec![splat(0.0); self.machine.parameter_count()],
            q: vec![splat(0.0); self.machine.axis_count().max(1)],
            row: vec![0.0; self.machine.parameter_count()],
        }
    }

    /// Volumetric errors of up to [`LANES`] poses (`axis_count` positions each, mm, rad, canonical
    /// order) into `out` (one per pose), at the per-pose `state`.
    pub(crate) fn evaluate_block(&self, ws: &mut KernelWorkspace, poses: &[f64], state: &BlockState, out: &mut [VolumetricError]) {
        (self.block)(self, ws, poses, state, None, out)
    }

    /// The actual relative pose of up to [`LANES`] poses (the set-points `poses`, mm, rad) minus
    /// `targets` (lane `l` for pose `l`; a block of fewer poses repeats its last target as it repeats
    /// its last pose), into `out`: `position` = actual tool point relative to the workpiece point
    /// minus the target position (mm, workpiece frame), `orientation` = rotation vector of
    /// `R_rel,actual R_target^T` (rad), `length` = `|actual| - |target|` (mm). The error values are
    /// taken at `poses` in `state`. With the nominal relative pose at other set-points as the target,
    /// this is the residual of a correction (`crate::compensate::correction`). The kernel's frame
    /// must be [`Frame::Workpiece`].
    pub(crate) fn residual_block(
        &self,
        ws: &mut KernelWorkspace,
        poses: &[f64],
        state: &BlockState,
        targets: &RelativeTargets,
        out: &mut [VolumetricError],
    ) {
        debug_assert_eq!(self.frame, Frame::Workpiece, "residuals are in the workpiece frame");
        (self.block)(self, ws, poses, state, Some(targets), out)
    }

    /// Volumetric errors of many poses (`axis_count` positions each, mm, rad), at rest and at the
    /// reference temperature, on the calling thread.
    pub fn evaluate(&self, ws: &mut KernelWorkspace, poses: &[f64], out: &mut [VolumetricError]) {
        let n_axes = self.machine.axis_count().max(1);
        let state = BlockState { directions: None, temperatures: &[] };
        for (q, o) in poses.chunks(LANES * n_axes).zip(out.chunks_mut(LANES)) {
            self.evaluate_block(ws, q, &state, o);
        }
    }
}

/// The instruction sets the block function is compiled for, best first.
pub const INSTRUCTION_SETS: [&str; 3] = ["AVX-512F", "AVX2", "baseline"];

/// The block function for `instruction_set` (one of [`INSTRUCTION_SETS`]) if this CPU has it.
fn block_for(instruction_set: &str) -> Option<BlockFn> {
    match instruction_set {
        #[cfg(target_arch = "x86_64")]
        "AVX-512F"
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512dq")
                && std::arch::is_x86_feature_detected!("fma") =>
        {
            // SAFETY: the CPU has the features block_avx512 is compiled for
            Some(|k, ws, q, s, t, o| unsafe { block_avx512(k, ws, q, s, t, o) })
        }
        #[cfg(target_arch = "x86_64")]
        "AVX2" if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") => {
            // SAFETY: the CPU has the feature block_avx2 is compiled for
            Some(|k, ws, q, s, t, o| unsafe { block_avx2(k, ws, q, s, t, o) })
        }
        "baseline" => Some(block::<BaselineMulAdd>),
        _ => None,
    }
}

/// The arithmetic of the baseline block function: every AArch64 CPU has fused multiply-add, an
/// x86-64 CPU without AVX2 may not (`f64::mul_add` would then be a library call).
#[cfg(target_arch = "aarch64")]
type BaselineMulAdd = Fused;
#[cfg(not(target_arch = "aarch64"))]
type BaselineMulAdd = Separate;

/// The block function for the best instruction set this CPU has.
fn dispatch() -> (BlockFn, &'static str) {
    INSTRUCTION_SETS.iter().find_map(|&name| block_for(name).map(|f| (f, name))).expect("the baseline is always available")
}

/// [`block`] compiled with AVX-512F (8 f64 per register) and fused multiply-add.
///
/// # Safety
/// The CPU must have AVX-512F, AVX-512DQ and FMA ([`dispatch`] checks it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,fma")]
unsafe fn block_avx512(
    k: &VolumetricKernel,
    ws: &mut KernelWorkspace,
    poses: &[f64],
    state: &BlockState,
    targets: Option<&RelativeTargets>,
    out: &mut [VolumetricError],
) {
    block::<Fused>(k, ws, poses, state, targets, out)
}

/// [`block`] compiled with AVX2 (4 f64 per register) and fused multiply-add.
///
/// # Safety
/// The CPU must have AVX2 and FMA ([`dispatch`] checks it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn block_avx2(
    k: &VolumetricKernel,
    ws: &mut KernelWorkspace,
    poses: &[f64],
    state: &BlockState,
    targets: Option<&RelativeTargets>,
    out: &mut [VolumetricError],
) {
    block::<Fused>(k, ws, poses, state, targets, out)
}

/// One block: error values, both chains, the relative pose and its error against the nominal
/// relative pose at the same set-points, or against `targets`. A block of fewer than [`LANES`] poses
/// repeats its last pose in the unused lanes.
#[inline(always)]
fn block<M: MulAdd>(
    k: &VolumetricKernel,
    ws: &mut KernelWorkspace,
    poses: &[f64],
    state: &BlockState,
    targets: Option<&RelativeTargets>,
    out: &mut [VolumetricError],
) {
    let n_axes = k.machine.axis_count().max(1);
    let n = poses.len() / n_axes;
    debug_assert!((1..=LANES).contains(&n) && out.len() >= n);
    for l in 0..LANES {
        let pose = &poses[l.min(n - 1) * n_axes..][..n_axes];
        for (a, &q) in pose.iter().enumerate() {
            ws.q[a][l] = q;
        }
    }
    error_values(k, ws, poses, n, state);
    let (tool_nominal, tool) = chain::<M>(&k.tool_steps, &ws.q, &ws.values);
    let (work_nominal, work) = chain::<M>(&k.work_steps, &ws.q, &ws.values);
    let offset = |index: Option<usize>, point: &Vec3| {
        let mut p = splat_vec(point);
        if let Some(i) = index {
            p = add(&p, &[ws.values[i], ws.values[i + 1], ws.values[i + 2]]);
        }
        p
    };
    let (tool_point, work_point) = (splat_vec(&k.setup.tool_point), splat_vec(&k.setup.work_point));
    let tool_point_actual = tool.transform_point::<M>(&offset(k.tool_offset, &k.setup.tool_point));
    let work_point_actual = work.transform_point::<M>(&offset(k.work_offset, &k.setup.work_point));
    let (r_nominal, relative_nominal) = match targets {
        Some(t) => (t.position, t.rotation),
        None => (
            mat_t_vec::<M>(
                &work_nominal.rotation,
                &sub(&tool_nominal.transform_point::<M>(&tool_point), &work_nominal.transform_point::<M>(&work_point)),
            ),
            mat_t_mul::<M>(&work_nominal.rotation, &tool_nominal.rotation),
        ),
    };
    let r_actual = mat_t_vec::<M>(&work.rotation, &sub(&tool_point_actual, &work_point_actual));
    let position = sub(&r_actual, &r_nominal);
    let relative_actual = mat_t_mul::<M>(&work.rotation, &tool.rotation);
    let orientation = rotation_log_lanes::<M>(&mat_mul_t::<M>(&relative_actual, &relative_nominal));
    let norms: Lanes = {
        let (a, b) = (norm::<M>(&r_actual), norm::<M>(&r_nominal));
        std::array::from_fn(|l| a[l] + b[l])
    };
    let projection = dot::<M>(&position, &add(&r_actual, &r_nominal));
    let length: Lanes = std::array::from_fn(|l| if norms[l] > 0.0 { projection[l] / norms[l] } else { 0.0 });
    let (position, orientation) = match k.frame {
        Frame::Workpiece => (position, orientation),
        Frame::Machine => (mat_vec::<M>(&work_nominal.rotation, &position), mat_vec::<M>(&work_nominal.rotation, &orientation)),
    };
    for (l, o) in out.iter_mut().enumerate().take(n) {
        *o = VolumetricError {
            position: Vec3::new(position[0][l], position[1][l], position[2][l]),
            orientation: Vec3::new(orientation[0][l], orientation[1][l], orientation[2][l]),
            length: length[l],
        };
    }
}

/// The parameter values of the block's poses into `ws.values`: constants, tables over the lanes,
/// then the state-dependent part pose by pose (the scalar code of
/// [`ErrorModel::add_state_dependent`], on each pose's own parameter vector).
#[inline(always)]
fn error_values(k: &VolumetricKernel, ws: &mut KernelWorkspace, poses: &[f64], n: usize, state: &BlockState) {
    for &(i, c) in &k.live {
        ws.values[i] = splat(c);
    }
    for (index, axis, f) in k.errors.position_plan().1 {
        f.add_lanes(&ws.q[*axis], &mut ws.values[*index]);
    }
    if k.state_dependent.is_empty() {
        return;
    }
    let n_axes = k.machine.axis_count().max(1);
    let n_inputs = k.errors.sensors().len();
    for l in 0..LANES {
        let p = l.min(n - 1);
        let q = &poses[p * n_axes..][..n_axes];
        let pose_state = MachineState {
            directions: state.directions.map(|d| &d[p * n_axes..][..n_axes]),
            temperatures: if n_inputs > 0 && !state.temperatures.is_empty() {
                &state.temperatures[p * n_inputs..][..n_inputs]
            } else {
                &[]
            },
        };
        for &i in &k.state_dependent {
            ws.row[i] = ws.values[i][l];
        }
        k.errors.add_state_dependent(k.machine, q, &pose_state, &mut ws.row);
        for &i in &k.state_dependent {
            ws.values[i][l] = ws.row[i];
        }
    }
}

/// The nominal and the actual pose of the end of a chain, as `nominal_and_actual_chain`: the
/// products start from the first factor (the identity is not multiplied).
#[inline(always)]
fn chain<M: MulAdd>(steps: &[Step], q: &[Lanes], values: &[Lanes]) -> (LanePose, LanePose) {
    let (mut nominal, mut actual): (Option<LanePose>, Option<LanePose>) = (None, None);
    let then = |pose: &mut Option<LanePose>, factor: &LanePose| {
        *pose = Some(match pose {
            Some(p) => p.then::<M>(factor),
            None => *factor,
        })
    };
    for step in steps {
        match step {
            Step::Error(d) => {
                let factor = match d {
                    Displacement::Fixed(pose) => **pose,
                    Displacement::Varying { start, centre } => {
                        let v = &values[*start..*start + 6];
                        small_transform::<M>(&[v[3], v[4], v[5]], &[v[0], v[1], v[2]], &centre_lanes::<M>(centre, q))
                    }
                    Displacement::FixedAlong { rotation, e, centre } => {
                        let c = centre_lanes::<M>(centre, q);
                        LanePose { rotation: **rotation, translation: sub(&add(&c, e), &mat_vec::<M>(rotation, &c)) }
                    }
                };
                then(&mut actual, &factor);
            }
            Step::Translate { axis, direction } => {
                let t: LaneVec = std::array::from_fn(|i| std::array::from_fn(|l| direction[i] * q[*axis][l]));
                for pose in [&mut nominal, &mut actual] {
                    *pose = Some(match pose {
                        Some(p) => p.then_translation::<M>(&t),
                        None => LanePose { rotation: LanePose::IDENTITY.rotation, translation: t },
                    });
                }
            }
            Step::Rotate { axis, direction, point } => {
                let rotation = rotation_about_axis::<M>(direction, &q[*axis]);
                let motion = LanePose { rotation, translation: sub(point, &mat_vec::<M>(&rotation, point)) };
                then(&mut nominal, &motion);
                then(&mut actual, &motion);
            }
        }
    }
    (nominal.unwrap_or(LanePose::IDENTITY), actual.unwrap_or(LanePose::IDENTITY))
}

/// The centre of a small transform per lane.
#[inline(always)]
fn centre_lanes<M: MulAdd>(centre: &Centre, q: &[Lanes]) -> LaneVec {
    match centre {
        Centre::Constant(c) => splat_vec(c),
        Centre::Along { axis, point, direction } => {
            let mut c = [splat(0.0); 3];
            for i in 0..3 {
                for l in 0..LANES {
                    c[i][l] = M::mul_add(direction[i], q[*axis][l], point[i]);
                }
            }
            c
        }
    }
}
