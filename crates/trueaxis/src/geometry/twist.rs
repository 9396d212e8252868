//! Small displacement screws (twists) and their transport between frames: the adjoint
//! (F-matrix) form of Soons 1993 eqs. 2.15-2.28.

use super::{Pose, Vec3};

/// A small rigid displacement in a stated frame: a point `x` moves by `omega x x + v`
/// (`omega` in rad, `v` in mm).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Twist {
    pub omega: Vec3,
    pub v: Vec3,
}

impl Twist {
    /// The first-order twist of the small transform `Trans(c) [exp([eps]x), e] Trans(-c)` stated in
    /// a frame whose nominal pose in the reference frame is `frame`: `omega = R eps`,
    /// `v = R e - omega x (frame * c)` (Soons 1993 eq. 2.24, adjoint transport).
    pub fn of_small_transform(frame: &Pose, eps: &Vec3, e: &Vec3, c: &Vec3) -> Twist {
        let omega = frame.rotation * eps;
        let centre = frame.transform_point(c);
        Twist { omega, v: frame.rotation * e - omega.cross(&centre) }
    }

    /// First-order displacement of the point `x` (mm).
    #[inline]
    pub fn displacement_of(&self, x: &Vec3) -> Vec3 {
        self.omega.cross(x) + self.v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transported_twist_matches_the_exact_small_transform_to_second_order() {
        let frame = Pose::rotation_about_line(&Vec3::new(1.0, 0.0, 1.0).normalize(), &Vec3::new(3.0, 4.0, 5.0), 0.9);
        let c = Vec3::new(10.0, -20.0, 5.0);
        let x_world = Vec3::new(200.0, 100.0, -50.0);
        for scale in [1e-4, 1e-5] {
            let eps = Vec3::new(1.0, -2.0, 0.5) * scale;
            let e = Vec3::new(3.0, 1.0, -2.0) * scale * 100.0;
            let exact_frame = frame * Pose::small_transform(&eps, &e, &c);
            let x_local = frame.inverse().transform_point(&x_world);
            let exact = exact_frame.transform_point(&x_local) - x_world;
            let first = Twist::of_small_transform(&frame, &eps, &e, &c).displacement_of(&x_world);
            // second-order remainder ~ |eps|^2 * lever arm (about 300 mm here)
            assert!((exact - first).norm() < 10.0 * scale * scale * 300.0, "scale {scale}");
        }
    }
}
