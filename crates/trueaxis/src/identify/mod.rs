//! Identification: least squares by QR with unit-length scaling, stepwise selection, drift
//! removal, and fitting of parametric error functions to direct measurements (Soons 1993 §3.2).

pub mod campaign;
pub mod campaign_screening;
mod candidates;
mod cycle_drift;
pub mod design_units;
mod direct;
pub mod direct_job;
pub mod direct_screening;
pub mod export;
mod fit;
mod gram;
pub mod identifiability;
pub mod indirect;
mod least_squares;
pub mod optimal_design;
pub mod pige;
pub mod pige_report;
pub mod pige_sensitivity;
mod reduction;
pub mod robust_campaign;
pub mod simulate;
mod stepwise;
pub mod tmbb;
pub mod tmbb_report;
pub mod tmbb_setup;
pub mod unknowns;

pub use campaign::{Campaign, DesignMatrix, Measurement};
pub use candidates::{optimal_design_json, CampaignCandidates};
pub use cycle_drift::{remove_cycle_drift, CycleDrift};
pub use design_units::{criteria_units, CriteriaUnits};
pub use direct::{run_direct_fit, DirectFitReport, DirectFitRequest, DirectModel};
pub use direct_job::{run_direct_job, DirectFitJob, DirectFitRun, Given};
pub use export::{error_values_text, identification_json};
pub use fit::{
    alias_wavelength, dominant_period, fit_error_function, refine_wavelength, residual_period, sampling_step, FitOptions, FittedFunction,
    ResidualPeriod,
};
pub use gram::weighted_gram;
pub use identifiability::{Combination, IdentifiabilityReport, ScaledSvd};
pub use indirect::{identify, solve, ChannelStatistics, Identification, IndirectOptions, Refinement, Solver};
pub use least_squares::{fit_linear, t_quantile, LinearFit, RANK_TOLERANCE};
pub use optimal_design::{start_rng, CandidateSet, Criterion, DesignCriteria, ExchangeOutcome};
pub use simulate::{measurement_csv, simulate_campaign};
pub use stepwise::{f_critical, stepwise, StepwiseResult};
pub use unknowns::{Unknown, UnknownKind};

use thiserror::Error;

#[derive(Debug, Error)]
pub enum IdentifyError {
    #[error("{0}")]
    Input(String),
    #[error("rank deficient: {message}")]
    RankDeficient { message: String },
    #[error(transparent)]
    Data(#[from] crate::data::DataError),
}

impl IdentifyError {
    /// Bad input, with the message of `e`.
    pub(crate) fn input(e: impl std::fmt::Display) -> IdentifyError {
        IdentifyError::Input(e.to_string())
    }
}

impl From<IdentifyError> for crate::Error {
    /// A rank-deficient identification is a failed computation; the rest is bad input (or the
    /// environment, when the cause of a data error says so).
    fn from(e: IdentifyError) -> crate::Error {
        let kind = match e {
            IdentifyError::RankDeficient { .. } => crate::ErrorKind::Computation,
            _ => crate::ErrorKind::Input,
        };
        crate::Error::new(kind, e.to_string()).caused_by(e)
    }
}
