//! The exact volumetric error between a tool-side point and a workpiece-side point
//! (docs/design.md, Conventions, "Volumetric error").

use super::chain::nominal_and_actual_chain;
use crate::geometry::{rotation_log, Mat3, Pose, Vec3};
use crate::machine::{Component, Machine, SetupSide};

/// The two points whose relative position is evaluated, in M at home (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// A point carried by the tool-side chain (the tool point, a spindle ball).
    pub tool_point: Vec3,
    /// A point carried by the workpiece-side chain (the workpiece origin, a master ball, a pivot).
    pub work_point: Vec3,
}

impl Setup {
    /// The machine's tool point and the workpiece origin (the `predict` defaults).
    pub fn of_machine(machine: &Machine) -> Setup {
        Setup { tool_point: machine.tool_point, work_point: Vec3::zeros() }
    }
}

/// The frame the components of a volumetric error are expressed in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Frame {
    /// The workpiece body frame (default).
    #[default]
    Workpiece,
    /// The machine frame M: the workpiece-frame vector rotated by the nominal `T_w`.
    Machine,
}

/// A volumetric error in internal units.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct VolumetricError {
    /// Tool point relative to the workpiece point, actual minus nominal (mm).
    pub position: Vec3,
    /// Rotation vector of `R_rel,actual R_rel,nominal^T` (rad).
    pub orientation: Vec3,
    /// `|actual| - |nominal|` of the vector from the workpiece point to the tool point (mm).
    pub length: f64,
}

impl VolumetricError {
    /// `dx dy dz` (um), `drx dry drz` (urad), `dL` (um): the `predict` columns.
    pub fn to_user_units(&self) -> [f64; 7] {
        let p = self.position * 1e3;
        let o = self.orientation * 1e6;
        [p.x, p.y, p.z, o.x, o.y, o.z, self.length * 1e3]
    }
}

/// Tool-side and workpiece-side poses and points of one chain evaluation.
pub(crate) struct Relative {
    pub tool: Pose,
    pub work: Pose,
    /// Tool point in M (mm).
    pub tool_point: Vec3,
    /// Workpiece point in M (mm).
    pub work_point: Vec3,
}

impl Relative {
    /// Vector from the workpiece point to the tool point, in the workpiece frame.
    fn vector_in_workpiece(&self) -> Vec3 {
        self.work.rotation.transpose() * (self.tool_point - self.work_point)
    }

    /// Tool orientation relative to the workpiece.
    fn rotation(&self) -> Mat3 {
        self.work.rotation.transpose() * self.tool.rotation
    }
}

/// Exact volumetric error at pose `q` (mm, rad) for the parameter vector `params` (mm, rad):
/// the tool point relative to the workpiece point, actual minus nominal, in `frame`
/// (docs/design.md, Conventions; the matrix form of NISTIR 5236 eq. 2.9, `E = T_TOOL^-1 T_WORK`, with the sign
/// of the tool relative to the workpiece).
pub fn volumetric_error(machine: &Machine, q: &[f64], params: &[f64], setup: &Setup, frame: Frame) -> VolumetricError {
    let (tool_nominal, tool) = nominal_and_actual_chain(machine, machine.tool_chain(), q, params);
    let (work_nominal, work) = nominal_and_actual_chain(machine, machine.work_chain(), q, params);
    let nominal = Relative {
        tool_point: tool_nominal.transform_point(&setup.tool_point),
        work_point: work_nominal.transform_point(&setup.work_point),
        tool: tool_nominal,
        work: work_nominal,
    };
    let setup_offset = |side: SetupSide| {
        let i = machine.setup_index(side, Component::X);
        Vec3::new(params[i], params[i + 1], params[i + 2])
    };
    let actual = Relative {
        tool_point: tool.transform_point(&(setup.tool_point + setup_offset(SetupSide::Tool))),
        work_point: work.transform_point(&(setup.work_point + setup_offset(SetupSide::Workpiece))),
        tool,
        work,
    };
    let r_actual = actual.vector_in_workpiece();
    let r_nominal = nominal.vector_in_workpiece();
    let position = r_actual - r_nominal;
    let orientation = rotation_log(&(actual.rotation() * nominal.rotation().transpose()));
    // |a| - |n| = (a - n).(a + n) / (|a| + |n|), without the cancellation of the direct difference
    let norms = r_actual.norm() + r_nominal.norm();
    let length = if norms > 0.0 { position.dot(&(r_actual + r_nominal)) / norms } else { 0.0 };
    match frame {
        Frame::Workpiece => VolumetricError { position, orientation, length },
        Frame::Machine => {
            let r = nominal.work.rotation;
            VolumetricError { position: r * position, orientation: r * orientation, length }
        }
    }
}
