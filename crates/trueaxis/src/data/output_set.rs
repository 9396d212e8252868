//! Outputs written together: all of them or none (DESIGN.md section 3: never a partially written
//! output; docs/reliability.md states the guarantee).
//!
//! An [`OutputSet`] holds the files of one run: single files at any path (`identify --out E.toml
//! --residuals R.csv`) and directories replaced whole (`compensate --out DIR`, plot directories,
//! the demo's folder). [`OutputSet::commit`] works in two phases:
//!
//! 1. prepare: every path is checked (an existing directory output may hold nothing but files of
//!    this set, a single file's target must not be a directory) and every file is written and
//!    synced to a temporary next to its target (a directory output into a fresh temporary
//!    directory beside it). Any failure removes every temporary: nothing was written.
//! 2. commit: each directory is swapped in by one `renameat2(RENAME_EXCHANGE)` on Linux (a new
//!    directory by one `rename`), so that its path holds the complete old or the complete new set
//!    at every instant, then each single file is renamed over its target, then the old directories
//!    are removed.
//!
//! A run killed between the phases leaves only temporaries (`.NAME.trueaxis-PID-XXXXXX.tmp`,
//! [`super::temporaries`]); they are ignored by the checks and removed by the next run that writes
//! the same output. Single files at separate paths are renamed one after the other (microseconds,
//! no computation in between): there is no system call that renames several at once, so a kill in
//! that window can leave some of them new. Outputs that must change together belong in one
//! directory.

use super::temporaries::{affixes, clean_abandoned, is_temporary_name};
use super::DataError;
use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Component, Path, PathBuf};

/// The files of one run, committed together by [`OutputSet::commit`].
#[derive(Debug, Default)]
pub struct OutputSet {
    files: Vec<(PathBuf, Vec<u8>)>,
    directories: Vec<DirectoryOutput>,
    /// Directories of single files created when missing (`--plots DIR`)
    parents: Vec<PathBuf>,
}

/// A directory replaced whole: its files by path relative to it.
#[derive(Debug)]
struct DirectoryOutput {
    path: PathBuf,
    files: Vec<(PathBuf, Vec<u8>)>,
}

impl OutputSet {
    pub fn new() -> OutputSet {
        OutputSet::default()
    }

    /// A single file at `path` (its directory must exist).
    pub fn file(&mut self, path: impl AsRef<Path>, contents: impl Into<Vec<u8>>) -> &mut OutputSet {
        self.files.push((path.as_ref().to_path_buf(), contents.into()));
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
        let dir = dir.as_ref();
        self.directory(dir);
        let entry = self.directories.iter_mut().find(|d| d.path == dir).expect("declared above");
        entry.files.push((relative.as_ref().to_path_buf(), contents.into()));
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
        let several = self.paths().len() > 1;
        let mut created = Vec::new();
        match self.prepare(&mut created) {
            // the commit phase only renames: an error there (a file system gone read-only between
            // the phases) is reported as it is
            Ok(prepared) => commit_prepared(prepared),
            Err(e) => {
                // the temporaries went with their handles; directories made for the run go too,
                // deepest first, and only when empty
                for dir in created.iter().rev() {
                    let _ = std::fs::remove_dir(dir);
                }
                Err(if several { DataError::NothingWritten(Box::new(e)) } else { e })
            }
        }
    }

    fn prepare(&self, created: &mut Vec<PathBuf>) -> Result<Prepared, DataError> {
        let mut seen = BTreeSet::new();
        for path in self.paths() {
            if !seen.insert(path.clone()) {
                return Err(invalid(&path, "given for two outputs of the same run"));
            }
        }
        for dir in &self.parents {
            create_missing(dir, created).map_err(write_error(dir))?;
        }
        let directories = self.directories.iter().map(|d| stage_directory(d, created)).collect::<Result<Vec<_>, _>>()?;
        let files = self.files.iter().map(|(path, contents)| stage_file(path, contents)).collect::<Result<Vec<_>, _>>()?;
        Ok(Prepared { directories, files })
    }
}

/// Writes `contents` to `path` through a temporary file in the same directory and a rename, so
/// that a reader never sees a partial file. A new file gets the usual mode `0666 & !umask`; a file
/// that is replaced keeps its mode. Abandoned temporaries of the same path are removed.
pub fn write_atomically(path: &Path, contents: &[u8]) -> Result<(), DataError> {
    let mut set = OutputSet::new();
    set.file(path, contents);
    set.commit()
}

struct Prepared {
    directories: Vec<StagedDirectory>,
    files: Vec<(PathBuf, tempfile::NamedTempFile)>,
}

struct StagedDirectory {
    target: PathBuf,
    staging: tempfile::TempDir,
    relative: Vec<PathBuf>,
    exists: bool,
}

fn invalid(path: &Path, message: &str) -> DataError {
    DataError::Invalid { origin: path.display().to_string(), message: message.to_string() }
}

fn write_error(path: &Path) -> impl Fn(std::io::Error) -> DataError + '_ {
    move |source| DataError::Write { path: path.display().to_string(), source: without_temporary_path(source) }
}

/// The directory holding `path` (`.` for a bare name).
fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// A builder of temporary files (`directory == false`, mode `0666 & !umask`) or directories
/// (`0777 & !umask`) named `prefix...suffix`.
fn temporary_builder<'a>(prefix: &'a str, suffix: &'static str, directory: bool) -> tempfile::Builder<'a, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(prefix).suffix(suffix);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(if directory { 0o777 } else { 0o666 }));
    }
    #[cfg(not(unix))]
    let _ = directory;
    builder
}

fn temporary_file(dir: &Path, target_name: &str) -> std::io::Result<tempfile::NamedTempFile> {
    let (prefix, suffix) = affixes(target_name);
    temporary_builder(&prefix, suffix, false).tempfile_in(dir)
}

fn temporary_directory(dir: &Path, target_name: &str) -> std::io::Result<tempfile::TempDir> {
    let (prefix, suffix) = affixes(target_name);
    temporary_builder(&prefix, suffix, true).tempdir_in(dir)
}

/// The name of `path`'s last component, for the names of its temporaries.
fn target_name(path: &Path) -> Result<String, DataError> {
    match path.file_name() {
        Some(n) => Ok(n.to_string_lossy().into_owned()),
        None => Err(invalid(path, "not a file or directory name (give a path that ends in a name)")),
    }
}

/// Writes and syncs `contents` to a temporary beside `path`, with the mode of the file it replaces.
fn stage_file(path: &Path, contents: &[u8]) -> Result<(PathBuf, tempfile::NamedTempFile), DataError> {
    let err = write_error(path);
    if path.is_dir() {
        return Err(invalid(path, "is a directory; give the path of a file"));
    }
    let name = target_name(path)?;
    let dir = parent_of(path);
    clean_abandoned(dir, &name);
    let mut tmp = temporary_file(dir, &name).map_err(&err)?;
    if let Ok(existing) = std::fs::metadata(path) {
        tmp.as_file().set_permissions(existing.permissions()).map_err(&err)?;
    }
    tmp.write_all(contents).map_err(&err)?;
    tmp.as_file().sync_all().map_err(&err)?;
    Ok((path.to_path_buf(), tmp))
}

/// Checks the directory output and writes its files into a fresh temporary directory beside it
/// (missing parents are created and recorded in `created`).
fn stage_directory(output: &DirectoryOutput, created: &mut Vec<PathBuf>) -> Result<StagedDirectory, DataError> {
    let mut relative = Vec::new();
    for (r, _) in &output.files {
        if r.as_os_str().is_empty() || !r.components().all(|c| matches!(c, Component::Normal(_))) {
            return Err(invalid(&output.path.join(r), "not a path of names inside the output directory"));
        }
        relative.push(r.clone());
    }
    // an existing target is resolved (symbolic links, `.`) so that the swap replaces the directory
    // itself, not a link to it
    let exists = output.path.exists();
    let target = if exists { output.path.canonicalize().map_err(write_error(&output.path))? } else { output.path.clone() };
    if exists && !target.is_dir() {
        return Err(invalid(&output.path, "exists and is not a directory; give the path of a directory"));
    }
    if exists {
        refuse_foreign_files(&output.path, &target, &relative)?;
    }
    let name = target_name(&target)?;
    let parent = parent_of(&target).to_path_buf();
    create_missing(&parent, created).map_err(write_error(&parent))?;
    clean_abandoned(&parent, &name);
    let err = write_error(&output.path);
    let staging = temporary_directory(&parent, &name).map_err(&err)?;
    if exists {
        let mode = std::fs::metadata(&target).map_err(&err)?.permissions();
        std::fs::set_permissions(staging.path(), mode).map_err(&err)?;
    }
    for (r, contents) in &output.files {
        let path = staging.path().join(r);
        let final_path = output.path.join(r);
        let err = write_error(&final_path);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(&err)?;
        }
        let mut file = std::fs::File::create(&path).map_err(&err)?;
        if exists {
            if let Ok(old) = std::fs::metadata(target.join(r)) {
                file.set_permissions(old.permissions()).map_err(&err)?;
            }
        }
        file.write_all(contents).map_err(&err)?;
        file.sync_all().map_err(&err)?;
    }
    sync_directory(staging.path()).map_err(&err)?;
    Ok(StagedDirectory { target, staging, relative, exists })
}

/// Creates `dir` and its missing parents, recording each one created (outermost first).
fn create_missing(dir: &Path, created: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let missing: Vec<&Path> = dir.ancestors().take_while(|d| !d.as_os_str().is_empty() && !d.exists()).collect();
    for d in missing.into_iter().rev() {
        std::fs::create_dir(d)?;
        created.push(d.to_path_buf());
    }
    Ok(())
}

/// Refuses a directory output that holds anything but files of this set (and temporaries): the
/// swap replaces the whole directory, and a user's file must never go with it; a stale table of
/// another run must not stay next to the new ones either.
fn refuse_foreign_files(given: &Path, target: &Path, relative: &[PathBuf]) -> Result<(), DataError> {
    let wanted: BTreeSet<&Path> = relative.iter().map(|p| p.as_path()).collect();
    let mut foreign = Vec::new();
    collect_foreign(target, Path::new(""), &wanted, &mut foreign).map_err(write_error(given))?;
    if foreign.is_empty() {
        return Ok(());
    }
    foreign.sort();
    Err(invalid(
        given,
        &format!(
            "the output directory holds files this run does not write ({}); use an empty or new directory so that tables \
             of different runs do not mix",
            foreign.join(" ")
        ),
    ))
}

fn collect_foreign(root: &Path, below: &Path, wanted: &BTreeSet<&Path>, foreign: &mut Vec<String>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(root.join(below))? {
        let entry = entry?;
        let name = entry.file_name();
        if name.to_str().is_some_and(is_temporary_name) {
            continue;
        }
        let relative = below.join(&name);
        if entry.file_type()?.is_dir() {
            if wanted.iter().any(|w| w.starts_with(&relative) && *w != relative) {
                collect_foreign(root, &relative, wanted, foreign)?;
            } else {
                foreign.push(format!("{}/", relative.display()));
            }
        } else if !wanted.contains(relative.as_path()) {
            foreign.push(relative.display().to_string());
        }
    }
    Ok(())
}

/// The commit phase: directories swapped in, then single files renamed, then old directories
/// removed (when their `TempDir` handles drop).
fn commit_prepared(prepared: Prepared) -> Result<(), DataError> {
    let Prepared { directories, files } = prepared;
    let mut old = Vec::new();
    for d in directories {
        let err = write_error(&d.target);
        let parent = parent_of(&d.target).to_path_buf();
        let in_use = std::env::current_dir().ok().and_then(|c| c.canonicalize().ok()).is_some_and(|c| c == d.target);
        if !d.exists {
            std::fs::rename(d.staging.path(), &d.target).map_err(&err)?;
            let _ = d.staging.keep();
        } else if in_use || exchange(d.staging.path(), &d.target).is_err() {
            // the working directory (its inode must stay), or a file system without the exchange:
            // the files are renamed into it one by one
            for r in &d.relative {
                let to = d.target.join(r);
                if let Some(dir) = to.parent() {
                    std::fs::create_dir_all(dir).map_err(&err)?;
                }
                std::fs::rename(d.staging.path().join(r), &to).map_err(&err)?;
            }
            old.push(d.staging);
        } else {
            old.push(d.staging);
        }
        // durability of the rename; the output is in place whatever this says
        let _ = sync_directory(&parent);
    }
    for (path, tmp) in files {
        tmp.persist(&path).map_err(|e| write_error(&path)(e.error))?;
        let _ = sync_directory(parent_of(&path));
    }
    drop(old);
    Ok(())
}

/// Exchanges the directories `a` and `b` in one step (Linux `renameat2` with `RENAME_EXCHANGE`,
/// supported by ext4, xfs, btrfs, tmpfs and most local file systems; man 2 rename).
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    let c = |p: &Path| CString::new(p.as_os_str().as_bytes()).map_err(|_| std::io::Error::from(std::io::ErrorKind::InvalidInput));
    let (a, b) = (c(a)?, c(b)?);
    // SAFETY: two valid NUL-terminated paths; the call reads them and changes nothing in memory
    let status = unsafe { libc::renameat2(libc::AT_FDCWD, a.as_ptr(), libc::AT_FDCWD, b.as_ptr(), libc::RENAME_EXCHANGE) };
    if status == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> std::io::Result<()> {
    Err(std::io::Error::from(std::io::ErrorKind::Unsupported))
}

/// Makes the entries of `dir` durable (a rename is recorded in its directory); a no-op where a
/// directory cannot be opened as a file.
fn sync_directory(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    std::fs::File::open(dir)?.sync_all()?;
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

/// The system error without the name of the temporary file that `tempfile` appends to it (`... at
/// path "/dir/.X.trueaxis-...tmp"`): the user asked for the final path, which the message names.
fn without_temporary_path(e: std::io::Error) -> std::io::Error {
    let text = e.to_string();
    match text.rfind(" at path \"") {
        Some(i) if e.raw_os_error().is_none() => std::io::Error::new(e.kind(), text[..i].to_string()),
        _ => e,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
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
