//! Laser interferometer readings on the exact kinematic chain (NISTIR 5236 §3.2-3.3, Soons 1993 §3.2):
//! linear optics (displacement along the beam), straightness optics (displacement perpendicular to
//! the beam, in a named direction) and angular optics (relative rotation about a named axis).
//!
//! Set-up: one optic (the interferometer, which fixes the beam) is mounted on one body, the other
//! (the retroreflector or the straightness reflector) on the other body: the tool-side optic at
//! `setup.tool_point`, the workpiece-side optic at `setup.work_point` (mm, in M at home). The beam,
//! the sensitive direction and the rotation axis are fixed in the body that carries the
//! interferometer ([`Laser::beam_on`]) and are given in M at home (where every body frame is M).
//!
//! Reading (actual minus nominal, docs/design.md, Conventions): the displacement of the tool-side optic
//! relative to the workpiece-side optic, projected on the direction `d` in the frame of the
//! interferometer's body,
//! `r = d . (R_b^T (P_t - P_w))_actual - d . (R_b^T (P_t - P_w))_nominal`,
//! and for angular optics the rotation vector of the tool relative to the workpiece, in that body's
//! frame, projected on the axis `a`. The optics' positions carry the Abbe effect: an angular error
//! `eps` of a slide moves the optic by `eps x (lever)` through the chain, with the lever from the
//! slide's reference point to the optic.

use super::measurement::nominal_vector;
use crate::geometry::{rotation_exp, Mat3, Vec3};
use crate::machine::{Machine, Side};
use crate::model::{nominal_chain, volumetric_error, Frame, Setup};

/// The optics of a laser interferometer; vectors are unit vectors in M at home.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LaserOptics {
    /// Linear optics: displacement along the beam (um), e.g. the positioning error `EXX`.
    Linear { beam: Vec3 },
    /// Straightness optics: displacement along `sensitive`, perpendicular to the beam (um), e.g.
    /// `EYX` with the beam along x and `sensitive` along y.
    Straightness { beam: Vec3, sensitive: Vec3 },
    /// Angular optics: relative rotation about `axis` (urad), e.g. pitch `EBX` about y.
    Angular { axis: Vec3 },
}

/// A laser interferometer set up on a machine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Laser {
    pub optics: LaserOptics,
    /// Positions of the tool-side and the workpiece-side optic (mm, in M at home).
    pub setup: Setup,
    /// The body that carries the interferometer: its frame fixes the beam.
    pub beam_on: Side,
}

/// Why a laser set-up is refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LaserError {
    #[error("laser {what}: {vector:?} is not a finite non-zero vector")]
    BadDirection { what: &'static str, vector: [f64; 3] },
    #[error("laser straightness: the sensitive direction must be perpendicular to the beam (their angle is {angle_deg:.3} deg)")]
    NotPerpendicular { angle_deg: f64 },
}

crate::error::error_of_kind!(LaserError, Input);

fn unit(what: &'static str, v: Vec3) -> Result<Vec3, LaserError> {
    let n = v.norm();
    if n.is_finite() && n > 0.0 {
        Ok(v / n)
    } else {
        Err(LaserError::BadDirection { what, vector: [v.x, v.y, v.z] })
    }
}

impl LaserOptics {
    /// Linear optics with the beam along `beam` (normalised).
    pub fn linear(beam: Vec3) -> Result<Self, LaserError> {
        Ok(LaserOptics::Linear { beam: unit("beam", beam)? })
    }

    /// Straightness optics: beam and sensitive direction (normalised), perpendicular within 1e-6 rad.
    pub fn straightness(beam: Vec3, sensitive: Vec3) -> Result<Self, LaserError> {
        let (beam, sensitive) = (unit("beam", beam)?, unit("sensitive direction", sensitive)?);
        let cos = beam.dot(&sensitive);
        if cos.abs() > 1e-6 {
            return Err(LaserError::NotPerpendicular { angle_deg: cos.clamp(-1.0, 1.0).acos().to_degrees() });
        }
        Ok(LaserOptics::Straightness { beam, sensitive })
    }

    /// Angular optics about `axis` (normalised).
    pub fn angular(axis: Vec3) -> Result<Self, LaserError> {
        Ok(LaserOptics::Angular { axis: unit("rotation axis", axis)? })
    }

    /// Whether the reading is a rotation (urad) rather than a displacement (um).
    pub fn is_angular(&self) -> bool {
        matches!(self, LaserOptics::Angular { .. })
    }
}

impl Laser {
    /// The exact reading at pose `q` (mm, rad) with the parameter vector `params` (mm, rad): mm for
    /// linear and straightness optics, rad for angular optics (module documentation).
    pub fn exact(&self, machine: &Machine, q: &[f64], params: &[f64]) -> f64 {
        let error = volumetric_error(machine, q, params, &self.setup, Frame::Workpiece);
        // rotation from the workpiece frame into the frame of the interferometer's body (nominal:
        // the body's actual rotation is applied below for displacements)
        let into_beam_body = match self.beam_on {
            Side::Workpiece => Mat3::identity(),
            Side::Tool => relative_rotation(machine, q).transpose(),
        };
        match self.optics {
            LaserOptics::Angular { axis } => axis.dot(&(into_beam_body * error.orientation)),
            LaserOptics::Linear { beam: d } | LaserOptics::Straightness { sensitive: d, .. } => match self.beam_on {
                Side::Workpiece => d.dot(&error.position),
                Side::Tool => {
                    // R_rel,actual = exp(o) R_rel,nominal (orientation in the workpiece frame)
                    let r_nominal = nominal_vector(machine, q, &self.setup);
                    let rel_actual = rotation_exp(&error.orientation) * relative_rotation(machine, q);
                    d.dot(&(rel_actual.transpose() * (r_nominal + error.position) - into_beam_body * r_nominal))
                }
            },
        }
    }

    /// The reading in user units: um (linear, straightness) or urad (angular).
    pub fn reading_user(&self, machine: &Machine, q: &[f64], params: &[f64]) -> f64 {
        self.exact(machine, q, params) * if self.optics.is_angular() { 1e6 } else { 1e3 }
    }
}

/// Nominal tool orientation relative to the workpiece, `R_w^T R_t`, at pose `q` (mm, rad).
fn relative_rotation(machine: &Machine, q: &[f64]) -> Mat3 {
    let tool = nominal_chain(machine, machine.tool_chain(), q, None);
    let work = nominal_chain(machine, machine.work_chain(), q, None);
    work.rotation.transpose() * tool.rotation
}
