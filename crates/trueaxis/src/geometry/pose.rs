//! Homogeneous transformation matrices stored as rotation + translation.

use super::so3::{rotation_about_axis, rotation_exp};
use super::{Mat3, Vec3};

/// A rigid transform `x -> R x + t`, the HTM `[R t; 0 0 0 1]` of Soons 1993 eq. 2.1 (mm, rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub rotation: Mat3,
    pub translation: Vec3,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    pub const IDENTITY: Pose =
        Pose { rotation: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0), translation: Vec3::new(0.0, 0.0, 0.0) };

    /// `Trans(t)`.
    pub fn translation(t: Vec3) -> Self {
        Pose { rotation: Mat3::identity(), translation: t }
    }

    /// `Trans(p) Rot(d, angle) Trans(-p)`: rotation by `angle` (rad) about the line through `p`
    /// with unit direction `d` (docs/design.md, Conventions, nominal rotary axis motion).
    pub fn rotation_about_line(d: &Vec3, p: &Vec3, angle: f64) -> Self {
        let r = rotation_about_axis(d, angle);
        Pose { rotation: r, translation: p - r * p }
    }

    /// The exact small transform of docs/design.md, Conventions:
    /// `Trans(c) [exp([eps]x), e; 0 1] Trans(-c)`, rotation vector `eps` (rad) and translation `e` (mm)
    /// about the point `c` (mm).
    pub fn small_transform(eps: &Vec3, e: &Vec3, c: &Vec3) -> Self {
        let r = rotation_exp(eps);
        Pose { rotation: r, translation: c + e - r * c }
    }

    /// Composition `self * other` (apply `other` first, then `self`).
    #[inline]
    pub fn then(&self, other: &Pose) -> Pose {
        Pose { rotation: self.rotation * other.rotation, translation: self.rotation * other.translation + self.translation }
    }

    /// Composition with a pure translation, `self * Trans(t)`.
    #[inline]
    pub fn then_translation(&self, t: &Vec3) -> Pose {
        Pose { rotation: self.rotation, translation: self.rotation * t + self.translation }
    }

    /// The inverse HTM `[R^T, -R^T t]` (Soons 1993 eq. 2.5).
    pub fn inverse(&self) -> Pose {
        let rt = self.rotation.transpose();
        Pose { rotation: rt, translation: -(rt * self.translation) }
    }

    /// Maps a point.
    #[inline]
    pub fn transform_point(&self, x: &Vec3) -> Vec3 {
        self.rotation * x + self.translation
    }
}

impl std::ops::Mul for Pose {
    type Output = Pose;
    fn mul(self, rhs: Pose) -> Pose {
        self.then(&rhs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_composes_to_identity() {
        let a = Pose::rotation_about_line(&Vec3::new(1.0, 2.0, 2.0).normalize(), &Vec3::new(5.0, -3.0, 1.0), 0.7);
        let i = a * a.inverse();
        assert!((i.rotation - Mat3::identity()).norm() < 1e-14);
        assert!(i.translation.norm() < 1e-13);
    }

    #[test]
    fn rotation_about_line_keeps_points_on_the_line() {
        let d = Vec3::new(0.0, 0.0, 1.0);
        let p = Vec3::new(10.0, 20.0, 0.0);
        let a = Pose::rotation_about_line(&d, &p, 1.3);
        let on_line = p + d * 42.0;
        assert!((a.transform_point(&on_line) - on_line).norm() < 1e-12);
    }

    #[test]
    fn small_transform_fixes_its_centre_when_pure_rotation() {
        let c = Vec3::new(100.0, -50.0, 30.0);
        let s = Pose::small_transform(&Vec3::new(1e-4, -2e-4, 3e-4), &Vec3::zeros(), &c);
        assert!((s.transform_point(&c) - c).norm() < 1e-13);
    }
}
