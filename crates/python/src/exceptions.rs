//! trueaxis errors as Python exceptions: `TrueaxisError`, with `InputError` for bad input (the
//! command line's exit status 2), `ComputationError` for a failed computation (exit status 1) and
//! `ResourceError` for the environment (a full disk, a permission, memory: exit status 3). The kind
//! is decided here ([`input`], [`computation`]): an error whose chain holds a system error of the
//! environment (`trueaxis::files::environment_cause`) is a `ResourceError` whichever the caller
//! said, as the command line decides in one place (`exit.rs`). The message is the command line's,
//! without its `trueaxis: error: ` prefix. Warnings and notes the command line prints on stderr are
//! `TrueaxisWarning`s.

use pyo3::create_exception;
use pyo3::PyErr;

create_exception!(
    trueaxis,
    TrueaxisError,
    pyo3::exceptions::PyException,
    "An error of trueaxis (the base of InputError and ComputationError)."
);
create_exception!(trueaxis, InputError, TrueaxisError, "Bad input: a file, a parameter or a value (the command line's exit status 2).");
create_exception!(trueaxis, ComputationError, TrueaxisError, "A failed computation, e.g. a rank-deficient identification (exit status 1).");
create_exception!(
    trueaxis,
    ResourceError,
    TrueaxisError,
    "The environment failed, not the input: a full disk or quota, a permission, a read-only file system, a device error, memory (the command line's exit status 3)."
);
create_exception!(
    trueaxis,
    TrueaxisWarning,
    pyo3::exceptions::PyUserWarning,
    "A warning or note of trueaxis (what the command line prints on stderr: plausibility findings, corrections applied)."
);

/// Issues each message as a `TrueaxisWarning` (Python's `warnings` module), where the command line
/// prints `trueaxis: warning: ...` or a note on stderr.
pub fn warn(py: pyo3::Python<'_>, messages: &[String]) -> pyo3::PyResult<()> {
    use pyo3::types::PyAnyMethods;
    let warnings = py.import("warnings")?;
    for m in messages {
        warnings.call_method1("warn", (m.as_str(), py.get_type::<TrueaxisWarning>(), 2))?;
    }
    Ok(())
}

/// `text` with every number of more than 12 characters (e.g. a position of 1e300 printed in full,
/// 301 digits) written with 7 significant digits in scientific notation (`1e300`,
/// `1.234568e-17`), so that a message stays one readable line.
pub fn short(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        out.push_str(&rest[..start]);
        let end = rest[start..].find(|c: char| !(c.is_ascii_digit() || c == '.')).map_or(rest.len(), |e| start + e);
        let token = &rest[start..end];
        match token.parse::<f64>() {
            Ok(v) if token.len() > 12 && v.is_finite() => out.push_str(&scientific(v)),
            _ => out.push_str(token),
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// `v` with 7 significant digits in scientific notation, trailing zeros of the mantissa dropped.
fn scientific(v: f64) -> String {
    let text = format!("{v:.6e}");
    match text.split_once('e') {
        Some((mantissa, exponent)) if mantissa.contains('.') => {
            format!("{}e{exponent}", mantissa.trim_end_matches('0').trim_end_matches('.'))
        }
        _ => text,
    }
}

/// The one-line message of an error as the command line prints it: its text followed by each
/// cause that the text does not already contain.
pub fn message(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut cause = error.source();
    while let Some(c) = cause {
        let t = c.to_string();
        if !text.contains(&t) {
            text.push_str(": ");
            text.push_str(&t);
        }
        cause = c.source();
    }
    short(&text)
}

/// The exception of a library error, by its kind (`trueaxis::ErrorKind`; the environment also when
/// its chain says so): the one place where the kinds of the core become exceptions.
pub fn of(error: impl Into<trueaxis::Error>) -> PyErr {
    let error = error.into();
    if error.is_environment() {
        return ResourceError::new_err(message(&error));
    }
    match error.kind() {
        trueaxis::ErrorKind::Input => InputError::new_err(message(&error)),
        trueaxis::ErrorKind::Computation => ComputationError::new_err(message(&error)),
        trueaxis::ErrorKind::Environment => ResourceError::new_err(message(&error)),
    }
}

/// Bad input from a library error (or the environment, when its chain says so).
pub fn input(error: impl std::error::Error + 'static) -> PyErr {
    match trueaxis::files::environment_cause(&error) {
        Some(_) => ResourceError::new_err(message(&error)),
        None => InputError::new_err(message(&error)),
    }
}

/// Bad input from a message.
pub fn input_msg(text: impl Into<String>) -> PyErr {
    InputError::new_err(short(&text.into()))
}

/// A failed computation from a library error (or the environment, when its chain says so).
pub fn computation(error: impl std::error::Error + 'static) -> PyErr {
    match trueaxis::files::environment_cause(&error) {
        Some(_) => ResourceError::new_err(message(&error)),
        None => ComputationError::new_err(message(&error)),
    }
}

/// A failed computation from a message.
pub fn computation_msg(text: impl Into<String>) -> PyErr {
    ComputationError::new_err(short(&text.into()))
}
