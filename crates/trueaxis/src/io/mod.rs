//! Files from the outside world (docs/design.md, The pipeline, before `instruments`): vendor files in
//! (Renishaw `.rtl` laser files, the Etalon exchange format of LaserTRACER / TRAC-CAL results,
//! ballbar text exports), the pieces of the forgiving table reader that `data::CsvTable` is built
//! on (units in headers, `;` and tab separators, decimal commas, byte-order marks, the wide laser
//! layout), and plausibility checks of units and coverage. Formats, what is known about them and
//! what is assumed: docs/user-guide.md, "Instrument files".

pub mod ballbar;
pub mod calendar;
pub mod etalon;
pub mod header;
pub mod metadata;
pub mod plausibility;
pub mod ranges;
pub mod rtl;
pub mod text;
pub mod toml_numbers;
pub mod units;

pub use metadata::{Environment, Metadata};
pub use plausibility::{Finding, Severity};
pub use ranges::PhysicalRange;
pub use units::{Dimension, Unit};

use thiserror::Error;

/// Why a file could not be read. Both are bad input; messages name the file and, where there is
/// one, the line.
#[derive(Debug, Error)]
pub enum IoError {
    #[error("{path}: cannot read: {source}")]
    Read { path: String, source: std::io::Error },
    #[error("{origin}: {message}")]
    Invalid { origin: String, message: String },
}

crate::error::error_of_kind!(IoError, Input);

/// The kind of an instrument file, detected from its contents.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// A table (trueaxis CSV or a forgiving variant; ballbar text exports are tables with a
    /// `Key: value` header).
    Table,
    /// A Renishaw laser file.
    Rtl,
    /// The Etalon exchange format (error parameters, not readings).
    Etalon,
}

impl Format {
    pub fn name(self) -> &'static str {
        match self {
            Format::Table => "table (CSV)",
            Format::Rtl => "Renishaw laser file (.rtl)",
            Format::Etalon => "Etalon exchange format",
        }
    }
}

/// Detects the format of a file's text: a Renishaw file by its `TARGET DATA::` / `DEVIATIONS::`
/// sections, an Etalon exchange file by `[NAME]` blocks with `VALUE =` or `Gridpoints =`, else a table.
pub fn detect(text: &str) -> Format {
    if rtl::looks_like(text) {
        Format::Rtl
    } else if etalon::looks_like(text) {
        Format::Etalon
    } else {
        Format::Table
    }
}

/// Reads a file as text (see [`text_of`]).
pub fn read_text(path: &std::path::Path) -> Result<String, IoError> {
    let bytes = crate::files::inputs::read(path).map_err(|source| IoError::Read { path: path.display().to_string(), source })?;
    text_of(bytes, &path.display().to_string())
}

/// The text of `bytes` without a byte-order mark: UTF-8, or else Latin-1 / Windows-1252 as older
/// instrument software on Windows writes it (the degree sign and `µ` are the same in both);
/// `origin` names them in messages. A file with NUL bytes is not a text file and is refused.
pub fn text_of(bytes: Vec<u8>, origin: &str) -> Result<String, IoError> {
    if let Some(i) = bytes.iter().position(|b| *b == 0) {
        let line = bytes[..i].iter().filter(|b| **b == b'\n').count() + 1;
        return Err(IoError::Invalid {
            origin: origin.to_string(),
            message: format!("line {line}: a NUL byte: this is not a text file (export the data as text or CSV)"),
        });
    }
    let text = match String::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => e.into_bytes().iter().map(|&b| b as char).collect(),
    };
    Ok(text::strip_bom(&text).to_string())
}
