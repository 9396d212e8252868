//! The state of a live compensation, saved after every step so that a restarted process (after a
//! crash, `kill -9`, a reboot) goes on where it was: the run and its reference readings, the lag
//! states of each model, the last accepted sample and the offsets at the controller.
//!
//! The file (JSON) is written to a temporary file in the same directory, flushed to the disk
//! (`fsync`) and renamed over the old one: at any moment the file on disk is either the previous
//! state or the new one, whole. Units: s, degC, um.

use crate::{environment, input, LiveError};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path;
use trueaxis::thermal::stepping::StepState;

/// The format named in every state file.
pub const FORMAT: &str = "trueaxis-live-state 1";

/// What the offsets are doing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// No sample accepted yet: nothing written.
    #[default]
    Waiting,
    /// Offsets follow the model.
    Compensating,
    /// No accepted sample for longer than expected: the last offsets are held.
    Held,
    /// The hold time is over: the offsets go linearly to zero.
    Ramping,
    /// The offsets are zero until an accepted sample comes.
    Zero,
}

/// The last accepted sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Accepted {
    /// Source time (s, Unix epoch for OPC UA and HAL, campaign time for a replay).
    pub time_s: f64,
    /// Readings of the engine's inputs (degC, or their unit).
    pub readings: Vec<f64>,
    /// Predicted drift of each model (um).
    pub drift_um: Vec<f64>,
    /// Interval to the accepted sample before (s), if any.
    pub interval_s: Option<f64>,
}

/// Everything a restarted process needs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EngineState {
    pub format: String,
    /// Digest of each model file's contents: a state is only continued with the same models.
    pub models: Vec<String>,
    /// The current run (value of the run signal; `None` without one).
    pub run: Option<String>,
    /// Source time of the first sample of the run (s).
    pub run_start_s: Option<f64>,
    /// The state of each model in this run.
    pub steps: Vec<StepState>,
    pub accepted: Option<Accepted>,
    /// The offsets last written (um, per axis of the offset map).
    pub written_um: Vec<f64>,
    /// The offsets of the last accepted sample (um): what a hold keeps and a ramp scales down.
    pub held_um: Vec<f64>,
    /// Source time when the offsets last followed the model (s).
    pub written_time_s: Option<f64>,
    pub phase: Phase,
    /// Samples accepted since the state was created.
    pub samples: u64,
}

impl EngineState {
    /// Reads a state file; `None` when it does not exist.
    pub fn load(path: &Path) -> Result<Option<EngineState>, LiveError> {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(environment(format!("{}: cannot read the state file: {e}", path.display()))),
        };
        let state: EngineState =
            serde_json::from_str(&text).map_err(|e| input(format!("{}: not a trueaxis live state file: {e}", path.display())))?;
        if state.format != FORMAT {
            return Err(input(format!("{}: state format `{}` (this trueaxis reads `{FORMAT}`)", path.display(), state.format)));
        }
        Ok(Some(state))
    }

    /// Writes the state atomically (temporary file, fsync, rename); `sync = false` skips the fsync
    /// (still whole after a crash of the process, not after a power loss).
    pub fn save(&self, path: &Path, sync: bool) -> Result<(), LiveError> {
        let fail = |e: &dyn std::fmt::Display| environment(format!("{}: cannot write the state file: {e}", path.display()));
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        let mut file = tempfile::NamedTempFile::new_in(dir).map_err(|e| fail(&e))?;
        let text = serde_json::to_vec(self).map_err(|e| fail(&e))?;
        file.write_all(&text).map_err(|e| fail(&e))?;
        if sync {
            file.as_file().sync_data().map_err(|e| fail(&e))?;
        }
        file.persist(path).map_err(|e| fail(&e.error))?;
        Ok(())
    }
}

/// A digest of a model file's contents (FNV-1a, 64 bits, hexadecimal).
pub fn digest(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}
