//! What an output path is, and so how it is written (docs/reliability.md):
//!
//! - a regular file, new or existing, is written to a temporary beside it and renamed over it
//!   (never half written). A symbolic link to a regular file stays a link: the file it points to is
//!   replaced. An existing file this user may not write (read-only, or another user's in a
//!   directory this user may write) is refused, as `cp` refuses it: renaming over it would bypass
//!   its permissions;
//! - a device (`/dev/null`, a tape, a serial line), a FIFO, a socket, or a path that leads through
//!   a file descriptor (`/dev/stdout`, `/dev/fd/N`, `/proc/self/fd/N`) is written in place as a
//!   stream, never replaced: a rename would put a regular file where the device was;
//! - `-` is standard output (streamed), for every output that names a file.

use super::DataError;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicI32, Ordering};

/// The path that means standard output.
pub const STANDARD_OUTPUT: &str = "-";

/// Whether `path` means standard output (`-`).
pub fn is_standard_output(path: &Path) -> bool {
    path.as_os_str() == STANDARD_OUTPUT
}

/// The name of an output in messages: its path, or `standard output` for `-`.
pub fn output_name(path: &Path) -> String {
    if is_standard_output(path) {
        "standard output".into()
    } else {
        path.display().to_string()
    }
}

/// The file descriptor `-` writes to.
static STANDARD_OUTPUT_FD: AtomicI32 = AtomicI32::new(1);

/// Makes `-` write to the file descriptor `fd` instead of 1: the command line moves its own
/// messages off standard output when an output goes there, and keeps the original here.
pub fn set_standard_output_descriptor(fd: i32) {
    STANDARD_OUTPUT_FD.store(fd, Ordering::SeqCst);
}

/// How an output is written.
#[derive(Debug)]
pub(crate) enum Target {
    /// A regular file replaced through a temporary: `path` with symbolic links resolved, and the
    /// metadata of the file it replaces.
    File { path: PathBuf, existing: Option<std::fs::Metadata> },
    /// Written in place: a device, FIFO, socket, or a path through a file descriptor.
    Stream { path: PathBuf },
    /// `-`.
    StandardOutput,
}

/// Most symbolic links followed from an output path (Linux's own limit, `MAXSYMLINKS`).
const MAX_LINKS: usize = 40;

/// Whether `path` names a file through a file descriptor (`/proc/<pid>/fd/N`, `/dev/fd/N`).
fn through_descriptor(path: &Path) -> bool {
    let parts: Vec<_> = path.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
    let proc_fd = parts.len() >= 5 && parts[1] == "proc" && parts[3] == "fd";
    let dev_fd = parts.len() >= 4 && parts[1] == "dev" && parts[2] == "fd";
    path.is_absolute() && (proc_fd || dev_fd)
}

/// What the output `path` is (module documentation).
pub(crate) fn target_of(path: &Path) -> Result<Target, DataError> {
    if is_standard_output(path) {
        return Ok(Target::StandardOutput);
    }
    let mut at = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        if through_descriptor(&at) {
            return Ok(Target::Stream { path: path.to_path_buf() });
        }
        match at.symlink_metadata() {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Target::File { path: at, existing: None }),
            Err(source) => return Err(DataError::Write { path: path.display().to_string(), source }),
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&at).map_err(|source| DataError::Write { path: path.display().to_string(), source })?;
                at = if to.is_absolute() { to } else { at.parent().unwrap_or(Path::new("")).join(to) };
            }
            Ok(m) if m.is_dir() => {
                return Err(DataError::Invalid {
                    origin: path.display().to_string(),
                    message: "is a directory; give the path of a file".into(),
                })
            }
            Ok(m) if m.is_file() => return Ok(Target::File { path: at, existing: Some(m) }),
            Ok(_) => return Ok(Target::Stream { path: path.to_path_buf() }),
        }
    }
    Err(DataError::Invalid { origin: path.display().to_string(), message: format!("more than {MAX_LINKS} symbolic links in a chain") })
}

/// Refuses to replace an existing file or directory that this user may not write (module
/// documentation); a permission error (a failure of the environment).
pub(crate) fn refuse_unwritable(given: &Path, path: &Path) -> Result<(), DataError> {
    match writable(path) {
        Ok(()) => Ok(()),
        Err(e) => {
            let detail = ownership(path);
            Err(DataError::Write {
                path: given.display().to_string(),
                source: std::io::Error::new(
                    e.kind(),
                    format!("{e}: this user may not write it{detail}, so trueaxis does not replace it (make it writable, or choose another path)"),
                ),
            })
        }
    }
}

#[cfg(unix)]
fn writable(path: &Path) -> std::io::Result<()> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(path.as_os_str().as_bytes()).map_err(|_| std::io::Error::from(std::io::ErrorKind::InvalidInput))?;
    // SAFETY: a valid NUL-terminated path; access(2) only reads it
    if unsafe { libc::access(c.as_ptr(), libc::W_OK) } == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

#[cfg(not(unix))]
fn writable(path: &Path) -> std::io::Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if m.permissions().readonly() => Err(std::io::Error::from(std::io::ErrorKind::PermissionDenied)),
        _ => Ok(()),
    }
}

/// ` (mode 0444, owner uid 1000)` for messages.
fn ownership(path: &Path) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let Ok(m) = std::fs::metadata(path) {
            return format!(" (mode {:04o}, owner uid {})", m.mode() & 0o7777, m.uid());
        }
    }
    let _ = path;
    String::new()
}

/// Gives a new file the owner and group of the file it replaces, when they differ (root writing
/// a user's file leaves it that user's); errors are ignored (only root may change an owner).
pub(crate) fn keep_owner(file: &std::fs::File, existing: &std::fs::Metadata) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let Ok(now) = file.metadata() {
            if (now.uid(), now.gid()) != (existing.uid(), existing.gid()) {
                let _ = std::os::unix::fs::fchown(file, Some(existing.uid()), Some(existing.gid()));
            }
        }
    }
    #[cfg(not(unix))]
    let _ = (file, existing);
}

/// Opens a stream target for writing in place (appending: a file reached through a descriptor
/// keeps what is before).
pub(crate) fn open_stream(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::OpenOptions::new().append(true).open(path)
}

/// Standard output as a file of its own (a duplicate of the descriptor `-` writes to).
#[cfg(unix)]
pub(crate) fn open_standard_output() -> std::io::Result<Box<dyn std::io::Write + Send>> {
    use std::os::fd::{BorrowedFd, OwnedFd};
    let fd = STANDARD_OUTPUT_FD.load(Ordering::SeqCst);
    // SAFETY: the descriptor of standard output (or the one the command line keeps for it) stays
    // open for the life of the process; it is only borrowed to duplicate it
    let borrowed = unsafe { BorrowedFd::borrow_raw(fd) };
    let owned: OwnedFd = borrowed.try_clone_to_owned()?;
    Ok(Box::new(std::fs::File::from(owned)))
}

#[cfg(not(unix))]
pub(crate) fn open_standard_output() -> std::io::Result<Box<dyn std::io::Write + Send>> {
    Ok(Box::new(std::io::stdout()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_told_apart() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("e.toml");
        assert!(matches!(target_of(&file).unwrap(), Target::File { existing: None, .. }));
        std::fs::write(&file, "x").unwrap();
        assert!(matches!(target_of(&file).unwrap(), Target::File { existing: Some(_), .. }));
        assert!(matches!(target_of(Path::new("-")).unwrap(), Target::StandardOutput));
        assert!(target_of(dir.path()).unwrap_err().to_string().contains("is a directory"));
        #[cfg(unix)]
        {
            use std::os::unix::fs::symlink;
            // a link to a file: the file is replaced, the link stays
            symlink("e.toml", dir.path().join("link")).unwrap();
            match target_of(&dir.path().join("link")).unwrap() {
                Target::File { path, existing: Some(_) } => assert_eq!(path, file),
                other => panic!("{other:?}"),
            }
            // a dangling link: the file it names is created
            symlink("sub-new.toml", dir.path().join("dangling")).unwrap();
            assert!(
                matches!(target_of(&dir.path().join("dangling")).unwrap(), Target::File { path, existing: None } if path == dir.path().join("sub-new.toml"))
            );
            for stream in ["/dev/null", "/dev/stdout", "/dev/fd/1", "/proc/self/fd/2"] {
                if Path::new(stream).exists() {
                    assert!(matches!(target_of(Path::new(stream)).unwrap(), Target::Stream { .. }), "{stream}");
                }
            }
            symlink("/dev/null", dir.path().join("null")).unwrap();
            assert!(matches!(target_of(&dir.path().join("null")).unwrap(), Target::Stream { .. }));
            symlink("loop", dir.path().join("loop")).unwrap();
            assert!(target_of(&dir.path().join("loop")).unwrap_err().to_string().contains("symbolic links"));
        }
    }
}
