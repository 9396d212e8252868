//! The inputs of an error model (temperatures `T:`, spindle speeds `S:`, loads `F:`, positions
//! `P:`; `trueaxis::error_model::inputs`) given on the command line as `NAME=VALUE` options, for every
//! row of a pose file that has no column of that name; shared by `predict`, `compensate`, `nc`,
//! `verify` and `thermal beam`. Temperatures of the sensors in degC.

use crate::Failure;
use trueaxis::compensate::sensor_index;
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

/// Sensor temperatures from `T:name=value` options, in the model's order (20 degC when not given).
pub fn temperatures(errors: &ErrorModel, given: &[String]) -> Result<Vec<f64>, Failure> {
    Ok(given_temperatures(errors, given)?.into_iter().zip(errors.input_references()).map(|(t, r)| t.unwrap_or(*r)).collect())
}

/// Sensor temperatures from `T:name=value` options, in the model's order (`None`: not given).
pub fn given_temperatures(errors: &ErrorModel, given: &[String]) -> Result<Vec<Option<f64>>, Failure> {
    let mut values = vec![None; errors.sensors().len()];
    for g in given {
        let (name, value) = g.rsplit_once('=').ok_or_else(|| Failure::input(anyhow::anyhow!("--temperature `{g}` is not T:name=degC")))?;
        let i = sensor_index(errors, name).map_err(Failure::of)?;
        values[i] = Some(
            value
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| Failure::input(anyhow::anyhow!("--temperature `{g}`: not a number")))?,
        );
    }
    Ok(values)
}
