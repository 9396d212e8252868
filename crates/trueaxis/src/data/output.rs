//! Prediction tables (the `predict` contract of DESIGN.md section 4).

use super::DataError;
use crate::machine::Machine;
use crate::model::VolumetricError;

/// Error columns of `trueaxis predict`, with their units.
pub const PREDICTION_COLUMNS: [(&str, &str); 7] =
    [("dx", "um"), ("dy", "um"), ("dz", "um"), ("drx", "urad"), ("dry", "urad"), ("drz", "urad"), ("dL", "um")];

fn check_finite(errors: &[VolumetricError]) -> Result<(), DataError> {
    match errors.iter().position(|e| e.to_user_units().iter().any(|v| !v.is_finite())) {
        Some(i) => Err(DataError::NotFinite { message: format!("the prediction of pose {} is not a finite number", i + 1) }),
        None => Ok(()),
    }
}

/// CSV with the axis columns (mm, deg) followed by `dx dy dz` (um), `drx dry drz` (urad), `dL` (um).
pub fn predictions_csv(machine: &Machine, poses_user: &[f64], errors: &[VolumetricError]) -> Result<String, DataError> {
    check_finite(errors)?;
    let n = machine.axis_count().max(1);
    let mut out = String::new();
    let header: Vec<String> =
        machine.axes().iter().map(|a| a.letter.to_string()).chain(PREDICTION_COLUMNS.iter().map(|(c, _)| c.to_string())).collect();
    out.push_str(&header.join(","));
    out.push('\n');
    for (pose, error) in poses_user.chunks(n).zip(errors) {
        let fields: Vec<String> =
            pose.iter().map(|v| format!("{v}")).chain(error.to_user_units().iter().map(|v| format!("{v:.4}"))).collect();
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    Ok(out)
}

/// JSON document `{"frame":..,"units":{..},"poses":[{"X":..,"dx":..,..}, ..]}`.
pub fn predictions_json(
    machine: &Machine,
    poses_user: &[f64],
    errors: &[VolumetricError],
    frame: &str,
) -> Result<serde_json::Value, DataError> {
    check_finite(errors)?;
    let n = machine.axis_count().max(1);
    let mut units = serde_json::Map::new();
    for axis in machine.axes() {
        units.insert(axis.letter.to_string(), axis.position_unit().into());
    }
    for (c, u) in PREDICTION_COLUMNS {
        units.insert(c.into(), u.into());
    }
    let poses: Vec<serde_json::Value> = poses_user
        .chunks(n)
        .zip(errors)
        .map(|(pose, error)| {
            let mut row = serde_json::Map::new();
            for (axis, v) in machine.axes().iter().zip(pose) {
                row.insert(axis.letter.to_string(), (*v).into());
            }
            for ((c, _), v) in PREDICTION_COLUMNS.iter().zip(error.to_user_units()) {
                row.insert((*c).into(), ((v * 1e4).round() / 1e4).into());
            }
            serde_json::Value::Object(row)
        })
        .collect();
    Ok(serde_json::json!({ "machine": machine.name, "frame": frame, "units": units, "poses": poses }))
}
