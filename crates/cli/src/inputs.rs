//! The inputs of an error model (temperatures `T:`, spindle speeds `S:`, loads `F:`, positions
//! `P:` and the lagged sensor rises of drift models; `trueaxis::errors::inputs`) for the rows of a
//! pose file: its columns, else `NAME=VALUE` options; shared by `predict`, `compensate` and `verify`.

use crate::Failure;
use std::path::Path;
use trueaxis::errors::{pose_file_inputs, ErrorModel};

/// `NAME=VALUE` options (`--input`, `--temperature`) as `(name, value)`; an error names the option.
pub fn parse_given(given: &[String], option: &str) -> Result<Vec<(String, f64)>, Failure> {
    given
        .iter()
        .map(|g| {
            let (name, value) = g
                .rsplit_once('=')
                .ok_or_else(|| Failure::input(anyhow::anyhow!("{option} `{g}` is not NAME=VALUE (e.g. T:spindle=24.5)")))?;
            let value: f64 = value
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| Failure::input(anyhow::anyhow!("{option} `{g}`: `{}` is not a number", value.trim())))?;
            Ok((name.trim().to_string(), value))
        })
        .collect()
}

/// The values of the inputs of `errors` for every row of the pose file `path` (`rows` rows):
/// columns named like the inputs, else `given`; the drift lags from the columns `t` (s) and `run`.
pub fn pose_inputs(errors: &ErrorModel, path: &Path, rows: usize, given: &[(String, f64)]) -> Result<Vec<f64>, Failure> {
    pose_file_inputs(errors, path, rows, given).map_err(|m| Failure::input(anyhow::anyhow!("{m}")))
}

/// The inputs of `errors` for one state from `given` (`NAME=VALUE`), every other input at its
/// reference (20 degC, 0 rpm, 0 N, ...); an error names a given input the model does not have.
pub fn state_inputs(errors: &ErrorModel, given: &[(String, f64)], option: &str) -> Result<Vec<f64>, Failure> {
    let mut values = errors.input_references().to_vec();
    for (name, v) in given {
        let i = errors.sensors().iter().position(|s| s == name).ok_or_else(|| {
            Failure::input(anyhow::anyhow!(
                "{option}: the error model has no input `{name}` (inputs: {})",
                if errors.sensors().is_empty() { "none".to_string() } else { errors.sensors().join(", ") }
            ))
        })?;
        values[i] = *v;
    }
    Ok(values)
}
