//! The files a run reads, so that none of its outputs overwrites one of them (docs/reliability.md):
//! `report --out m.toml --machine m.toml` would turn the machine file into HTML, `predict --poses
//! p.csv --out p.csv` would replace the poses with their errors.
//!
//! Two files are the same when they are the same inode on the same device (a hard link, a symbolic
//! link, `./p.csv` and `p.csv` alike) or, where a system has no inode numbers, the same canonical
//! path. A run that tracks its inputs ([`track`]: the command line does, a library caller may)
//! records every file its readers open through [`open`], [`read`] or [`read_to_string`]; an
//! output set refuses an output that is one of them, or a directory it replaces whole that holds
//! one, before it writes anything (`data::OutputSet`). The command line also compares the paths
//! of its arguments before it starts (`data::overlap`), so that a long run is not wasted.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// What makes two paths the same file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileIdentity {
    /// Device and inode (Unix), when known.
    inode: Option<(u64, u64)>,
    canonical: PathBuf,
}

impl FileIdentity {
    /// The identity of an existing file or directory (symbolic links followed); `None` when the
    /// path does not exist.
    pub fn of(path: &Path) -> Option<FileIdentity> {
        let canonical = path.canonicalize().ok()?;
        #[cfg(unix)]
        let inode = {
            use std::os::unix::fs::MetadataExt;
            std::fs::metadata(&canonical).ok().map(|m| (m.dev(), m.ino()))
        };
        #[cfg(not(unix))]
        let inode = None;
        Some(FileIdentity { inode, canonical })
    }

    /// Whether both name the same file.
    pub fn same(&self, other: &FileIdentity) -> bool {
        match (self.inode, other.inode) {
            (Some(a), Some(b)) => a == b,
            _ => self.canonical == other.canonical,
        }
    }

    /// Whether this file lies inside the directory `dir` (at any depth).
    pub fn inside(&self, dir: &FileIdentity) -> bool {
        self.canonical != dir.canonical && self.canonical.starts_with(&dir.canonical)
    }
}

static TRACKING: AtomicBool = AtomicBool::new(false);
/// The files read since [`track`], as the readers were given them. Identified again when an output
/// is checked: an inode number is reused once its file is deleted.
static READ: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Records from now on every input opened through this module (one run per process: the command
/// line). Without it nothing is recorded: a library session may read a file and later write it.
pub fn track() {
    TRACKING.store(true, Ordering::SeqCst);
}

fn note(path: &Path) {
    if !TRACKING.load(Ordering::SeqCst) {
        return;
    }
    let mut read = READ.lock().unwrap_or_else(|p| p.into_inner());
    if !read.iter().any(|p| p == path) {
        read.push(path.to_path_buf());
    }
}

/// Opens an input file for reading (recorded when tracking).
pub fn open(path: &Path) -> std::io::Result<std::fs::File> {
    let file = std::fs::File::open(path)?;
    note(path);
    Ok(file)
}

/// `std::fs::read` of an input file (recorded when tracking).
pub fn read(path: &Path) -> std::io::Result<Vec<u8>> {
    let bytes = std::fs::read(path)?;
    note(path);
    Ok(bytes)
}

/// `std::fs::read_to_string` of an input file (recorded when tracking).
pub fn read_to_string(path: &Path) -> std::io::Result<String> {
    let text = std::fs::read_to_string(path)?;
    note(path);
    Ok(text)
}

/// The path of an input read by this run that is the file `identity`, or that lies inside it when
/// `whole_directory` (a directory output replaced whole).
pub(crate) fn input_at(identity: &FileIdentity, whole_directory: bool) -> Option<PathBuf> {
    let read = READ.lock().unwrap_or_else(|p| p.into_inner());
    read.iter().find(|p| FileIdentity::of(p).is_some_and(|i| i.same(identity) || (whole_directory && i.inside(identity)))).cloned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_read_while_tracking_are_found_by_identity() {
        let dir = tempfile::tempdir().unwrap();
        let data = dir.path().join("station1.csv");
        std::fs::write(&data, "x").unwrap();
        track();
        read_to_string(&data).unwrap();
        let again = FileIdentity::of(&dir.path().join("./station1.csv")).unwrap();
        assert_eq!(input_at(&again, false), Some(data.clone()));
        assert_eq!(input_at(&FileIdentity::of(dir.path()).unwrap(), true), Some(data));
        assert_eq!(input_at(&FileIdentity::of(dir.path()).unwrap(), false), None);
    }
}
