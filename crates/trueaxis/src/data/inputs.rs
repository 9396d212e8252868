//! The files a run reads, so that none of its outputs overwrites one of them (docs/reliability.md):
//! `report --out m.toml --machine m.toml` would turn the machine file into HTML, `predict --poses
//! p.csv --out p.csv` would replace the poses with their errors.
//!
//! Two files are the same when they are the same inode on the same device (a hard link, a symbolic
//! link, `./p.csv` and `p.csv` alike) or, where a system has no inode numbers, the same canonical
//! path. A run that tracks its inputs ([`track`]: the command line does, a library caller may)
//! records every file its readers open through [`open`], [`read`] or [`read_to_string`]; an
//! output set refuses an output that is one of them, or a directory it replaces whole that holds
//! one, before it writes anything ([`super::OutputSet`]). The command line also compares the paths
//! of its arguments before it starts ([`refuse_overlap`]), so that a long run is not wasted.

use super::DataError;
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

/// An output of a command: the option that names it, its path, and whether it is a directory the
/// run replaces whole (`compensate --out DIR`).
#[derive(Clone, Debug)]
pub struct NamedOutput {
    pub option: String,
    pub path: PathBuf,
    pub whole_directory: bool,
}

/// Refuses, before a run starts, an output that is the same file as one of the inputs `(option,
/// path)`, or a directory replaced whole that holds one; and standard output (`-`) given to two
/// outputs. Bad input: the message names both options and the file.
pub fn refuse_overlap(outputs: &[NamedOutput], inputs: &[(String, PathBuf)]) -> Result<(), DataError> {
    let to_stdout: Vec<&str> = outputs.iter().filter(|o| super::is_standard_output(&o.path)).map(|o| o.option.as_str()).collect();
    if to_stdout.len() > 1 {
        return Err(DataError::Invalid {
            origin: "standard output".into(),
            message: format!("given to {}; one output at most can go there", to_stdout.join(" and ")),
        });
    }
    for output in outputs {
        let Some(out) = FileIdentity::of(&output.path) else { continue };
        for (option, path) in inputs {
            let Some(input) = FileIdentity::of(path) else { continue };
            let what = if input.same(&out) {
                "is the same file as"
            } else if output.whole_directory && input.inside(&out) {
                "is a directory this run replaces whole, and it holds"
            } else {
                continue;
            };
            return Err(DataError::Invalid {
                origin: output.path.display().to_string(),
                message: format!(
                    "{} {what} the input {option} {}: writing it would destroy the input; choose another output path",
                    output.option,
                    path.display()
                ),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn output(option: &str, path: &Path, whole_directory: bool) -> NamedOutput {
        NamedOutput { option: option.into(), path: path.to_path_buf(), whole_directory }
    }

    #[test]
    fn the_same_file_by_any_path_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let poses = dir.path().join("p.csv");
        std::fs::write(&poses, "X\n1\n").unwrap();
        let inputs = [("--poses".to_string(), poses.clone())];
        let mut same = vec![dir.path().join("./p.csv"), dir.path().join("sub/../p.csv")];
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&poses, dir.path().join("link.csv")).unwrap();
            std::fs::hard_link(&poses, dir.path().join("hard.csv")).unwrap();
            same.extend([dir.path().join("link.csv"), dir.path().join("hard.csv")]);
        }
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        for path in same {
            let e = refuse_overlap(&[output("--out", &path, false)], &inputs).unwrap_err().to_string();
            assert!(e.contains("--out is the same file as the input --poses") && e.contains("p.csv"), "{e}");
        }
        // a new file, another file, and a directory of plots beside the input are outputs
        std::fs::write(dir.path().join("other.csv"), "x").unwrap();
        for (path, whole) in [(dir.path().join("new.csv"), false), (dir.path().join("other.csv"), false), (dir.path().to_path_buf(), false)]
        {
            refuse_overlap(&[output("--out", &path, whole)], &inputs).unwrap();
        }
        // a directory replaced whole must not hold an input
        let e = refuse_overlap(&[output("--out", dir.path(), true)], &inputs).unwrap_err().to_string();
        assert!(e.contains("replaces whole, and it holds the input --poses"), "{e}");
        let e = refuse_overlap(&[output("--out", Path::new("-"), false), output("--residuals", Path::new("-"), false)], &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("standard output: given to --out and --residuals"), "{e}");
    }

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
