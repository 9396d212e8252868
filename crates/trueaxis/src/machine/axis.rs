//! One machine axis: its kind, nominal direction and point, range, and nominal motion.

use crate::geometry::{Pose, Vec3};

/// Linear (prismatic) or rotary (revolute) axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxisKind {
    Linear,
    Rotary,
}

/// Which chain an axis belongs to (docs/design.md, Conventions, structure code).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Workpiece,
    Tool,
}

/// An axis as described in the machine file. Directions and points are in the parent body's frame,
/// which coincides with the machine frame M at home (all axis positions zero).
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub letter: char,
    pub kind: AxisKind,
    pub side: Side,
    /// Unit direction of motion (linear) or of the rotation axis, right-hand rule (rotary).
    pub direction: Vec3,
    /// Rotary: a point on the axis line (mm); the centre of its location and motion errors.
    /// Linear: the reference point `r` (mm); motion errors act about `r + q d`.
    pub point: Vec3,
    /// Travel in user units (mm or deg); `None` for a continuous rotary axis.
    pub range: Option<[f64; 2]>,
}

impl Axis {
    /// User units of positions of this axis.
    pub fn position_unit(&self) -> &'static str {
        match self.kind {
            AxisKind::Linear => "mm",
            AxisKind::Rotary => "deg",
        }
    }

    /// Converts a position from user units (mm, deg) to internal units (mm, rad).
    pub fn position_to_internal(&self, user: f64) -> f64 {
        match self.kind {
            AxisKind::Linear => user,
            AxisKind::Rotary => user.to_radians(),
        }
    }

    /// Converts a position from internal units (mm, rad) to user units (mm, deg).
    pub fn position_to_user(&self, internal: f64) -> f64 {
        match self.kind {
            AxisKind::Linear => internal,
            AxisKind::Rotary => internal.to_degrees(),
        }
    }

    /// Nominal motion `J_k(q)` in the parent frame, `q` in mm or rad (docs/design.md, Conventions):
    /// linear `Trans(q d)`, rotary `Trans(p) Rot(d, q) Trans(-p)`.
    pub fn nominal_motion(&self, q: f64) -> Pose {
        match self.kind {
            AxisKind::Linear => Pose::translation(self.direction * q),
            AxisKind::Rotary => Pose::rotation_about_line(&self.direction, &self.point, q),
        }
    }

    /// Centre of the location errors `L_k`: the axis point (rotary) or the origin (linear).
    pub fn location_error_centre(&self) -> Vec3 {
        match self.kind {
            AxisKind::Linear => Vec3::zeros(),
            AxisKind::Rotary => self.point,
        }
    }

    /// Centre of the motion errors `S_k(q)`: the axis point (rotary) or `r + q d` (linear), in
    /// the parent frame, `q` in mm or rad.
    pub fn motion_error_centre(&self, q: f64) -> Vec3 {
        match self.kind {
            AxisKind::Linear => self.point + self.direction * q,
            AxisKind::Rotary => self.point,
        }
    }

    /// Whether a user-unit position lies within the travel (inclusive, with a 1e-9 tolerance).
    pub fn in_range(&self, user: f64) -> bool {
        match self.range {
            None => true,
            Some([lo, hi]) => user >= lo - 1e-9 && user <= hi + 1e-9,
        }
    }
}
