//! Prediction tables (the `predict` contract of docs/design.md, Command line): CSV with the axis columns
//! (mm, deg) followed by `dx dy dz` (um), `drx dry drz` (urad), `dL` (um), or one JSON document
//! `{"frame":..,"machine":..,"poses":[{"X":..,"dx":..,..}, ..],"units":{..}}`. Written whole
//! ([`predictions_csv`], [`predictions_json`]) or block of rows after block of rows
//! ([`PredictionWriter`]: the same bytes, in memory independent of the number of poses). No
//! output holds a number that is not finite.

use crate::data::{push_fixed, DataError};
use crate::machine::Machine;
use crate::model::VolumetricError;
use rayon::prelude::*;
use std::io::Write;

/// Error columns of `trueaxis predict`, with their units.
pub const PREDICTION_COLUMNS: [(&str, &str); 7] =
    [("dx", "um"), ("dy", "um"), ("dz", "um"), ("drx", "urad"), ("dry", "urad"), ("drz", "urad"), ("dL", "um")];

/// The format of a prediction table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PredictionFormat {
    Csv,
    /// The JSON document, naming the frame of the components (`workpiece` or `machine`).
    Json {
        frame: String,
    },
}

/// Index of the first prediction that holds a number that is not finite.
fn first_not_finite(errors: &[VolumetricError]) -> Option<usize> {
    errors.iter().position(|e| e.to_user_units().iter().any(|v| !v.is_finite()))
}

/// One CSV row: positions as given, errors to 0.1 nm / 0.1 nrad.
fn csv_row(out: &mut String, pose: &[f64], error: &VolumetricError) {
    use std::fmt::Write;
    for v in pose {
        let _ = write!(out, "{v},");
    }
    for (k, v) in error.to_user_units().iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        push_fixed(out, *v, 4);
    }
    out.push('\n');
}

/// One JSON pose: positions and errors (rounded to 1e-4) by name.
fn json_row(machine: &Machine, pose: &[f64], error: &VolumetricError) -> serde_json::Value {
    let mut row = serde_json::Map::new();
    for (axis, v) in machine.axes().iter().zip(pose) {
        row.insert(axis.letter.to_string(), (*v).into());
    }
    for ((c, _), v) in PREDICTION_COLUMNS.iter().zip(error.to_user_units()) {
        row.insert((*c).into(), ((v * 1e4).round() / 1e4).into());
    }
    serde_json::Value::Object(row)
}

/// The JSON document without its poses.
fn json_document(machine: &Machine, frame: &str, poses: Vec<serde_json::Value>) -> serde_json::Value {
    let mut units = serde_json::Map::new();
    for axis in machine.axes() {
        units.insert(axis.letter.to_string(), axis.position_unit().into());
    }
    for (c, u) in PREDICTION_COLUMNS {
        units.insert(c.into(), u.into());
    }
    serde_json::json!({ "machine": machine.name, "frame": frame, "units": units, "poses": poses })
}

/// A prediction table written block of rows after block of rows.
pub struct PredictionWriter<'a> {
    machine: &'a Machine,
    format: PredictionFormat,
    /// The JSON document after its poses.
    tail: String,
    rows: usize,
    /// The output's name in messages.
    name: String,
    out: &'a mut dyn Write,
}

/// Rows formatted per task when a block is formatted in parallel.
const ROWS_PER_TASK: usize = 4096;

impl<'a> PredictionWriter<'a> {
    /// Writes the head of the table (the CSV header, or the JSON document up to its poses) to
    /// `out`, named `name` in messages.
    pub fn begin(
        machine: &'a Machine,
        format: PredictionFormat,
        out: &'a mut dyn Write,
        name: &str,
    ) -> Result<PredictionWriter<'a>, DataError> {
        let write_error = |source| DataError::Write { path: name.to_string(), source };
        let tail = match &format {
            PredictionFormat::Csv => {
                let header: Vec<String> = machine
                    .axes()
                    .iter()
                    .map(|a| a.letter.to_string())
                    .chain(PREDICTION_COLUMNS.iter().map(|(c, _)| c.to_string()))
                    .collect();
                writeln!(out, "{}", header.join(",")).map_err(write_error)?;
                String::new()
            }
            PredictionFormat::Json { frame } => {
                // the document's own key order, split where its poses go
                let empty = json_document(machine, frame, Vec::new()).to_string();
                let at = empty.find("\"poses\":[]").expect("the poses key") + "\"poses\":[".len();
                out.write_all(&empty.as_bytes()[..at]).map_err(write_error)?;
                format!("{}\n", &empty[at..])
            }
        };
        Ok(PredictionWriter { machine, format, tail, rows: 0, name: name.to_string(), out })
    }

    /// Writes the rows of `poses_user` (`axis_count` positions per pose, mm and deg) and their
    /// predictions. A prediction that is not a finite number is refused, naming its place by
    /// `place(index in this block)`, before anything of the block is written.
    pub fn write(&mut self, poses_user: &[f64], errors: &[VolumetricError], place: &dyn Fn(usize) -> String) -> Result<(), DataError> {
        if let Some(i) = first_not_finite(errors) {
            return Err(DataError::NotFinite { message: format!("the prediction of {} is not a finite number", place(i)) });
        }
        let n = self.machine.axis_count().max(1);
        let machine = self.machine;
        let format = &self.format;
        let first = self.rows == 0;
        let texts: Vec<String> = poses_user
            .par_chunks(n * ROWS_PER_TASK)
            .zip(errors.par_chunks(ROWS_PER_TASK))
            .enumerate()
            .map(|(task, (poses, errors))| {
                let mut text = String::with_capacity(errors.len() * 96);
                for (k, (pose, error)) in poses.chunks(n).zip(errors).enumerate() {
                    match format {
                        PredictionFormat::Csv => csv_row(&mut text, pose, error),
                        PredictionFormat::Json { .. } => {
                            if !(first && task == 0 && k == 0) {
                                text.push(',');
                            }
                            text.push_str(&json_row(machine, pose, error).to_string());
                        }
                    }
                }
                text
            })
            .collect();
        let write_error = |source| DataError::Write { path: self.name.clone(), source };
        for t in texts {
            self.out.write_all(t.as_bytes()).map_err(write_error)?;
        }
        self.rows += errors.len();
        Ok(())
    }

    /// Ends the table (the JSON document's tail); returns the number of rows written.
    pub fn finish(self) -> Result<usize, DataError> {
        self.out.write_all(self.tail.as_bytes()).map_err(|source| DataError::Write { path: self.name.clone(), source })?;
        Ok(self.rows)
    }
}

/// The CSV table of `predictions` at `poses_user` (`axis_count` per pose), whole.
pub fn predictions_csv(machine: &Machine, poses_user: &[f64], errors: &[VolumetricError]) -> Result<String, DataError> {
    let mut bytes = Vec::new();
    let mut writer = PredictionWriter::begin(machine, PredictionFormat::Csv, &mut bytes, "the prediction table")?;
    writer.write(poses_user, errors, &|i| format!("pose {}", i + 1))?;
    writer.finish()?;
    Ok(String::from_utf8(bytes).expect("formatted numbers"))
}

/// The JSON document `{"frame":..,"machine":..,"poses":[{"X":..,"dx":..,..}, ..],"units":{..}}`.
pub fn predictions_json(
    machine: &Machine,
    poses_user: &[f64],
    errors: &[VolumetricError],
    frame: &str,
) -> Result<serde_json::Value, DataError> {
    if let Some(i) = first_not_finite(errors) {
        return Err(DataError::NotFinite { message: format!("the prediction of pose {} is not a finite number", i + 1) });
    }
    let n = machine.axis_count().max(1);
    let poses = poses_user.chunks(n).zip(errors).map(|(pose, error)| json_row(machine, pose, error)).collect();
    Ok(json_document(machine, frame, poses))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_point_text_equals_the_standard_formatting() {
        let mut rng = 0x2545f4914f6cdd1du64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            rng
        };
        let mut values: Vec<f64> =
            vec![0.0, -0.0, 0.5, 1.5, 2.5, -2.5, 0.00005, -0.00005, 0.00015, 1e-320, -1e-9, 99999.99995, 1e12, -3e15, 5.2001];
        for _ in 0..200_000 {
            let mantissa = (next() % 2_000_000_001) as f64 / 1e3 - 1e6;
            values.push(mantissa * [1.0, 1e-3, 1e-6, 0.5, 1e3][(next() % 5) as usize]);
            // exact halves at every scale of interest
            values.push((next() % 100_000) as f64 / 2e4 * if next() % 2 == 0 { 1.0 } else { -1.0 });
        }
        for v in values {
            for decimals in [0, 3, 4, 6] {
                let mut fast = String::new();
                push_fixed(&mut fast, v, decimals);
                assert_eq!(fast, format!("{v:.decimals$}"), "{v:e} to {decimals} decimals");
            }
        }
    }

    #[test]
    fn streamed_tables_equal_whole_ones_byte_for_byte() {
        let machine = Machine::from_toml_str(
            "name = \"m\"\nstructure = \"wXbYt\"\n[axes]\nX = { kind = \"linear\", direction = [1, 0, 0], range = [-1e4, 1e4] }\n\
             Y = { kind = \"linear\", direction = [0, 1, 0], range = [-1e4, 1e4] }\n[tool]\npoint = [0, 0, 0]\n",
            "m.toml",
        )
        .unwrap();
        let count = 2 * ROWS_PER_TASK + 17;
        let poses: Vec<f64> = (0..2 * count).map(|k| k as f64 * 0.25 - 100.0).collect();
        let errors: Vec<VolumetricError> = (0..count)
            .map(|k| {
                let mut e = VolumetricError::default();
                e.position[0] = k as f64 * 1e-7;
                e.orientation[2] = -(k as f64) * 3e-9;
                e
            })
            .collect();
        let whole_json = format!("{}\n", predictions_json(&machine, &poses, &errors, "machine").unwrap());
        for (format, whole) in [
            (PredictionFormat::Csv, predictions_csv(&machine, &poses, &errors).unwrap()),
            (PredictionFormat::Json { frame: "machine".into() }, whole_json),
        ] {
            let mut bytes = Vec::new();
            let mut w = PredictionWriter::begin(&machine, format.clone(), &mut bytes, "p.csv").unwrap();
            // blocks of uneven sizes
            for (start, end) in [(0, 1), (1, 5000), (5000, count)] {
                w.write(&poses[2 * start..2 * end], &errors[start..end], &|i| format!("row {i}")).unwrap();
            }
            assert_eq!(w.finish().unwrap(), count);
            assert_eq!(String::from_utf8(bytes).unwrap(), whole, "{format:?}");
        }
        let mut bad = errors.clone();
        bad[3].position[1] = f64::NAN;
        let e = predictions_csv(&machine, &poses, &bad).unwrap_err().to_string();
        assert_eq!(e, "the prediction of pose 4 is not a finite number");
    }
}
