//! Identification: least squares by QR with unit-length scaling, stepwise selection, drift
//! removal, and fitting of parametric error functions to direct measurements (seed 000 §3.2).

mod direct;
mod drift;
mod fit;
mod least_squares;
pub mod pige;
mod stepwise;
pub mod tmbb;

pub use direct::{run_direct_fit, DirectFitReport, DirectFitRequest, DirectModel};
pub use drift::{remove_cycle_drift, CycleDrift};
pub use fit::{alias_wavelength, dominant_period, fit_error_function, refine_wavelength, FitOptions, FittedFunction};
pub use least_squares::{fit_linear, t_quantile, LinearFit, RANK_TOLERANCE};
pub use stepwise::{f_critical, stepwise, StepwiseResult};

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
