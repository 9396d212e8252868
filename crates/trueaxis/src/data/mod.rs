//! Data files: tables in (read forgivingly, `columns`, with their checks), and the output layer
//! (docs/design.md, Conventions: never a partially written output; docs/reliability.md): output sets
//! written all or none (`output_set`, `staging`, `commit`), what an output path is (`target`), an
//! output that would destroy an input refused (`overlap`), a run's temporaries (`temporaries`).
//! Pose files and prediction tables are the module `poses`, above the model; the inputs a run reads
//! and the environment's failures are the module `files`, below everything.

pub mod checks;
pub(crate) mod columns;
mod commit;
mod decimal;
pub(crate) mod lines;
mod output_set;
pub mod overlap;
mod staging;
pub(crate) mod table_head;
mod target;
pub mod temporaries;
pub(crate) mod value_column;
mod working_directory;

pub use columns::{CsvTable, Layout};
pub(crate) use decimal::push_fixed;
pub use output_set::{write_atomically, write_streamed, OutputSet, PreparedSet};
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

impl From<crate::io::IoError> for DataError {
    fn from(e: crate::io::IoError) -> DataError {
        match e {
            crate::io::IoError::Read { path, source } => DataError::Read { path, source },
            crate::io::IoError::Invalid { origin, message } => DataError::Invalid { origin, message },
        }
    }
}
