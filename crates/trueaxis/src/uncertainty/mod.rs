//! Measurement uncertainty (issue 5): the GUM law of propagation (JCGM 100, Soons 1993 App. A),
//! the adaptive Monte Carlo method (JCGM 101 §7.9, several outputs as in JCGM 102), input
//! distributions, drift of the measurement chain (Andolfatto et al. 2011 §4.4: statistical and cyclic methods),
//! and budgets per source (Andolfatto et al. 2011 Table 5).
//!
//! The identification is linear, `p = P y` with `P = (X^T W X)^-1 X^T W` (Andolfatto et al. 2011 eq. 5): an
//! [`IdentificationMap`] holds `P` once, and each uncertainty source becomes a linear map from its
//! few random inputs to the parameters, so that a Monte Carlo trial costs a few hundred flops. A
//! brute-force path re-solves the least squares in every trial; the tests prove both agree.
//!
//! Units: observations and their errors in um, parameters in their user units (um or urad), times
//! in s. Results are reproducible from a seed and identical for any number of threads.

mod budget;
mod chain_drift;
mod design_matrix;
mod distributions;
mod gum;
mod intervals;
mod linear_map;
mod monte_carlo;
mod prediction;
mod report;
mod sort;
mod sources;

pub use budget::{run_budget, Budget, BudgetPlan, BudgetRow, Stage};
pub use chain_drift::{measurement_time, statistical_drift_uncertainty, PeriodicDrift, StartPhase};
pub use design_matrix::{from_identification, DesignMatrix};
pub use distributions::{Distribution, MultivariateNormal};
pub use gum::{confidence_ellipsoid, normal_coverage_factor, principal_axes, propagate, Ellipsoid, PrincipalAxes};
pub use intervals::{
    coverage_count, coverage_intervals_of_unsorted, shortest_interval, shortest_interval_of_unsorted, symmetric_interval,
    symmetric_interval_of_unsorted, CoverageInterval, SampleSummary,
};
pub use linear_map::{Evaluation, IdentificationMap, LinearModel, LinearWorkspace};
pub use monte_carlo::{
    blocks_per_sequence, minimum_trials, run_adaptive, run_chunk, run_sequences, trial_rng, trials_one_by_one, AdaptiveRun, Chunk,
    ControlVariables, IntervalKind, McResult, McSettings, OutputResult, TrialModel, BLOCK, MAX_KEPT_VALUES, MAX_TRIALS_PER_SEQUENCE,
};
pub use prediction::VolumetricUncertainty;
pub use report::{budget_json, pose_uncertainties, PoseUncertainty};
pub use sources::{CyclicDrift, Source, SourceKind, Sources};
