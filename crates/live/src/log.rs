//! The logs of a live compensation, appended one line per step:
//!
//! - CSV (`--log FILE.csv`): one row per accepted sample, a thermal campaign that `trueaxis thermal
//!   predict` reads: `run`, `t` (s since the run's first sample), the inputs (`T:<sensor>` degC),
//!   `<error>_predicted` (um, each model), `offset_<axis>` (um, the offset at the controller after
//!   the sample), `lag_<error>_<sensor>_<j>` (degC: the lagged rise z_ij of a drift model). Every
//!   other step (refusal, hold, ramp, resume, restart) is a `#` comment line with the wall time.
//! - JSON lines (`--log FILE.jsonl`): every step as one object (`wall`, `time_s`, `run`, `t`,
//!   `inputs`, `drift_um`, `offsets_um`, `written`, `phase`, `message`, `lags`).
//!
//! A log is appended to after a restart; a CSV log whose header differs (other models or inputs)
//! is refused. Lines are written with one `write` each, so a killed process leaves whole lines.

use crate::engine::{Engine, Step};
use crate::source::Sink;
use crate::{environment, input, LiveError};
use serde_json::{json, Map, Value};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// Names of what a step carries, in the engine's order.
#[derive(Clone, Debug)]
pub struct Names {
    pub inputs: Vec<String>,
    /// Model errors (`dz`) and, per model, its sensors and time constants (drift models).
    pub models: Vec<(String, Vec<String>, usize)>,
    pub axes: Vec<char>,
}

impl Names {
    pub fn of(engine: &Engine) -> Names {
        let models = engine
            .models()
            .map(|(m, _)| {
                let lags = match m {
                    trueaxis::thermal::error_model::ThermalErrorModel::Drift(d) => d.time_constants_s.len(),
                    _ => 0,
                };
                (m.error().to_string(), m.inputs().to_vec(), lags)
            })
            .collect();
        Names { inputs: engine.inputs.clone(), models, axes: engine.offsets.letters.clone() }
    }

    /// The lagged rises `z_ij = x_ij / tau_j` (degC) of model `m` from its lag states.
    fn lagged_rises(&self, engine_taus: &[Vec<f64>], m: usize, lags: &[f64]) -> Vec<f64> {
        let taus = &engine_taus[m];
        lags.iter().enumerate().map(|(s, x)| x / taus[s % taus.len().max(1)]).collect()
    }
}

/// The wall time now, UTC, as `YYYY-MM-DDTHH:MM:SS.mmmZ`.
pub fn wall_time() -> String {
    let d = SystemTime::now().duration_since(SystemTime::UNIX_EPOCH).unwrap_or_default();
    utc(d.as_secs_f64())
}

/// Seconds since the Unix epoch as UTC (days to civil date: `trueaxis::io::calendar`).
pub fn utc(seconds: f64) -> String {
    let ms = (seconds * 1e3).round() as i64;
    let (days, rem) = (ms.div_euclid(86_400_000), ms.rem_euclid(86_400_000));
    let (year, month, day) = trueaxis::io::calendar::civil_from_days(days);
    format!("{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}.{:03}Z", rem / 3_600_000, rem / 60_000 % 60, rem / 1000 % 60, rem % 1000)
}

fn open_append(path: &Path) -> Result<File, LiveError> {
    OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| environment(format!("{}: cannot open the log: {e}", path.display())))
}

fn append(file: &mut File, path: &Path, text: &str) -> Result<(), LiveError> {
    file.write_all(text.as_bytes()).map_err(|e| environment(format!("{}: cannot write the log: {e}", path.display())))
}

/// The CSV log.
pub struct CsvLog {
    path: PathBuf,
    file: File,
    names: Names,
    taus: Vec<Vec<f64>>,
}

impl CsvLog {
    /// Opens (or continues) a CSV log; after a restart, appends the last accepted step of the state
    /// when the log does not have it yet (the process ended between saving and logging).
    pub fn open(path: &Path, engine: &Engine) -> Result<CsvLog, LiveError> {
        let names = Names::of(engine);
        let header = header(&names);
        let existing = std::fs::read_to_string(path).unwrap_or_default();
        let mut file = open_append(path)?;
        let last_row = existing.lines().rev().find(|l| !l.starts_with('#') && !l.trim().is_empty()).map(str::to_string);
        match existing.lines().find(|l| !l.starts_with('#') && !l.trim().is_empty()) {
            None => append(&mut file, path, &format!("# trueaxis live log: t in s since the run's first sample, inputs in degC, <error>_predicted and offset_<axis> in um, lag_* in degC\n{header}\n"))?,
            Some(h) if h == header => {}
            Some(h) => return Err(input(format!("{}: the log has the columns `{h}`, this compensation writes `{header}`: use another --log", path.display()))),
        }
        let taus = engine
            .models()
            .map(|(m, _)| match m {
                trueaxis::thermal::error_model::ThermalErrorModel::Drift(d) => d.time_constants_s.clone(),
                _ => Vec::new(),
            })
            .collect();
        let mut log = CsvLog { path: path.into(), file, names, taus };
        if let Some(step) = engine.last_step() {
            // the row's run and time, as the log writes them
            let key = format!("{},{},", step.run.clone().unwrap_or_default(), step.run_time_s);
            if !last_row.as_deref().is_some_and(|r| r.starts_with(&key)) {
                let note = format!("# {}: restarted; the last sample of the state file was not logged yet\n", wall_time());
                let row = log.row(&step);
                append(&mut log.file, &log.path, &(note + &row))?;
            }
        }
        Ok(log)
    }

    fn row(&self, step: &Step) -> String {
        let mut cells = vec![step.run.clone().unwrap_or_default(), format!("{}", step.run_time_s)];
        if let (Some(r), Some(d)) = (&step.readings, &step.drift_um) {
            cells.extend(r.iter().map(|v| format!("{v}")));
            cells.extend(d.iter().map(|v| format!("{v:.6}")));
        }
        cells.extend(step.offsets_um.iter().map(|v| format!("{v:.6}")));
        for (m, lags) in step.lags.iter().enumerate() {
            cells.extend(self.names.lagged_rises(&self.taus, m, lags).iter().map(|v| format!("{v:.9}")));
        }
        cells.join(",") + "\n"
    }
}

fn header(names: &Names) -> String {
    let mut cols = vec!["run".to_string(), "t".to_string()];
    cols.extend(names.inputs.iter().cloned());
    cols.extend(names.models.iter().map(|(e, _, _)| format!("{e}_predicted")));
    cols.extend(names.axes.iter().map(|a| format!("offset_{a}")));
    for (e, sensors, lags) in &names.models {
        for s in sensors {
            for j in 1..=*lags {
                cols.push(format!("lag_{e}_{}_{j}", s.trim_start_matches("T:")));
            }
        }
    }
    cols.join(",")
}

impl Sink for CsvLog {
    fn write(&mut self, step: &Step) -> Result<(), LiveError> {
        let mut text = String::new();
        if let Some(m) = &step.message {
            text += &format!("# {}: t {} s: {:?}: {m}\n", wall_time(), step.run_time_s, step.phase);
        }
        if step.readings.is_some() && step.drift_um.is_some() {
            text += &self.row(step);
        } else if step.write {
            let offsets: Vec<String> = self.names.axes.iter().zip(&step.offsets_um).map(|(a, v)| format!("{a} {v:.3}")).collect();
            text += &format!("# {}: t {} s: offsets {} um\n", wall_time(), step.run_time_s, offsets.join(" "));
        }
        append(&mut self.file, &self.path, &text)
    }

    fn note(&mut self, message: &str) {
        let _ = append(&mut self.file, &self.path, &format!("# {}: {message}\n", wall_time()));
    }
}

/// The JSON-lines log.
pub struct JsonLog {
    path: PathBuf,
    file: File,
    names: Names,
}

impl JsonLog {
    pub fn open(path: &Path, engine: &Engine) -> Result<JsonLog, LiveError> {
        Ok(JsonLog { path: path.into(), file: open_append(path)?, names: Names::of(engine) })
    }
}

/// A step as a JSON object (the JSON-lines log and the status file).
pub fn step_json(names: &Names, step: &Step) -> Value {
    let named = |keys: &[String], values: &[f64]| -> Value {
        Value::Object(keys.iter().cloned().zip(values.iter().map(|v| json!(v))).collect::<Map<_, _>>())
    };
    let errors: Vec<String> = names.models.iter().map(|(e, _, _)| e.clone()).collect();
    let axes: Vec<String> = names.axes.iter().map(char::to_string).collect();
    json!({
        "wall": wall_time(),
        "time_s": step.time_s,
        "run": step.run,
        "t": step.run_time_s,
        "inputs": step.readings.as_ref().map(|r| named(&names.inputs, r)),
        "drift_um": step.drift_um.as_ref().map(|d| named(&errors, d)),
        "offsets_um": named(&axes, &step.offsets_um),
        "written": step.write,
        "phase": step.phase,
        "message": step.message,
        "lags": Value::Object(errors.iter().cloned().zip(step.lags.iter().map(|l| json!(l))).collect()),
    })
}

impl Sink for JsonLog {
    fn write(&mut self, step: &Step) -> Result<(), LiveError> {
        let line = format!("{}\n", step_json(&self.names, step));
        append(&mut self.file, &self.path, &line)
    }

    fn note(&mut self, message: &str) {
        let _ = append(&mut self.file, &self.path, &format!("{}\n", json!({"wall": wall_time(), "message": message})));
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn utc_of_known_instants() {
        assert_eq!(super::utc(0.0), "1970-01-01T00:00:00.000Z");
        // 2026-01-01T00:00:00Z = 1767225600 s
        assert_eq!(super::utc(1_767_225_600.5), "2026-01-01T00:00:00.500Z");
        assert_eq!(super::utc(951_782_400.0), "2000-02-29T00:00:00.000Z");
    }
}
