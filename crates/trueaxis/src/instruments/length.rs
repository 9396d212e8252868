//! Length instruments.
//!
//! - [`Length`]: the distance between a tool-side and a workpiece-side point at one pose: a
//!   telescoping ballbar, a laser in distance mode, a machine checking gauge swung about a pivot
//!   (Soons 1993 §5.2.2). Reading `dL = |actual| - |nominal|` (docs/design.md, Conventions), the projection of
//!   the volumetric error on the bar direction to first order.
//! - [`PointLength`]: a length measured by the machine itself between two probed points at two poses
//!   (a bar or step gauge on a CMM or a probing machine tool, Soons 1993 eqs. 4.3-4.5 and 4.19-4.21).
//!   Reading: measured minus calibrated length. A measuring machine reads the negative of its
//!   positioning error (Soons 1993 eq. 2.31), so to first order `dL = -u . (delta_2 - delta_1)`.

use super::measurement::nominal_vector;
use crate::geometry::Vec3;
use crate::machine::Machine;
use crate::model::{volumetric_error, Frame, Setup};

/// Length between the setup's tool point and workpiece point at one pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Length {
    pub setup: Setup,
}

impl Length {
    /// Exact `dL` (mm) at pose `q` (mm, rad) with the parameter vector `params` (mm, rad).
    pub fn exact(&self, machine: &Machine, q: &[f64], params: &[f64]) -> f64 {
        volumetric_error(machine, q, params, &self.setup, Frame::Workpiece).length
    }
}

/// Length between the tool point (probe tip) at two poses, measured by the machine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLength {
    pub setup: Setup,
}

impl PointLength {
    /// Exact reading (mm): `|N2 - N1| - |A2 - A1|` with `N_i` the nominal and `A_i = N_i + delta_i`
    /// the actual tip positions relative to the workpiece, in the workpiece frame (the machine reports
    /// the nominal positions while the artefact sits where the actual tip touched it).
    pub fn exact(&self, machine: &Machine, poses: [&[f64]; 2], params: [&[f64]; 2]) -> f64 {
        let nominal = poses.map(|q| nominal_vector(machine, q, &self.setup));
        let actual: Vec<Vec3> =
            (0..2).map(|i| nominal[i] + volumetric_error(machine, poses[i], params[i], &self.setup, Frame::Workpiece).position).collect();
        (nominal[1] - nominal[0]).norm() - (actual[1] - actual[0]).norm()
    }

    /// First-order row `-u . (J_2 - J_1)` (Soons 1993 eq. 4.5 with the sign of eq. 2.31), `u` the
    /// unit vector from `n1` to `n2`, from the workpiece-frame Jacobians of the two poses.
    pub fn linear_row(j1: &[f64], j2: &[f64], n1: &Vec3, n2: &Vec3, p: usize, out: &mut [f64]) {
        let d = n2 - n1;
        let u = if d.norm() > 0.0 { d / d.norm() } else { Vec3::zeros() };
        for (c, o) in out.iter_mut().enumerate() {
            *o = -(0..3).map(|i| u[i] * (j2[i * p + c] - j1[i * p + c])).sum::<f64>();
        }
    }
}
