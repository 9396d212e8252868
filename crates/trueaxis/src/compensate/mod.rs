//! Compensation (docs/design.md, The pipeline, NISTIR 5236 section 4, Soons 1993 §2.3.5): the correction of a
//! pose, own-axis / cross-axis tables and a volumetric grid, controller exporters with their limit
//! checks, NC-program correction, and an allocation-free real-time corrector with a C ABI.
//!
//! Sign convention: a correction is what is *added to the axis set-point* so that the actual tool
//! point lands where the nominal one would (correction = minus the error, to first order, for an
//! error along the axis).

pub mod batch_correction;
pub mod correction;
pub mod coverage;
pub mod export;
pub mod job;
pub mod kinematic;
pub mod nc;
pub mod realtime;
mod solve;
mod summary;
pub mod tables;

pub use batch_correction::correct_batch;
pub use correction::{direction_of, Correction, CorrectionOptions, CorrectionWorkspace, Corrector, OrientationTarget, WarmStart, MAX_AXES};
pub use export::residual::{residual_of_format, uncertainty_of_error_left, FormatResidual, LeftUncertainty};
pub use job::{compensation, compensation_with, sensor_index, sensor_temperatures, Compensation, CompensationRequest};
pub use realtime::RealtimeCorrector;
pub use summary::{compensation_json, kinematics_json, nc_json, round4, ExportFormat, FormatOptions};
pub use tables::{axis_tables, line_tables, volumetric_grid, AxisTable, TableSet, TableSpec, VolumetricGrid};

use crate::error::{Error, ErrorKind};

/// Why a compensation could not be produced. Kept as a typed error because callers match on it:
/// a refused export ([`CompensateError::Limit`], the tests of the controller limits) and an error
/// table that does not cover the travel ([`CompensateError::Coverage`], which the command line
/// names by its error file).
#[derive(Debug, thiserror::Error)]
pub enum CompensateError {
    /// Bad input: a parameter, a file, a pose outside the travel.
    #[error("{0}")]
    Input(String),
    /// A controller limit or the user's correction limit is exceeded: the export is refused.
    #[error("{0}")]
    Limit(String),
    /// An error table of the error model does not cover the positions to correct
    /// ([`coverage`]); the message does not name the error file (the caller knows it).
    #[error("{0}")]
    Coverage(String),
    /// The computation failed (no convergence, not a finite number).
    #[error("{0}")]
    Computation(String),
    /// A file could not be read or written (bad input, or the environment: a full disk, a
    /// permission; `files::environment_cause` tells).
    #[error(transparent)]
    Data(#[from] crate::data::DataError),
}

impl CompensateError {
    /// Bad input (a parameter, a file, a limit, an error table that does not cover the travel) or
    /// a failed computation.
    pub fn kind(&self) -> ErrorKind {
        match self {
            CompensateError::Computation(_) => ErrorKind::Computation,
            _ => ErrorKind::Input,
        }
    }
}

impl From<CompensateError> for Error {
    /// Its [`CompensateError::kind`], the message unchanged and the error kept as the cause (a
    /// full disk in its chain is still the environment).
    fn from(e: CompensateError) -> Error {
        Error::new(e.kind(), e.to_string()).caused_by(e)
    }
}
