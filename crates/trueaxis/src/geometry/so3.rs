//! Rotations: Rodrigues' formula, the exponential and logarithm maps of SO(3).

use super::{Mat3, Vec3};

/// The skew-symmetric matrix `[v]x` with `[v]x y = v x y` (Soons 1993 eq. 2.10, Jiang 2014 section 1.3).
pub fn skew(v: &Vec3) -> Mat3 {
    Mat3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Rotation by `angle` (rad) about the unit vector `axis`, right-hand rule: Rodrigues' formula
/// `R = I + sin(a) [d]x + (1 - cos(a)) [d]x^2`, written with `[d]x^2 = d d^T - I` for a unit `d`
/// as `R = cos(a) I + sin(a) [d]x + (1 - cos(a)) d d^T` (no matrix product: this is the nominal
/// motion of every rotary axis at every pose).
pub fn rotation_about_axis(axis: &Vec3, angle: f64) -> Mat3 {
    let (s, c) = angle.sin_cos();
    rodrigues(axis, c, s, 1.0 - c)
}

/// `d I + a [w]x + b w w^T`, the form both Rodrigues matrices above and below take.
#[inline]
fn rodrigues(w: &Vec3, d: f64, a: f64, b: f64) -> Mat3 {
    let (x, y, z) = (w.x, w.y, w.z);
    Mat3::new(
        d + b * x * x,
        b * x * y - a * z,
        b * x * z + a * y,
        b * y * x + a * z,
        d + b * y * y,
        b * y * z - a * x,
        b * z * x - a * y,
        b * z * y + a * x,
        d + b * z * z,
    )
}

/// Exact rotation for a rotation vector `eps` (rad): `exp([eps]x)`, by Rodrigues' formula
/// `R = I + a [eps]x + b [eps]x^2` with `a = sin t / t`, `b = (1 - cos t) / t^2`, `t = |eps|`, and
/// `[eps]x^2 = eps eps^T - t^2 I`.
///
/// Below `t = 0.01 rad` (every machine error) `a` and `b` come from their Taylor series to `t^6`,
/// whose remainders (`t^8/9!`, `t^8/10!`) are below 1e-21: exact to rounding, without the square
/// root and the two sines of the closed form, which dominated the cost of the exact chain.
/// Above, `b = 2 (sin(t/2)/t)^2` keeps full precision.
pub fn rotation_exp(eps: &Vec3) -> Mat3 {
    let t2 = eps.norm_squared();
    let (a, b) = if t2 < 1e-4 {
        // a = 1 - t^2/3! + t^4/5! - t^6/7!, b = 1/2! - t^2/4! + t^4/6! - t^6/8!, by Horner with the
        // reciprocal factorials as constants (multiplications, no divisions)
        const A: [f64; 3] = [1.0 / 6.0, 1.0 / 120.0, 1.0 / 5040.0];
        const B: [f64; 3] = [1.0 / 24.0, 1.0 / 720.0, 1.0 / 40320.0];
        (1.0 - t2 * (A[0] - t2 * (A[1] - t2 * A[2])), 0.5 - t2 * (B[0] - t2 * (B[1] - t2 * B[2])))
    } else {
        let theta = t2.sqrt();
        let h = (0.5 * theta).sin() / theta;
        (theta.sin() / theta, 2.0 * h * h)
    };
    rodrigues(eps, 1.0 - b * t2, a, b)
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

    #[test]
    fn exp_equals_the_power_series_on_both_sides_of_the_series_threshold() {
        // independent: sum_n K^n / n! to 40 terms
        for scale in [1e-7, 1e-4, 0.0099, 0.0101, 0.3, 1.5] {
            let eps = Vec3::new(-0.41, 0.77, 0.49).normalize() * scale;
            let k = skew(&eps);
            let (mut term, mut sum) = (Mat3::identity(), Mat3::identity());
            for n in 1..40 {
                term = term * k / n as f64;
                sum += term;
            }
            let r = rotation_exp(&eps);
            assert!((r - sum).norm() < 4e-16, "scale {scale}: {:e}", (r - sum).norm());
            assert!((r * r.transpose() - Mat3::identity()).norm() < 4e-16);
        }
    }
}
