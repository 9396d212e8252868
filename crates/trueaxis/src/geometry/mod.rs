//! Rigid-body geometry: homogeneous transforms (HTMs), small-displacement 6-vectors and their transport.
//!
//! Conventions (docs/design.md, Conventions): lengths in mm, angles in rad. An HTM `[R t; 0 1]` maps a point
//! `x` to `R x + t` (Soons 1993 eqs. 2.1-2.5). A small displacement is written translation first,
//! `[e; eps]`, whereas Soons 1993 orders it rotation first; the content is the same.

mod pose;
mod so3;
mod twist;

pub use pose::Pose;
pub use so3::{rotation_about_axis, rotation_exp, rotation_log, skew};
pub use twist::Twist;

/// A 3-vector in mm (positions) or rad (rotation vectors).
pub type Vec3 = nalgebra::Vector3<f64>;
/// A 3x3 rotation matrix.
pub type Mat3 = nalgebra::Matrix3<f64>;
