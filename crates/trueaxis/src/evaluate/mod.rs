//! Standard evaluations: ISO 230-2 positioning accuracy (and a positioning test from its file,
//! `positioning_test`; its measurement uncertainty, `positioning_uncertainty`), ISO 230-4 circular
//! tests with ballbar diagnostics (and from a file, `circular_test`), verification of a
//! compensation by a re-measurement.

pub mod ballbar_diagnostics;
pub mod ballbar_screening;
pub mod circular_test;
pub mod iso230_2;
pub mod iso230_4;
pub mod positioning_screening;
pub mod positioning_test;
pub mod positioning_uncertainty;
pub mod verification;

use crate::data::DataError;
use thiserror::Error;

/// Why an evaluation failed. `Data` and `Invalid` are bad input (the message names the file, line and
/// the offending value); `NotFinite` is a failed computation (e.g. overflow).
#[derive(Debug, Error)]
pub enum EvaluateError {
    #[error(transparent)]
    Data(#[from] DataError),
    #[error("{origin}: {message}")]
    Invalid { origin: String, message: String },
    /// Bad input whose message names its file or parameter itself (a refused plausibility check,
    /// an option out of range).
    #[error("{0}")]
    Input(String),
    #[error("{0}")]
    NotFinite(String),
}

impl EvaluateError {
    /// True for errors in the input (exit status 2 in the command line), false for failed computations.
    pub fn is_input(&self) -> bool {
        matches!(self, EvaluateError::Data(_) | EvaluateError::Invalid { .. } | EvaluateError::Input(_))
    }
}
