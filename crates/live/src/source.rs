//! Sources of samples and the sinks of offsets, as the run loop sees them, and the CSV replay: a
//! campaign file of `thermal fit` (columns `run`, `t` s, `T:<sensor>` degC, ...) played row by
//! row at `speed` times its own pace (`inf`: as fast as the engine takes them). After a restart the
//! rows up to the saved state's last sample are skipped, so a replay goes on where it was.

use crate::engine::{Sample, Step};
use crate::mapping::{AddressKind, Mapping};
use crate::state::EngineState;
use crate::{input, LiveError};
use std::path::Path;
use std::time::{Duration, Instant};
use trueaxis::thermal::thermal_campaign::Campaign;

/// What a source has to say.
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    Sample(Sample),
    /// A change of the connection worth a log line (lost, reconnected, a bad status).
    Note(String),
    /// The source has no more samples (end of a replay).
    End,
}

/// A source of samples.
pub trait Source {
    /// The next event, waiting at most `timeout`; `None` when nothing came.
    fn next(&mut self, timeout: Duration) -> Result<Option<Event>, LiveError>;
}

/// Where offsets go (a controller).
pub trait Sink {
    /// Writes the offsets of a step (um per axis of the engine's offset map).
    fn write(&mut self, step: &Step) -> Result<(), LiveError>;

    /// A message that is not a step (connection lost, restart); logs record it.
    fn note(&mut self, _message: &str) {}

    /// The sink's own messages since the last call (a connection lost, reconnected); an error
    /// ends the run (a connection given up).
    fn notes(&mut self) -> Result<Vec<String>, LiveError> {
        Ok(Vec::new())
    }
}

/// The CSV replay.
pub struct CsvReplay {
    rows: std::vec::IntoIter<Sample>,
    speed: f64,
    previous: Option<(f64, Instant)>,
}

impl CsvReplay {
    /// Reads the campaign and its columns for `inputs`; skips what `resume` already took.
    pub fn open(
        path: &Path,
        inputs: &[String],
        mapping: &Mapping,
        speed: f64,
        resume: Option<&EngineState>,
    ) -> Result<CsvReplay, LiveError> {
        if speed.is_nan() || speed <= 0.0 {
            return Err(input(format!("--speed {speed} must be positive (inf: as fast as possible)")));
        }
        let campaign = Campaign::read(path)?;
        let columns = mapping.addresses(inputs, AddressKind::Column)?;
        let all: Vec<usize> = (0..campaign.len()).collect();
        let values = campaign.select(&columns, &all)?;
        let units: Vec<String> = inputs.iter().map(|n| mapping.input_of(n).map_or("degC".into(), |i| i.unit.clone())).collect();
        let t = campaign.column("t")?;
        let has_runs = campaign.runs.iter().any(|r| !r.is_empty());
        let mut rows: Vec<Sample> = (0..campaign.len())
            .map(|i| Sample {
                time_s: t[i],
                run: has_runs.then(|| campaign.runs[i].clone()),
                readings: values.iter().zip(&units).map(|(c, u)| crate::mapping::to_degc(c[i], u)).collect(),
            })
            .collect();
        if let Some(state) = resume {
            if let Some(done) = state.accepted.as_ref().and_then(|a| rows.iter().position(|s| s.run == state.run && s.time_s == a.time_s)) {
                rows.drain(..=done);
            }
        }
        Ok(CsvReplay { rows: rows.into_iter(), speed, previous: None })
    }
}

impl Source for CsvReplay {
    fn next(&mut self, _timeout: Duration) -> Result<Option<Event>, LiveError> {
        let Some(sample) = self.rows.next() else { return Ok(Some(Event::End)) };
        // pace: the row's interval from the previous row of the same clock, at `speed`
        if let Some((t0, at)) = self.previous {
            let due = (sample.time_s - t0) / self.speed;
            if due.is_finite() && due > 0.0 {
                let wait = Duration::from_secs_f64(due).saturating_sub(at.elapsed());
                std::thread::sleep(wait);
            }
        }
        self.previous = Some((sample.time_s, Instant::now()));
        Ok(Some(Event::Sample(sample)))
    }
}
