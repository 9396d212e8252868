//! A directory output that a run builds up file by file and reads back while it runs (`trueaxis
//! demo` writes a campaign, identifies from it, writes what it found, ...): the run works in a
//! fresh temporary directory beside the target (`.DIR.trueaxis-PID-XXXXXX.tmp`), and
//! [`WorkingDirectory::commit`] swaps it in whole, as an [`super::OutputSet`] swaps a directory
//! output. A run that fails (a full disk, an error) or is stopped leaves the target as it was and
//! no temporary; its message says that nothing was written.

use super::commit::{PreparedSet, StagedDirectory};
use super::staging::{check_directory_target, create_missing, parent_of, temporary_builder, write_error};
use super::temporaries::{affixes, clean_abandoned, LiveTemporary};
use super::DataError;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A directory output being built (module documentation).
pub struct WorkingDirectory {
    given: PathBuf,
    target: PathBuf,
    exists: bool,
    staging: tempfile::TempDir,
    live: LiveTemporary,
    /// Directories created for the target's parent, removed again when the run fails.
    created: Vec<PathBuf>,
    files: Vec<PathBuf>,
}

impl WorkingDirectory {
    /// Starts the output `dir` (created with its parents at commit when missing; an existing one
    /// may hold only files this run writes).
    pub fn create(dir: &Path) -> Result<WorkingDirectory, DataError> {
        let (target, exists, name) = check_directory_target(dir)?;
        let parent = parent_of(&target).to_path_buf();
        let mut created = Vec::new();
        create_missing(&parent, &mut created).map_err(write_error(dir))?;
        clean_abandoned(&parent, &name);
        let (prefix, suffix) = affixes(&name);
        let staging = temporary_builder(&prefix, suffix, true).tempdir_in(&parent).map_err(write_error(dir))?;
        let live = LiveTemporary::register(staging.path());
        Ok(WorkingDirectory { given: dir.to_path_buf(), target, exists, staging, live, created, files: Vec::new() })
    }

    /// Where the files are while the run works (to read them back).
    pub fn path(&self, relative: &str) -> PathBuf {
        self.staging.path().join(relative)
    }

    /// The final path of a file (for what the run reports).
    pub fn final_path(&self, relative: &str) -> PathBuf {
        self.given.join(relative)
    }

    /// Writes the file `relative` (its directories made as needed) and syncs it; returns its
    /// working path. An error names the final path.
    pub fn write(&mut self, relative: &str, bytes: &[u8]) -> Result<PathBuf, DataError> {
        let path = self.path(relative);
        let err = write_error(&self.final_path(relative));
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(&err)?;
        }
        let mut file = std::fs::File::create(&path).map_err(&err)?;
        file.write_all(bytes).map_err(&err)?;
        file.sync_all().map_err(&err)?;
        if !self.files.iter().any(|f| f == Path::new(relative)) {
            self.files.push(PathBuf::from(relative));
        }
        Ok(path)
    }

    /// The final paths of the files written, in the order first written.
    pub fn files(&self) -> Vec<PathBuf> {
        self.files.iter().map(|f| self.given.join(f)).collect()
    }

    /// Swaps the directory in whole (an existing target must hold only files of this run).
    pub fn commit(self) -> Result<(), DataError> {
        let WorkingDirectory { given, target, exists, staging, live, created, files } = self;
        let directory = StagedDirectory { given, target, staging, live, relative: files, exists };
        let prepared = PreparedSet { directories: vec![directory], ..PreparedSet::default() };
        let result = super::staging::refuse_foreign_in(&prepared.directories[0]).and_then(|_| prepared.commit());
        if result.is_err() {
            for dir in created.iter().rev() {
                let _ = std::fs::remove_dir(dir);
            }
        }
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_working_directory_is_swapped_in_whole_or_not_at_all() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("demo");
        let mut work = WorkingDirectory::create(&dir).unwrap();
        let campaign = work.write("campaign/campaign.toml", b"x").unwrap();
        assert_eq!(std::fs::read(&campaign).unwrap(), b"x", "read back while the run works");
        assert!(!dir.exists(), "nothing at the target before the commit");
        work.write("report.html", b"r").unwrap();
        assert_eq!(work.files(), [dir.join("campaign/campaign.toml"), dir.join("report.html")]);
        work.commit().unwrap();
        assert_eq!(std::fs::read(dir.join("report.html")).unwrap(), b"r");
        // a failed run leaves the old set and no temporary
        let mut work = WorkingDirectory::create(&dir).unwrap();
        work.write("report.html", b"new").unwrap();
        drop(work);
        assert_eq!(std::fs::read(dir.join("report.html")).unwrap(), b"r");
        let names: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names, ["demo"]);
        // a user's file in the target: refused at the commit, the target kept
        std::fs::write(dir.join("notes.txt"), "mine").unwrap();
        let mut work = WorkingDirectory::create(&dir).unwrap();
        work.write("report.html", b"new").unwrap();
        assert!(work.commit().unwrap_err().to_string().contains("notes.txt"));
        assert_eq!(std::fs::read(dir.join("notes.txt")).unwrap(), b"mine");
    }
}
