//! The sensitivity (error-gain) matrix `SE` of Zhu 2008 eqs. B.1-B.2: `VE = SE e`, the tool-point
//! position error `VE` (um) for component errors `e` (um, urad). It is the derivative of the exact
//! chain at zero errors, i.e. the first-order model of [`crate::model::jacobian`] (Soons 1993 eq.
//! 2.24), restricted to the position rows and the budget's components; the tests check it against
//! central differences of [`crate::model::volumetric_error`].

use super::components::BudgetComponent;
use crate::geometry::Vec3;
use crate::machine::Machine;
use crate::model::{jacobian, Frame, JacobianWorkspace, Setup, JACOBIAN_ROWS};
use rayon::prelude::*;

/// Sensitivity matrices at many poses: `3 x n` per pose (rows dx, dy, dz; columns the components),
/// in um per um (linear errors) or um per urad (angular and squareness errors).
#[derive(Clone, Debug)]
pub struct Sensitivity {
    pub components: usize,
    /// Row-major, pose after pose: `values[(3 p + d) n + j]`.
    pub values: Vec<f64>,
}

impl Sensitivity {
    pub fn poses(&self) -> usize {
        self.values.len() / (3 * self.components.max(1))
    }

    /// Row `d` (0 = x, 1 = y, 2 = z) of pose `p`.
    pub fn row(&self, p: usize, d: usize) -> &[f64] {
        let n = self.components;
        &self.values[(3 * p + d) * n..(3 * p + d + 1) * n]
    }

    /// Column `j` of pose `p`: the error vector (um) of a unit component error.
    pub fn column(&self, p: usize, j: usize) -> Vec3 {
        Vec3::new(self.row(p, 0)[j], self.row(p, 1)[j], self.row(p, 2)[j])
    }

    /// The `3 x n` matrix of pose `p`, row-major.
    pub fn pose(&self, p: usize) -> &[f64] {
        let n = self.components;
        &self.values[3 * p * n..3 * (p + 1) * n]
    }
}

/// The sensitivity matrix of `components` at each pose of `poses` (`machine.axis_count()` values per
/// pose, internal units mm and rad), for the tool point and workpiece point of `setup`, with the
/// error expressed in `frame`. Parallel over poses.
pub fn sensitivity(machine: &Machine, components: &[BudgetComponent], poses: &[f64], setup: &Setup, frame: Frame) -> Sensitivity {
    let n = components.len();
    let axes = machine.axis_count().max(1);
    let count = poses.len() / axes;
    let columns = machine.parameter_count();
    let mut values = vec![0.0; 3 * n * count];
    values.par_chunks_mut((3 * n).max(1)).zip(poses.par_chunks(axes)).for_each_init(
        || (JacobianWorkspace::default(), vec![0.0; JACOBIAN_ROWS * columns]),
        |(ws, full), (out, q)| {
            jacobian(machine, q, setup, frame, ws, full);
            for d in 0..3 {
                for (j, c) in components.iter().enumerate() {
                    // mm per mm is um per um; mm per rad is 1e3 um per 1e6 urad
                    let unit = if c.id.component().is_rotation() { 1e-3 } else { 1.0 };
                    out[d * n + j] = full[d * columns + c.index] * unit;
                }
            }
        },
    );
    Sensitivity { components: n, values }
}
