//! The outside tools the tests run what trueaxis writes through (docs/design.md, Validation): whether
//! CI requires one (TRUEAXIS_REQUIRE_*; elsewhere a test without its tool is skipped with a reason),
//! and LinuxCNC's halcompile and halrun: found, a directory its realtime user may write in, a
//! component installed. Also included by path by `crates/cli/tests/it/live/mod.rs`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Whether a test that needs a tool must run (CI sets the variable to 1 once the tool is installed).
pub fn required(variable: &str) -> bool {
    std::env::var(variable).is_ok_and(|v| v == "1")
}

/// Whether halcompile and halrun can be run; when not, the test is skipped with a reason (and fails
/// where CI requires them).
pub fn linuxcnc_found() -> bool {
    let available = Command::new("halcompile").arg("--help").output().is_ok() && Command::new("halrun").arg("-h").output().is_ok();
    if !available {
        assert!(!required("TRUEAXIS_REQUIRE_HALCOMPILE"), "halcompile / halrun are required but not found");
        eprintln!("SKIPPED: halcompile / halrun (Debian linuxcnc-uspace-dev) not installed");
    }
    available
}

/// `dir` writable by everyone: halrun's realtime part runs as another user.
pub fn open_to_all(dir: &Path) {
    let mut perms = std::fs::metadata(dir).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perms, 0o777);
    std::fs::set_permissions(dir, perms).unwrap();
}

/// `halcompile --install FILE` (a `.comp`) in `dir`: `None` when it failed (the test skipped, not
/// being root, unless CI requires it), else where the module was installed if halcompile said so.
pub fn halcompile_install(dir: &Path, file: &str) -> Option<Option<PathBuf>> {
    let build = Command::new("halcompile").arg("--install").arg(file).current_dir(dir).output().unwrap();
    let log = String::from_utf8_lossy(&build.stdout).into_owned() + &String::from_utf8_lossy(&build.stderr);
    if !build.status.success() {
        assert!(!required("TRUEAXIS_REQUIRE_HALCOMPILE"), "halcompile --install {file} failed: {log}");
        eprintln!("SKIPPED: halcompile --install failed (not root?): {log}");
        return None;
    }
    let so = file.replace(".comp", ".so");
    Some(log.lines().find_map(|l| l.strip_prefix(&format!("cp {so} ")).map(|d| Path::new(d.trim()).join(&so))))
}
