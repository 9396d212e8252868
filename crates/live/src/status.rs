//! What a live compensation tells a person or a supervisor while it runs:
//!
//! - the status file (`--status FILE`, JSON, replaced atomically after every step): `machine`,
//!   `updated` (wall time, UTC), `samples`, the last step (`time_s`, `run`, `t`, `phase`, `inputs`
//!   degC, `drift_um`, `offsets_um`) and the last `warnings` (refusals, holds, ramps, with their
//!   wall time); a supervisor or a dashboard reads it;
//! - on a terminal, one status line rewritten in place, and each message on a line of its own;
//!   otherwise (a service, a pipe) each message as one JSON object per line on stderr.

use crate::engine::Step;
use crate::log::{step_json, wall_time, Names};
use crate::state::Phase;
use serde_json::json;
use std::collections::VecDeque;
use std::io::{IsTerminal, Write};
use std::path::PathBuf;

/// How many warnings the status file keeps.
pub const WARNINGS_KEPT: usize = 20;

/// The status of one machine.
pub struct Status {
    machine: String,
    names: Names,
    file: Option<PathBuf>,
    terminal: bool,
    warnings: VecDeque<(String, String)>,
}

impl Status {
    pub fn new(machine: &str, names: Names, file: Option<PathBuf>) -> Status {
        Status { machine: machine.into(), names, file, terminal: std::io::stderr().is_terminal(), warnings: VecDeque::new() }
    }

    /// A message that is not a step (start, connection lost, end).
    pub fn note(&mut self, message: &str) {
        if self.terminal {
            eprintln!("\r\x1b[K{}  {message}", wall_time());
        } else {
            eprintln!("{}", json!({"wall": wall_time(), "machine": self.machine, "message": message}));
        }
    }

    /// Reports a step; writes the status file.
    pub fn step(&mut self, step: &Step, samples: u64) {
        if let Some(m) = &step.message {
            if m.starts_with("refused") || matches!(step.phase, Phase::Held | Phase::Ramping | Phase::Zero) {
                self.warnings.push_back((wall_time(), m.clone()));
                if self.warnings.len() > WARNINGS_KEPT {
                    self.warnings.pop_front();
                }
            }
            if self.terminal {
                eprintln!("\r\x1b[K{}  {m}", wall_time());
            } else {
                let mut line = step_json(&self.names, step);
                line["machine"] = json!(self.machine);
                eprintln!("{line}");
            }
        }
        if self.terminal {
            let offsets: Vec<String> = self.names.axes.iter().zip(&step.offsets_um).map(|(a, v)| format!("{a} {v:+.2}")).collect();
            let mut err = std::io::stderr();
            let _ =
                write!(err, "\r\x1b[K{:?}  t {:.0} s  offsets {} um  ({samples} samples)", step.phase, step.run_time_s, offsets.join(" "));
            let _ = err.flush();
        }
        if let Some(path) = &self.file {
            let mut doc = step_json(&self.names, step);
            doc["machine"] = json!(self.machine);
            doc["updated"] = json!(wall_time());
            doc["samples"] = json!(samples);
            doc["warnings"] = json!(self.warnings.iter().map(|(w, m)| json!({"wall": w, "message": m})).collect::<Vec<_>>());
            // whole or not at all; a failed status write is not worth stopping the compensation
            let _ = trueaxis::data::write_atomically(path, format!("{doc:#}\n").as_bytes());
        }
    }
}
