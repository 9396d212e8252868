//! Exit status of `trueaxis`, decided here and nowhere else (docs/reliability.md):
//!
//! | status | meaning |
//! |---|---|
//! | 0 | success |
//! | 1 | a failed computation (an unidentifiable parameter set, a correction that does not converge) |
//! | 2 | bad input: a file, a line, a parameter or an option (the message names it) |
//! | 3 | the environment: a full disk or quota, a permission, a read-only file system, a device error, memory that cannot be had, an interruption (SIGINT, SIGTERM, SIGHUP) |
//!
//! A command says whether it failed on its input or in its computation ([`Failure`]); an error
//! whose chain holds a system error of the environment (`trueaxis::files::is_environment`) is
//! status 3 whichever it said, so that a script can tell "fix the input" from "fix the machine it
//! runs on". Signals and memory exhaustion end the process from their own handlers
//! (`signals`, `memory`) with [`ENVIRONMENT`].

use std::process::ExitCode;

/// A failed computation.
pub const COMPUTATION: u8 = 1;
/// Bad input.
pub const INPUT: u8 = 2;
/// The environment: disk, permission, memory, interruption.
pub const ENVIRONMENT: u8 = 3;

/// Why a command failed: bad input, a failed computation, or the environment as the command
/// knows it (a server that cannot be reached, a program that is missing); the environment is also
/// found in the causes of the first two.
pub enum Failure {
    Input(anyhow::Error),
    Computation(anyhow::Error),
    Environment(anyhow::Error),
}

impl Failure {
    pub fn input(e: impl Into<anyhow::Error>) -> Failure {
        Failure::Input(e.into())
    }
    pub fn computation(e: impl Into<anyhow::Error>) -> Failure {
        Failure::Computation(e.into())
    }
    /// The failure of a library error, by its kind (`trueaxis::ErrorKind`): the one place where
    /// the kinds of the core become exit statuses.
    pub fn of(e: impl Into<trueaxis::Error>) -> Failure {
        let e = e.into();
        match e.kind() {
            trueaxis::ErrorKind::Input => Failure::Input(e.into()),
            trueaxis::ErrorKind::Computation => Failure::Computation(e.into()),
            trueaxis::ErrorKind::Environment => Failure::Environment(e.into()),
        }
    }

    /// The exit status (module documentation).
    pub fn status(&self) -> u8 {
        let (error, said) = match self {
            Failure::Input(e) => (e, INPUT),
            Failure::Computation(e) => (e, COMPUTATION),
            Failure::Environment(e) => (e, ENVIRONMENT),
        };
        let error: &(dyn std::error::Error + 'static) = error.as_ref();
        if trueaxis::files::environment_cause(error).is_some() {
            ENVIRONMENT
        } else {
            said
        }
    }

    /// Prints the one-line message on stderr and returns the exit status.
    pub fn report(self) -> ExitCode {
        let status = self.status();
        let (Failure::Input(e) | Failure::Computation(e) | Failure::Environment(e)) = self;
        eprintln!("trueaxis: error: {}", message(&e));
        ExitCode::from(status)
    }
}

/// The one-line message of an error: its own text followed by each cause in its chain that the text
/// does not already contain. Error types that print their cause in their message (`{path}: cannot
/// read: {source}`) and also return it as `source()` would otherwise show it twice, as `{:#}` does.
pub fn message(error: &anyhow::Error) -> String {
    let mut text = error.to_string();
    for cause in error.chain().skip(1) {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            text.push_str(": ");
            text.push_str(&cause);
        }
    }
    text
}
