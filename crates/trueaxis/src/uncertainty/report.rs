//! The uncertainty results as one JSON document (the `trueaxis uncertainty --json` contract, also
//! the dictionaries of the Python package), and the uncertainty of predicted volumetric errors at
//! poses (Soons 1993 App. A eq. A.4).
//!
//! Units: parameters in their own units (um, urad), volumetric errors in um, covariances in the
//! squares of those units.

use super::{Budget, IdentificationMap, McSettings, VolumetricUncertainty};
use crate::error::Error;
use crate::identify::{Campaign, Identification};
use crate::machine::Machine;
use crate::model::{Frame, Setup};
use serde_json::{json, Map, Value};

/// The uncertainty of the predicted volumetric error `dx dy dz` at one pose, GUM and Monte Carlo.
#[derive(Clone, Debug)]
pub struct PoseUncertainty {
    /// Axis letter and position (mm, deg).
    pub user: Vec<(char, f64)>,
    pub gum: VolumetricUncertainty,
    pub monte_carlo: VolumetricUncertainty,
}

/// Soons 1993 App. A eq. A.4 at every pose (`poses_user`, `axis_count` positions per pose in mm and
/// deg): the GUM covariance of the parameters (all sources) through
/// [`Identification::volumetric_covariance`], and the Monte Carlo covariance of the parameter
/// trials through the same `F` (the prediction is linear in the parameters); `level` is the
/// coverage probability of the ellipsoids.
#[allow(clippy::too_many_arguments)]
pub fn pose_uncertainties(
    machine: &Machine,
    campaign: &Campaign,
    identification: &Identification,
    budget: &Budget,
    poses_user: &[f64],
    setup: &Setup,
    frame: Frame,
    level: f64,
) -> Result<Vec<PoseUncertainty>, Error> {
    let mut gum_identification = identification.clone();
    gum_identification.covariance = budget.gum_covariance.clone();
    let n = machine.axis_count().max(1);
    let mut q = vec![0.0; n];
    let mut out = Vec::new();
    for user in poses_user.chunks(n) {
        machine.pose_to_internal(user, &mut q);
        let gum = VolumetricUncertainty::from_covariance(
            gum_identification.volumetric_covariance(campaign, machine, &q, setup, frame),
            [0.0; 3],
            level,
        )?;
        let f = campaign.unknown_jacobian(machine, &q, setup, frame).rows(0, 3) * 1e3;
        let monte_carlo = VolumetricUncertainty::propagated(&f, &budget.total.covariance, [0.0; 3], level)?;
        out.push(PoseUncertainty { user: machine.axes().iter().map(|a| a.letter).zip(user.iter().copied()).collect(), gum, monte_carlo });
    }
    Ok(out)
}

/// JSON of one pose's volumetric uncertainty (um, um^2).
fn volumetric_json(v: &VolumetricUncertainty) -> Value {
    let e = &v.ellipsoid;
    let axes: Vec<Value> = e
        .semi_axes
        .iter()
        .enumerate()
        .map(|(i, a)| {
            json!({"semi_axis_um": a, "std_uncertainty_um": e.axes.variances[i].sqrt(),
                   "direction": e.axes.directions.column(i).iter().copied().collect::<Vec<f64>>()})
        })
        .collect();
    json!({
        "std_uncertainty_um": v.std_uncertainty,
        "covariance_um2": (0..3).map(|i| (0..3).map(|j| v.covariance[(i, j)]).collect::<Vec<f64>>()).collect::<Vec<_>>(),
        "ellipsoid": {"level": e.level, "dof": e.dof, "chi2": e.chi2, "axes": axes},
    })
}

/// Rows of a matrix as JSON arrays.
fn matrix_json(m: &nalgebra::DMatrix<f64>) -> Value {
    json!((0..m.nrows()).map(|i| m.row(i).iter().copied().collect::<Vec<f64>>()).collect::<Vec<_>>())
}

/// The document of `trueaxis uncertainty --json`: per parameter the Monte Carlo estimate,
/// standard uncertainty, intervals, the GUM values and the budget; the run's settings, the
/// convergence history, both covariance matrices and the pose uncertainties. `design` names where
/// the design came from.
pub fn budget_json(design: &str, map: &IdentificationMap, budget: &Budget, settings: &McSettings, poses: &[PoseUncertainty]) -> Value {
    let s = settings;
    let k = budget.gum_coverage_factor;
    let mut parameters = Map::new();
    for (j, row) in budget.rows.iter().enumerate() {
        let o = &budget.total.outputs[j];
        let (gum_mean, gum_u) = (budget.gum_estimate[j], row.gum_total_u);
        let mut per_source = Map::new();
        for (name, w) in budget.source_names.iter().zip(&row.widths) {
            per_source.insert(name.clone(), json!(w));
        }
        if !row.widths.is_empty() {
            per_source.insert("rss".into(), json!(row.rss));
        }
        per_source.insert("total".into(), json!(row.total));
        parameters.insert(
            row.parameter.clone(),
            json!({
                "unit": row.unit,
                "estimate": o.mean,
                "std_uncertainty": o.std_uncertainty,
                "interval": [o.symmetric.low, o.symmetric.high],
                "shortest_interval": [o.shortest.low, o.shortest.high],
                "skewness": o.skewness,
                "excess_kurtosis": o.excess_kurtosis,
                "gum": {"estimate": gum_mean, "std_uncertainty": gum_u, "interval": [gum_mean - k * gum_u, gum_mean + k * gum_u]},
                "budget_interval_widths": per_source,
                "gum_std_uncertainty_per_source": budget.source_names.iter().zip(&row.gum_u).map(|(n, u)| (n.clone(), json!(u))).collect::<Map<_, _>>(),
            }),
        );
    }
    let history: Vec<Value> = budget
        .total
        .history
        .iter()
        .map(|c| json!({"sequence": c.sequence, "s_estimate": c.max[0], "s_std_uncertainty": c.max[1], "s_low": c.max[2], "s_high": c.max[3]}))
        .collect();
    json!({
        "design": design,
        "observations": map.design.observations(),
        "parameter_order": map.design.parameters,
        "parameters": parameters,
        "sources": budget.source_names,
        "coverage": s.coverage,
        "interval": s.interval,
        "tolerance": s.tolerance,
        "seed": s.seed,
        "trials_per_sequence": s.trials_per_sequence,
        "sequences": budget.total.sequences,
        "trials": budget.total.trials,
        "converged": budget.total.converged,
        "budget_sequences": budget.per_source.iter().map(|r| r.sequences).collect::<Vec<_>>(),
        "condition_number": map.condition_number,
        "history": history,
        "covariance": {"parameter_order": map.design.parameters, "units": map.design.units,
                       "gum": matrix_json(&budget.gum_covariance), "monte_carlo": matrix_json(&budget.total.covariance)},
        "poses": poses.iter().map(|p| json!({"pose": p.user.iter().map(|(a, v)| (a.to_string(), json!(v))).collect::<Map<_, _>>(), "gum": volumetric_json(&p.gum), "monte_carlo": volumetric_json(&p.monte_carlo)})).collect::<Vec<_>>(),
    })
}
