//! Rotations: Rodrigues' formula, the exponential and logarithm maps of SO(3).

use super::{Mat3, Vec3};

/// The skew-symmetric matrix `[v]x` with `[v]x y = v x y` (seed 000 eq. 2.10, seed 001 section 1.3).
pub fn skew(v: &Vec3) -> Mat3 {
    Mat3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Rotation by `angle` (rad) about the unit vector `axis`, right-hand rule (Rodrigues' formula).
pub fn rotation_about_axis(axis: &Vec3, angle: f64) -> Mat3 {
    let (s, c) = angle.sin_cos();
    let k = skew(axis);
    Mat3::identity() + k * s + k * k * (1.0 - c)
}

/// Exact rotation for a rotation vector `eps` (rad): `exp([eps]x)`.
///
/// Uses `(1 - cos t)/t^2 = 2 (sin(t/2)/t)^2`, which keeps full precision for the micro-radian
/// rotations of machine errors.
pub fn rotation_exp(eps: &Vec3) -> Mat3 {
    let theta = eps.norm();
    let k = skew(eps);
    if theta < 1e-12 {
        return Mat3::identity() + k + k * k * 0.5;
    }
    let a = theta.sin() / theta;
    let h = (0.5 * theta).sin() / theta;
    Mat3::identity() + k * a + k * k * (2.0 * h * h)
}

/// Rotation vector (rad) of a rotation matrix: the inverse of [`rotation_exp`] for angles below pi.
///
/// Computed from the skew part and the trace with `atan2`, which is accurate near the identity,
/// where the orientation errors of a machine live.
pub fn rotation_log(r: &Mat3) -> Vec3 {
    let w = Vec3::new(r[(2, 1)] - r[(1, 2)], r[(0, 2)] - r[(2, 0)], r[(1, 0)] - r[(0, 1)]) * 0.5;
    let sin_theta = w.norm();
    let cos_theta = 0.5 * (r.trace() - 1.0);
    let theta = sin_theta.atan2(cos_theta);
    if sin_theta < 1e-300 {
        return Vec3::zeros();
    }
    w * (theta / sin_theta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_and_log_are_inverse_from_micro_to_large_angles() {
        for scale in [1e-9, 1e-6, 1e-3, 0.5, 2.0] {
            let eps = Vec3::new(0.3, -0.8, 0.52).normalize() * scale;
            let back = rotation_log(&rotation_exp(&eps));
            assert!((back - eps).norm() <= 1e-15 + 1e-13 * scale, "scale {scale}: {back} vs {eps}");
        }
    }

    #[test]
    fn rodrigues_matches_exp_and_is_orthonormal() {
        let axis = Vec3::new(0.0, 1.0, 1.0).normalize();
        let r = rotation_about_axis(&axis, 1.1);
        assert!((r - rotation_exp(&(axis * 1.1))).norm() < 1e-14);
        assert!((r * r.transpose() - Mat3::identity()).norm() < 1e-14);
        assert!((r.determinant() - 1.0).abs() < 1e-14);
        // right-hand rule: +90 deg about z takes x to y
        let rz = rotation_about_axis(&Vec3::z(), std::f64::consts::FRAC_PI_2);
        assert!((rz * Vec3::x() - Vec3::y()).norm() < 1e-15);
    }
}
