//! Evaluation over many poses: a [`Predictor`] binds a machine, its error model and a setup; batch
//! functions split the poses over threads with rayon, one workspace per thread; volumetric errors
//! by the batch kernel of [`super::kernel`].

use super::jacobian::{jacobian, JacobianWorkspace, JACOBIAN_ROWS};
use super::kernel::{BlockState, KernelWorkspace, VolumetricKernel};
use super::lanes::LANES;
use super::volumetric::{volumetric_error, Frame, Setup, VolumetricError};
use crate::error_model::{Direction, ErrorModel};
use crate::machine::Machine;
use rayon::prelude::*;

/// Predicts volumetric errors of one machine with one error model.
pub struct Predictor<'a> {
    pub machine: &'a Machine,
    pub errors: &'a ErrorModel,
    pub setup: Setup,
    pub frame: Frame,
}

impl<'a> Predictor<'a> {
    pub fn new(machine: &'a Machine, errors: &'a ErrorModel) -> Self {
        Predictor { machine, errors, setup: Setup::of_machine(machine), frame: Frame::Workpiece }
    }

    /// Exact volumetric error at pose `q` (mm, rad); `values` is a buffer of
    /// `machine.parameter_count()` reused between calls.
    pub fn predict_with(&self, q: &[f64], values: &mut [f64]) -> VolumetricError {
        self.errors.values_at(self.machine, q, values);
        volumetric_error(self.machine, q, values, &self.setup, self.frame)
    }

    /// Exact volumetric error at pose `q` (mm, rad).
    pub fn predict(&self, q: &[f64]) -> VolumetricError {
        self.predict_with(q, &mut vec![0.0; self.machine.parameter_count()])
    }

    /// Exact volumetric errors at many poses: `poses` holds `axis_count` positions (mm, rad) per
    /// pose, in canonical axis order; at rest and at the reference temperature. Parallel over poses.
    pub fn predict_batch(&self, poses: &[f64]) -> Vec<VolumetricError> {
        self.predict_states(poses, None, &[])
    }

    /// As [`Predictor::predict_batch`] with, per pose, the directions of motion (`axis_count` per
    /// pose) and the temperatures of the model's sensors (`errors.sensors().len()` per pose, degC).
    ///
    /// Evaluated by the batch kernel ([`VolumetricKernel`]: blocks of poses as structure of
    /// arrays, the instruction set chosen at run time), in parallel over chunks of poses; the
    /// results equal those of [`Predictor::predict_with`] pose by pose to rounding.
    pub fn predict_states(&self, poses: &[f64], directions: Option<&[Option<Direction>]>, temperatures: &[f64]) -> Vec<VolumetricError> {
        let n_axes = self.machine.axis_count().max(1);
        let kernel = VolumetricKernel::new(self.machine, self.errors, &self.setup, self.frame);
        let mut out = vec![VolumetricError::default(); poses.len() / n_axes];
        self.by_blocks(
            &mut out,
            1,
            &kernel,
            || (),
            |ws, _, range, out| {
                let state = self.block_state(range.clone(), directions, temperatures);
                kernel.evaluate_block(ws, &poses[range.start * n_axes..range.end * n_axes], &state, out);
            },
        );
        out
    }

    /// As [`Predictor::predict_states`], written in place: `user` holds the positions in the
    /// machine's units (mm, deg; `axis_count` per pose, the axis order of the machine file) and
    /// `out` receives per pose the first `columns` (1..=7) of
    /// [`VolumetricError::to_user_units`]: dx dy dz (um), drx dry drz (urad), dL (um), row-major.
    /// Nothing of the size of the batch is allocated: each block of poses is converted to mm and
    /// rad, evaluated and written out while it is in cache. For a caller that owns the output
    /// array (the Python binding's numpy array).
    pub fn predict_user_into(
        &self,
        user: &[f64],
        directions: Option<&[Option<Direction>]>,
        temperatures: &[f64],
        columns: usize,
        out: &mut [f64],
    ) {
        assert!((1..=7).contains(&columns), "predict_user_into: 1 to 7 columns, got {columns}");
        let n_axes = self.machine.axis_count().max(1);
        assert_eq!(out.len() * n_axes, user.len() * columns, "predict_user_into: one output row per pose");
        let kernel = VolumetricKernel::new(self.machine, self.errors, &self.setup, self.frame);
        let scratch = || (vec![0.0; LANES * n_axes], [VolumetricError::default(); LANES]);
        self.by_blocks(out, columns, &kernel, scratch, |ws, (q, errors), range, out| {
            let q = &mut q[..range.len() * n_axes];
            for (u, q) in user[range.start * n_axes..range.end * n_axes].chunks(n_axes).zip(q.chunks_mut(n_axes)) {
                self.machine.pose_to_internal(u, q);
            }
            let errors = &mut errors[..range.len()];
            kernel.evaluate_block(ws, q, &self.block_state(range, directions, temperatures), errors);
            for (e, row) in errors.iter().zip(out.chunks_mut(columns)) {
                row.copy_from_slice(&e.to_user_units()[..columns]);
            }
        });
    }

    /// The directions and temperatures of the poses `range` (see [`Predictor::predict_states`]).
    fn block_state<'s>(
        &self,
        range: std::ops::Range<usize>,
        directions: Option<&'s [Option<Direction>]>,
        temperatures: &'s [f64],
    ) -> BlockState<'s> {
        let n_axes = self.machine.axis_count().max(1);
        let n_inputs = self.errors.sensors().len();
        BlockState {
            directions: directions.map(|d| &d[range.start * n_axes..range.end * n_axes]),
            temperatures: if n_inputs > 0 && !temperatures.is_empty() {
                &temperatures[range.start * n_inputs..range.end * n_inputs]
            } else {
                &[]
            },
        }
    }

    /// Runs `block` on every block of [`LANES`] poses of `out` (`stride` items per pose), in
    /// parallel over chunks of whole blocks, with one kernel workspace and one `scratch` per thread.
    fn by_blocks<T: Send, S>(
        &self,
        out: &mut [T],
        stride: usize,
        kernel: &VolumetricKernel,
        scratch: impl Fn() -> S + Sync + Send,
        block: impl Fn(&mut KernelWorkspace, &mut S, std::ops::Range<usize>, &mut [T]) + Sync + Send,
    ) {
        let n = out.len() / stride;
        // chunks of whole blocks, enough of them for the threads to share the work evenly
        let chunk = LANES * (n / (LANES * 8 * rayon::current_num_threads().max(1))).clamp(1, 64);
        out.par_chunks_mut(chunk * stride).enumerate().for_each_init(
            || (kernel.workspace(), scratch()),
            |(ws, s), (c, out)| {
                let first = c * chunk;
                for (b, out) in out.chunks_mut(LANES * stride).enumerate() {
                    let start = first + b * LANES;
                    block(ws, s, start..start + out.len() / stride, out);
                }
            },
        );
    }
}

/// Jacobians of many poses stacked: `7 * n_poses` rows by `machine.parameter_count()` columns,
/// row-major, the rows of pose `i` at `7 i .. 7 i + 7` (see [`jacobian`]). Parallel over poses.
pub fn jacobian_batch(machine: &Machine, poses: &[f64], setup: &Setup, frame: Frame) -> Vec<f64> {
    let n_axes = machine.axis_count().max(1);
    let block = JACOBIAN_ROWS * machine.parameter_count();
    let mut out = vec![0.0; block * (poses.len() / n_axes)];
    out.par_chunks_mut(block)
        .zip(poses.par_chunks(n_axes))
        .for_each_init(JacobianWorkspace::default, |ws, (rows, q)| jacobian(machine, q, setup, frame, ws, rows));
    out
}
