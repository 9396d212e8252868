//! Standard evaluations: ISO 230-2 positioning accuracy, ISO 230-4 circular tests with ballbar
//! diagnostics, verification of a compensation by a re-measurement.

pub mod ballbar_diagnostics;
pub mod iso230_2;
pub mod iso230_4;
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
    #[error("{0}")]
    NotFinite(String),
}

impl EvaluateError {
    /// True for errors in the input (exit status 2 in the command line), false for failed computations.
    pub fn is_input(&self) -> bool {
        matches!(self, EvaluateError::Data(_) | EvaluateError::Invalid { .. })
    }
}
