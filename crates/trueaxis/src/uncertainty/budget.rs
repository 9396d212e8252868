//! Uncertainty budget of an identification (Andolfatto et al. 2011 §5.3, Table 5): the coverage interval of
//! each source alone, their root-sum-square, and the interval with all sources together, by
//! adaptive Monte Carlo; with the GUM standard uncertainties alongside.

use super::gum::normal_coverage_factor;
use super::linear_map::{Evaluation, IdentificationMap, LinearModel};
use super::monte_carlo::{run_adaptive, ControlVariables, IntervalKind, McResult, McSettings};
use super::sources::Source;
use crate::error::Error;
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

/// The Monte Carlo runs of a budget: each source alone (when there are several and `alone` is
/// set), then all sources together, with the same settings. Each stage is an independent adaptive
/// run ([`super::AdaptiveRun`]), so the stages and the chunks of their sequences can be computed
/// anywhere and assembled here.
#[derive(Clone, Copy)]
pub struct BudgetPlan<'a> {
    pub map: &'a IdentificationMap,
    pub sources: &'a [Source],
    pub settings: &'a McSettings,
    pub evaluation: Evaluation,
    pub alone: bool,
}

impl<'a> BudgetPlan<'a> {
    pub fn new(
        map: &'a IdentificationMap,
        sources: &'a [Source],
        settings: &'a McSettings,
        evaluation: Evaluation,
        alone: bool,
    ) -> Result<BudgetPlan<'a>, Error> {
        if sources.is_empty() {
            return Err(Error::input("no uncertainty source given"));
        }
        settings.validate()?;
        Ok(BudgetPlan { map, sources, settings, evaluation, alone })
    }

    /// Number of Monte Carlo runs: one per source alone (with several sources and `alone`), then
    /// the run with all sources.
    pub fn stages(&self) -> usize {
        if self.alone && self.sources.len() > 1 {
            self.sources.len() + 1
        } else {
            1
        }
    }

    /// The source run alone at stage `k`, `None` for the run with all sources (the last stage).
    pub fn stage(&self, k: usize) -> Stage<'a> {
        (k + 1 < self.stages()).then(|| self.sources[k].name.as_str())
    }

    /// The Monte Carlo model of stage `k`.
    pub fn model(&self, k: usize) -> Result<LinearModel<'a>, Error> {
        let sources: Vec<&Source> = match self.stage(k) {
            Some(_) => vec![&self.sources[k]],
            None => self.sources.iter().collect(),
        };
        self.map.model(&sources, self.evaluation)
    }

    /// Andolfatto et al. 2011 Table 5 from the results of the stages, in stage order.
    pub fn assemble(&self, mut runs: Vec<McResult>) -> Result<Budget, Error> {
        if runs.len() != self.stages() {
            return Err(Error::input(format!("{} Monte Carlo results for a budget of {} runs", runs.len(), self.stages())));
        }
        let (map, sources, settings) = (self.map, self.sources, self.settings);
        let total = runs.pop().expect("at least one stage");
        let per_source = runs;
        let width = |r: &McResult, j: usize| match settings.interval {
            IntervalKind::Symmetric => r.outputs[j].symmetric.width(),
            IntervalKind::Shortest => r.outputs[j].shortest.width(),
        };
        let all: Vec<&Source> = sources.iter().collect();
        let gum_each = sources.iter().map(|s| map.gum_covariance(s)).collect::<Result<Vec<_>, _>>()?;
        let n = map.parameter_count();
        let gum_covariance = gum_each.iter().fold(DMatrix::zeros(n, n), |acc, c| acc + c);
        let alone = |j: usize| -> Vec<f64> {
            if !self.alone {
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
}

/// Runs the adaptive Monte Carlo for each source alone (when there are several and `alone` is
/// set) and for all sources together, with the same settings, in one process, and assembles seed
/// 004 Table 5 ([`BudgetPlan`]).
pub fn run_budget(
    map: &IdentificationMap,
    sources: &[Source],
    settings: &McSettings,
    evaluation: Evaluation,
    alone: bool,
    progress: &mut dyn FnMut(Stage, usize, Option<&ControlVariables>),
) -> Result<Budget, Error> {
    let plan = BudgetPlan::new(map, sources, settings, evaluation, alone)?;
    let runs = (0..plan.stages())
        .map(|k| run_adaptive(&plan.model(k)?, settings, &mut |h, c| progress(plan.stage(k), h, c)))
        .collect::<Result<Vec<_>, _>>()?;
    plan.assemble(runs)
}
