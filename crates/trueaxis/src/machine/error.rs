//! Errors of the machine module. Every message names the file (or origin) it concerns.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum MachineError {
    #[error("{path}: cannot read machine file: {source}")]
    Read { path: String, source: std::io::Error },
    #[error("{origin}: {message}")]
    Syntax { origin: String, message: String },
    #[error("{origin}: {message}")]
    Invalid { origin: String, message: String },
    #[error("{origin}: unknown parameter: {message}")]
    Parameter { origin: String, message: String },
}

crate::error::error_of_kind!(MachineError, Input);
