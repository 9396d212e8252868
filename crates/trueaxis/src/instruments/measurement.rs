//! The measurement equations of the instruments used for indirect identification, behind one
//! type: what a record (one data row) of an instrument observes, its first-order rows with respect
//! to the machine's parameter vector, and its exact value on the kinematic chain.
//!
//! Units: internal (mm, rad) throughout; a row holds mm of reading per mm or rad of parameter.

use super::ball3d::Ball3d;
use super::length::{Length, PointLength};
use super::probe::Probe;
use crate::machine::Machine;
use crate::model::{nominal_chain, Frame, Setup, JACOBIAN_ROWS};

/// One indirect instrument with its setup.
#[derive(Clone, Debug, PartialEq)]
pub enum Instrument {
    /// 3D ball: R-test (workpiece frame) or CapBall (machine frame); channels `dx dy dz`.
    Ball3d(Ball3d),
    /// Length between a tool-side and a workpiece-side point at one pose (ballbar, laser
    /// distance, machine checking gauge); channel `dL`.
    Length(Length),
    /// Length between two points probed at two poses (a bar or gauge measured by the machine as a
    /// measuring machine, Soons 1993 eq. 4.5); channel `dL`.
    PointLength(PointLength),
    /// Probed points (hole plates): measured minus calibrated coordinates; channels `dx dy dz`.
    Probe(Probe),
}

impl Instrument {
    /// The name used in campaign files: `ball3d`, `length`, `point_length`, `probe`.
    pub fn kind(&self) -> &'static str {
        match self {
            Instrument::Ball3d(_) => "ball3d",
            Instrument::Length(_) => "length",
            Instrument::PointLength(_) => "point_length",
            Instrument::Probe(_) => "probe",
        }
    }

    /// Names of the data columns a record provides (um).
    pub fn channels(&self) -> &'static [&'static str] {
        match self {
            Instrument::Ball3d(_) | Instrument::Probe(_) => &["dx", "dy", "dz"],
            Instrument::Length(_) | Instrument::PointLength(_) => &["dL"],
        }
    }

    /// Poses per record: 2 for a two-point length, else 1.
    pub fn poses_per_record(&self) -> usize {
        match self {
            Instrument::PointLength(_) => 2,
            _ => 1,
        }
    }

    /// The tool-side and workpiece-side points the instrument relates.
    pub fn setup(&self) -> Setup {
        match self {
            Instrument::Ball3d(b) => b.setup,
            Instrument::Length(l) => l.setup,
            Instrument::PointLength(l) => l.setup,
            Instrument::Probe(p) => p.setup,
        }
    }

    /// The frame of the Jacobian the linear rows are built from.
    pub fn frame(&self) -> Frame {
        match self {
            Instrument::Ball3d(b) => b.frame,
            _ => Frame::Workpiece,
        }
    }

    /// First-order rows of one record: `jacobians[i]` is the `7 x p` Jacobian (row-major, see
    /// [`crate::model::jacobian`]) at pose `i` of the record in [`Instrument::frame`], `nominal[i]`
    /// the nominal tool point relative to the workpiece point in the workpiece frame (mm), from
    /// [`nominal_vector`]; `out` receives `channels().len()` rows of `p` (mm per unit).
    pub fn linear_rows(&self, jacobians: &[&[f64]], nominal: &[crate::geometry::Vec3], p: usize, out: &mut [f64]) {
        debug_assert!(jacobians.iter().all(|j| j.len() == JACOBIAN_ROWS * p));
        match self {
            Instrument::Ball3d(_) => out.copy_from_slice(&jacobians[0][..3 * p]),
            Instrument::Length(_) => out.copy_from_slice(&jacobians[0][6 * p..7 * p]),
            Instrument::PointLength(_) => PointLength::linear_row(jacobians[0], jacobians[1], &nominal[0], &nominal[1], p, out),
            Instrument::Probe(_) => Probe::linear_rows(jacobians[0], p, out),
        }
    }

    /// Exact reading of one record (mm) on the kinematic chain: `poses[i]` (mm, rad) and
    /// `params[i]` (the full parameter vector at that pose, mm, rad).
    pub fn exact(&self, machine: &Machine, poses: &[&[f64]], params: &[&[f64]], out: &mut [f64]) {
        match self {
            Instrument::Ball3d(b) => out.copy_from_slice(&b.exact(machine, poses[0], params[0])),
            Instrument::Length(l) => out[0] = l.exact(machine, poses[0], params[0]),
            Instrument::PointLength(l) => out[0] = l.exact(machine, [poses[0], poses[1]], [params[0], params[1]]),
            Instrument::Probe(p) => out.copy_from_slice(&p.exact(machine, poses[0], params[0])),
        }
    }
}

/// Nominal vector from the workpiece point to the tool point, in the workpiece frame (mm), at pose
/// `q` (mm, rad).
pub fn nominal_vector(machine: &Machine, q: &[f64], setup: &Setup) -> crate::geometry::Vec3 {
    let tool = nominal_chain(machine, machine.tool_chain(), q, None);
    let work = nominal_chain(machine, machine.work_chain(), q, None);
    work.rotation.transpose() * (tool.transform_point(&setup.tool_point) - work.transform_point(&setup.work_point))
}
