//! Temporaries of atomic outputs: their names, and the clean-up of those a killed run left behind.
//!
//! Every output is first written to a temporary next to its final path and then renamed over it
//! (DESIGN.md section 3: never a partially written output). A temporary of the output `NAME` (a file
//! or a directory) in the directory `D` is `D/.NAME.trueaxis-PID-XXXXXX.tmp`: hidden, named after its
//! target and after the process that writes it. A run killed with `kill -9` cannot remove it; the
//! next run writing the same target removes it once it is abandoned: its process no longer runs on
//! this machine (Linux `/proc`), or it is older than [`ABANDONED_AFTER`] (other systems, or a
//! process id that was reused). A temporary of another target, or of a live run, is left alone.

use std::path::Path;
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
    fn a_day_old_temporary_is_abandoned_whatever_its_process() {
        assert!(abandoned(std::process::id(), ABANDONED_AFTER));
        assert!(!abandoned(std::process::id(), Duration::from_secs(60)));
    }
}
