//! Electronic levels on the exact kinematic chain (NISTIR 5236 §3.3, Soons 1993 §3.2): a level reads the
//! rotation of the body it stands on relative to gravity, about a horizontal axis. Gravity is fixed
//! to the base (the machine frame M), so the reading is the rotation of the body relative to the
//! base. A differential level pair reads the moving level minus a reference level on another body
//! (the base, or a slide that stays still), which removes the tilt of the whole machine.
//!
//! A level senses only rotations about horizontal axes: pitch and roll of a horizontal slide (`EBX`
//! about y and `EAX` about x for X), never yaw (`ECX`, about the vertical), which needs angular
//! laser optics.
//!
//! Reading (urad at the user interface, rad here): `h . (w_level - w_reference)`, where `w_B` is the
//! rotation vector of `R_B,actual R_B,nominal^T` in M (the actual minus nominal orientation of body
//! B, from the exact chain) and `h` the level's sensitive axis, horizontal, in M.

use crate::geometry::{rotation_log, Vec3};
use crate::machine::Machine;
use crate::model::{actual_chain, nominal_chain};

/// A body a level stands on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LevelBody {
    /// The machine base (bed), fixed to gravity.
    Base,
    /// The body carried by the axis with this letter (its slide, table or head).
    CarriedBy(char),
}

/// A level (or a differential pair of levels) set up on a machine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    /// The body of the moving level.
    pub on: LevelBody,
    /// The body of the reference level (`Base` for a single level).
    pub reference: LevelBody,
    /// The sensitive axis: the reading is the rotation about it (unit, horizontal, in M).
    pub axis: Vec3,
}

/// Why a level set-up is refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LevelError {
    #[error(
        "a level senses rotations about horizontal axes only (pitch, roll), never about the vertical (yaw): \
         its axis {axis:?} is {angle_deg:.2} deg from horizontal (up = {up:?})"
    )]
    NotHorizontal { axis: [f64; 3], up: [f64; 3], angle_deg: f64 },
    #[error("level: {what} {vector:?} is not a finite non-zero vector")]
    BadDirection { what: &'static str, vector: [f64; 3] },
    #[error("level on the body carried by axis {letter}: machine `{machine}` has no such axis (axes: {axes})")]
    UnknownAxis { letter: char, machine: String, axes: String },
    #[error("the level and its reference stand on the same body: the reading is always zero")]
    SameBody,
}

crate::error::error_of_kind!(LevelError, Input);

impl Level {
    /// A level with sensitive `axis` perpendicular to `up` (both in M, normalised here; within
    /// 0.01 deg of horizontal), on body `on`, read against a reference level on `reference`.
    pub fn new(machine: &Machine, on: LevelBody, reference: LevelBody, axis: Vec3, up: Vec3) -> Result<Level, LevelError> {
        let unit = |what, v: Vec3| {
            let n = v.norm();
            if n.is_finite() && n > 0.0 {
                Ok(v / n)
            } else {
                Err(LevelError::BadDirection { what, vector: [v.x, v.y, v.z] })
            }
        };
        let (axis, up) = (unit("axis", axis)?, unit("up direction", up)?);
        let sine = axis.dot(&up);
        if sine.abs() > (0.01f64).to_radians().sin() {
            return Err(LevelError::NotHorizontal {
                axis: [axis.x, axis.y, axis.z],
                up: [up.x, up.y, up.z],
                angle_deg: sine.asin().to_degrees(),
            });
        }
        for body in [on, reference] {
            if let LevelBody::CarriedBy(letter) = body {
                if machine.axis_index(letter).is_none() {
                    return Err(LevelError::UnknownAxis { letter, machine: machine.name.clone(), axes: machine.axis_letters() });
                }
            }
        }
        if on == reference {
            return Err(LevelError::SameBody);
        }
        Ok(Level { on, reference, axis })
    }

    /// The exact reading (rad) at pose `q` (mm, rad) with the parameter vector `params` (mm, rad).
    pub fn exact(&self, machine: &Machine, q: &[f64], params: &[f64]) -> f64 {
        self.axis.dot(&(body_rotation(machine, self.on, q, params) - body_rotation(machine, self.reference, q, params)))
    }

    /// The reading in urad.
    pub fn reading_user(&self, machine: &Machine, q: &[f64], params: &[f64]) -> f64 {
        self.exact(machine, q, params) * 1e6
    }
}

/// Rotation vector (rad, in M) of the actual orientation of `body` relative to its nominal one.
fn body_rotation(machine: &Machine, body: LevelBody, q: &[f64], params: &[f64]) -> Vec3 {
    let LevelBody::CarriedBy(letter) = body else { return Vec3::zeros() };
    let k = machine.axis_index(letter).expect("checked by Level::new");
    let chain = [machine.tool_chain(), machine.work_chain()].into_iter().find(|c| c.contains(&k)).expect("every axis is in a chain");
    let prefix = &chain[..=chain.iter().position(|&i| i == k).expect("found above")];
    let actual = actual_chain(machine, prefix, q, params);
    let nominal = nominal_chain(machine, prefix, q, None);
    rotation_log(&(actual.rotation * nominal.rotation.transpose()))
}
