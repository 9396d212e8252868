//! Verification of a compensation by a re-measurement (NISTIR 5236 §4: the accuracy reached after
//! compensation; Soons 1993 §5.1.1: "if the developed models are correct, the compensated errors
//! should be close to the observed repeatability of the hole plate measurements").
//!
//! The re-measurement is a campaign (any instrument of [`crate::identify`]: probed hole plates,
//! 3D ball, lengths) measured either with the compensation active (`compensated`), when under the
//! model every reading should be zero, or without it, when the model's prediction is subtracted
//! off-line (Soons 1993 §5.1.1: "these simulated errors are used to compensate the errors in the
//! actual measurements of the hole plate"). What the campaign lists as unknowns is fitted to the
//! residuals: the nuisances that a verification must remove (a plate's rigid misalignment, a gauge
//! offset) and any error parameter the user suspects is left (Soons 1993: a squareness changed by
//! wear), each with its uncertainty and significance.
//!
//! Expected residual: the repeatability of each reading (its `sigma_um`, one standard deviation),
//! plus, when the identification the model came from is given, the uncertainty of the model's
//! prediction `g^T Cov g` (Soons 1993 eq. 4.12; the digest of §4.3: "used to test whether an
//! observed-minus-predicted residual is consistent with the model's uncertainty"). Readings share
//! the model's parameters, so the covariance of the expected residuals is
//! `V = diag(sigma^2) + G Cov G^T`; the fit is generalised least squares in `V` and the test
//! statistic is `chi2 = r^T V^-1 r` on `nu = n - rank` degrees of freedom:
//! - repeatability known (its standard deviation taken as exact): chi-square test, consistent when
//!   `chi2 <= chi2_nu(level)`;
//! - repeatability estimated from `nu_r` degrees of freedom (e.g. 5 repeats of each of 8 holes:
//!   `nu_r = 32`): `F = (chi2 / nu)` against `F(nu, nu_r)(level)`.

use crate::error_model::ErrorModel;
use crate::identify::{Campaign, Identification, IdentifyError};
use crate::machine::Machine;
use nalgebra::{DMatrix, DVector};
use statrs::distribution::{ChiSquared, ContinuousCDF, FisherSnedecor, StudentsT};

/// What the re-measurement is and how it is tested.
#[derive(Clone, Debug)]
pub struct VerificationOptions {
    /// Measured with the compensation active (expected readings zero) or without it (expected
    /// readings the model's prediction).
    pub compensated: bool,
    /// Degrees of freedom of the repeatability (`None`: taken as exact, chi-square test).
    pub repeatability_dof: Option<usize>,
    /// Confidence level of the tests (0.95).
    pub level: f64,
    /// Channels (`measurement:column`) left out, e.g. the out-of-plane `dz` of a hole plate in XY.
    pub ignored_channels: Vec<String>,
}

/// Per channel: what the model predicted, what was measured, what is left.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ChannelVerification {
    pub name: String,
    pub count: usize,
    /// The error the model predicts without compensation (um): what compensation removes.
    pub predicted_rms: f64,
    pub predicted_max: f64,
    /// The readings (um).
    pub measured_rms: f64,
    pub measured_max: f64,
    /// Residual after the expected readings and the fitted unknowns are removed (um).
    pub residual_rms: f64,
    pub residual_max: f64,
    /// RMS over the readings of the expected residual standard deviation `sqrt(V_ii)` (um), and of
    /// the repeatability alone.
    pub expected_rms: f64,
    pub repeatability: f64,
}

/// A fitted unknown of the re-measurement.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FittedUnknown {
    pub name: String,
    pub unit: String,
    pub value: f64,
    pub std_uncertainty: f64,
    /// `|value| / u` above the Student-t quantile of the level (two-sided).
    pub significant: bool,
    /// Whether this is an error parameter of the machine (else a nuisance of one measurement).
    pub model: bool,
}

/// The result of a verification.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Verification {
    pub compensated: bool,
    pub readings: usize,
    pub channels: Vec<ChannelVerification>,
    pub fitted: Vec<FittedUnknown>,
    /// Unknowns of the campaign that the kept readings do not see, left out of the fit.
    pub unseen: Vec<String>,
    /// Residual per reading (um), in campaign order, ignored channels included (not fitted).
    pub residuals: Vec<f64>,
    pub chi2: f64,
    pub dof: usize,
    /// `sqrt(chi2 / dof)`: 1 when the residuals are as large as expected.
    pub s0: f64,
    /// "chi-square" or "F".
    pub test: &'static str,
    pub statistic: f64,
    pub critical: f64,
    pub p_value: f64,
    pub level: f64,
    /// The residuals are within what the repeatability (and the model's uncertainty) explain.
    pub consistent: bool,
    /// Whether the model's uncertainty is part of the expected residuals.
    pub with_model_uncertainty: bool,
}

fn input(message: String) -> IdentifyError {
    IdentifyError::Input(message)
}

/// Verifies `errors` (the model the compensation used) against the re-measurement `campaign`;
/// `calibration`: the campaign and identification the model came from, for the model's
/// uncertainty.
pub fn verify(
    campaign: &Campaign,
    machine: &Machine,
    errors: &ErrorModel,
    calibration: Option<(&Campaign, &Identification)>,
    options: &VerificationOptions,
) -> Result<Verification, IdentifyError> {
    if !(options.level > 0.0 && options.level < 1.0) {
        return Err(input(format!("the confidence level {} must lie in (0, 1)", options.level)));
    }
    if options.repeatability_dof == Some(0) {
        return Err(input("the repeatability needs at least 1 degree of freedom".into()));
    }
    let design = campaign.design_matrix(machine, errors)?;
    for c in &options.ignored_channels {
        if !design.channel_names.contains(c) {
            return Err(input(format!("{}: no channel `{c}` to ignore (channels: {})", campaign.origin, design.channel_names.join(", "))));
        }
    }
    let n_all = design.rows();
    // readings minus the model's prediction (what off-line compensation leaves); with the
    // compensation active the readings themselves
    let predicted_before = campaign.predict(machine, errors, &vec![0.0; campaign.unknowns.len()])?;
    let measured: Vec<f64> = design.observations.iter().zip(&predicted_before).map(|(o, p)| o + p).collect();
    let observed: Vec<f64> = if options.compensated { measured.clone() } else { design.observations.clone() };
    let kept: Vec<usize> = (0..n_all).filter(|&i| !options.ignored_channels.contains(&design.channel_names[design.channels[i]])).collect();
    let n = kept.len();
    if n <= design.matrix.ncols() {
        return Err(input(format!(
            "{}: {n} readings cannot test a fit of {} unknowns; measure more",
            campaign.origin,
            design.matrix.ncols()
        )));
    }
    // the covariance of the expected residuals
    let mut v = DMatrix::from_diagonal(&DVector::from_iterator(n, kept.iter().map(|&i| design.sigma_um[i].powi(2))));
    let with_model = calibration.is_some();
    if let Some((cal, id)) = calibration {
        let g = model_rows(campaign, cal, machine, errors)?;
        let k = g.ncols();
        let cov = id.covariance.view((0, 0), (k, k)).into_owned();
        let g = DMatrix::from_fn(n, k, |r, c| g[(kept[r], c)]);
        v += &g * cov * g.transpose();
    }
    let cholesky = v.clone().cholesky().ok_or_else(|| input("the covariance of the expected residuals is not positive definite".into()))?;
    // unknowns the kept readings do not see (a plate's out-of-plane misalignment when the
    // out-of-plane channel is ignored) are left out of the fit
    let norms: Vec<f64> =
        (0..design.matrix.ncols()).map(|c| kept.iter().map(|&r| design.matrix[(r, c)].powi(2)).sum::<f64>().sqrt()).collect();
    let largest = norms.iter().copied().fold(0.0, f64::max);
    let seen: Vec<usize> = (0..norms.len()).filter(|&c| norms[c] > 1e-12 * largest).collect();
    let unseen: Vec<String> = (0..norms.len()).filter(|c| !seen.contains(c)).map(|c| design.names[c].clone()).collect();
    let p = seen.len();
    let x = DMatrix::from_fn(n, p, |r, c| design.matrix[(kept[r], seen[c])]);
    let y = DVector::from_iterator(n, kept.iter().map(|&i| observed[i]));
    let (wx, wy) =
        (cholesky.l().solve_lower_triangular(&x).expect("L regular"), cholesky.l().solve_lower_triangular(&y).expect("L regular"));
    let (theta, covariance, rank) = if p == 0 {
        (DVector::zeros(0), DMatrix::zeros(0, 0), 0)
    } else {
        let svd = wx.clone().svd(true, true);
        let tol = 1e-10 * svd.singular_values.max();
        let rank = svd.singular_values.iter().filter(|s| **s > tol).count();
        if rank < p {
            return Err(IdentifyError::RankDeficient {
                message: format!(
                    "{}: the re-measurement cannot separate its {p} unknowns ({} of them are combinations of the others); list fewer parameters",
                    campaign.origin,
                    p - rank
                ),
            });
        }
        let theta = svd.solve(&wy, tol).expect("full rank");
        let covariance = (wx.transpose() * &wx).try_inverse().ok_or_else(|| input("singular information matrix".into()))?;
        (theta, covariance, rank)
    };
    let whitened_residual = &wy - &wx * &theta;
    let chi2 = whitened_residual.norm_squared();
    let dof = n - rank;
    let fit = DMatrix::from_fn(n_all, p, |r, c| design.matrix[(r, seen[c])]) * &theta;
    let residuals: Vec<f64> = (0..n_all).map(|i| observed[i] - fit[i]).collect();
    let (test, statistic, critical, p_value) = match options.repeatability_dof {
        None => {
            let d = ChiSquared::new(dof as f64).map_err(|e| input(e.to_string()))?;
            ("chi-square", chi2, d.inverse_cdf(options.level), 1.0 - d.cdf(chi2))
        }
        Some(r) => {
            let d = FisherSnedecor::new(dof as f64, r as f64).map_err(|e| input(e.to_string()))?;
            let f = chi2 / dof as f64;
            ("F", f, d.inverse_cdf(options.level), 1.0 - d.cdf(f))
        }
    };
    let t = StudentsT::new(0.0, 1.0, dof as f64).map_err(|e| input(e.to_string()))?.inverse_cdf(0.5 + options.level / 2.0);
    let fitted = (0..p)
        .map(|j| {
            let u = covariance[(j, j)].max(0.0).sqrt();
            FittedUnknown {
                name: design.names[seen[j]].clone(),
                unit: design.units[seen[j]].clone(),
                value: theta[j],
                std_uncertainty: u,
                significant: theta[j].abs() > t * u,
                model: campaign.unknowns[seen[j]].is_model(),
            }
        })
        .collect();
    let variance: Vec<f64> = {
        let mut all = vec![f64::NAN; n_all];
        for (r, &i) in kept.iter().enumerate() {
            all[i] = v[(r, r)];
        }
        all
    };
    let channels = design
        .channel_names
        .iter()
        .enumerate()
        .filter(|(_, name)| !options.ignored_channels.contains(name))
        .map(|(c, name)| {
            let rows: Vec<usize> = kept.iter().copied().filter(|&i| design.channels[i] == c).collect();
            let rms = |f: &dyn Fn(usize) -> f64| (rows.iter().map(|&i| f(i).powi(2)).sum::<f64>() / rows.len().max(1) as f64).sqrt();
            let max = |f: &dyn Fn(usize) -> f64| rows.iter().map(|&i| f(i).abs()).fold(0.0, f64::max);
            ChannelVerification {
                name: name.clone(),
                count: rows.len(),
                predicted_rms: rms(&|i| predicted_before[i]),
                predicted_max: max(&|i| predicted_before[i]),
                measured_rms: rms(&|i| measured[i]),
                measured_max: max(&|i| measured[i]),
                residual_rms: rms(&|i| residuals[i]),
                residual_max: max(&|i| residuals[i]),
                expected_rms: rms(&|i| variance[i].sqrt()),
                repeatability: rms(&|i| design.sigma_um[i]),
            }
        })
        .collect();
    Ok(Verification {
        compensated: options.compensated,
        readings: n,
        channels,
        fitted,
        unseen,
        residuals,
        chi2,
        dof,
        s0: (chi2 / dof as f64).sqrt(),
        test,
        statistic,
        critical,
        p_value,
        level: options.level,
        consistent: statistic <= critical,
        with_model_uncertainty: with_model,
    })
}

/// The rows (um per user unit) of the re-measurement's readings in the model unknowns of the
/// calibration campaign (the leading unknowns of its identification).
fn model_rows(campaign: &Campaign, calibration: &Campaign, machine: &Machine, errors: &ErrorModel) -> Result<DMatrix<f64>, IdentifyError> {
    let mut probe = campaign.clone();
    probe.unknowns = calibration.unknowns.iter().take_while(|u| u.is_model()).cloned().collect();
    probe.bases = calibration.bases.clone();
    Ok(probe.design_matrix(machine, errors)?.matrix)
}
