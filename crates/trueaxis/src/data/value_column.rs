//! A numeric column of a table: its values read forgivingly (`io::text::parse_number`) and
//! converted from the unit its header names to the unit trueaxis works in (docs/design.md, Conventions),
//! each refusal naming the file, the line and the column. Shared by the table read whole
//! ([`super::CsvTable`]) and the rows of a table read as a stream ([`super::pose_stream`]).

use super::DataError;
use crate::io::header::Header;
use crate::io::text::{parse_number, underflows};
use crate::io::units::{Dimension, Unit};

/// Column `column` of a table: how to read and convert its cells.
#[derive(Clone, Debug)]
pub(crate) struct ValueColumn {
    pub(crate) column: usize,
    /// The header as written, for messages.
    text: String,
    /// The header's unit and the unit returned; `None` when the header names no unit (the value as
    /// written).
    conversion: Option<(Unit, Unit)>,
    /// What a value is, before it in messages (`axis C at `).
    subject: String,
}

impl ValueColumn {
    /// Column `column` of `headers`, returned in `to` (when its header names a unit).
    pub(crate) fn new(headers: &[Header], column: usize, to: Option<Unit>) -> ValueColumn {
        let h = &headers[column];
        ValueColumn { column, text: h.text.clone(), conversion: h.unit.zip(to), subject: String::new() }
    }

    /// Names what the values are in messages (`axis C at `).
    pub(crate) fn named(self, subject: String) -> ValueColumn {
        ValueColumn { subject, ..self }
    }

    /// As [`ValueColumn::new`], refusing a header whose unit is not of `dimension` (`dev [mm]` where
    /// an angle is expected); `expected` names the unit in the message.
    pub(crate) fn of_dimension(
        headers: &[Header],
        column: usize,
        dimension: Dimension,
        expected: Unit,
        origin: &str,
    ) -> Result<ValueColumn, DataError> {
        match headers[column].unit {
            Some(u) if u.dimension != dimension => Err(DataError::Invalid {
                origin: origin.to_string(),
                message: format!(
                    "column {}: {} is {}, but {} ({}) is expected here",
                    headers[column].text,
                    u.symbol,
                    u.dimension.name(),
                    dimension.name(),
                    expected.symbol
                ),
            }),
            _ => Ok(ValueColumn::new(headers, column, Some(expected))),
        }
    }

    /// The header as written.
    pub(crate) fn text(&self) -> &str {
        &self.text
    }

    /// The value of this column in `row` (line `line` of `origin`): a finite number, converted.
    pub(crate) fn value(&self, row: &[String], line: u64, decimal_comma: bool, origin: &str) -> Result<f64, DataError> {
        let raw = &row[self.column];
        let refuse = |what: String| DataError::Invalid {
            origin: origin.to_string(),
            message: format!("line {line}: column {}: {}`{raw}` {what}", self.text, self.subject),
        };
        let v = parse_number(raw, decimal_comma).ok_or_else(|| refuse("is not a number".into()))?;
        if !v.is_finite() {
            return Err(refuse("is not a finite number".into()));
        }
        if underflows(raw.trim(), v) {
            return Err(refuse("is below the smallest number a double holds (about 4.9e-324) and would be read as 0".into()));
        }
        let Some((from, to)) = self.conversion else { return Ok(v) };
        let converted = from.convert(v, to);
        if converted.is_finite() {
            Ok(converted)
        } else {
            Err(refuse(format!("is too large in {}", to.symbol)))
        }
    }
}
