//! Robust regression by M-estimation (Huber 1981): iteratively reweighted least squares (IRLS)
//! with Huber or Tukey (bisquare) weights, and the covariance of the estimate.
//!
//! A fit with stated weights w_i (1 / sigma_i^2; 1 for an unweighted fit) has standardized
//! residuals u_i = sqrt(w_i) r_i / s, with s the MAD of the sqrt(w_i) r_i scaled by 1.4826
//! (`robust::mad_sigma`), recomputed at every step. Each step solves the least-squares problem
//! with weights w_i omega(u_i):
//! - Huber: omega(u) = 1 for |u| <= k, k / |u| beyond; psi(u) = u omega(u), k = 1.345;
//! - Tukey: omega(u) = (1 - (u/c)^2)^2 for |u| <= c, 0 beyond, c = 4.685;
//!
//! both 95 % efficient at normal errors (Holland and Welsch 1977). Tukey's objective is not convex:
//! its steps start from the Huber solution. The iteration stops when no coefficient moves by more
//! than 1e-9 of its size (or of 1), at most 100 steps.
//!
//! The covariance of the estimate is the asymptotic one of an M-estimator with Huber's
//! small-sample correction (Huber 1981 §7.6, the first of his three forms; "H1" of statsmodels):
//! `Cov = K^2 [sum psi(u_i)^2 / (n - p)] / [sum psi'(u_i) / n]^2 s^2 (X^T W X)^-1`,
//! `K = 1 + (p / n) var(psi') / mean(psi')^2`, with (X^T W X)^-1 of the stated weights. On normal
//! errors the factor K^2 E psi^2 / (E psi')^2 is 1 / 0.95 for both weight functions.

use super::robust::{mad_sigma, HUBER_K};

/// The Tukey (bisquare) tuning constant (95 % efficiency at normal data).
pub const TUKEY_C: f64 = 4.685;

/// A weight below this leaves a reading as good as out of the fit; such readings are listed.
pub const LISTED_WEIGHT: f64 = 0.1;

/// The weight function of an M-estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Weighting {
    Huber,
    Tukey,
}

impl Weighting {
    /// `huber` or `tukey`.
    pub fn parse(name: &str) -> Option<Weighting> {
        match name {
            "huber" => Some(Weighting::Huber),
            "tukey" => Some(Weighting::Tukey),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Weighting::Huber => "huber",
            Weighting::Tukey => "tukey",
        }
    }

    /// The tuning constant, in robust standard deviations of the residuals.
    pub fn constant(self) -> f64 {
        match self {
            Weighting::Huber => HUBER_K,
            Weighting::Tukey => TUKEY_C,
        }
    }

    /// "Huber weights (k = 1.345 MAD-based sigmas)": the method as printed.
    pub fn describe(self) -> String {
        let (who, sym) = match self {
            Weighting::Huber => ("Huber", "k"),
            Weighting::Tukey => ("Tukey bisquare", "c"),
        };
        format!("{who} weights ({sym} = {} MAD-based sigmas)", self.constant())
    }

    /// omega(u): the weight of a standardized residual.
    pub fn weight(self, u: f64) -> f64 {
        let c = self.constant();
        match self {
            Weighting::Huber if u.abs() <= c => 1.0,
            Weighting::Huber => c / u.abs(),
            Weighting::Tukey if u.abs() <= c => (1.0 - (u / c).powi(2)).powi(2),
            Weighting::Tukey => 0.0,
        }
    }

    /// psi(u) = u omega(u).
    pub fn psi(self, u: f64) -> f64 {
        u * self.weight(u)
    }

    /// psi'(u).
    pub fn psi_derivative(self, u: f64) -> f64 {
        let c = self.constant();
        match self {
            Weighting::Huber => f64::from(u.abs() <= c),
            Weighting::Tukey if u.abs() <= c => {
                let q = (u / c).powi(2);
                (1.0 - q) * (1.0 - 5.0 * q)
            }
            Weighting::Tukey => 0.0,
        }
    }
}

/// What the iteration ended with.
#[derive(Clone, Debug, PartialEq)]
pub struct RobustWeights {
    pub weighting: Weighting,
    /// omega(u_i) of every reading at the solution.
    pub weights: Vec<f64>,
    /// u_i at the solution.
    pub standardized: Vec<f64>,
    /// The robust scale s of sqrt(w_i) r_i (um for readings in um).
    pub scale: f64,
    pub iterations: usize,
    pub converged: bool,
}

impl RobustWeights {
    /// The factor of `s^2 (X^T W X)^-1` that makes the covariance of the estimate (Huber 1981
    /// §7.6, module text); `p` unknowns.
    pub fn covariance_factor(&self, p: usize) -> f64 {
        let n = self.standardized.len() as f64;
        let w = self.weighting;
        let d: Vec<f64> = self.standardized.iter().map(|&u| w.psi_derivative(u)).collect();
        let mean = d.iter().sum::<f64>() / n;
        let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
        let k = 1.0 + p as f64 / n * var / (mean * mean);
        let psi2 = self.standardized.iter().map(|&u| w.psi(u).powi(2)).sum::<f64>() / (n - p as f64).max(1.0);
        k * k * psi2 / (mean * mean) * self.scale * self.scale
    }

    /// Indices of the readings whose weight is under [`LISTED_WEIGHT`].
    pub fn listed(&self) -> Vec<usize> {
        (0..self.weights.len()).filter(|&i| self.weights[i] < LISTED_WEIGHT).collect()
    }

    /// The sum of the weights: how many readings the fit effectively rests on.
    pub fn effective_readings(&self) -> f64 {
        self.weights.iter().sum()
    }
}

/// IRLS for a linear problem whose least-squares solution `solve(extra)` with the stated weights
/// multiplied by `extra` returns (coefficients, residuals). `stated` are the stated weights w_i.
/// Returns the last solution and the robust weights it was found with.
pub fn irls<T, E>(
    weighting: Weighting,
    stated: &[f64],
    mut solve: impl FnMut(&[f64]) -> Result<(T, Vec<f64>, Vec<f64>), E>,
) -> Result<(T, RobustWeights), E> {
    let n = stated.len();
    let (mut fit, mut coefficients, mut residuals) = solve(&vec![1.0; n])?;
    let mut out =
        RobustWeights { weighting, weights: vec![1.0; n], standardized: vec![0.0; n], scale: 0.0, iterations: 0, converged: false };
    // Tukey from the Huber solution (a convex start)
    let stages: &[Weighting] = if weighting == Weighting::Tukey { &[Weighting::Huber, Weighting::Tukey] } else { &[Weighting::Huber] };
    for &stage in stages {
        for _ in 0..100 {
            let scaled: Vec<f64> = residuals.iter().zip(stated).map(|(r, w)| r * w.sqrt()).collect();
            let s = mad_sigma(&scaled);
            if !(s.is_finite() && s > 0.0) {
                break;
            }
            // a zero weight would make the problem singular where few readings carry a parameter
            let weights: Vec<f64> = scaled.iter().map(|x| stage.weight(x / s).max(1e-9)).collect();
            let (next, next_coefficients, next_residuals) = solve(&weights)?;
            let moved = next_coefficients.iter().zip(&coefficients).any(|(a, b)| (a - b).abs() > 1e-9 * a.abs().max(1.0));
            (fit, coefficients, residuals) = (next, next_coefficients, next_residuals);
            out.iterations += 1;
            if !moved {
                out.converged = stage == weighting;
                break;
            }
        }
    }
    let scaled: Vec<f64> = residuals.iter().zip(stated).map(|(r, w)| r * w.sqrt()).collect();
    out.scale = mad_sigma(&scaled);
    out.standardized = scaled.iter().map(|x| x / out.scale).collect();
    out.weights = out.standardized.iter().map(|&u| weighting.weight(u)).collect();
    Ok((fit, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// E psi^2 / (E psi')^2 on normal errors by quadrature: 1 / 0.95 for both tuning constants
    /// (they are chosen for 95 % efficiency).
    #[test]
    fn both_weightings_are_95_percent_efficient_at_normal_errors() {
        for w in [Weighting::Huber, Weighting::Tukey] {
            let (mut psi2, mut dpsi) = (0.0, 0.0);
            let h = 1e-3;
            for i in -10_000..=10_000 {
                let u = i as f64 * h;
                let phi = (-0.5 * u * u).exp() / (2.0 * std::f64::consts::PI).sqrt() * h;
                psi2 += w.psi(u).powi(2) * phi;
                dpsi += w.psi_derivative(u) * phi;
            }
            let efficiency = dpsi * dpsi / psi2;
            assert!((efficiency - 0.95).abs() < 0.001, "{w:?}: {efficiency}");
        }
    }
}
