//! The one way the tests run `trueaxis`: the built binary with arguments, in the repository root
//! (so that `examples/...` resolves) or another directory, with an optional environment and time
//! limit; the result is the process's `Output` (status, stdout, stderr), read
//! with `json`, `ok`, `text` and `refused`.
//!
//! All tests share this process. A test whose assertions depend on having the machine to itself
//! (a time limit on a run, a kill timed into a write phase, a server played in real time) holds
//! `alone()` for its whole length: every other test's run waits for it, as it waited when each
//! test file was a binary of its own run one after another.

use std::cell::Cell;
use std::ffi::OsStr;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::{PoisonError, RwLock, RwLockReadGuard, RwLockWriteGuard};
use std::time::{Duration, Instant};

/// The repository root: the examples, the documentation.
pub const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// The `trueaxis` binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_trueaxis");

/// `ROOT` as a path.
pub fn root() -> PathBuf {
    Path::new(ROOT).to_path_buf()
}

/// The file `path` of the repository (`examples/...`) read whole.
pub fn read(path: &str) -> String {
    std::fs::read_to_string(Path::new(ROOT).join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Shared by every run, taken whole by `alone()`.
static MACHINE: RwLock<()> = RwLock::new(());

thread_local! {
    /// Whether this test's thread holds `alone()` (its own runs then take no shared guard).
    static ALONE: Cell<bool> = const { Cell::new(false) };
}

/// The machine to one test: no other test's `trueaxis` runs until it is dropped.
pub struct Alone(#[allow(dead_code)] RwLockWriteGuard<'static, ()>);

impl Drop for Alone {
    fn drop(&mut self) {
        ALONE.set(false);
    }
}

/// The machine to this test alone, for as long as the guard lives.
pub fn alone() -> Alone {
    let guard = MACHINE.write().unwrap_or_else(PoisonError::into_inner);
    ALONE.set(true);
    Alone(guard)
}

/// The shared guard a run holds (none inside a test that holds `alone()`).
fn shared() -> Option<RwLockReadGuard<'static, ()>> {
    (!ALONE.get()).then(|| MACHINE.read().unwrap_or_else(PoisonError::into_inner))
}

/// One run of `trueaxis`, built up and then `output()` (or `spawn()`ed).
pub struct Run {
    command: Command,
    limit: Option<Duration>,
}

impl Run {
    /// `trueaxis ARGS` in the repository root.
    pub fn new<S: AsRef<OsStr>>(args: impl IntoIterator<Item = S>) -> Run {
        let mut command = Command::new(BIN);
        command.args(args).current_dir(ROOT);
        Run { command, limit: None }
    }

    /// Run in `dir` instead.
    pub fn dir(mut self, dir: impl AsRef<Path>) -> Run {
        self.command.current_dir(dir);
        self
    }

    /// With `key=value` in the environment of the run (never of this process).
    pub fn env(mut self, key: &str, value: impl AsRef<OsStr>) -> Run {
        self.command.env(key, value);
        self
    }

    /// Ended (and the test failed) when it runs longer than `limit`.
    pub fn limit(mut self, limit: Duration) -> Run {
        self.limit = Some(limit);
        self
    }

    /// The command as built, for a test that spawns and signals it itself.
    pub fn command(self) -> Command {
        self.command
    }

    /// Runs to the end: status, stdout, stderr.
    pub fn output(mut self) -> Output {
        let _shared = shared();
        let Some(limit) = self.limit else {
            return self.command.output().unwrap_or_else(|e| panic!("{BIN}: {e}"));
        };
        let child = self.command.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
        finish(child, limit)
    }
}

/// Drains the output of `child` and waits for it, at most `limit`.
fn finish(mut child: Child, limit: Duration) -> Output {
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            pipe.read_to_end(&mut bytes).ok();
            bytes
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            panic!("{BIN} ran longer than {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    Output { status, stdout: stdout.join().unwrap(), stderr: stderr.join().unwrap() }
}

/// `trueaxis ARGS` run in the repository root.
pub fn trueaxis(args: &[&str]) -> Output {
    Run::new(args).output()
}

/// `trueaxis ARGS` run in `dir`.
pub fn trueaxis_in(dir: &Path, args: &[&str]) -> Output {
    Run::new(args).dir(dir).output()
}

/// The bytes of a run's output as text (invalid UTF-8 replaced).
pub fn utf8(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A successful run.
pub fn ok(out: &Output) {
    assert!(out.status.success(), "{}", utf8(&out.stderr));
}

/// The JSON document of a successful run.
pub fn json(out: &Output) -> serde_json::Value {
    ok(out);
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The JSON document of `trueaxis ARGS` in the repository root, which must succeed.
pub fn json_of(args: &[&str]) -> serde_json::Value {
    let out = trueaxis(args);
    assert!(out.status.success(), "{args:?}: {}", utf8(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

/// A run that ended with exit status `code` and a message holding every one of `fragments`; the
/// message.
pub fn failed(out: &Output, code: i32, fragments: &[&str]) -> String {
    let err = utf8(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{err}");
    for f in fragments {
        assert!(err.contains(f), "`{f}` not in: {err}");
    }
    err
}

/// A run refused with exit status `code` and a one-line message holding every one of `fragments`;
/// the message.
pub fn refused(out: &Output, code: i32, fragments: &[&str]) -> String {
    let err = failed(out, code, fragments);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    err
}

/// `trueaxis ARGS` run in the repository root: exit status, stdout and stderr (UTF-8).
pub fn outcome(args: &[&str]) -> (i32, String, String) {
    let out = trueaxis(args);
    (out.status.code().unwrap(), String::from_utf8(out.stdout).unwrap(), String::from_utf8(out.stderr).unwrap())
}
