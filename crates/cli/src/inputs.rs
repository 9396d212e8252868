//! The inputs of an error model (temperatures `T:`, spindle speeds `S:`, loads `F:`, positions
//! `P:`; `trueaxis::error_model::inputs`) given on the command line as `NAME=VALUE` options, for every
//! row of a pose file that has no column of that name; shared by `predict`, `compensate` and `verify`.

use crate::Failure;
use trueaxis::error_model::ErrorModel;

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
