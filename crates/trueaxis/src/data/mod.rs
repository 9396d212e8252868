//! Data files: tables in (read forgivingly, `columns`), pose CSVs in, prediction tables out, and
//! the output layer (docs/design.md sections 3-4: never a partially written output; docs/reliability.md):
//! output sets written all or none (`output_set`, `staging`, `commit`), what an output path is
//! (`target`), the inputs a run read (`inputs`), its temporaries (`temporaries`), and which
//! failures are the environment's (`environment`).

pub mod checks;
mod columns;
mod commit;
mod environment;
pub mod inputs;
mod lines;
mod output;
mod output_set;
mod pose_columns;
mod pose_stream;
mod poses;
mod prediction;
mod staging;
mod table_head;
mod target;
pub mod temporaries;
mod value_column;
mod working_directory;

pub use columns::{CsvTable, Layout};
pub use environment::{environment_cause, is_environment};
pub(crate) use output::push_fixed;
pub use output::{predictions_csv, predictions_json, PredictionFormat, PredictionWriter, PREDICTION_COLUMNS};
pub use output_set::{write_atomically, write_streamed, OutputSet, PreparedSet};
pub use pose_stream::{PoseChunk, PoseStream, MAX_PREAMBLE};
pub use poses::{poses_of, read_poses, read_poses_from, PoseTable};
pub use prediction::{predict_poses, CHUNK};
pub use target::{is_standard_output, output_name, set_standard_output_descriptor, STANDARD_OUTPUT};
pub use working_directory::WorkingDirectory;

use thiserror::Error;

#[derive(Debug, Error)]
pub enum DataError {
    #[error("{path}: cannot read: {source}")]
    Read { path: String, source: std::io::Error },
    #[error("{path}: cannot write: {source}")]
    Write { path: String, source: std::io::Error },
    #[error("{origin}: {message}")]
    Invalid { origin: String, message: String },
    #[error("{message}")]
    NotFinite { message: String },
    /// An output of an [`OutputSet`] of several failed before any was written.
    #[error("{0}; nothing was written")]
    NothingWritten(Box<DataError>),
}

impl From<DataError> for crate::Error {
    /// A prediction that is not finite is a failed computation; the rest is bad input (or the
    /// environment, when the cause says so: a full disk, a permission).
    fn from(e: DataError) -> crate::Error {
        let kind = match e {
            DataError::NotFinite { .. } => crate::ErrorKind::Computation,
            _ => crate::ErrorKind::Input,
        };
        crate::Error::new(kind, e.to_string()).caused_by(e)
    }
}

impl From<crate::io::IoError> for DataError {
    fn from(e: crate::io::IoError) -> DataError {
        match e {
            crate::io::IoError::Read { path, source } => DataError::Read { path, source },
            crate::io::IoError::Invalid { origin, message } => DataError::Invalid { origin, message },
        }
    }
}
