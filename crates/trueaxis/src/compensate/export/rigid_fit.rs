//! The least-squares rigid motion between two point sets (Kabsch 1976; Umeyama 1991 without the
//! scale): the rotation `R` and translation `t` minimising `Σ |R n_i + t - a_i|²`.
//!
//! Used to judge a compensation up to the placement of the workpiece: a table frame that is
//! shifted or tilted as a whole is where a workpiece datum puts it (probing sets it), not an error
//! of the machine, so the errors before and after compensation are compared after the best rigid
//! fit of the reached points (`a_i`, actual) to the programmed ones (`n_i`, nominal), as a measured
//! part is aligned before it is judged. Units: mm (positions), rad (rotations).

use crate::geometry::{rotation_log, Mat3, Vec3};

/// A rigid motion `x -> R x + t` fitted to pairs of points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidFit {
    pub rotation: Mat3,
    pub translation: Vec3,
}

impl RigidFit {
    /// The fit of `actual[i] ≈ R nominal[i] + t` (equal lengths, at least one pair). The
    /// cross-covariance is formed from the differences `actual - nominal`, which are small, so that
    /// the rotation of sub-micrometre errors over metre-sized sets keeps its digits.
    pub fn of(nominal: &[Vec3], actual: &[Vec3]) -> RigidFit {
        let count = nominal.len() as f64;
        let mean = |v: &[Vec3]| v.iter().fold(Vec3::zeros(), |s, x| s + x) / count;
        let (n_mean, a_mean) = (mean(nominal), mean(actual));
        // H = Σ (a_i - ā)(n_i - n̄)^T = Σ n'n'^T + Σ e'n'^T with e = a - n
        let (mut spread, mut coupling) = (Mat3::zeros(), Mat3::zeros());
        for (n, a) in nominal.iter().zip(actual) {
            let centred = n - n_mean;
            let error = (a - n) - (a_mean - n_mean);
            spread += centred * centred.transpose();
            coupling += error * centred.transpose();
        }
        let h = spread + coupling;
        let svd = h.svd(true, true);
        let (u, v_t) = (svd.u.expect("u requested"), svd.v_t.expect("v requested"));
        let mut d = Mat3::identity();
        if (u * v_t).determinant() < 0.0 {
            d[(2, 2)] = -1.0;
        }
        let rotation = u * d * v_t;
        RigidFit { rotation, translation: a_mean - rotation * n_mean }
    }

    /// The identity (no fit).
    pub fn identity() -> RigidFit {
        RigidFit { rotation: Mat3::identity(), translation: Vec3::zeros() }
    }

    /// What is left of the error at a pair: `R^T (a - t) - n`.
    pub fn left(&self, nominal: &Vec3, actual: &Vec3) -> Vec3 {
        self.rotation.transpose() * (actual - self.translation) - nominal
    }

    /// The fitted rotation as a rotation vector (rad).
    pub fn rotation_vector(&self) -> Vec3 {
        rotation_log(&self.rotation)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::rotation_exp;

    #[test]
    fn recovers_a_small_rigid_motion_exactly() {
        let r = rotation_exp(&Vec3::new(120e-6, -349e-6, 35e-6));
        let t = Vec3::new(0.012, -0.0257, 0.0188);
        let nominal: Vec<Vec3> = (0..60)
            .map(|i| Vec3::new(-300.0 + 10.0 * i as f64, 250.0 * ((i * 7 % 11) as f64 / 10.0 - 0.5), -40.0 * (i % 5) as f64))
            .collect();
        let actual: Vec<Vec3> = nominal.iter().map(|n| r * n + t).collect();
        let fit = RigidFit::of(&nominal, &actual);
        assert!((fit.rotation_vector() - Vec3::new(120e-6, -349e-6, 35e-6)).norm() < 1e-12);
        assert!((fit.translation - t).norm() < 1e-10);
        for (n, a) in nominal.iter().zip(&actual) {
            assert!(fit.left(n, a).norm() < 1e-10);
        }
    }
}
