//! The commit phase of an [`super::OutputSet`] (its module documentation): streamed contents
//! flushed and synced, outputs written in place (devices, FIFOs, standard output), then every
//! directory swapped in and every single file renamed over its target, holding the commit lock of
//! [`super::temporaries`] so that a signal's clean-up waits for the renames.

use super::staging::{open_in_place, parent_of, refuse_foreign_files, write_error};
use super::temporaries::{commit_lock, LiveTemporary};
use super::DataError;
use std::io::Write;
use std::path::{Path, PathBuf};

/// An [`super::OutputSet`] after its prepare phase: every temporary written, every streamed
/// output open. Dropping it without [`PreparedSet::commit`] removes the temporaries and leaves
/// every final path as it was.
#[derive(Default)]
pub struct PreparedSet {
    pub(super) directories: Vec<StagedDirectory>,
    pub(super) files: Vec<StagedFile>,
    pub(super) sinks: Vec<Sink>,
}

impl std::fmt::Debug for PreparedSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sinks: Vec<&PathBuf> = self.sinks.iter().map(|s| &s.path).collect();
        f.debug_struct("PreparedSet")
            .field("directories", &self.directories.len())
            .field("files", &self.files.len())
            .field("streamed", &sinks)
            .finish()
    }
}

/// A streamed output: where the caller's bytes go (buffered), and the file to sync at commit.
pub(super) struct Sink {
    path: PathBuf,
    writer: std::io::BufWriter<Box<dyn Write + Send>>,
    durable: Option<std::fs::File>,
}

impl Sink {
    pub(super) fn new(path: &Path, writer: Box<dyn Write + Send>, durable: Option<std::fs::File>) -> Sink {
        Sink { path: path.to_path_buf(), writer: std::io::BufWriter::with_capacity(1 << 16, writer), durable }
    }

    fn finish(mut self) -> Result<(), DataError> {
        let err = write_error(&self.path);
        self.writer.flush().map_err(&err)?;
        if let Some(file) = &self.durable {
            file.sync_all().map_err(&err)?;
        }
        Ok(())
    }
}

/// A single file, staged.
pub(super) enum StagedFile {
    /// A regular file: its temporary, renamed over `target` (symbolic links resolved) at commit.
    Renamed { given: PathBuf, target: PathBuf, tmp: tempfile::NamedTempFile, live: LiveTemporary },
    /// Written in place at commit: standard output (`device` none) or a device, FIFO, descriptor.
    InPlace { given: PathBuf, device: Option<PathBuf>, bytes: Vec<u8> },
}

/// A directory output written into `staging`, a temporary directory beside `target`.
pub(super) struct StagedDirectory {
    pub(super) given: PathBuf,
    pub(super) target: PathBuf,
    /// Declared before `live`: the directory is removed before it is unregistered.
    pub(super) staging: tempfile::TempDir,
    pub(super) live: LiveTemporary,
    pub(super) relative: Vec<PathBuf>,
    pub(super) exists: bool,
}

impl PreparedSet {
    /// The writer of the streamed output `path` (as declared: a single file's path, or a directory
    /// output's `dir.join(relative)`); buffered, flushed and synced by [`PreparedSet::commit`].
    pub fn stream(&mut self, path: &Path) -> Result<&mut dyn Write, DataError> {
        match self.sinks.iter_mut().find(|s| s.path == path) {
            Some(s) => Ok(&mut s.writer),
            None => Err(DataError::Invalid { origin: super::output_name(path), message: "is not a streamed output of this run".into() }),
        }
    }

    /// The commit phase: streamed contents flushed and synced, outputs in place written, then
    /// directories swapped in, single files renamed, old directories removed.
    pub fn commit(self) -> Result<(), DataError> {
        let PreparedSet { directories, files, sinks } = self;
        for sink in sinks {
            sink.finish()?;
        }
        let mut renamed = Vec::new();
        for file in files {
            match file {
                StagedFile::InPlace { given, device, bytes } => write_in_place(&given, device.as_deref(), &bytes)?,
                StagedFile::Renamed { given, target, tmp, live } => renamed.push((given, target, tmp, live)),
            }
        }
        for d in &directories {
            sync_directory(d.staging.path()).map_err(write_error(&d.given))?;
        }
        let mut old = Vec::new();
        let committing = commit_lock();
        for d in directories {
            old.extend(swap_in(d)?);
        }
        for (given, target, tmp, guard) in renamed {
            tmp.persist(&target).map_err(|e| write_error(&given)(e.error))?;
            drop(guard);
            let _ = sync_directory(parent_of(&target));
        }
        drop(committing);
        drop(old);
        Ok(())
    }
}

/// Writes whole contents to an output in place.
fn write_in_place(given: &Path, device: Option<&Path>, bytes: &[u8]) -> Result<(), DataError> {
    let err = write_error(given);
    let mut out = open_in_place(device).map_err(&err)?;
    out.write_all(bytes).map_err(&err)?;
    out.flush().map_err(&err)
}

/// Puts a staged directory at its target; returns the staged directory when it now holds the old
/// one (removed when dropped). A new target another run created meanwhile is exchanged like an
/// existing one, after the same check of its files.
fn swap_in(d: StagedDirectory) -> Result<Option<StagedDirectory>, DataError> {
    let err = write_error(&d.given);
    let parent = parent_of(&d.target).to_path_buf();
    let mut exists = d.exists;
    if !exists {
        match std::fs::rename(d.staging.path(), &d.target) {
            Ok(()) => {
                let StagedDirectory { staging, live, .. } = d;
                let _ = staging.keep();
                drop(live);
                let _ = sync_directory(&parent);
                return Ok(None);
            }
            // another run made the directory between the prepare phase and now
            Err(e)
                if matches!(e.kind(), std::io::ErrorKind::DirectoryNotEmpty | std::io::ErrorKind::AlreadyExists) && d.target.is_dir() =>
            {
                refuse_foreign_files(&d.given, &d.target, &d.relative)?;
                exists = true;
            }
            Err(e) => return Err(err(e)),
        }
    }
    debug_assert!(exists);
    let in_use = std::env::current_dir().ok().and_then(|c| c.canonicalize().ok()).is_some_and(|c| c == d.target);
    if in_use || exchange(d.staging.path(), &d.target).is_err() {
        // the working directory (its inode must stay), or a file system without the exchange:
        // the files are renamed into it one by one
        for r in &d.relative {
            let to = d.target.join(r);
            if let Some(dir) = to.parent() {
                std::fs::create_dir_all(dir).map_err(&err)?;
            }
            std::fs::rename(d.staging.path().join(r), &to).map_err(&err)?;
        }
    }
    // durability of the rename; the output is in place whatever this says
    let _ = sync_directory(&parent);
    Ok(Some(d))
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

#[cfg(test)]
mod tests {
    use super::super::output_set::tests::names;
    use super::super::OutputSet;

    #[test]
    fn streamed_contents_are_committed_whole_or_not_at_all() {
        let tmp = tempfile::tempdir().unwrap();
        let (file, dir) = (tmp.path().join("p.csv"), tmp.path().join("comp"));
        let declare = || {
            let mut set = OutputSet::new();
            set.streamed_file(&file).in_directory(&dir, "X.comp", "x").streamed_in_directory(&dir, "corrections.csv");
            set
        };
        // dropped before its commit (the caller's computation failed): nothing, not even temporaries
        let mut prepared = declare().prepare().unwrap();
        prepared.stream(&file).unwrap().write_all(b"half").unwrap();
        drop(prepared);
        assert_eq!(names(tmp.path()), Vec::<String>::new());
        let mut prepared = declare().prepare().unwrap();
        for k in 0..1000 {
            writeln!(prepared.stream(&file).unwrap(), "{k}").unwrap();
        }
        prepared.stream(&dir.join("corrections.csv")).unwrap().write_all(b"c").unwrap();
        assert!(prepared.stream(&tmp.path().join("other")).err().unwrap().to_string().contains("not a streamed output"));
        prepared.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&file).unwrap().lines().count(), 1000);
        assert_eq!(std::fs::read_to_string(dir.join("corrections.csv")).unwrap(), "c");
        assert_eq!(names(tmp.path()), ["comp", "p.csv"]);
    }

    #[cfg(unix)]
    #[test]
    fn devices_fifos_and_links_to_them_are_written_in_place_never_replaced() {
        use std::os::unix::fs::{symlink, FileTypeExt};
        let tmp = tempfile::tempdir().unwrap();
        let link = tmp.path().join("null");
        symlink("/dev/null", &link).unwrap();
        let mut set = OutputSet::new();
        set.file(&link, "to the bit bucket");
        set.commit().unwrap();
        assert!(link.symlink_metadata().unwrap().file_type().is_symlink(), "the link stays");
        assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
        // a FIFO: its reader gets the contents, and it stays a FIFO
        let fifo = tmp.path().join("fifo");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
        };
        crate::data::write_streamed(&fifo, |w| {
            w.write_all(b"through the pipe").map_err(|source| crate::data::DataError::Write { path: "fifo".into(), source })
        })
        .unwrap();
        assert_eq!(reader.join().unwrap(), "through the pipe");
        assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        // a device node of its own (root only: mknod)
        if !nix_root() {
            println!("skipped the device made with mknod: needs root");
            return;
        }
        let device = tmp.path().join("null-copy");
        let c = std::ffi::CString::new(device.to_str().unwrap()).unwrap();
        // SAFETY: a valid path; 1:3 is the null device of Linux
        if unsafe { libc::mknod(c.as_ptr(), libc::S_IFCHR | 0o666, libc::makedev(1, 3)) } != 0 {
            println!("skipped the device made with mknod: {}", std::io::Error::last_os_error());
            return;
        }
        crate::data::write_atomically(&device, b"nothing").unwrap();
        assert!(std::fs::metadata(&device).unwrap().file_type().is_char_device(), "the device stays a device");
        assert_eq!(names(tmp.path()), ["fifo", "null", "null-copy"]);
    }

    #[cfg(unix)]
    fn nix_root() -> bool {
        // SAFETY: geteuid has no preconditions
        unsafe { libc::geteuid() == 0 }
    }

    #[test]
    fn runs_that_create_the_same_new_directory_at_once_all_succeed() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("new/comp");
        let runs = 4;
        let barrier = std::sync::Arc::new(std::sync::Barrier::new(runs));
        let handles: Vec<_> = (0..runs)
            .map(|k| {
                let (dir, barrier) = (dir.clone(), barrier.clone());
                std::thread::spawn(move || {
                    let mut set = OutputSet::new();
                    set.in_directory(&dir, "X.comp", format!("run {k}")).in_directory(&dir, "Y.comp", format!("run {k}"));
                    let prepared = set.prepare();
                    barrier.wait();
                    prepared.and_then(|p| p.commit())
                })
            })
            .collect();
        for h in handles {
            h.join().unwrap().unwrap();
        }
        // one run's set, whole
        let x = std::fs::read_to_string(dir.join("X.comp")).unwrap();
        assert_eq!(std::fs::read_to_string(dir.join("Y.comp")).unwrap(), x);
        assert_eq!(names(&dir), ["X.comp", "Y.comp"]);
        assert_eq!(names(dir.parent().unwrap()), ["comp"], "temporaries left");
    }
}
