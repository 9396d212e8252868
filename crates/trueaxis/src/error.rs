//! The error vocabulary of the core (docs/design.md, Errors): every failure the library reports is
//! an [`Error`] with a kind (bad input, a failed computation, the environment), the origin (a file
//! with its line and column, or a parameter) and the one-line message a user reads. The library
//! never decides what a kind means to a program: the command line decides what each kind means to a shell in
//! `crates/cli/src/exit.rs`, the Python package to exceptions in `crates/python/src/exceptions.rs`.
//!
//! Modules whose callers match on what went wrong keep an error of their own that carries typed
//! data (as `machine::MachineError`, `data::DataError`, `error_model::ErrorModelError`); each
//! converts into an [`Error`] with its kind, so that a caller that only reports can use `?`.
//!
//! ```
//! use trueaxis::error::{Error, ErrorKind};
//! let e = Error::input("the range is empty").in_file("vmc3.toml").at_line(12);
//! assert_eq!(e.kind(), ErrorKind::Input);
//! assert_eq!(e.to_string(), "vmc3.toml: line 12: the range is empty");
//! ```

use std::fmt;

/// What kind of failure an [`Error`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// Bad input: a file, a line, a key, a column, a parameter or an option (the message names it).
    Input,
    /// A computation that failed on valid input: a rank-deficient identification, a correction
    /// that does not converge, a singular matrix.
    Computation,
    /// The environment, not the input: a full disk, a permission, memory, a device.
    Environment,
}

/// Where an [`Error`] came from, printed before its message.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Origin {
    /// Not stated apart from the message (which may name it itself).
    #[default]
    Unstated,
    /// A file (as the user named it), with the line and column counted from 1 where known.
    File { path: String, line: Option<usize>, column: Option<usize> },
    /// A parameter or option, by its name (an ISO 230-1 name, a TOML key, a command-line option).
    Parameter(String),
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Origin::Unstated => Ok(()),
            Origin::File { path, line, column } => {
                write!(f, "{path}")?;
                if let Some(line) = line {
                    write!(f, ": line {line}")?;
                }
                if let Some(column) = column {
                    write!(f, ", column {column}")?;
                }
                Ok(())
            }
            Origin::Parameter(name) => write!(f, "{name}"),
        }
    }
}

/// A failure of the library: kind, origin, message and the error that caused it, if any.
#[derive(Debug)]
pub struct Error {
    kind: ErrorKind,
    /// Boxed, so that an `Error` stays small in every `Result` that carries it.
    origin: Box<Origin>,
    message: String,
    source: Option<Box<dyn std::error::Error + Send + Sync + 'static>>,
}

/// The result of the library's functions.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An error of `kind` with `message` and no origin apart from it.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error { kind, origin: Box::new(Origin::Unstated), message: message.into(), source: None }
    }
    /// Bad input.
    pub fn input(message: impl Into<String>) -> Error {
        Error::new(ErrorKind::Input, message)
    }
    /// A failed computation.
    pub fn computation(message: impl Into<String>) -> Error {
        Error::new(ErrorKind::Computation, message)
    }
    /// The environment.
    pub fn environment(message: impl Into<String>) -> Error {
        Error::new(ErrorKind::Environment, message)
    }

    /// The same error, from the file `path`.
    pub fn in_file(mut self, path: impl Into<String>) -> Error {
        let (line, column) = match *self.origin {
            Origin::File { line, column, .. } => (line, column),
            _ => (None, None),
        };
        *self.origin = Origin::File { path: path.into(), line, column };
        self
    }
    /// The same error, at `line` (from 1) of its file.
    pub fn at_line(mut self, line: usize) -> Error {
        match &mut *self.origin {
            Origin::File { line: l, .. } => *l = Some(line),
            other => *other = Origin::File { path: String::new(), line: Some(line), column: None },
        }
        self
    }
    /// The same error, at `column` (from 1) of its line.
    pub fn at_column(mut self, column: usize) -> Error {
        match &mut *self.origin {
            Origin::File { column: c, .. } => *c = Some(column),
            other => *other = Origin::File { path: String::new(), line: None, column: Some(column) },
        }
        self
    }
    /// The same error, of the parameter or option `name`.
    pub fn for_parameter(mut self, name: impl Into<String>) -> Error {
        *self.origin = Origin::Parameter(name.into());
        self
    }
    /// The same error, with `context` (where in the input it arose: a key, a pose, a row) before
    /// its message: `parse(name).map_err(|e| e.context("exclude").in_file(path))` reads
    /// `budget.toml: exclude: ...`.
    pub fn context(mut self, context: impl fmt::Display) -> Error {
        self.message = format!("{context}: {}", self.message);
        self
    }
    /// The same error, caused by `source` (kept in the chain, e.g. for the environment test of
    /// `files::environment_cause`).
    pub fn caused_by(mut self, source: impl std::error::Error + Send + Sync + 'static) -> Error {
        self.source = Some(Box::new(source));
        self
    }

    pub fn kind(&self) -> ErrorKind {
        self.kind
    }
    pub fn origin(&self) -> &Origin {
        &self.origin
    }
    /// The message without its origin.
    pub fn message(&self) -> &str {
        &self.message
    }
    /// Whether the environment failed: said so, or a system error of the environment in the chain
    /// (a full disk, a permission, memory), whatever the kind said.
    pub fn is_environment(&self) -> bool {
        self.kind == ErrorKind::Environment || crate::files::environment_cause(self).is_some()
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &*self.origin {
            Origin::Unstated => write!(f, "{}", self.message),
            Origin::File { path, line: None, column: None } if path.is_empty() => write!(f, "{}", self.message),
            Origin::File { path, .. } if path.is_empty() => {
                let origin = self.origin.to_string();
                write!(f, "{}: {}", origin.trim_start_matches(": "), self.message)
            }
            origin => write!(f, "{origin}: {}", self.message),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.source.as_deref().map(|e| e as &(dyn std::error::Error + 'static))
    }
}

impl From<std::io::Error> for Error {
    /// A system error: the environment when it is one (`files::is_environment`), else bad input
    /// (a file that is not there, a name that is a directory).
    fn from(e: std::io::Error) -> Error {
        let kind = if crate::files::is_environment(&e) { ErrorKind::Environment } else { ErrorKind::Input };
        Error::new(kind, e.to_string()).caused_by(e)
    }
}

/// Returns early with an [`Error`] of a kind: `bail!(input, "{name}: no such axis")`,
/// `bail!(computation, "...")`, `bail!(environment, "...")`.
#[macro_export]
macro_rules! bail {
    ($kind:ident, $($message:tt)+) => {
        return ::core::result::Result::Err($crate::error::Error::$kind(format!($($message)+)).into())
    };
}

/// Returns early with an [`Error`] of a kind unless `condition` holds:
/// `ensure!(step > 0.0, input, "the step must be positive, not {step}")`.
#[macro_export]
macro_rules! ensure {
    ($condition:expr, $kind:ident, $($message:tt)+) => {
        let holds: bool = $condition;
        if !holds {
            $crate::bail!($kind, $($message)+);
        }
    };
}

/// `impl From<$error> for Error` for a module error of one kind: the message is the module error's,
/// which stays the cause (so that `Error::is_environment` still finds a full disk behind it):
/// `error_of_kind!(MachineError, Input)`.
macro_rules! error_of_kind {
    ($error:ty, $kind:ident) => {
        impl From<$error> for $crate::Error {
            fn from(e: $error) -> $crate::Error {
                $crate::Error::new($crate::ErrorKind::$kind, e.to_string()).caused_by(e)
            }
        }
    };
}
pub(crate) use error_of_kind;

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(step: f64) -> Result<f64> {
        crate::ensure!(step > 0.0, input, "the step must be positive, not {step}");
        if step > 1e3 {
            crate::bail!(computation, "no convergence after {} iterations", 40);
        }
        Ok(step)
    }

    #[test]
    fn origins_print_before_the_message() {
        let e = Error::computation("singular").for_parameter("EXX");
        assert_eq!(e.to_string(), "EXX: singular");
        assert_eq!(Error::input("bad").at_line(3).to_string(), "line 3: bad");
        let e = Error::input("bad").at_line(3).at_column(7).in_file("p.ngc");
        assert_eq!(e.to_string(), "p.ngc: line 3, column 7: bad");
        assert_eq!(e.origin(), &Origin::File { path: "p.ngc".into(), line: Some(3), column: Some(7) });
        assert_eq!(e.message(), "bad");
        let e = Error::input("bad").context("pose 3").in_file("poses.csv");
        assert_eq!((e.to_string(), e.message()), ("poses.csv: pose 3: bad".to_string(), "pose 3: bad"));
    }

    #[test]
    fn macros_return_the_kind() {
        assert_eq!(parse(1.0).unwrap(), 1.0);
        let e = parse(-1.0).unwrap_err();
        assert_eq!((e.kind(), e.to_string()), (ErrorKind::Input, "the step must be positive, not -1".to_string()));
        assert_eq!(parse(1e4).unwrap_err().kind(), ErrorKind::Computation);
    }

    #[test]
    fn a_full_disk_is_the_environment_whatever_the_kind() {
        let full = std::io::Error::from_raw_os_error(28); // ENOSPC
        let e = Error::input("out.csv: cannot write").caused_by(full);
        assert_eq!(e.kind(), ErrorKind::Input);
        assert!(e.is_environment());
        assert_eq!(Error::from(std::io::Error::from_raw_os_error(28)).kind(), ErrorKind::Environment);
        assert_eq!(Error::from(std::io::Error::from(std::io::ErrorKind::NotFound)).kind(), ErrorKind::Input);
    }
}
