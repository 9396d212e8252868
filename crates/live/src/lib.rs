//! Live thermal compensation (`trueaxis live`): a long-running process beside one machine that
//! reads its temperature sensors as they change, predicts the thermal drift with a model fitted by
//! `trueaxis thermal fit`, and writes the opposite offsets to the controller.
//!
//! ```text
//! source (OPC UA subscription | LinuxCNC HAL pins | CSV replay)
//!   -> samples (time s, readings degC)
//!   -> engine: physical range and rate screening, the thermal model one sample at a time
//!      (trueaxis::thermal::stepping, the code of `thermal predict`), drift um -> axis offsets,
//!      the machine file's correction limit, hold / ramp / resume across gaps,
//!      the state saved atomically after every step
//!   -> sinks (OPC UA node writes | LinuxCNC external offsets | CSV / JSON-lines log, status file)
//! ```
//!
//! Units: readings in degC, times in s, drift and offsets in um in logs, status and state files;
//! offsets reach a controller in mm (LinuxCNC external offsets, OPC UA nodes by default) or in the
//! unit a mapping names. The engine ([`engine`]) has no network code; the OPC UA client
//! (async-opcua) is behind the cargo feature `opcua`.

pub mod assemble;
pub mod axes;
pub mod clock;
pub mod engine;
pub mod hal;
pub mod log;
pub mod mapping;
#[cfg(feature = "opcua")]
pub mod opcua;
pub mod run;
pub mod screen;
pub mod source;
pub mod state;
pub mod status;

use thiserror::Error;

/// Why live compensation cannot start or go on.
#[derive(Debug, Error)]
pub enum LiveError {
    /// Bad input: a file, a key, a node id, a pin, an option.
    #[error("{0}")]
    Input(String),
    /// A computation failed on valid input.
    #[error("{0}")]
    Computation(String),
    /// The environment: a server that cannot be reached, a program that is missing, a file that
    /// cannot be written.
    #[error("{0}")]
    Environment(String),
}

pub(crate) fn input(message: impl Into<String>) -> LiveError {
    LiveError::Input(message.into())
}

pub(crate) fn environment(message: impl Into<String>) -> LiveError {
    LiveError::Environment(message.into())
}

impl From<trueaxis::Error> for LiveError {
    fn from(e: trueaxis::Error) -> Self {
        match e.kind() {
            trueaxis::ErrorKind::Computation => LiveError::Computation(e.to_string()),
            _ => LiveError::Input(e.to_string()),
        }
    }
}

impl From<LiveError> for trueaxis::Error {
    /// The kind of each variant, the message unchanged.
    fn from(e: LiveError) -> trueaxis::Error {
        let kind = match e {
            LiveError::Input(_) => trueaxis::ErrorKind::Input,
            LiveError::Computation(_) => trueaxis::ErrorKind::Computation,
            LiveError::Environment(_) => trueaxis::ErrorKind::Environment,
        };
        trueaxis::Error::new(kind, e.to_string()).caused_by(e)
    }
}
