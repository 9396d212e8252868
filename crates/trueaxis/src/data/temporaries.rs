//! Temporaries of atomic outputs: their names, and the clean-up of those a killed run left behind.
//!
//! Every output is first written to a temporary next to its final path and then renamed over it
//! (docs/design.md, Files: never a partially written output). A temporary of the output `NAME` (a file
//! or a directory) in the directory `D` is `D/.NAME.trueaxis-PID-XXXXXX.tmp`: hidden, named after its
//! target and after the process that writes it. A run killed with `kill -9` cannot remove it; the
//! next run writing the same target removes it once it is abandoned: its process no longer runs on
//! this machine (Linux `/proc`), or it is older than [`ABANDONED_AFTER`] (other systems, or a
//! process id that was reused). A temporary of another target, or of a live run, is left alone.
//!
//! A run that is asked to stop (SIGINT, SIGTERM, SIGHUP) or that runs out of memory removes its own
//! temporaries first: each one is registered while it exists ([`LiveTemporary`]), and
//! [`remove_live`] removes those registered. A commit holds a lock while it renames its
//! temporaries into place ([`commit_lock`]), so that a removal waits until the renames are done and
//! never leaves a set half renamed.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

/// Age after which a temporary is abandoned whatever its process id says (24 h).
pub const ABANDONED_AFTER: Duration = Duration::from_secs(24 * 3600);

const MARK: &str = ".trueaxis-";
const SUFFIX: &str = ".tmp";

/// The prefix and suffix of this process's temporaries of the output named `target_name`.
pub(crate) fn affixes(target_name: &str) -> (String, &'static str) {
    (format!(".{target_name}{MARK}{}-", std::process::id()), SUFFIX)
}

/// The target name and process id of a temporary name, `None` for any other name.
fn parse(name: &str) -> Option<(&str, u32)> {
    let inner = name.strip_prefix('.')?.strip_suffix(SUFFIX)?;
    let at = inner.rfind(MARK)?;
    let pid = inner[at + MARK.len()..].split('-').next()?.parse().ok()?;
    Some((&inner[..at], pid))
}

/// True for the name of a temporary of an atomic output: trueaxis's own
/// (`.NAME.trueaxis-PID-XXXXXX.tmp`) and those of earlier versions (`.tmpXXXXXX`, the default name
/// of the `tempfile` crate). Such names are never taken for a user's file.
pub fn is_temporary_name(name: &str) -> bool {
    let legacy = name.len() == 10 && name.starts_with(".tmp") && name[4..].chars().all(|c| c.is_ascii_alphanumeric());
    legacy || parse(name).is_some()
}

/// The temporaries of this process that exist now (files and directories).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Held by a commit while it renames temporaries into place, and by [`remove_live`].
static COMMITTING: Mutex<()> = Mutex::new(());

fn lock<T>(m: &'static Mutex<T>) -> MutexGuard<'static, T> {
    // a panic elsewhere does not make the registry unusable
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Held while a commit renames its temporaries: [`remove_live`] waits for it.
pub(crate) fn commit_lock() -> MutexGuard<'static, ()> {
    lock(&COMMITTING)
}

/// A temporary registered while it exists: unregistered when dropped (removed, or renamed into
/// place).
#[derive(Debug)]
pub(crate) struct LiveTemporary(PathBuf);

impl LiveTemporary {
    pub(crate) fn register(path: &Path) -> LiveTemporary {
        lock(&LIVE).push(path.to_path_buf());
        LiveTemporary(path.to_path_buf())
    }
}

impl Drop for LiveTemporary {
    fn drop(&mut self) {
        lock(&LIVE).retain(|p| *p != self.0);
    }
}

/// Removes every live temporary of this process (files and whole directories) and returns how many
/// were removed; for a handler of a signal that ends the run. Waits for a commit in progress.
pub fn remove_live() -> usize {
    let _commit = commit_lock();
    remove_all(&mut lock(&LIVE))
}

/// As [`remove_live`], unless a registry is held (by the calling thread, which may be the one that
/// ran out of memory): then nothing is removed and `None` returned.
pub fn try_remove_live() -> Option<usize> {
    let _commit = try_lock(&COMMITTING)?;
    let mut live = try_lock(&LIVE)?;
    Some(remove_all(&mut live))
}

fn try_lock<T>(m: &'static Mutex<T>) -> Option<MutexGuard<'static, T>> {
    match m.try_lock() {
        Ok(g) => Some(g),
        Err(std::sync::TryLockError::Poisoned(p)) => Some(p.into_inner()),
        Err(std::sync::TryLockError::WouldBlock) => None,
    }
}

fn remove_all(live: &mut Vec<PathBuf>) -> usize {
    let mut removed = 0;
    for path in live.drain(..) {
        let done = match path.symlink_metadata() {
            Ok(m) if m.is_dir() => std::fs::remove_dir_all(&path),
            Ok(_) => std::fs::remove_file(&path),
            Err(e) => Err(e),
        };
        removed += usize::from(done.is_ok());
    }
    removed
}

/// True when the process `pid` that made a temporary modified at `age` ago is gone.
fn abandoned(pid: u32, age: Duration) -> bool {
    if age >= ABANDONED_AFTER {
        return true;
    }
    // Linux: the process table; elsewhere only the age tells
    Path::new("/proc/self").is_dir() && !Path::new(&format!("/proc/{pid}")).exists()
}

/// Removes the abandoned temporaries of the output `target_name` in `dir` (files or whole
/// directories); returns how many were removed. Errors are ignored: a temporary that cannot be
/// removed is only ignored, as every temporary is.
pub fn clean_abandoned(dir: &Path, target_name: &str) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else { return 0 };
    let own = std::process::id();
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some((target, pid)) = name.to_str().and_then(parse) else { continue };
        let Ok(meta) = entry.path().symlink_metadata() else { continue };
        let age = meta.modified().ok().and_then(|m| m.elapsed().ok()).unwrap_or_default();
        if target != target_name || pid == own || !abandoned(pid, age) {
            continue;
        }
        let done = if meta.is_dir() { std::fs::remove_dir_all(entry.path()) } else { std::fs::remove_file(entry.path()) };
        removed += usize::from(done.is_ok());
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_of_temporaries_are_recognised() {
        let (prefix, suffix) = affixes("X.comp");
        let name = format!("{prefix}a1B2c3{suffix}");
        assert_eq!(parse(&name), Some(("X.comp", std::process::id())));
        assert!(is_temporary_name(&name));
        assert_eq!(parse(".my.trueaxis-dir.trueaxis-42-zz.tmp"), Some(("my.trueaxis-dir", 42)));
        assert!(is_temporary_name(".tmpAb12Cd"));
        for other in ["X.comp", ".tmp", ".tmpAb12Cd.svg", "tables.csv.tmp", ".X.comp.trueaxis-x-1.tmp", ".hidden"] {
            assert!(!is_temporary_name(other), "{other}");
        }
    }

    #[test]
    fn only_abandoned_temporaries_of_the_target_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        // a process id that cannot run: above the Linux maximum (2^22)
        let dead = dir.path().join(".out.trueaxis-99999999-abcdef.tmp");
        std::fs::create_dir(&dead).unwrap();
        std::fs::write(dead.join("X.comp"), "x").unwrap();
        let mine = dir.path().join(format!(".out.trueaxis-{}-abcdef.tmp", std::process::id()));
        std::fs::write(&mine, "x").unwrap();
        let other_target = dir.path().join(".other.trueaxis-99999999-abcdef.tmp");
        std::fs::write(&other_target, "x").unwrap();
        let user = dir.path().join(".out.notes");
        std::fs::write(&user, "x").unwrap();
        let expected = if Path::new("/proc/self").is_dir() { 1 } else { 0 };
        assert_eq!(clean_abandoned(dir.path(), "out"), expected);
        assert_eq!(dead.exists(), expected == 0);
        assert!(mine.exists() && other_target.exists() && user.exists());
    }

    #[test]
    fn live_temporaries_are_registered_while_they_exist_and_removed_whole() {
        let dir = tempfile::tempdir().unwrap();
        let (file, folder, settled) = (dir.path().join(".a.tmp"), dir.path().join(".b.tmp"), dir.path().join(".c.tmp"));
        std::fs::write(&file, "x").unwrap();
        std::fs::create_dir(&folder).unwrap();
        std::fs::write(folder.join("X.comp"), "x").unwrap();
        std::fs::write(&settled, "x").unwrap();
        let ours = |p: &&PathBuf| p.starts_with(dir.path());
        let guards = [LiveTemporary::register(&file), LiveTemporary::register(&folder)];
        drop(LiveTemporary::register(&settled));
        let mut registered: Vec<PathBuf> = lock(&LIVE).iter().filter(ours).cloned().collect();
        assert_eq!(registered, [file.clone(), folder.clone()]);
        drop(guards);
        assert!(!lock(&LIVE).iter().any(|p| ours(&p)), "unregistered when dropped");
        // the removal itself, on a registry of its own (the process's serves the other tests)
        assert_eq!(remove_all(&mut registered), 2);
        assert!(!file.exists() && !folder.exists() && settled.exists());
    }

    #[test]
    fn a_day_old_temporary_is_abandoned_whatever_its_process() {
        assert!(abandoned(std::process::id(), ABANDONED_AFTER));
        assert!(!abandoned(std::process::id(), Duration::from_secs(60)));
    }
}
