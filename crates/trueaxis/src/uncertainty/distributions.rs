//! Probability distributions of input quantities (JCGM 101 §6.4, Table 1): their expectation,
//! standard uncertainty and sampling. Quantities known only by their limits are rectangular
//! (Soons 1993 App. A, WECC 19-1990).

use crate::error::Error;
use nalgebra::{DMatrix, DVector};
use rand::Rng;
use rand_distr::{Distribution as _, StandardNormal, StudentT};

/// A scalar input distribution, in the unit of the quantity (e.g. um).
#[derive(Clone, Debug, PartialEq)]
pub enum Distribution {
    /// Gaussian N(mean, u^2) (JCGM 101 §6.4.7).
    Normal { mean: f64, u: f64 },
    /// Uniform over `[low, high]` (JCGM 101 §6.4.2): `u = (high - low) / (2 sqrt 3)`.
    Rectangular { low: f64, high: f64 },
    /// Triangular over `[low, high]` with its peak at `mode` (JCGM 101 §6.4.5 for the symmetric case):
    /// `u^2 = (a^2 + b^2 + c^2 - ab - ac - bc) / 18`.
    Triangular { low: f64, mode: f64, high: f64 },
    /// U-shaped (arc sine) over `[low, high]` (JCGM 101 §6.4.6), e.g. a sinusoidal quantity at a
    /// random phase: `u = (high - low) / (2 sqrt 2)`.
    Arcsine { low: f64, high: f64 },
    /// Scaled and shifted Student t with `dof` degrees of freedom (JCGM 101 §6.4.9):
    /// `u = scale sqrt(dof / (dof - 2))`, defined for `dof > 2`.
    StudentT { mean: f64, scale: f64, dof: f64 },
}

impl Distribution {
    /// Symmetric distribution of `kind` (`normal`, `rectangular`, `triangular`, `arcsine`) about `mean`
    /// with the given standard uncertainty `u`; the form the tests and budgets use to compare shapes.
    pub fn with_uncertainty(kind: &str, mean: f64, u: f64) -> Result<Distribution, Error> {
        let d = match kind {
            "normal" => Distribution::Normal { mean, u },
            "rectangular" => Distribution::Rectangular { low: mean - u * 3f64.sqrt(), high: mean + u * 3f64.sqrt() },
            "triangular" => Distribution::Triangular { low: mean - u * 6f64.sqrt(), mode: mean, high: mean + u * 6f64.sqrt() },
            "arcsine" => Distribution::Arcsine { low: mean - u * 2f64.sqrt(), high: mean + u * 2f64.sqrt() },
            other => return Err(Error::input(format!("unknown distribution `{other}`"))),
        };
        d.validated()
    }

    /// Checks the parameters: finite, positive widths, `low <= mode <= high`, `dof > 2`.
    pub fn validated(self) -> Result<Distribution, Error> {
        let bad = |m: &str| Err(Error::input(format!("{m} (in {self:?})")));
        let finite = match self {
            Distribution::Normal { mean, u } => mean.is_finite() && u.is_finite(),
            Distribution::Rectangular { low, high } | Distribution::Arcsine { low, high } => low.is_finite() && high.is_finite(),
            Distribution::Triangular { low, mode, high } => [low, mode, high].iter().all(|v| v.is_finite()),
            Distribution::StudentT { mean, scale, dof } => [mean, scale, dof].iter().all(|v| v.is_finite()),
        };
        if !finite {
            return bad("distribution parameters must be finite numbers");
        }
        match self {
            Distribution::Normal { u, .. } if u < 0.0 => bad("a standard uncertainty cannot be negative"),
            Distribution::Rectangular { low, high } | Distribution::Arcsine { low, high } if high < low => {
                bad("high must not be below low")
            }
            Distribution::Triangular { low, mode, high } if !(low <= mode && mode <= high) => bad("need low <= mode <= high"),
            Distribution::StudentT { scale, dof, .. } if scale < 0.0 || dof <= 2.0 => {
                bad("a Student t input needs scale >= 0 and more than 2 degrees of freedom (finite variance)")
            }
            _ => Ok(self),
        }
    }

    /// Expectation.
    pub fn mean(&self) -> f64 {
        match *self {
            Distribution::Normal { mean, .. } | Distribution::StudentT { mean, .. } => mean,
            Distribution::Rectangular { low, high } | Distribution::Arcsine { low, high } => 0.5 * (low + high),
            Distribution::Triangular { low, mode, high } => (low + mode + high) / 3.0,
        }
    }

    /// Standard uncertainty (standard deviation), JCGM 101 Table 1.
    pub fn standard_uncertainty(&self) -> f64 {
        match *self {
            Distribution::Normal { u, .. } => u,
            Distribution::Rectangular { low, high } => (high - low) / (2.0 * 3f64.sqrt()),
            Distribution::Arcsine { low, high } => (high - low) / (2.0 * 2f64.sqrt()),
            Distribution::Triangular { low: a, mode: c, high: b } => {
                ((a * a + b * b + c * c - a * b - a * c - b * c) / 18.0).max(0.0).sqrt()
            }
            Distribution::StudentT { scale, dof, .. } => scale * (dof / (dof - 2.0)).sqrt(),
        }
    }

    /// True for the Gaussian, whose linear images are Gaussian again (used to reduce sources).
    pub fn is_normal(&self) -> bool {
        matches!(self, Distribution::Normal { .. })
    }

    /// One draw (JCGM 101 §6.4 and Annex C): inverse distribution functions for the rectangular,
    /// triangular and arc sine laws, the ziggurat for the Gaussian.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        match *self {
            Distribution::Normal { mean, u } => {
                let z: f64 = StandardNormal.sample(rng);
                mean + u * z
            }
            Distribution::Rectangular { low, high } => low + (high - low) * rng.gen::<f64>(),
            Distribution::Arcsine { low, high } => {
                0.5 * (low + high) - 0.5 * (high - low) * (std::f64::consts::PI * rng.gen::<f64>()).cos()
            }
            Distribution::Triangular { low, mode, high } => {
                let r: f64 = rng.gen();
                let width = high - low;
                if width <= 0.0 {
                    return low;
                }
                let f_mode = (mode - low) / width;
                if r < f_mode {
                    low + (r * width * (mode - low)).sqrt()
                } else {
                    high - ((1.0 - r) * width * (high - mode)).sqrt()
                }
            }
            Distribution::StudentT { mean, scale, dof } => {
                let t = StudentT::new(dof).map(|d| d.sample(rng)).unwrap_or(0.0);
                mean + scale * t
            }
        }
    }
}

/// A multivariate Gaussian N(mean, V) (JCGM 102 §6.3), sampled as `mean + A z` with `A A^T = V`
/// from the symmetric eigendecomposition, so that singular (positive semidefinite) covariances
/// such as those of a projected source are allowed.
#[derive(Clone, Debug)]
pub struct MultivariateNormal {
    mean: DVector<f64>,
    factor: DMatrix<f64>,
}

impl MultivariateNormal {
    /// `covariance` must be symmetric positive semidefinite (eigenvalues below `-1e-10` times the
    /// largest are refused; smaller negative ones from rounding are set to zero).
    pub fn new(mean: DVector<f64>, covariance: &DMatrix<f64>) -> Result<MultivariateNormal, Error> {
        let n = mean.len();
        if covariance.shape() != (n, n) {
            return Err(Error::input(format!("covariance is {:?} for a mean of {n} values", covariance.shape())));
        }
        if covariance.iter().chain(mean.iter()).any(|v| !v.is_finite()) {
            return Err(Error::input("mean and covariance must be finite"));
        }
        let symmetric = (covariance + covariance.transpose()) * 0.5;
        let eigen = symmetric.symmetric_eigen();
        let largest = eigen.eigenvalues.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
        if eigen.eigenvalues.iter().any(|&l| l < -1e-10 * largest) {
            return Err(Error::input("covariance matrix is not positive semidefinite"));
        }
        let mut factor = eigen.eigenvectors;
        for (j, l) in eigen.eigenvalues.iter().enumerate() {
            factor.column_mut(j).scale_mut(l.max(0.0).sqrt());
        }
        Ok(MultivariateNormal { mean, factor })
    }

    pub fn dimension(&self) -> usize {
        self.mean.len()
    }

    /// The covariance `A A^T`.
    pub fn covariance(&self) -> DMatrix<f64> {
        &self.factor * self.factor.transpose()
    }

    /// Adds one draw of `A z` (zero mean) to `out`, without allocating.
    pub fn add_centred_sample<R: Rng + ?Sized>(&self, rng: &mut R, out: &mut [f64]) {
        // the factor's columns as contiguous slices (column-major storage): one vectorised
        // multiply-add per column
        let n = self.factor.nrows();
        for column in self.factor.as_slice().chunks_exact(n) {
            let z: f64 = StandardNormal.sample(rng);
            for (o, a) in out[..n].iter_mut().zip(column) {
                *o += a * z;
            }
        }
    }

    /// Adds `A z` for `n` draws at once, `z` (standard normal variates) and `out` component-major
    /// (`z[j n + i]` component `j` of draw `i`, `n = out.len() / dimension`): per value the same
    /// products and additions, in the same order (column `j` of `A` after column `j - 1`), as `n`
    /// calls of [`MultivariateNormal::add_centred_sample`], so the same result bit for bit;
    /// eight draws at a time kept in registers across the columns.
    pub fn add_centred_block(&self, z: &[f64], out: &mut [f64]) {
        const LANES: usize = 8;
        let d = self.factor.nrows();
        let n = out.len() / d;
        for (r, o) in out.chunks_exact_mut(n).enumerate() {
            let a: Vec<f64> = (0..d).map(|j| self.factor[(r, j)]).collect();
            let whole = n - n % LANES;
            for i0 in (0..whole).step_by(LANES) {
                let mut acc: [f64; LANES] = o[i0..i0 + LANES].try_into().expect("eight lanes");
                for (j, aj) in a.iter().enumerate() {
                    let zj = &z[j * n + i0..j * n + i0 + LANES];
                    for (s, zl) in acc.iter_mut().zip(zj) {
                        *s += aj * zl;
                    }
                }
                o[i0..i0 + LANES].copy_from_slice(&acc);
            }
            for (i, o) in o.iter_mut().enumerate().skip(whole) {
                for (j, aj) in a.iter().enumerate() {
                    *o += aj * z[j * n + i];
                }
            }
        }
    }

    /// Writes one draw of `mean + A z` into `out`.
    pub fn sample_into<R: Rng + ?Sized>(&self, rng: &mut R, out: &mut [f64]) {
        out.copy_from_slice(self.mean.as_slice());
        self.add_centred_sample(rng, out);
    }
}
