//! Uncertainty budget of an identification (seed 004 §5.3, Table 5): the coverage interval of
//! each source alone, their root-sum-square, and the interval with all sources together, by
//! adaptive Monte Carlo; with the GUM standard uncertainties alongside.

use super::gum::normal_coverage_factor;
use super::linear_map::{Evaluation, IdentificationMap};
use super::monte_carlo::{run_adaptive, ControlVariables, IntervalKind, McResult, McSettings};
use super::sources::Source;
use super::UncertaintyError;
use nalgebra::DMatrix;

/// One parameter's line of the budget.
#[derive(Clone, Debug, PartialEq)]
pub struct BudgetRow {
    pub parameter: String,
    pub unit: String,
    /// Width of the coverage interval with each source alone (parameter unit), in source order;
    /// empty when the sources were not run alone.
    pub widths: Vec<f64>,
    /// `sqrt(sum width^2)` (0 when `widths` is empty).
    pub rss: f64,
    /// Width with all sources together.
    pub total: f64,
    /// GUM standard uncertainty with each source alone, and with all.
    pub gum_u: Vec<f64>,
    pub gum_total_u: f64,
}

/// The budget and the Monte Carlo runs behind it.
#[derive(Clone, Debug)]
pub struct Budget {
    pub source_names: Vec<String>,
    pub rows: Vec<BudgetRow>,
    /// The run with all sources.
    pub total: McResult,
    /// The run of each source alone (empty with a single source: it is the total).
    pub per_source: Vec<McResult>,
    /// GUM covariance with all sources (parameter units squared).
    pub gum_covariance: DMatrix<f64>,
    /// GUM estimate `p0 + P E{e}`.
    pub gum_estimate: Vec<f64>,
    /// GUM coverage factor of a Gaussian at the coverage probability.
    pub gum_coverage_factor: f64,
}

/// A stage of the budget for progress reports: the source run alone, or `None` for all together.
pub type Stage<'a> = Option<&'a str>;

/// Runs the adaptive Monte Carlo for each source alone (when there are several and `alone` is
/// set) and for all sources together, with the same settings, and assembles seed 004 Table 5.
pub fn run_budget(
    map: &IdentificationMap,
    sources: &[Source],
    settings: &McSettings,
    evaluation: Evaluation,
    alone: bool,
    progress: &mut dyn FnMut(Stage, usize, Option<&ControlVariables>),
) -> Result<Budget, UncertaintyError> {
    if sources.is_empty() {
        return Err(UncertaintyError::Input("no uncertainty source given".into()));
    }
    let all: Vec<&Source> = sources.iter().collect();
    let width = |r: &McResult, j: usize| match settings.interval {
        IntervalKind::Symmetric => r.outputs[j].symmetric.width(),
        IntervalKind::Shortest => r.outputs[j].shortest.width(),
    };
    let mut per_source = Vec::new();
    if alone && sources.len() > 1 {
        for s in sources {
            let model = map.model(&[s], evaluation)?;
            per_source.push(run_adaptive(&model, settings, &mut |h, c| progress(Some(&s.name), h, c))?);
        }
    }
    let total = run_adaptive(&map.model(&all, evaluation)?, settings, &mut |h, c| progress(None, h, c))?;
    let gum_each = sources.iter().map(|s| map.gum_covariance(s)).collect::<Result<Vec<_>, _>>()?;
    let n = map.parameter_count();
    let gum_covariance = gum_each.iter().fold(DMatrix::zeros(n, n), |acc, c| acc + c);
    let alone = |j: usize| -> Vec<f64> {
        if !alone {
            Vec::new()
        } else if per_source.is_empty() {
            vec![width(&total, j)]
        } else {
            per_source.iter().map(|r| width(r, j)).collect()
        }
    };
    let rows = (0..n)
        .map(|j| {
            let widths = alone(j);
            BudgetRow {
                parameter: map.design.parameters[j].clone(),
                unit: map.design.units[j].clone(),
                rss: widths.iter().map(|w| w * w).sum::<f64>().sqrt(),
                widths,
                total: width(&total, j),
                gum_u: gum_each.iter().map(|c| c[(j, j)].max(0.0).sqrt()).collect(),
                gum_total_u: gum_covariance[(j, j)].max(0.0).sqrt(),
            }
        })
        .collect();
    Ok(Budget {
        source_names: sources.iter().map(|s| s.name.clone()).collect(),
        rows,
        total,
        per_source,
        gum_covariance,
        gum_estimate: map.gum_estimate(&all)?,
        gum_coverage_factor: normal_coverage_factor(settings.coverage),
    })
}
