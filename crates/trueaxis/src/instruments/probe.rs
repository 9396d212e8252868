//! Probed points and hole plates (Soons 1993 §4.2, §5.1.1): the machine, used as a measuring machine,
//! probes points of a calibrated artefact. Reading: measured minus calibrated coordinates (mm) in the
//! workpiece frame, the negative of the volumetric error of the probe tip (Soons 1993 eq. 2.31).
//!
//! A plate clamped on the table is never exactly where it is assumed: its small rigid misalignment
//! (three translations and three rotations about a plate centre) is estimated with the machine
//! parameters ("best-fit plate misalignment removed") through [`plate_rows`].

use crate::geometry::{Pose, Vec3};
use crate::machine::Machine;
use crate::model::{volumetric_error, Frame, Setup};

/// A probing setup: `setup.tool_point` is the probe tip at home, `setup.work_point` the origin of
/// the artefact coordinates (both in M at home, mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    pub setup: Setup,
}

impl Probe {
    /// Exact reading `dx dy dz` (mm) at pose `q` (mm, rad) with the parameter vector `params`.
    pub fn exact(&self, machine: &Machine, q: &[f64], params: &[f64]) -> [f64; 3] {
        let p = volumetric_error(machine, q, params, &self.setup, Frame::Workpiece).position;
        [-p.x, -p.y, -p.z]
    }

    /// First-order rows: minus the position rows of the workpiece-frame Jacobian.
    pub fn linear_rows(jacobian: &[f64], p: usize, out: &mut [f64]) {
        for (o, j) in out.iter_mut().zip(&jacobian[..3 * p]) {
            *o = -j;
        }
    }
}

/// Rows (3 x 6, row-major, mm per mm or rad) of the plate misalignment at a nominal point `point`
/// (workpiece frame, mm): a small rigid displacement of the plate, translations `t` then rotations
/// `w` about `centre`, moves the point by `t + w x (point - centre)`, which the probe reads.
pub fn plate_rows(point: &Vec3, centre: &Vec3) -> [f64; 18] {
    let r = point - centre;
    // columns: tx ty tz wx wy wz; w x r = [0 r.z -r.y; -r.z 0 r.x; r.y -r.x 0] w
    [1.0, 0.0, 0.0, 0.0, r.z, -r.y, 0.0, 1.0, 0.0, -r.z, 0.0, r.x, 0.0, 0.0, 1.0, r.y, -r.x, 0.0]
}

/// Exact displacement (mm) of the nominal point `point` by the plate misalignment `t` (mm) and `w`
/// (rotation vector, rad) about `centre`.
pub fn plate_displacement(point: &Vec3, centre: &Vec3, t: &Vec3, w: &Vec3) -> Vec3 {
    Pose::small_transform(w, t, centre).transform_point(point) - point
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plate_rows_are_the_derivative_of_the_exact_displacement() {
        let (point, centre) = (Vec3::new(120.0, -40.0, 15.0), Vec3::new(50.0, 10.0, 0.0));
        let rows = plate_rows(&point, &centre);
        let (t, w) = (Vec3::new(2e-3, -1e-3, 5e-4), Vec3::new(3e-6, -2e-6, 8e-6));
        let exact = plate_displacement(&point, &centre, &t, &w);
        let params = [t.x, t.y, t.z, w.x, w.y, w.z];
        for i in 0..3 {
            let linear: f64 = (0..6).map(|c| rows[i * 6 + c] * params[c]).sum();
            // second order: |w|^2 |r| ~ 1e-10 * 140 mm
            assert!((linear - exact[i]).abs() < 1e-8, "{i}: {linear} vs {}", exact[i]);
        }
    }
}
