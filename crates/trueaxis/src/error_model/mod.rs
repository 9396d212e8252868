//! Parametric error functions and the error-values file (docs/design.md, Files).
//!
//! This first part holds constants, tables with linear interpolation and polynomials of the own
//! axis position.

mod basis;
mod evaluator;
mod file;
mod function;
pub mod inputs;
mod model;
mod quadrature;
mod write;

pub use basis::{Basis, BasisSpec, PeriodicSpec};
pub use function::ErrorFunction;
pub use inputs::{input_values, InputKind, InputRows, InputSource};
pub use model::{Direction, DriftTerm, ErrorModel, LoadTerm, MachineState, ProductTerm, REFERENCE_TEMPERATURE};
pub use quadrature::{gauss_legendre, integrate, legendre};
pub use write::{set_error_function, set_uncertainty};

use crate::machine::Machine;
use thiserror::Error;

/// Errors reading an error-values file; every message names the file.
#[derive(Debug, Error)]
pub enum ErrorModelError {
    #[error("{path}: cannot read error-values file: {source}")]
    Read { path: String, source: std::io::Error },
    #[error("{origin}: {message}")]
    Syntax { origin: String, message: String },
    #[error("{origin}: {message}")]
    Invalid { origin: String, message: String },
}

impl ErrorModel {
    /// Parses an error-values TOML for `machine`.
    pub fn from_toml_str(text: &str, origin: &str, machine: &Machine) -> Result<ErrorModel, ErrorModelError> {
        file::parse(text, origin, machine)
    }

    /// Reads an error-values TOML file for `machine`. A file that defines no error at all is
    /// refused (most likely the wrong file; docs/limits.md): an error-free machine is stated with
    /// `[constant]` and `EXX = 0`. ([`ErrorModel::from_toml_str`] accepts an empty text: the
    /// commands that add terms to an optional base start from it.)
    pub fn load(path: impl AsRef<std::path::Path>, machine: &Machine) -> Result<ErrorModel, ErrorModelError> {
        let path = path.as_ref();
        let text = crate::files::inputs::read_to_string(path)
            .map_err(|source| ErrorModelError::Read { path: path.display().to_string(), source })?;
        let model = Self::from_toml_str(&text, &path.display().to_string(), machine)?;
        if model.is_empty() {
            return Err(ErrorModelError::Invalid {
                origin: path.display().to_string(),
                message: "the file defines no error ([constant], [table.NAME], [polynomial.NAME], [basis.NAME], [[term.NAME]], \
                          [load.NAME], [[drift.NAME]]); to state an error-free machine, write `[constant]` with `EXX = 0`"
                    .into(),
            });
        }
        Ok(model)
    }
}
