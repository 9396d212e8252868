//! Reliability round two (docs/reliability.md): each defect the attacks beyond the bad-input suite
//! found is a test here. Outputs (`outputs`): devices, FIFOs and links to them written in place,
//! `-` and `/dev/stdout`, an output that is an input refused for every command, a file this user
//! may not write, several runs making one directory, a full disk and a read-only file system with
//! exit status 3. Signals (`signals`): SIGINT, SIGTERM, SIGHUP remove the run's temporaries.
//! Memory (`memory`): predict and compensate --poses under `ulimit -v` on an input ten times the
//! limit, and an allocation that cannot be met reported. Inputs (`inputs`): pose columns of axes
//! the machine lacks, parallel linear axes, unbounded limits, numbers that underflow to zero,
//! table positions out of range. Cases that need root (mknod, mount, another user) print why they
//! are skipped when it is missing; CI runs as root.

mod bad_input;
mod crash_safety;
mod determinism;
mod inputs;
mod memory;
mod outputs;
mod signals;

use crate::support::Run;
pub use crate::support::ROOT;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn example(path: &str) -> PathBuf {
    Path::new(ROOT).join(path)
}

/// `trueaxis` with `args`, run in the repository.
pub fn trueaxis(args: &[&str]) -> Command {
    Run::new(args).command()
}

/// Runs `args`; (exit status, stdout, stderr).
pub fn run(args: &[&str]) -> (Option<i32>, Vec<u8>, String) {
    let Output { status, stdout, stderr } = Run::new(args).output();
    (status.code(), stdout, String::from_utf8_lossy(&stderr).into_owned())
}

/// Whether the tests run as root (mknod, mount, other users).
pub fn is_root() -> bool {
    Command::new("id").arg("-u").output().is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// The names in `dir`, sorted.
pub fn names(dir: &Path) -> Vec<String> {
    let mut n: Vec<String> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    n.sort();
    n
}

/// A tmpfs mounted at `dir` with `options` (root only), unmounted when dropped; `None`, with the
/// reason printed, where the system refuses (a container without CAP_SYS_ADMIN).
pub struct Mount(PathBuf);

impl Mount {
    pub fn tmpfs(dir: &Path, options: &str) -> Option<Mount> {
        std::fs::create_dir_all(dir).unwrap();
        let o = Command::new("mount").args(["-t", "tmpfs", "-o", options, "tmpfs"]).arg(dir).output().ok()?;
        if !o.status.success() {
            println!("skipped: mount -t tmpfs -o {options} failed: {}", String::from_utf8_lossy(&o.stderr).trim());
            return None;
        }
        Some(Mount(dir.to_path_buf()))
    }
}

impl Drop for Mount {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

/// A character device node `major:minor` made at `path` (root only); false, with the reason
/// printed, where the system refuses (a container without CAP_MKNOD).
pub fn make_device(path: &Path, major: u32, minor: u32) -> bool {
    let o = Command::new("mknod").arg(path).args(["c", &major.to_string(), &minor.to_string()]).output().unwrap();
    if !o.status.success() {
        println!("skipped: mknod {} c {major} {minor} failed: {}", path.display(), String::from_utf8_lossy(&o.stderr).trim());
    }
    o.status.success()
}

/// A full device (every write fails with ENOSPC): as root a private node in `dir` (mknod c 1 7),
/// so that a regression could never replace the system's /dev/full; else /dev/full itself.
pub fn full_device(dir: &Path) -> PathBuf {
    let device = dir.join("full-device");
    if is_root() && make_device(&device, 1, 7) {
        device
    } else {
        // a user may not replace /dev/full; root uses it only where it may not make a node
        PathBuf::from("/dev/full")
    }
}

/// `compensate` of the vmc3 example into CSV files, with `extra` options.
pub fn vmc3_compensate<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let base = ["compensate", "--machine", "examples/machines/vmc3.toml", "--errors", "examples/errors/vmc3.toml", "--format", "csv"];
    [&base[..], extra].concat()
}

/// vmc3 files copied into `dir`: m.toml, e.toml, p.csv.
pub fn vmc3_in(dir: &Path) {
    std::fs::copy(example("examples/machines/vmc3.toml"), dir.join("m.toml")).unwrap();
    std::fs::copy(example("examples/errors/vmc3.toml"), dir.join("e.toml")).unwrap();
    std::fs::copy(example("examples/poses/vmc3.csv"), dir.join("p.csv")).unwrap();
}
