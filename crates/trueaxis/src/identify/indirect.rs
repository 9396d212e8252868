//! Indirect identification: the parameters of a campaign from measurements that see the combined
//! (volumetric) error (Andolfatto et al. 2011 eqs. 3-5; Soons 1993 §4.2-4.3).
//!
//! - Weighted least squares on the stacked design matrix, by QR (Soons 1993 §3.2.2, unit-length
//!   scaling) or by SVD (minimum-norm pseudo-inverse, Andolfatto et al. 2011 eq. 5, also for rank-deficient sets
//!   when allowed).
//! - Optional Levenberg-Marquardt refinement on the exact kinematic chain.
//! - Covariance `s0^2 (X^T W X)^-1` with `s0^2 = r^T W r / (n - rank)` estimated from the residuals
//!   (Soons 1993 eq. 4.11 with weights; `s0 = 1` when the stated noise is right), the prediction
//!   variance `g^T Cov g` (eq. 4.12), residual statistics per channel.

use super::campaign::{Campaign, DesignMatrix};
use super::identifiability::{IdentifiabilityReport, ScaledSvd, RANK_TOLERANCE};
use super::least_squares::design_times;
use super::IdentifyError;
use crate::error_model::ErrorModel;
use crate::machine::Machine;
use crate::model::{Frame, Setup};
use nalgebra::{DMatrix, DVector, Matrix3};

/// The linear solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Solver {
    /// QR of the scaled matrix (full rank only).
    #[default]
    Qr,
    /// SVD pseudo-inverse (minimum norm in scaled units when rank deficient).
    Svd,
}

impl Solver {
    pub fn name(self) -> &'static str {
        match self {
            Solver::Qr => "qr",
            Solver::Svd => "svd",
        }
    }
}

/// Options of [`identify`].
#[derive(Clone, Copy, Debug)]
pub struct IndirectOptions {
    pub solver: Solver,
    /// Return a (minimum-norm) solution of a rank-deficient set instead of an error.
    pub allow_rank_deficient: bool,
    /// Refine by Levenberg-Marquardt on the exact chain after the linear solution.
    pub refine: bool,
    /// Relative singular-value threshold of the rank decision.
    pub rank_tolerance: f64,
}

impl Default for IndirectOptions {
    fn default() -> Self {
        IndirectOptions { solver: Solver::Qr, allow_rank_deficient: false, refine: false, rank_tolerance: RANK_TOLERANCE }
    }
}

/// Residual statistics of one channel (um).
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelStatistics {
    pub name: String,
    pub count: usize,
    pub mean: f64,
    pub rms: f64,
    pub max_abs: f64,
    /// The stated noise of the channel (um; the mean if it varies).
    pub sigma: f64,
}

/// What the Levenberg-Marquardt refinement did.
#[derive(Clone, Debug, PartialEq)]
pub struct Refinement {
    pub iterations: usize,
    /// Weighted RMS (`sqrt(r^T W r / n)`) of the exact residuals at the linear and the refined solution.
    pub initial_weighted_rms: f64,
    pub final_weighted_rms: f64,
    /// Largest change of a parameter by the refinement, in its standard uncertainties.
    pub largest_change_in_u: f64,
}

/// The result of an indirect identification.
#[derive(Clone, Debug)]
pub struct Identification {
    pub names: Vec<String>,
    pub units: Vec<String>,
    /// Values of the unknowns before (from the nominal errors) and after, and the difference
    /// (user units).
    pub nominal: Vec<f64>,
    pub values: Vec<f64>,
    pub delta: Vec<f64>,
    /// Standard uncertainty of each value; `None` for a parameter in an unidentifiable combination.
    pub std_uncertainty: Vec<Option<f64>>,
    /// `s0^2 (X^T W X)^+` (user units squared).
    pub covariance: DMatrix<f64>,
    /// Standard deviation of unit weight `s0 = sqrt(r^T W r / (n - rank))` (1 when the residuals
    /// match the stated noise).
    pub sigma0: f64,
    pub dof: usize,
    /// Readings minus the model at the solution (um), one per row of the design matrix.
    pub residuals: Vec<f64>,
    pub residual_rms_um: f64,
    pub channels: Vec<ChannelStatistics>,
    pub identifiability: IdentifiabilityReport,
    pub solver: Solver,
    pub refinement: Option<Refinement>,
}

impl Identification {
    /// Variance (um^2) of a predicted reading with design row `g` (um per user unit), from the
    /// parameter covariance: `g^T Cov g` (Soons 1993 eq. 4.12 with `Cov = s0^2 (X^T W X)^-1`).
    pub fn prediction_variance(&self, g: &[f64]) -> f64 {
        let g = DVector::from_column_slice(g);
        (g.transpose() * &self.covariance * &g)[(0, 0)].max(0.0)
    }

    /// Covariance (um^2) of the predicted volumetric position error `dx dy dz` at pose `q` (mm,
    /// rad) between the points of `setup` in `frame`, propagated from the identified parameters:
    /// `F Cov F^T` (Soons 1993 App. A eq. A.4).
    pub fn volumetric_covariance(&self, campaign: &Campaign, machine: &Machine, q: &[f64], setup: &Setup, frame: Frame) -> Matrix3<f64> {
        let f = campaign.unknown_jacobian(machine, q, setup, frame).rows(0, 3) * 1e3;
        let c = &f * &self.covariance * f.transpose();
        Matrix3::from_fn(|i, j| c[(i, j)])
    }
}

/// Identifies the unknowns of `campaign` starting from the known errors `nominal`.
pub fn identify(
    campaign: &Campaign,
    machine: &Machine,
    nominal: &ErrorModel,
    options: &IndirectOptions,
) -> Result<Identification, IdentifyError> {
    let design = campaign.design_matrix(machine, nominal)?;
    let start = campaign.nominal_values(nominal)?;
    let mut result = solve(&design, &start, options)?;
    if options.refine {
        refine(campaign, machine, nominal, &design, options.rank_tolerance, &mut result)?;
    }
    Ok(result)
}

/// The linear weighted least-squares solution of a design matrix; `start` are the values of the
/// unknowns the observations were reduced with (user units).
pub fn solve(design: &DesignMatrix, start: &[f64], options: &IndirectOptions) -> Result<Identification, IdentifyError> {
    let (n, p) = design.matrix.shape();
    if n <= p {
        return Err(IdentifyError::Input(format!("{n} readings cannot determine {p} unknowns and a residual variance; measure more")));
    }
    let svd = ScaledSvd::with_observations(&design.matrix, &design.weights, &design.observations, options.rank_tolerance);
    let report = IdentifiabilityReport::new(&design.matrix, &svd, &design.names, &design.units);
    let deficient = svd.rank < p;
    if deficient && !options.allow_rank_deficient {
        return Err(IdentifyError::RankDeficient {
            message: format!(
                "{} of {p} parameter combinations are not identifiable: {}",
                p - svd.rank,
                report.combinations_summary("the scaled design matrix is singular")
            ),
        });
    }
    let solver = if deficient { Solver::Svd } else { options.solver };
    let (delta, unscaled) = match solver {
        Solver::Qr => svd.solve_triangular().ok_or_else(|| IdentifyError::RankDeficient {
            message: "the triangular factor of the scaled design matrix is singular".into(),
        })?,
        Solver::Svd => (svd.solve_minimum_norm(), svd.pseudo_inverse_normal()),
    };
    let fitted = design_times(&design.matrix, &delta);
    let residuals: Vec<f64> = design.observations.iter().zip(&fitted).map(|(y, f)| y - f).collect();
    Ok(assemble(design, start, delta, unscaled, residuals, svd.rank, report, solver))
}

#[allow(clippy::too_many_arguments)]
fn assemble(
    design: &DesignMatrix,
    start: &[f64],
    delta: Vec<f64>,
    unscaled: DMatrix<f64>,
    residuals: Vec<f64>,
    rank: usize,
    report: IdentifiabilityReport,
    solver: Solver,
) -> Identification {
    let n = residuals.len();
    let dof = n - rank;
    let weighted: f64 = residuals.iter().zip(&design.weights).map(|(r, w)| r * r * w).sum();
    let sigma0 = (weighted / dof as f64).sqrt();
    let covariance = &unscaled * (sigma0 * sigma0);
    let std_uncertainty = (0..delta.len()).map(|j| report.identifiable[j].then(|| covariance[(j, j)].max(0.0).sqrt())).collect();
    let values = start.iter().zip(&delta).map(|(s, d)| s + d).collect();
    let residual_rms_um = (residuals.iter().map(|r| r * r).sum::<f64>() / n as f64).sqrt();
    let channels = channel_statistics(design, &residuals);
    Identification {
        names: design.names.clone(),
        units: design.units.clone(),
        nominal: start.to_vec(),
        values,
        delta,
        std_uncertainty,
        covariance,
        sigma0,
        dof,
        residuals,
        residual_rms_um,
        channels,
        identifiability: report,
        solver,
        refinement: None,
    }
}

/// Residual mean, RMS and largest absolute value per channel.
pub fn channel_statistics(design: &DesignMatrix, residuals: &[f64]) -> Vec<ChannelStatistics> {
    design
        .channel_names
        .iter()
        .enumerate()
        .map(|(c, name)| {
            let rows: Vec<usize> = (0..residuals.len()).filter(|&i| design.channels[i] == c).collect();
            let count = rows.len().max(1) as f64;
            ChannelStatistics {
                name: name.clone(),
                count: rows.len(),
                mean: rows.iter().map(|&i| residuals[i]).sum::<f64>() / count,
                rms: (rows.iter().map(|&i| residuals[i] * residuals[i]).sum::<f64>() / count).sqrt(),
                max_abs: rows.iter().map(|&i| residuals[i].abs()).fold(0.0, f64::max),
                sigma: rows.iter().map(|&i| design.sigma_um[i]).sum::<f64>() / count,
            }
        })
        .collect()
}

/// Levenberg-Marquardt on the exact chain, from the linear solution: minimises
/// `sum w_i (reading_i - exact_i(theta))^2` with central-difference Jacobians of the exact model,
/// then recomputes the covariance from the final Jacobian.
fn refine(
    campaign: &Campaign,
    machine: &Machine,
    nominal: &ErrorModel,
    design: &DesignMatrix,
    tolerance: f64,
    result: &mut Identification,
) -> Result<(), IdentifyError> {
    if result.identifiability.rank < result.delta.len() {
        return Err(IdentifyError::Input("refinement on the exact chain needs an identifiable parameter set".into()));
    }
    let p = result.delta.len();
    let zero = vec![0.0; p];
    let readings: Vec<f64> = campaign.predict(machine, nominal, &zero)?.iter().zip(&design.observations).map(|(f, y)| f + y).collect();
    let w = &design.weights;
    let cost = |theta: &[f64]| -> Result<(f64, Vec<f64>), IdentifyError> {
        let r: Vec<f64> = readings.iter().zip(campaign.predict(machine, nominal, theta)?).map(|(y, f)| y - f).collect();
        Ok((r.iter().zip(w).map(|(r, w)| r * r * w).sum(), r))
    };
    // steps giving about 0.01 um at the most sensitive reading
    let steps: Vec<f64> = (0..p).map(|j| 0.01 / design.matrix.column(j).amax().max(1e-12)).collect();
    let jacobian_at = |theta: &[f64]| -> Result<DMatrix<f64>, IdentifyError> {
        let mut j = DMatrix::zeros(readings.len(), p);
        for c in 0..p {
            let mut plus = theta.to_vec();
            let mut minus = theta.to_vec();
            plus[c] += steps[c];
            minus[c] -= steps[c];
            let (fp, fm) = (campaign.predict(machine, nominal, &plus)?, campaign.predict(machine, nominal, &minus)?);
            for i in 0..readings.len() {
                j[(i, c)] = (fp[i] - fm[i]) / (2.0 * steps[c]);
            }
        }
        Ok(j)
    };
    let linear = result.delta.clone();
    let mut theta = linear.clone();
    let (mut current, _) = cost(&theta)?;
    let initial = current;
    let mut lambda = 1e-3;
    let mut iterations = 0;
    while iterations < 30 {
        iterations += 1;
        let j = jacobian_at(&theta)?;
        let (_, r) = cost(&theta)?;
        let mut jw = j.clone();
        for (i, wi) in w.iter().enumerate() {
            jw.row_mut(i).scale_mut(*wi);
        }
        let normal = jw.transpose() * &j;
        let gradient = jw.transpose() * DVector::from_column_slice(&r);
        let mut accepted = None;
        for _ in 0..10 {
            let mut damped = normal.clone();
            for d in 0..p {
                damped[(d, d)] *= 1.0 + lambda;
            }
            if let Some(step) = damped.cholesky().map(|c| c.solve(&gradient)) {
                let trial: Vec<f64> = theta.iter().zip(step.iter()).map(|(t, s)| t + s).collect();
                let (c, _) = cost(&trial)?;
                if c <= current {
                    accepted = Some((trial, c, step));
                    lambda = (lambda / 10.0).max(1e-12);
                    break;
                }
            }
            lambda *= 10.0;
        }
        let Some((trial, c, step)) = accepted else { break };
        // converged: every step below 1e-6 standard uncertainties, or no measurable decrease
        let small = step.iter().zip(&result.std_uncertainty).all(|(s, u)| s.abs() <= 1e-6 * u.unwrap_or(0.0));
        let decrease = (current - c) / current.max(1e-300);
        theta = trial;
        current = c;
        if small || decrease < 1e-12 {
            break;
        }
    }
    let j = jacobian_at(&theta)?;
    let refined_design = DesignMatrix { matrix: j, ..design.clone() };
    let (_, residuals) = cost(&theta)?;
    let svd = ScaledSvd::new(&refined_design.matrix, w, tolerance);
    let unscaled = svd.pseudo_inverse_normal();
    let report = result.identifiability.clone();
    let mut refined = assemble(&refined_design, &result.nominal, theta.clone(), unscaled, residuals, svd.rank, report, result.solver);
    let largest_change_in_u = theta
        .iter()
        .zip(&linear)
        .zip(&refined.std_uncertainty)
        .map(|((a, b), u)| u.map_or(0.0, |u| if u > 0.0 { (a - b).abs() / u } else { 0.0 }))
        .fold(0.0, f64::max);
    let n = readings.len() as f64;
    refined.refinement = Some(Refinement {
        iterations,
        initial_weighted_rms: (initial / n).sqrt(),
        final_weighted_rms: (current / n).sqrt(),
        largest_change_in_u,
    });
    *result = refined;
    Ok(())
}
