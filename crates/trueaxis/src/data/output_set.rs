//! Outputs written together: all of them or none (docs/design.md, Files: never a partially written
//! output; docs/reliability.md states the guarantee).
//!
//! An [`OutputSet`] holds the files of one run: single files at any path (`identify --out E.toml
//! --residuals R.csv`) and directories replaced whole (`compensate --out DIR`, plot directories,
//! the demo's folder). A file's contents are given whole, or streamed by the caller once the set
//! is prepared (`predict` writes millions of rows without holding them). Writing works in two
//! phases:
//!
//! 1. prepare ([`OutputSet::prepare`], `staging`): every path is checked (an existing directory
//!    output may hold nothing but files of this set; a single file's target must not be a
//!    directory, nor an input of the run, nor a file this user may not write) and every file is
//!    written and synced to a temporary next to its target (a directory output into a fresh
//!    temporary directory beside it). Any failure removes every temporary: nothing was written.
//!    Streamed contents are then written by the caller ([`PreparedSet::stream`]);
//! 2. commit ([`PreparedSet::commit`], `commit`): each directory is swapped in by one
//!    `renameat2(RENAME_EXCHANGE)` on Linux (a new directory by one `rename`), so that its path
//!    holds the complete old or the complete new set at every instant, then each single file is
//!    renamed over its target, then the old directories are removed.
//!
//! Outputs that are not regular files (a device, a FIFO, `-` for standard output; `target`) are
//! written in place in the commit phase, before any rename, and are never replaced.
//!
//! A run killed between the phases leaves only temporaries (`.NAME.trueaxis-PID-XXXXXX.tmp`,
//! [`super::temporaries`]); they are ignored by the checks and removed by the next run that writes
//! the same output, and a run stopped by a signal removes its own ([`super::temporaries::remove_live`]).
//! Single files at separate paths are renamed one after the other (microseconds, no computation in
//! between): there is no system call that renames several at once, so a kill in that window can
//! leave some of them new. Outputs that must change together belong in one directory.

pub use super::commit::PreparedSet;
use super::DataError;
use std::path::{Path, PathBuf};

/// The files of one run, written together by [`OutputSet::commit`] (or [`OutputSet::prepare`],
/// then [`PreparedSet::commit`] when contents are streamed).
#[derive(Debug, Default)]
pub struct OutputSet {
    pub(super) files: Vec<(PathBuf, Contents)>,
    pub(super) directories: Vec<DirectoryOutput>,
    /// Directories of single files created when missing (`--plots DIR`)
    pub(super) parents: Vec<PathBuf>,
    /// Outputs may be inputs of the run ([`OutputSet::updating_inputs`]).
    pub(super) updates_inputs: bool,
}

/// The contents of an output: given whole, or written by the caller after the prepare phase.
#[derive(Debug)]
pub(super) enum Contents {
    Bytes(Vec<u8>),
    Streamed,
}

/// A directory replaced whole: its files by path relative to it.
#[derive(Debug)]
pub(super) struct DirectoryOutput {
    pub(super) path: PathBuf,
    pub(super) files: Vec<(PathBuf, Contents)>,
}

impl OutputSet {
    pub fn new() -> OutputSet {
        OutputSet::default()
    }

    /// A single file at `path` (its directory must exist; `-` is standard output).
    pub fn file(&mut self, path: impl AsRef<Path>, contents: impl Into<Vec<u8>>) -> &mut OutputSet {
        self.files.push((path.as_ref().to_path_buf(), Contents::Bytes(contents.into())));
        self
    }

    /// A single file at `path` whose contents the caller writes through [`PreparedSet::stream`].
    pub fn streamed_file(&mut self, path: impl AsRef<Path>) -> &mut OutputSet {
        self.files.push((path.as_ref().to_path_buf(), Contents::Streamed));
        self
    }

    /// Creates `dir` (and its parents) when missing, for single files in it: a directory of plots
    /// that may hold other files too (`--plots DIR`). It is created in the prepare phase and
    /// removed again when the set fails.
    pub fn create_directory(&mut self, dir: impl AsRef<Path>) -> &mut OutputSet {
        self.parents.push(dir.as_ref().to_path_buf());
        self
    }

    /// The directory `dir`, replaced whole by the files given with [`OutputSet::in_directory`]
    /// (created with its parents when missing; an existing one may hold only files of this set).
    pub fn directory(&mut self, dir: impl AsRef<Path>) -> &mut OutputSet {
        let dir = dir.as_ref();
        if !self.directories.iter().any(|d| d.path == dir) {
            self.directories.push(DirectoryOutput { path: dir.to_path_buf(), files: Vec::new() });
        }
        self
    }

    /// The file `relative` (a name, or a path of names below `dir`) of the directory output `dir`.
    pub fn in_directory(&mut self, dir: impl AsRef<Path>, relative: impl AsRef<Path>, contents: impl Into<Vec<u8>>) -> &mut OutputSet {
        self.add_in_directory(dir.as_ref(), relative.as_ref(), Contents::Bytes(contents.into()))
    }

    /// The file `relative` of the directory output `dir`, written by the caller through
    /// [`PreparedSet::stream`] with the path `dir.join(relative)`.
    pub fn streamed_in_directory(&mut self, dir: impl AsRef<Path>, relative: impl AsRef<Path>) -> &mut OutputSet {
        self.add_in_directory(dir.as_ref(), relative.as_ref(), Contents::Streamed)
    }

    fn add_in_directory(&mut self, dir: &Path, relative: &Path, contents: Contents) -> &mut OutputSet {
        self.directory(dir);
        let entry = self.directories.iter_mut().find(|d| d.path == dir).expect("declared above");
        entry.files.push((relative.to_path_buf(), contents));
        self
    }

    /// Lets the outputs be files the run read: a command whose job is to update its input files
    /// in place (`design simulate` writes the readings into the campaign's data files). Without
    /// it such an output is refused ([`super::inputs`]).
    pub fn updating_inputs(&mut self) -> &mut OutputSet {
        self.updates_inputs = true;
        self
    }

    /// True when nothing is to be written.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty() && self.directories.is_empty()
    }

    /// Every final path, single files first, then each directory's files.
    pub fn paths(&self) -> Vec<PathBuf> {
        let files = self.files.iter().map(|(p, _)| p.clone());
        files.chain(self.directories.iter().flat_map(|d| d.files.iter().map(|(r, _)| d.path.join(r)))).collect()
    }

    /// Writes every output, all or none (module documentation). An error names the output and
    /// its cause; when the set had more than one output it says that nothing was written.
    pub fn commit(self) -> Result<(), DataError> {
        self.prepare()?.commit()
    }

    /// The prepare phase (module documentation): every output checked, every given content
    /// written to its temporary, every streamed output opened. An error names the output and its
    /// cause; when the set had more than one output it says that nothing was written.
    pub fn prepare(self) -> Result<PreparedSet, DataError> {
        let several = self.paths().len() > 1;
        super::staging::prepare(self).map_err(|e| if several { DataError::NothingWritten(Box::new(e)) } else { e })
    }
}

/// Writes `contents` to `path` through a temporary file in the same directory and a rename, so
/// that a reader never sees a partial file (a device, a FIFO or `-` is written in place). A new
/// file gets the usual mode `0666 & !umask`; a file that is replaced keeps its mode. Abandoned
/// temporaries of the same path are removed.
pub fn write_atomically(path: &Path, contents: &[u8]) -> Result<(), DataError> {
    let mut set = OutputSet::new();
    set.file(path, contents);
    set.commit()
}

/// Writes the file `path` as [`write_atomically`] does, its contents streamed by `produce`
/// (buffered). An error of `produce` leaves the old file as it was (a stream gets what was written
/// before it).
pub fn write_streamed<E: From<DataError>>(path: &Path, produce: impl FnOnce(&mut dyn std::io::Write) -> Result<(), E>) -> Result<(), E> {
    let mut set = OutputSet::new();
    set.streamed_file(path);
    let mut prepared = set.prepare()?;
    produce(prepared.stream(path)?)?;
    Ok(prepared.commit()?)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// The names in `dir`, sorted (for the tests of the output layer).
    pub(in crate::data) fn names(dir: &Path) -> Vec<String> {
        let mut n: Vec<String> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        n.sort();
        n
    }

    #[test]
    fn a_set_writes_files_and_a_directory_together() {
        let tmp = tempfile::tempdir().unwrap();
        let (file, dir) = (tmp.path().join("a.toml"), tmp.path().join("new/deeper/tables"));
        let mut set = OutputSet::new();
        set.file(&file, "a = 1\n").in_directory(&dir, "X.comp", "x").in_directory(&dir, "sub/Y.comp", "y");
        assert_eq!(set.paths(), [file.clone(), dir.join("X.comp"), dir.join("sub/Y.comp")]);
        set.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "a = 1\n");
        assert_eq!(std::fs::read_to_string(dir.join("sub/Y.comp")).unwrap(), "y");
        assert_eq!(names(tmp.path()), ["a.toml", "new"]);
        // again, with other contents: the directory is replaced whole
        let mut set = OutputSet::new();
        set.in_directory(&dir, "X.comp", "x2").in_directory(&dir, "sub/Y.comp", "y2");
        set.commit().unwrap();
        assert_eq!(std::fs::read_to_string(dir.join("X.comp")).unwrap(), "x2");
        assert_eq!(names(dir.parent().unwrap()), ["tables"], "no temporary left beside the directory");
    }

    #[test]
    fn nothing_is_written_when_one_output_cannot_be() {
        let tmp = tempfile::tempdir().unwrap();
        let first = tmp.path().join("ok.toml");
        let dir = tmp.path().join("made/for/plots");
        let mut set = OutputSet::new();
        set.file(&first, "ok").create_directory(&dir).file(dir.join("p.svg"), "svg").in_directory(tmp.path().join("comp"), "X.comp", "x");
        set.file(tmp.path().join("missing/r.csv"), "r");
        let e = set.commit().unwrap_err().to_string();
        assert!(e.contains("missing/r.csv") && e.ends_with("nothing was written"), "{e}");
        assert!(!e.contains(".trueaxis-"), "the temporary's name in {e}");
        assert_eq!(names(tmp.path()), Vec::<String>::new(), "files, temporaries or created directories left");
    }

    #[test]
    fn a_directory_with_foreign_files_is_refused_and_left_as_it_was() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("comp");
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("X.comp"), "old").unwrap();
        std::fs::write(dir.join("sub/notes.txt"), "mine").unwrap();
        std::fs::write(dir.join(".tmpAb12Cd"), "an earlier run's temporary: ignored").unwrap();
        let mut set = OutputSet::new();
        set.in_directory(&dir, "X.comp", "new").in_directory(&dir, "sub/Y.comp", "y");
        let e = set.commit().unwrap_err().to_string();
        assert!(e.contains("holds files this run does not write (sub/notes.txt)"), "{e}");
        assert_eq!(std::fs::read_to_string(dir.join("X.comp")).unwrap(), "old");
        assert_eq!(names(tmp.path()), ["comp"]);
    }

    #[test]
    fn paths_that_cannot_be_outputs_are_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let mut twice = OutputSet::new();
        twice.file(tmp.path().join("a.csv"), "1").file(tmp.path().join("a.csv"), "2");
        assert!(twice.commit().unwrap_err().to_string().contains("given for two outputs"));
        let mut on_directory = OutputSet::new();
        on_directory.file(tmp.path(), "x");
        assert!(on_directory.commit().unwrap_err().to_string().contains("is a directory"));
        let file = tmp.path().join("plain");
        std::fs::write(&file, "x").unwrap();
        let mut into_file = OutputSet::new();
        into_file.in_directory(&file, "X.comp", "x");
        assert!(into_file.commit().unwrap_err().to_string().contains("not a directory"));
        let mut escaping = OutputSet::new();
        escaping.in_directory(tmp.path().join("d"), "../X.comp", "x");
        assert!(escaping.commit().unwrap_err().to_string().contains("not a path of names"));
        assert_eq!(names(tmp.path()), ["plain"]);
    }

    #[cfg(unix)]
    #[test]
    fn replaced_outputs_keep_their_modes() {
        use std::os::unix::fs::PermissionsExt;
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("comp");
        let file = tmp.path().join("e.toml");
        let mut set = OutputSet::new();
        set.file(&file, "1").in_directory(&dir, "X.comp", "1");
        set.commit().unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        // new outputs: the usual modes less the umask (never executable files)
        assert_eq!(mode(&file) & 0o111, 0);
        assert_eq!(mode(&dir) & 0o700, 0o700);
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o750)).unwrap();
        std::fs::set_permissions(dir.join("X.comp"), std::fs::Permissions::from_mode(0o640)).unwrap();
        std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o600)).unwrap();
        let mut set = OutputSet::new();
        set.file(&file, "2").in_directory(&dir, "X.comp", "2");
        set.commit().unwrap();
        assert_eq!((mode(&dir), mode(&dir.join("X.comp")), mode(&file)), (0o750, 0o640, 0o600));
    }
}
