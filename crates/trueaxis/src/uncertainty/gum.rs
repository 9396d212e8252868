//! The GUM law of propagation for linear(ised) models (JCGM 100 §5; Soons 1993 App. A eq. A.4):
//! `Cov{y} = F Cov{x} F^T`, principal axes of a covariance and chi-square confidence ellipsoids.

use crate::error::Error;
use nalgebra::{DMatrix, DVector};
use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};

/// `F Cov F^T` (Soons 1993 eq. A.4): the covariance of `y = F x` when `x` has covariance `cov`.
/// E.g. the identified parameters (`F` the pseudo-inverse, um per um) or predicted volumetric
/// errors (`F` the Jacobian rows, um per parameter unit).
pub fn propagate(f: &DMatrix<f64>, cov: &DMatrix<f64>) -> Result<DMatrix<f64>, Error> {
    if f.ncols() != cov.nrows() || !cov.is_square() {
        return Err(Error::input(format!(
            "cannot propagate a {}x{} covariance through a {}x{} sensitivity matrix",
            cov.nrows(),
            cov.ncols(),
            f.nrows(),
            f.ncols()
        )));
    }
    let y = f * cov * f.transpose();
    Ok((&y + y.transpose()) * 0.5)
}

/// Coverage factor of a Gaussian for coverage probability `p`: `k = Phi^-1((1 + p) / 2)`
/// (1.959964 for 0.95).
pub fn normal_coverage_factor(p: f64) -> f64 {
    Normal::new(0.0, 1.0).map(|n| n.inverse_cdf(0.5 * (1.0 + p))).unwrap_or(f64::NAN)
}

/// `Cov = Gamma Lambda Gamma^T` (Soons 1993 App. A): variances along the principal directions,
/// largest first; `directions.column(i)` belongs to `variances[i]`.
#[derive(Clone, Debug)]
pub struct PrincipalAxes {
    pub variances: Vec<f64>,
    pub directions: DMatrix<f64>,
}

/// Principal axes of a symmetric covariance matrix (the first is the direction of largest uncertainty).
pub fn principal_axes(cov: &DMatrix<f64>) -> PrincipalAxes {
    let eigen = ((cov + cov.transpose()) * 0.5).symmetric_eigen();
    let mut order: Vec<usize> = (0..eigen.eigenvalues.len()).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
    let n = cov.nrows();
    let mut directions = DMatrix::zeros(n, n);
    for (k, &i) in order.iter().enumerate() {
        directions.set_column(k, &eigen.eigenvectors.column(i));
    }
    PrincipalAxes { variances: order.iter().map(|&i| eigen.eigenvalues[i].max(0.0)).collect(), directions }
}

/// The region `(e - mu)^T Cov^+ (e - mu) <= chi2_nu(level)` that holds a Gaussian vector with
/// probability `level` (Soons 1993 App. A, with the `chi2` quantile at the confidence level; the
/// printed "1 - chi2" is an OCR slip). `nu` is the number of nonzero eigenvalues.
#[derive(Clone, Debug)]
pub struct Ellipsoid {
    pub centre: DVector<f64>,
    pub level: f64,
    pub dof: usize,
    /// `chi2_nu(level)`.
    pub chi2: f64,
    /// Semi-axis lengths `sqrt(lambda_i chi2)`, largest first, along `axes.directions`.
    pub semi_axes: Vec<f64>,
    pub axes: PrincipalAxes,
}

impl Ellipsoid {
    /// Squared Mahalanobis distance of `point` from the centre over the nonzero principal axes.
    pub fn mahalanobis2(&self, point: &[f64]) -> f64 {
        let d = DVector::from_column_slice(point) - &self.centre;
        (0..self.dof).map(|i| d.dot(&self.axes.directions.column(i)).powi(2) / self.axes.variances[i]).sum()
    }

    pub fn contains(&self, point: &[f64]) -> bool {
        self.mahalanobis2(point) <= self.chi2
    }
}

/// The `level` confidence ellipsoid of a Gaussian with mean `centre` and covariance `cov`.
/// Eigenvalues below `1e-12` times the largest count as zero.
pub fn confidence_ellipsoid(centre: &[f64], cov: &DMatrix<f64>, level: f64) -> Result<Ellipsoid, Error> {
    if cov.nrows() != centre.len() || !cov.is_square() {
        return Err(Error::input(format!("covariance is {}x{} for {} values", cov.nrows(), cov.ncols(), centre.len())));
    }
    if !(level > 0.0 && level < 1.0) {
        return Err(Error::input(format!("confidence level {level} must lie strictly between 0 and 1")));
    }
    let axes = principal_axes(cov);
    let largest = axes.variances.first().copied().unwrap_or(0.0);
    let dof = axes.variances.iter().filter(|&&l| l > 1e-12 * largest && l > 0.0).count();
    if dof == 0 {
        return Err(Error::computation("the covariance matrix is zero: no ellipsoid"));
    }
    let chi2 = ChiSquared::new(dof as f64).map(|c| c.inverse_cdf(level)).map_err(|e| Error::computation(e.to_string()))?;
    let semi_axes = axes.variances.iter().take(dof).map(|l| (l * chi2).sqrt()).collect();
    Ok(Ellipsoid { centre: DVector::from_column_slice(centre), level, dof, chi2, semi_axes, axes })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coverage_factor_and_chi2_quantiles() {
        assert!((normal_coverage_factor(0.95) - 1.959964).abs() < 1e-6);
        // chi2 with 3 degrees of freedom at 95 %: 7.814728
        let e = confidence_ellipsoid(&[0.0; 3], &DMatrix::identity(3, 3), 0.95).unwrap();
        assert!((e.chi2 - 7.814728).abs() < 1e-5);
        assert_eq!(e.dof, 3);
    }

    #[test]
    fn principal_axes_of_a_rotated_covariance() {
        // variances 4 and 1 along (1, 1)/sqrt2 and (1, -1)/sqrt2
        let cov = DMatrix::from_row_slice(2, 2, &[2.5, 1.5, 1.5, 2.5]);
        let axes = principal_axes(&cov);
        assert!((axes.variances[0] - 4.0).abs() < 1e-12 && (axes.variances[1] - 1.0).abs() < 1e-12);
        assert!((axes.directions[(0, 0)].abs() - 0.5f64.sqrt()).abs() < 1e-12);
        assert!((axes.directions[(0, 0)] - axes.directions[(1, 0)]).abs() < 1e-12);
    }
}
