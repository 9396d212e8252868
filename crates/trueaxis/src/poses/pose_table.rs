//! Pose CSV files (docs/design.md, Files): one row per sample, axis columns named by letter
//! (`X,Y,Z` in mm, `A,B,C` in deg; `pose_columns`); other columns are ignored here, but not a
//! column of an axis the machine lacks. Read forgivingly by [`CsvTable`] (separators, decimal
//! commas, units in headers), whole; [`super::PoseStream`] reads one in bounded memory.

use super::pose_columns::PoseColumns;
use crate::data::{CsvTable, DataError};
use crate::error_model::Direction;
use crate::machine::Machine;
use std::io::Read;

/// Axis positions read from a CSV, in the machine's canonical axis order and in user units, with
/// the optional directions of motion (`dir:<axis>` columns, `+`/`-`, empty = at rest) and
/// temperatures (`T:<sensor>` columns, degC).
#[derive(Clone, Debug, PartialEq)]
pub struct PoseTable {
    /// `machine.axis_count()` positions per pose (mm, deg).
    pub user: Vec<f64>,
    /// 1-based line number in the file of each pose, for messages.
    pub lines: Vec<u64>,
    /// `machine.axis_count()` directions per pose, when any `dir:<axis>` column is present.
    pub directions: Option<Vec<Option<Direction>>>,
    /// Temperature columns by name (`T:<sensor>`), one value per pose.
    pub temperatures: Vec<(String, Vec<f64>)>,
}

impl PoseTable {
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// Temperatures of `sensors` (names `T:<sensor>`), `sensors.len()` per pose; an error names a
    /// sensor without a column.
    pub fn temperatures_of(&self, sensors: &[String]) -> Result<Vec<f64>, String> {
        let columns = sensors
            .iter()
            .map(|s| {
                self.temperatures
                    .iter()
                    .find(|(n, _)| n == s)
                    .map(|(_, v)| v)
                    .ok_or_else(|| format!("missing column `{s}` (degC) needed by the error model"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok((0..self.len()).flat_map(|i| columns.iter().map(move |c| c[i])).collect())
    }

    /// Positions in internal units (mm, rad), `axis_count` per pose.
    pub fn internal(&self, machine: &Machine) -> Vec<f64> {
        let mut out = self.user.clone();
        let n = machine.axis_count().max(1);
        for (user, internal) in self.user.chunks(n).zip(out.chunks_mut(n)) {
            machine.pose_to_internal(user, internal);
        }
        out
    }
}

/// Reads a pose CSV for `machine`: every axis of the machine must have a column; each value must
/// be a finite number within the axis range. Read forgivingly ([`CsvTable`]): a unit in a header
/// is honoured (`C [rad]` comes in deg).
pub fn read_poses(path: impl AsRef<std::path::Path>, machine: &Machine) -> Result<PoseTable, DataError> {
    let path = path.as_ref();
    let table = CsvTable::read(path)?;
    poses_of(&table, machine)
}

/// As [`read_poses`], from any reader; `origin` names the source in messages.
pub fn read_poses_from(reader: impl Read, origin: &str, machine: &Machine) -> Result<PoseTable, DataError> {
    let table = CsvTable::from_reader(reader, origin).map_err(|e| match e {
        DataError::Invalid { origin, message } if message.starts_with("no data: the file has a header") => {
            DataError::Invalid { origin, message: "no poses: the file has a header but no data rows".into() }
        }
        other => other,
    })?;
    poses_of(&table, machine)
}

/// The poses of a table already read.
pub fn poses_of(table: &CsvTable, machine: &Machine) -> Result<PoseTable, DataError> {
    let columns = PoseColumns::new(table.headers(), table.origin(), table.decimal_comma(), machine)?;
    let mut poses = columns.table(table.len(), machine);
    for (row, &line) in table.rows.iter().zip(table.lines()) {
        columns.push_row(row, line, machine, &mut poses)?;
    }
    Ok(poses)
}
