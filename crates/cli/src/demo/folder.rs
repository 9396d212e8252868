//! The demo's output folder: every file is written into a working directory beside it
//! (`trueaxis::data::WorkingDirectory`) that replaces the folder whole at the end, so that a run
//! that fails (a full disk) or is stopped leaves the folder as it was, and the summary lists every
//! file written.

use super::error::DemoError;
use std::path::{Path, PathBuf};
use trueaxis::data::{DataError, WorkingDirectory};
use trueaxis_report::calibration::InputFile;

pub struct Output {
    work: WorkingDirectory,
}

impl Output {
    pub fn create(dir: &Path) -> Result<Output, DemoError> {
        Ok(Output { work: WorkingDirectory::create(dir).map_err(DemoError::Output)? })
    }

    /// The path of `name` while the demo runs (to read it back).
    pub fn path(&self, name: &str) -> PathBuf {
        self.work.path(name)
    }

    /// The path of `name` in the output folder, as the user will find it.
    pub fn final_path(&self, name: &str) -> PathBuf {
        self.work.final_path(name)
    }

    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<PathBuf, DemoError> {
        self.work.write(name, bytes).map_err(DemoError::Output)
    }

    /// An input of the report, named relative to the output folder.
    pub fn input(&self, role: &str, name: &str) -> Result<InputFile, DemoError> {
        let bytes = std::fs::read(self.path(name))
            .map_err(|source| DataError::Read { path: self.final_path(name).display().to_string(), source })?;
        Ok(InputFile::of_bytes(role, name, &bytes))
    }

    /// Swaps the working directory in for the folder; the files written, as the user finds them.
    pub fn commit(self) -> Result<Vec<PathBuf>, DemoError> {
        let files = self.work.files();
        self.work.commit().map_err(DemoError::Output)?;
        Ok(files)
    }
}
