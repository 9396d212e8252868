//! Corrections of many poses at once (volumetric grids, axis tables, a file of poses): the solve of
//! [`super::correction`], cold-started at every pose as [`Corrector::correct_state`] does, with the
//! exact residuals of [`LANES`] poses at a time from the batch kernel
//! ([`crate::model::VolumetricKernel`]) instead of the scalar chain pose by pose.
//!
//! The poses of a block iterate in lock step: each is linearised on its own (the nominal chain and
//! its joint Jacobian, scalar), then every iteration evaluates the actual relative pose at the
//! corrected set-points of all the block's poses in one kernel call, against each pose's nominal
//! target, until every pose has ended its solve. A pose that has ended is carried along (its lane is
//! evaluated and ignored), so a block costs as many kernel calls as its slowest pose needs; on a
//! grid, neighbouring poses need the same number. The results equal those of `correct_state` pose
//! by pose to rounding (the kernel agrees with the scalar chain to 1e-9 um).

use super::correction::{Correction, CorrectionWorkspace, Corrector, Iteration, Next, Target};
use super::solve::{Joints, Solver, MAX_AXES};
use crate::error_model::Direction;
use crate::geometry::Vec3;
use crate::model::{set_mat_lane, BlockState, Frame, RelativeTargets, VolumetricError, VolumetricKernel, LANES};
use rayon::prelude::*;

/// The corrections of many poses: `poses` holds `axis_count` positions (mm, rad, canonical order)
/// per pose. `directions` (the direction of motion of each axis) and `temperatures` (the model's
/// sensors, degC) are given either per pose (`axis_count`, `sensors().len()` values per pose) or
/// once for all poses (`axis_count`, `sensors().len()` values); `None` / empty: at rest, at the
/// reference temperature. Parallel over blocks of poses; each result as
/// [`Corrector::correct_state`] of that pose and state.
pub fn correct_batch(
    corrector: &Corrector,
    poses: &[f64],
    directions: Option<&[Option<Direction>]>,
    temperatures: &[f64],
) -> Vec<Correction> {
    let machine = corrector.machine;
    let n_axes = machine.axis_count().max(1);
    let n_inputs = corrector.errors.sensors().len();
    let n = poses.len() / n_axes;
    let kernel = VolumetricKernel::new(machine, corrector.errors, &corrector.setup, Frame::Workpiece);
    let states = States::new(directions, temperatures, n_axes, n_inputs, n);
    let mut out = vec![empty_correction(n_axes); n];
    // chunks of whole blocks, enough of them for the threads to share the work evenly
    let chunk = LANES * (n / (LANES * 8 * rayon::current_num_threads().max(1))).clamp(1, 64);
    out.par_chunks_mut(chunk).enumerate().for_each_init(
        || BlockWorkspace::new(corrector, &kernel),
        |ws, (c, out)| {
            for (b, out) in out.chunks_mut(LANES).enumerate() {
                let first = c * chunk + b * LANES;
                let range = first..first + out.len();
                states.copy_block(range.clone(), ws);
                correct_block(corrector, &kernel, &poses[range.start * n_axes..range.end * n_axes], ws, out);
            }
        },
    );
    out
}

/// The per-pose or shared states of a batch.
struct States<'s> {
    directions: Option<&'s [Option<Direction>]>,
    temperatures: &'s [f64],
    per_pose: (bool, bool),
    n_axes: usize,
    n_inputs: usize,
}

impl<'s> States<'s> {
    fn new(directions: Option<&'s [Option<Direction>]>, temperatures: &'s [f64], n_axes: usize, n_inputs: usize, n: usize) -> Self {
        let per_pose = (directions.is_some_and(|d| d.len() == n * n_axes && n > 1), temperatures.len() == n * n_inputs && n > 1);
        if let Some(d) = directions {
            assert!(per_pose.0 || d.len() == n_axes, "{} directions for {n} poses of {n_axes} axes", d.len());
        }
        assert!(
            per_pose.1 || temperatures.is_empty() || temperatures.len() == n_inputs,
            "{} temperatures for {n} poses and {n_inputs} sensors",
            temperatures.len()
        );
        States { directions, temperatures: if n_inputs > 0 { temperatures } else { &[] }, per_pose, n_axes, n_inputs }
    }

    /// The states of the poses `range` into the workspace's block buffers (`LANES` poses' worth;
    /// the kernel reads those of the block's poses).
    fn copy_block(&self, range: std::ops::Range<usize>, ws: &mut BlockWorkspace) {
        let (na, ni) = (self.n_axes, self.n_inputs);
        for (l, p) in range.enumerate() {
            if let Some(d) = self.directions {
                let from = if self.per_pose.0 { p * na } else { 0 };
                ws.directions[l * na..(l + 1) * na].copy_from_slice(&d[from..from + na]);
            }
            if !self.temperatures.is_empty() {
                let from = if self.per_pose.1 { p * ni } else { 0 };
                ws.temperatures[l * ni..(l + 1) * ni].copy_from_slice(&self.temperatures[from..from + ni]);
            }
        }
        ws.has_directions = self.directions.is_some();
        ws.has_temperatures = !self.temperatures.is_empty();
    }
}

/// The buffers of one thread.
struct BlockWorkspace {
    kernel: crate::model::KernelWorkspace,
    correction: CorrectionWorkspace,
    /// Directions and temperatures of the block's poses, `LANES` poses' worth.
    directions: Vec<Option<Direction>>,
    temperatures: Vec<f64>,
    has_directions: bool,
    has_temperatures: bool,
    /// The set-points the kernel evaluates (mm, rad), `axis_count` per pose.
    set_points: Vec<f64>,
    residuals: [VolumetricError; LANES],
}

impl BlockWorkspace {
    fn new(corrector: &Corrector, kernel: &VolumetricKernel) -> Self {
        let n_axes = corrector.machine.axis_count().max(1);
        BlockWorkspace {
            kernel: kernel.workspace(),
            correction: CorrectionWorkspace::new(corrector.machine),
            directions: vec![None; LANES * n_axes],
            temperatures: vec![0.0; LANES * corrector.errors.sensors().len()],
            has_directions: false,
            has_temperatures: false,
            set_points: vec![0.0; LANES * n_axes],
            residuals: [VolumetricError::default(); LANES],
        }
    }
}

/// The corrections of up to [`LANES`] poses (`q`, `axis_count` each, mm, rad) in the states copied
/// into `ws`, into `out` (one per pose).
fn correct_block(corrector: &Corrector, kernel: &VolumetricKernel, q: &[f64], ws: &mut BlockWorkspace, out: &mut [Correction]) {
    let n_axes = corrector.machine.axis_count().max(1);
    let n = out.len();
    // lane l holds pose min(l, n - 1), as the kernel fills a short block
    let linearised: [(Target, Solver); LANES] =
        std::array::from_fn(|l| corrector.linearise(&q[l.min(n - 1) * n_axes..][..n_axes], &mut ws.correction));
    let mut targets = RelativeTargets::default();
    for (l, (target, _)) in linearised.iter().enumerate() {
        for i in 0..3 {
            targets.position[i][l] = target.position[i];
        }
        set_mat_lane(&mut targets.rotation, l, &target.rotation);
    }
    let set_points = &mut ws.set_points[..n * n_axes];
    set_points.copy_from_slice(q);
    let state = BlockState {
        directions: ws.has_directions.then_some(&ws.directions[..n * n_axes]),
        temperatures: if ws.has_temperatures { &ws.temperatures[..n * ws.temperatures.len() / LANES] } else { &[] },
    };
    kernel.residual_block(&mut ws.kernel, set_points, &state, &targets, &mut ws.residuals[..n]);
    let residual = |e: &VolumetricError| (e.position, e.orientation);
    let mut iterations: [Option<Iteration>; LANES] = Default::default();
    for (iteration, r) in iterations.iter_mut().zip(&ws.residuals[..n]) {
        *iteration = Some(Iteration::start(Joints::zeros(), residual(r), false));
    }
    let mut pending: [Option<Joints>; LANES] = [None; LANES];
    loop {
        let mut any = false;
        for p in 0..n {
            let Some(iteration) = iterations[p].as_mut() else { continue };
            let (target, solver) = &linearised[p];
            match iteration.step(corrector, solver, target) {
                Next::Evaluate(u) => {
                    for k in 0..corrector.machine.axis_count() {
                        set_points[p * n_axes + k] = q[p * n_axes + k] + u[k] * corrector.weight(k);
                    }
                    pending[p] = Some(u);
                    any = true;
                }
                Next::Done { uncorrectable, .. } => {
                    out[p] = iteration.correction(corrector, uncorrectable);
                    iterations[p] = None;
                }
            }
        }
        if !any {
            return;
        }
        kernel.residual_block(&mut ws.kernel, set_points, &state, &targets, &mut ws.residuals[..n]);
        for p in 0..n {
            if let (Some(u), Some(iteration)) = (pending[p].take(), iterations[p].as_mut()) {
                iteration.checked(u, residual(&ws.residuals[p]));
            }
        }
    }
}

/// A placeholder result, overwritten by every block.
fn empty_correction(axis_count: usize) -> Correction {
    Correction {
        dq: [0.0; MAX_AXES],
        axis_count,
        original_position: Vec3::zeros(),
        original_orientation: Vec3::zeros(),
        residual_position: Vec3::zeros(),
        residual_orientation: Vec3::zeros(),
        uncorrectable_orientation: Vec3::zeros(),
        iterations: 0,
        evaluations: 0,
        converged: false,
    }
}
