//! Uncertainty of a predicted volumetric error `dx dy dz` (um) at one pose, from the covariance of
//! the identified parameters: `Cov{e} = F Cov{p} F^T` (Soons 1993 App. A eq. A.4, JCGM 102 §6.3),
//! `F` the first-order effect of the parameters on `dx dy dz` at the pose (um per parameter unit;
//! `identify::Campaign::unknown_jacobian`). The prediction is linear in the parameters, so the
//! Monte Carlo counterpart is the same product with the covariance of the Monte Carlo parameter
//! trials: mapping every trial through `F` and taking the covariance of the mapped trials gives
//! exactly `F Cov_MC F^T`.

use super::gum::{confidence_ellipsoid, propagate, Ellipsoid};
use crate::error::Error;
use nalgebra::{DMatrix, Matrix3};

/// The uncertainty of `dx dy dz` at one pose.
#[derive(Clone, Debug)]
pub struct VolumetricUncertainty {
    /// Covariance of `dx dy dz` (um^2).
    pub covariance: Matrix3<f64>,
    /// Standard uncertainties of `dx dy dz` (um): the square roots of the diagonal.
    pub std_uncertainty: [f64; 3],
    /// The `level` confidence ellipsoid about the predicted error: principal directions (unit
    /// vectors in the frame of `dx dy dz`, largest variance first) and semi-axes
    /// `sqrt(chi2_nu(level) lambda_i)` (um).
    pub ellipsoid: Ellipsoid,
}

impl VolumetricUncertainty {
    /// From the covariance of `dx dy dz` (um^2) and the predicted error `centre` (um).
    pub fn from_covariance(covariance: Matrix3<f64>, centre: [f64; 3], level: f64) -> Result<VolumetricUncertainty, Error> {
        if covariance.iter().any(|v| !v.is_finite()) {
            return Err(Error::computation("the covariance of the predicted error is not finite"));
        }
        let cov = DMatrix::from_fn(3, 3, |i, j| covariance[(i, j)]);
        let ellipsoid = confidence_ellipsoid(&centre, &cov, level)?;
        Ok(VolumetricUncertainty { covariance, std_uncertainty: [0, 1, 2].map(|i| covariance[(i, i)].max(0.0).sqrt()), ellipsoid })
    }

    /// `F Cov F^T` for `F` the `3 x p` effect of the parameters on `dx dy dz` (um per parameter
    /// unit) and `cov` their `p x p` covariance (parameter units squared).
    pub fn propagated(f: &DMatrix<f64>, cov: &DMatrix<f64>, centre: [f64; 3], level: f64) -> Result<VolumetricUncertainty, Error> {
        if f.nrows() != 3 {
            return Err(Error::input(format!("the sensitivity of dx dy dz has {} rows, not 3", f.nrows())));
        }
        let c = propagate(f, cov)?;
        Self::from_covariance(Matrix3::from_fn(|i, j| c[(i, j)]), centre, level)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipsoid_of_a_diagonal_covariance() {
        // variances 9, 4, 1 um^2: semi-axes sqrt(7.814728 * (9, 4, 1)) = 8.386, 5.591, 2.795 um
        let v =
            VolumetricUncertainty::from_covariance(Matrix3::from_diagonal(&nalgebra::Vector3::new(4.0, 9.0, 1.0)), [0.0; 3], 0.95).unwrap();
        assert_eq!(v.std_uncertainty, [2.0, 3.0, 1.0]);
        for (a, l) in v.ellipsoid.semi_axes.iter().zip([9.0, 4.0, 1.0]) {
            assert!((a - (7.814728f64 * l).sqrt()).abs() < 1e-5, "{a}");
        }
        assert!((v.ellipsoid.axes.directions[(1, 0)].abs() - 1.0).abs() < 1e-12, "largest along y");
    }
}
