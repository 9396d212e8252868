//! The first-order model: the Jacobian of the volumetric error with respect to every error
//! parameter, by transporting each error's small-displacement screw to the tool point
//! (Soons 1993 eqs. 2.15-2.28, the F-matrix `e = F E` of eq. 2.24; Andolfatto et al. 2011 eq. 2).

use super::chain::{error_centre, nominal_chain};
use super::volumetric::{Frame, Setup};
use crate::geometry::{Pose, Twist, Vec3};
use crate::machine::{Component, Machine, SetupSide};

/// Rows of one pose's Jacobian: `dx dy dz drx dry drz dL`.
pub const JACOBIAN_ROWS: usize = 7;

/// Reusable buffers for Jacobian evaluation (the parent frames of each chain).
#[derive(Default, Clone)]
pub struct JacobianWorkspace {
    tool_parents: Vec<Pose>,
    work_parents: Vec<Pose>,
}

/// Fills `out` (row-major, `JACOBIAN_ROWS x machine.parameter_count()`) with the derivatives of
/// the volumetric error at pose `q` (mm, rad): rows in mm (position, dL) or rad (orientation) per
/// mm or rad of parameter. Column order is the parameter vector of [`Machine::parameter_index`].
///
/// For an error with rotation `eps` and translation `e` about point `c` in a parent frame with nominal
/// pose `F`, the world twist is `omega = R_F eps`, `v = R_F e - omega x F(c)`; the tool point moves
/// by `omega x P_t + v`. Workpiece-side errors enter with the opposite sign, and the result is rotated
/// into the workpiece frame by `R_w^T` unless `frame` is the machine frame. The `dL` row is the
/// projection on the unit vector from the workpiece point to the tool point (zero where they
/// coincide).
pub fn jacobian(machine: &Machine, q: &[f64], setup: &Setup, frame: Frame, ws: &mut JacobianWorkspace, out: &mut [f64]) {
    let n = machine.parameter_count();
    assert_eq!(out.len(), JACOBIAN_ROWS * n, "Jacobian buffer must hold 7 rows of {n} parameters");
    let tool = nominal_chain(machine, machine.tool_chain(), q, Some(&mut ws.tool_parents));
    let work = nominal_chain(machine, machine.work_chain(), q, Some(&mut ws.work_parents));
    let tool_point = tool.transform_point(&setup.tool_point);
    let work_point = work.transform_point(&setup.work_point);
    let to_output = match frame {
        Frame::Workpiece => work.rotation.transpose(),
        Frame::Machine => nalgebra::Matrix3::identity(),
    };
    let separation = tool_point - work_point;
    let unit = if separation.norm() > 0.0 { to_output * separation / separation.norm() } else { Vec3::zeros() };

    let mut write = |column: usize, position: Vec3, rotation: Vec3| {
        for i in 0..3 {
            out[i * n + column] = position[i];
            out[(3 + i) * n + column] = rotation[i];
        }
        out[6 * n + column] = unit.dot(&position);
    };

    for (chain, parents, sign) in [(machine.tool_chain(), &ws.tool_parents, 1.0), (machine.work_chain(), &ws.work_parents, -1.0)] {
        for (&k, parent) in chain.iter().zip(parents.iter()) {
            let axis = &machine.axes()[k];
            for motion in [false, true] {
                let centre = error_centre(axis, motion, q[k]);
                for component in Component::ALL {
                    let (eps, e) = component.unit_displacement();
                    let twist = Twist::of_small_transform(parent, &eps, &e, &centre);
                    let column = if motion { machine.motion_index(k, component) } else { machine.location_index(k, component) };
                    write(column, to_output * twist.displacement_of(&tool_point) * sign, to_output * twist.omega * sign);
                }
            }
        }
    }
    for d in 0..3 {
        let component = Component::from_index(d);
        write(machine.setup_index(SetupSide::Tool, component), to_output * tool.rotation.column(d), Vec3::zeros());
        write(machine.setup_index(SetupSide::Workpiece, component), -(to_output * work.rotation.column(d)), Vec3::zeros());
    }
}
