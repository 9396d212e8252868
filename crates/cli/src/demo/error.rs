//! Why the demo failed: the error of the library step that failed, or an output directory that
//! could not be written (then nothing was: the directory is as it was).

use thiserror::Error;
use trueaxis::data::DataError;
use trueaxis::error_model::ErrorModelError;
use trueaxis::identify::IdentifyError;
use trueaxis::instruments::ballbar::BallbarError;
use trueaxis::machine::MachineError;
use trueaxis_report::calibration::CalibrationError;

#[derive(Debug, Error)]
pub enum DemoError {
    #[error(transparent)]
    Machine(#[from] MachineError),
    #[error(transparent)]
    Errors(#[from] ErrorModelError),
    #[error(transparent)]
    Data(#[from] DataError),
    #[error(transparent)]
    Identify(#[from] IdentifyError),
    #[error(transparent)]
    Core(#[from] trueaxis::Error),
    #[error(transparent)]
    Ballbar(#[from] BallbarError),
    #[error(transparent)]
    Report(#[from] CalibrationError),
    /// The output directory could not be written: nothing was (the directory is as it was).
    #[error("{0}; nothing was written")]
    Output(#[source] DataError),
}

impl From<DemoError> for trueaxis::Error {
    /// An output directory that cannot be written is bad input (a bad `--out`, or the environment: a
    /// full disk, a permission, found in the cause); anything else is a failed computation, since the
    /// demo's inputs are built in.
    fn from(e: DemoError) -> trueaxis::Error {
        let kind = match e {
            DemoError::Output(_) | DemoError::Data(DataError::Write { .. }) => trueaxis::ErrorKind::Input,
            _ => trueaxis::ErrorKind::Computation,
        };
        trueaxis::Error::new(kind, e.to_string()).caused_by(e)
    }
}
