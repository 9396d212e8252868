//! Data files: pose CSVs in, prediction tables out, and atomic file writing
//! (DESIGN.md sections 3-4: never a partially written output).

mod columns;
mod output;
mod poses;

pub use columns::CsvTable;
pub use output::{predictions_csv, predictions_json, write_atomically, PREDICTION_COLUMNS};
pub use poses::{read_poses, read_poses_from, PoseTable};

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
}
