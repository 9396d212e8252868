//! The linear solve of the pose correction (Soons 1993 §2.3.5: unknown joint corrections chosen by
//! linear least squares on the kinematic model), prioritised: the position of the tool point first
//! (minimum-norm least squares over all joints), then the targeted orientation in the null space of
//! the position task.
//!
//! Near a 5-axis singularity (a rotary axis nearly parallel to the tool axis) the orientation task
//! is ill-conditioned: tilting the tool by `t` needs a rotary correction of `t / sigma`, `sigma` the
//! singular value of that direction (for the C axis of a table-tilting machine `sigma = sin A`). A
//! hard cut-off at `sigma = eps` makes the correction jump there. Instead the gain `1 / sigma` of the
//! directions with `sigma < eps` is replaced by the variable damping (damped least squares with
//! `lambda^2 = eps^2 (1 - sigma^2 / eps^2) / 2`)
//!
//! ```text
//! g(sigma) = 2 sigma / (sigma^2 + eps^2)      (sigma < eps),    1 / sigma    (sigma >= eps),
//! ```
//!
//! which is continuous (both are `1 / eps` at `sigma = eps`), never exceeds `1 / eps`, vanishes at the
//! singularity and leaves the fraction `(eps^2 - sigma^2) / (eps^2 + sigma^2)` of that direction's
//! orientation error uncorrected. Above `eps` the solve is the exact least-squares one.
//!
//! Units: joints are scaled so that 1 rad of a rotary joint counts as `L` = 1000 mm of a linear one
//! (`u = dq / w`, `w = 1` linear, `1 / L` rotary); orientation rows are multiplied by `L`, so that
//! 1 urad of orientation weighs as 1 um of position.

use crate::geometry::{Mat3, Vec3};
use nalgebra::{Matrix2, SMatrix, SVector};

/// Most axes a machine can have (X Y Z U V W A B C).
pub const MAX_AXES: usize = 9;

/// A 3 x `MAX_AXES` block of the joint Jacobian (unused columns zero).
pub(crate) type Block = SMatrix<f64, 3, MAX_AXES>;
/// Joint-space vector (unused entries zero).
pub(crate) type Joints = SVector<f64, MAX_AXES>;
type Pinv = SMatrix<f64, MAX_AXES, 3>;

/// Characteristic length (mm) that makes rotary joints and orientation errors comparable with
/// linear ones: 1 rad of a rotary joint costs as much as 1000 mm of a linear one, and 1 urad of
/// orientation error weighs as 1 um of position error.
pub(crate) const CHARACTERISTIC_LENGTH_MM: f64 = 1000.0;

/// The orientation directions a correction targets: an orthonormal basis (rows of a 3 x 3 matrix,
/// unused rows zero) and how many there are (0 position only, 2 the tilt of the tool axis, 3 all).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct OrientationRows {
    pub rows: Mat3,
    pub count: usize,
}

impl OrientationRows {
    pub fn none() -> OrientationRows {
        OrientationRows { rows: Mat3::zeros(), count: 0 }
    }

    pub fn full() -> OrientationRows {
        OrientationRows { rows: Mat3::identity(), count: 3 }
    }

    /// The two directions perpendicular to the unit tool axis `axis` (tilts of the tool; the spin
    /// about the axis is left out). The result of the solve does not depend on which orthonormal
    /// pair is taken.
    pub fn tilt_of(axis: &Vec3) -> OrientationRows {
        let helper = if axis.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
        let e1 = (helper - axis * axis.dot(&helper)).normalize();
        let e2 = axis.cross(&e1);
        OrientationRows { rows: Mat3::from_rows(&[e1.transpose(), e2.transpose(), Vec3::zeros().transpose()]), count: 2 }
    }
}

/// The linear operators of one prioritised solve at one linearisation (allocation-free, `Copy`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Solver {
    /// Scaled joint Jacobians of the relative position (mm per scaled unit) and orientation (rad
    /// per scaled unit).
    jp: Block,
    jo: Block,
    jp_pinv: Pinv,
    /// Orientation task rows times `L`, and their part outside the position task's row space.
    b: Block,
    a_null: Block,
    /// `h(G)` of the Gram matrix `G = a_null a_null^T` (see [`inverse_gain`]).
    gain: Mat3,
    rows: OrientationRows,
    /// Whether this linearisation may serve a nearby pose (within 0.01 rad of rotary motion, which
    /// changes a singular value by at most 0.01): every position direction clears its threshold
    /// three times over, and every orientation direction either has no joint at all (a 3-axis
    /// machine) or a singular value of at least `1.5 eps`, well outside the fade-out, where the fixed
    /// point of the iteration does not depend on the Jacobian it was found with.
    pub reusable: bool,
}

impl Solver {
    /// Prepares the solve for the scaled joint Jacobians `jp`, `jo`; position directions with a
    /// singular value below `singular_threshold` are not corrected; orientation directions fade out
    /// below `fade` (the `eps` of the module documentation).
    pub fn new(jp: &Block, jo: &Block, rows: OrientationRows, singular_threshold: f64, fade: f64) -> Solver {
        let (jp_pinv, position_margin) = pseudo_inverse(jp, singular_threshold);
        let b = rows.rows * jo * CHARACTERISTIC_LENGTH_MM;
        let a_null = b - (b * jp_pinv) * jp;
        let gram = a_null * a_null.transpose();
        // no joint at all: an eigenvalue that is zero but for rounding (structurally zero columns)
        let clear = |lambda: f64| lambda < 1e-24 || lambda > 2.25 * fade * fade;
        let (gain, clear_of_fade) = match rows.count {
            0 => (Mat3::zeros(), true),
            2 => {
                let g2 = gram.fixed_view::<2, 2>(0, 0).into_owned();
                let (l1, l2) = eigenvalues_2x2(&g2);
                let mut g = Mat3::zeros();
                g.fixed_view_mut::<2, 2>(0, 0).copy_from(&gain_2x2(&g2, fade));
                (g, clear(l1) && clear(l2))
            }
            _ => {
                let eigen = gram.symmetric_eigen();
                let mut g = Mat3::zeros();
                for i in 0..3 {
                    let v = eigen.eigenvectors.column(i);
                    g += v * v.transpose() * inverse_gain(eigen.eigenvalues[i], fade);
                }
                (g, eigen.eigenvalues.iter().all(|&l| clear(l)))
            }
        };
        Solver { jp: *jp, jo: *jo, jp_pinv, b, a_null, gain, rows, reusable: position_margin && clear_of_fade }
    }

    /// The total scaled correction from the current one `u` and the exact residual there
    /// (`position` mm, `orientation` rad, the latter already reduced to its targeted part): the
    /// solve of the linear model `residual + J (u_new - u)`, i.e. of the targets `J u - residual`.
    pub fn solve(&self, u: &Joints, position: &Vec3, orientation: &Vec3) -> Step {
        let (jp_u, jo_u) = (self.jp * u, self.jo * u);
        let u1 = self.jp_pinv * (jp_u - position);
        let b = self.rows.rows * (jo_u - orientation) * CHARACTERISTIC_LENGTH_MM - self.b * u1;
        let u2 = self.a_null.transpose() * (self.gain * b);
        let left = self.rows.rows.transpose() * (self.a_null * u2 - b) / CHARACTERISTIC_LENGTH_MM;
        Step { u: u1 + u2, left, position_change: jp_u, orientation_change: jo_u }
    }
}

/// The result of one linear solve.
pub(crate) struct Step {
    /// The new total correction (scaled joint units).
    pub u: Joints,
    /// The targeted orientation residual the linear model predicts at `u` (rad; nonzero where the
    /// joints cannot reach or the correction fades out).
    pub left: Vec3,
    /// First-order change of the relative position (mm) and orientation (rad) by the correction the
    /// solve started from.
    pub position_change: Vec3,
    pub orientation_change: Vec3,
}

/// `h(lambda)` for an eigenvalue `lambda = sigma^2` of the orientation Gram matrix: `1 / lambda`
/// for `sigma >= eps`, `2 / (lambda + eps^2)` below, so that the gain `sigma h = g(sigma)` of the
/// module documentation is continuous and bounded by `1 / eps`.
pub(crate) fn inverse_gain(lambda: f64, fade: f64) -> f64 {
    let lambda = lambda.max(0.0);
    let e2 = fade * fade;
    if lambda >= e2 {
        1.0 / lambda
    } else {
        2.0 / (lambda + e2)
    }
}

/// `h(G)` of a symmetric positive semi-definite 2 x 2 matrix in closed form:
/// `h(G) = h(l2) I + (h(l1) - h(l2)) / (l1 - l2) (G - l2 I)` (Sylvester), with the derivative
/// for the divided difference when the eigenvalues `l1 >= l2` (nearly) coincide.
fn gain_2x2(g: &Matrix2<f64>, fade: f64) -> Matrix2<f64> {
    let mean = 0.5 * (g[(0, 0)] + g[(1, 1)]);
    let (l1, l2) = eigenvalues_2x2(g);
    let (h1, h2) = (inverse_gain(l1, fade), inverse_gain(l2, fade));
    let divided = if l1 - l2 > 1e-9 * (l1.abs() + fade * fade) {
        (h1 - h2) / (l1 - l2)
    } else {
        // derivative of h at the mean
        let m = mean.max(0.0);
        if m >= fade * fade {
            -1.0 / (m * m)
        } else {
            -2.0 / (m + fade * fade).powi(2)
        }
    };
    Matrix2::identity() * h2 + (g - Matrix2::identity() * l2) * divided
}

/// Eigenvalues `l1 >= l2` of a symmetric 2 x 2 matrix.
fn eigenvalues_2x2(g: &Matrix2<f64>) -> (f64, f64) {
    let mean = 0.5 * (g[(0, 0)] + g[(1, 1)]);
    let half_gap = (0.25 * (g[(0, 0)] - g[(1, 1)]).powi(2) + g[(0, 1)] * g[(1, 0)]).max(0.0).sqrt();
    (mean + half_gap, mean - half_gap)
}

/// Moore-Penrose pseudo-inverse `M^T (M M^T)^+` of a 3 x n block, singular values of `M` below
/// `threshold` treated as zero, and whether every singular value is at least three times the
/// threshold. Allocation-free (3 x 3 symmetric eigenproblem).
fn pseudo_inverse(m: &Block, threshold: f64) -> (Pinv, bool) {
    let gram = m * m.transpose();
    // fast path: the smallest eigenvalue of the Gram matrix is at least det / (trace / 2)^2 (the
    // product of the two largest is at most (trace / 2)^2); when det > threshold^2 trace^2 / 3
    // it clears threshold^2, and the plain inverse is the pseudo-inverse (with 9 threshold^2, every
    // singular value clears three thresholds)
    let trace = gram.trace();
    let det = gram.determinant();
    if det > threshold * threshold * trace * trace / 3.0 {
        if let Some(inverse) = gram.try_inverse() {
            return (m.transpose() * inverse, det > 9.0 * threshold * threshold * trace * trace / 3.0);
        }
    }
    let eigen = gram.symmetric_eigen();
    let mut gram_pinv = Mat3::zeros();
    for i in 0..3 {
        let lambda = eigen.eigenvalues[i];
        if lambda > threshold * threshold {
            let v = eigen.eigenvectors.column(i);
            gram_pinv += v * v.transpose() / lambda;
        }
    }
    (m.transpose() * gram_pinv, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gain_is_continuous_bounded_and_exact_above_the_fade() {
        let eps = 0.1;
        let g = |s: f64| s * inverse_gain(s * s, eps);
        assert!((g(eps) - 1.0 / eps).abs() < 1e-12);
        assert!((g(eps * (1.0 - 1e-12)) - g(eps * (1.0 + 1e-12))).abs() < 1e-9);
        assert_eq!(g(0.0), 0.0);
        for i in 0..=1000 {
            let s = i as f64 * 1e-3;
            assert!(g(s) <= 1.0 / eps + 1e-12, "{s}");
            if s >= eps {
                assert!((g(s) - 1.0 / s).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn the_closed_form_2x2_gain_equals_the_eigendecomposition() {
        let eps = 0.1;
        for (a, b, c) in [(1.0, 0.3, 0.02), (0.004, 0.001, 0.009), (0.5, 0.0, 0.5), (0.01, 0.0, 0.01), (0.0, 0.0, 0.0), (2.0, 1.0, 0.5)] {
            let g = Matrix2::new(a, b, b, c);
            let closed = gain_2x2(&g, eps);
            let eigen = g.symmetric_eigen();
            let mut reference = Matrix2::zeros();
            for i in 0..2 {
                let v = eigen.eigenvectors.column(i);
                reference += v * v.transpose() * inverse_gain(eigen.eigenvalues[i], eps);
            }
            assert!((closed - reference).norm() <= 1e-9 * reference.norm().max(1.0), "{g}: {closed} vs {reference}");
        }
    }
}
