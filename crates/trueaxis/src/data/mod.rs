//! Data files: tables in (read forgivingly, `columns`), pose CSVs in, prediction tables out, and
//! atomic file writing (DESIGN.md sections 3-4: never a partially written output).

pub mod checks;
mod columns;
mod output;
mod output_set;
mod poses;
pub mod temporaries;

pub use columns::{CsvTable, Layout};
pub use output::{predictions_csv, predictions_json, PREDICTION_COLUMNS};
pub use output_set::{write_atomically, OutputSet};
pub use poses::{poses_of, read_poses, read_poses_from, PoseTable};

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

impl From<crate::io::IoError> for DataError {
    fn from(e: crate::io::IoError) -> DataError {
        match e {
            crate::io::IoError::Read { path, source } => DataError::Read { path, source },
            crate::io::IoError::Invalid { origin, message } => DataError::Invalid { origin, message },
        }
    }
}
