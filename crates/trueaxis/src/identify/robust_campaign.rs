//! Robust identification of a campaign (`identify --robust huber|tukey`): the weighted
//! least-squares problem of `identify::solve` (weights 1 / sigma_i^2 of the stated noise) solved by
//! iteratively reweighted least squares with Huber or Tukey weights of the residuals in units of
//! their MAD-based scale (`screen::irls`), so that a few gross readings (a beam interruption, a
//! probe that missed) pull the parameters by their clipped size only (Huber) or not at all (Tukey).
//!
//! The reported values are those of the last reweighted solution; their covariance is the
//! M-estimator's, `K^2 [sum psi^2 / (n - p)] / [mean psi']^2 s^2 (X^T W X)^-1` (Huber 1981 §7.6)
//! with (X^T W X)^-1 of the stated weights, and s0 is replaced by the robust scale s (1 when the
//! residuals of the good readings match the stated noise). Readings left with a weight under 0.1
//! are listed by file, line and channel. Linear solution only: the refinement on the exact chain
//! is a least-squares step of its own and is not combined with robust weights.

use super::campaign_screening::{screen_and_fit, ScreenedIdentification};
use crate::error_model::ErrorModel;
use crate::identify::{solve, Campaign, DesignMatrix, Identification, IdentifyError, IndirectOptions};
use crate::machine::Machine;
use crate::screen::irls::{irls, RobustWeights, Weighting};

/// One reading the robust fit as good as left out.
#[derive(Clone, Debug, PartialEq)]
pub struct Downweighted {
    pub file: String,
    pub line: u64,
    pub channel: String,
    /// Residual of the robust solution (um) and the reading's weight.
    pub residual_um: f64,
    pub weight: f64,
}

/// The robust fit's weights and the readings it left out in effect.
#[derive(Clone, Debug, PartialEq)]
pub struct RobustFit {
    pub weights: RobustWeights,
    pub downweighted: Vec<Downweighted>,
}

impl RobustFit {
    /// The method and what it did, one paragraph for the printed output.
    pub fn text(&self) -> String {
        let w = &self.weights;
        let mut s = format!(
            "robust fit: {}, {} iterations{}; scale s = {:.3} (s0 of the readings it keeps); \
             uncertainties from the M-estimator covariance (Huber 1981 7.6); weights sum to {:.1} of {} readings; \
             {} reading(s) with weight under 0.1",
            w.weighting.describe(),
            w.iterations,
            if w.converged { "" } else { " (not converged)" },
            w.scale,
            w.effective_readings(),
            w.weights.len(),
            self.downweighted.len()
        );
        s += if self.downweighted.is_empty() { "\n" } else { ":\n" };
        for d in self.downweighted.iter().take(40) {
            s += &format!("  {} line {} {}: residual {:+.2} um, weight {:.3}\n", d.file, d.line, d.channel, d.residual_um, d.weight);
        }
        if self.downweighted.len() > 40 {
            s += &format!("  ... and {} more (all in --json)\n", self.downweighted.len() - 40);
        }
        s
    }

    /// `robust` of `identify --json`.
    pub fn json(&self) -> serde_json::Value {
        let w = &self.weights;
        serde_json::json!({
            "weighting": w.weighting.name(),
            "tuning_constant": w.weighting.constant(),
            "scale": w.scale,
            "iterations": w.iterations,
            "converged": w.converged,
            "effective_readings": w.effective_readings(),
            "covariance": "M-estimator, Huber 1981 7.6 (K^2 sum psi^2/(n-p) / mean(psi')^2 s^2 (X^T W X)^-1)",
            "downweighted": self.downweighted.iter().map(|d| serde_json::json!({
                "file": d.file, "line": d.line, "channel": d.channel, "residual_um": d.residual_um, "weight": d.weight
            })).collect::<Vec<_>>(),
        })
    }
}

/// The robust solution of `design` from the least-squares one `all`.
pub fn solve_robust(
    design: &DesignMatrix,
    start: &[f64],
    options: &IndirectOptions,
    all: &Identification,
    weighting: Weighting,
) -> Result<(Identification, RobustWeights), IdentifyError> {
    let (mut result, weights) = irls(weighting, &design.weights, |extra| {
        let mut reweighted = design.clone();
        reweighted.weights = design.weights.iter().zip(extra).map(|(w, e)| w * e).collect();
        let r = solve(&reweighted, start, options)?;
        let (delta, residuals) = (r.delta.clone(), r.residuals.clone());
        Ok::<_, IdentifyError>((r, delta, residuals))
    })?;
    // (X^T W X)^-1 of the stated weights, from the least-squares fit
    let unscaled = &all.covariance / (all.sigma0 * all.sigma0).max(1e-300);
    result.covariance = unscaled * weights.covariance_factor(result.identifiability.rank);
    result.std_uncertainty = (0..result.values.len())
        .map(|j| result.identifiability.identifiable[j].then(|| result.covariance[(j, j)].max(0.0).sqrt()))
        .collect();
    result.sigma0 = weights.scale;
    Ok((result, weights))
}

/// Screens `campaign`, identifies by least squares (for the screening after the fit and for
/// comparison) and robustly: the result is the robust one, `other` the least-squares one.
pub fn identify_robust(
    campaign: &Campaign,
    machine: &Machine,
    nominal: &ErrorModel,
    options: &IndirectOptions,
    weighting: Weighting,
) -> Result<ScreenedIdentification, IdentifyError> {
    if options.refine {
        return Err(IdentifyError::Input("--robust gives the linear solution; it does not combine with --refine".into()));
    }
    let (findings, all) = screen_and_fit(campaign, machine, nominal, options)?;
    let design = campaign.design_matrix(machine, nominal)?;
    let start = campaign.nominal_values(nominal)?;
    let (result, weights) = solve_robust(&design, &start, options, &all, weighting)?;
    let downweighted = weights
        .listed()
        .into_iter()
        .map(|i| {
            let (k, record) = design.records[i];
            let m = &campaign.measurements[k];
            Downweighted {
                file: m.data.display().to_string(),
                line: m.lines.get(record).copied().unwrap_or(0),
                channel: design.channel_names[design.channels[i]].clone(),
                residual_um: result.residuals[i],
                weight: weights.weights[i],
            }
        })
        .collect();
    Ok(ScreenedIdentification {
        result,
        campaign: campaign.clone(),
        findings,
        other: Some(all),
        excluded_records: 0,
        robust: Some(RobustFit { weights, downweighted }),
    })
}
