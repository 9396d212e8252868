//! Pose CSV files (DESIGN.md section 3): one row per sample, axis columns named by letter
//! (`X,Y,Z` in mm, `A,B,C` in deg); other columns are ignored here. Read forgivingly by
//! [`CsvTable`] (separators, decimal commas, units in headers).

use super::{CsvTable, DataError};
use crate::errors::Direction;
use crate::io::units::Dimension;
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
    let invalid = |message: String| DataError::Invalid { origin: table.origin().to_string(), message };
    let header_list = || table.headers().iter().map(|h| h.text.as_str()).collect::<Vec<_>>().join(",");
    let mut columns = Vec::new();
    for axis in machine.axes() {
        let name = axis.letter.to_string();
        if !table.has_column(&name) {
            return Err(invalid(format!(
                "missing column `{}` for axis {} ({}) of machine `{}`; the header has: {}",
                name,
                axis.letter,
                axis.position_unit(),
                machine.name,
                header_list()
            )));
        }
        let dimension = if axis.kind == crate::machine::AxisKind::Rotary { Dimension::Angle } else { Dimension::Length };
        let texts = table.texts(&name)?;
        if let Some(r) = texts.iter().position(|t| crate::io::text::parse_number(t, table.decimal_comma()).is_some_and(|v| !v.is_finite()))
        {
            return Err(invalid(format!(
                "line {}: column {}: axis {} at `{}` is not a finite number",
                table.lines()[r],
                table.column_text(&name).unwrap_or(&name),
                axis.letter,
                texts[r]
            )));
        }
        columns.push(table.numbers_as(&name, dimension)?);
    }
    let dir_columns: Vec<(usize, Vec<String>)> = machine
        .axes()
        .iter()
        .enumerate()
        .filter_map(|(a, axis)| {
            let name = format!("dir:{}", axis.letter);
            table.has_column(&name).then(|| table.texts(&name).map(|t| (a, t)))
        })
        .collect::<Result<_, _>>()?;
    let temperature_names: Vec<String> = table
        .headers()
        .iter()
        .filter(|h| h.name.len() > 2 && h.name.get(..2).is_some_and(|p| p.eq_ignore_ascii_case("T:")))
        .map(|h| format!("T:{}", &h.name[2..]))
        .collect();
    let mut temperatures = Vec::new();
    for name in &temperature_names {
        let texts = table.texts(name)?;
        let values = table.numbers_as(name, Dimension::Temperature).map_err(|_| {
            let bad = texts
                .iter()
                .position(|t| !crate::io::text::parse_number(t, table.decimal_comma()).is_some_and(f64::is_finite))
                .unwrap_or(0);
            invalid(format!("line {}: column {name}: `{}` is not a temperature", table.lines()[bad], texts[bad]))
        })?;
        super::checks::physical_range(table, name, &values, &crate::io::ranges::TEMPERATURE_DEGC)?;
        temperatures.push((name.clone(), values));
    }
    let n = machine.axis_count();
    let mut table_out = PoseTable {
        user: Vec::with_capacity(n * table.len()),
        lines: table.lines().to_vec(),
        directions: (!dir_columns.is_empty()).then(Vec::new),
        temperatures,
    };
    for (r, &line) in table.lines().iter().enumerate() {
        let start = table_out.user.len();
        table_out.user.extend(columns.iter().map(|c| c[r]));
        machine.check_range(&table_out.user[start..]).map_err(|m| invalid(format!("line {line}: {m}")))?;
        if let Some(directions) = table_out.directions.as_mut() {
            let mut row = vec![None; n];
            for (a, texts) in &dir_columns {
                row[*a] = match texts[r].as_str() {
                    "" | "0" => None,
                    other => match crate::io::header::RunDirection::parse(other) {
                        Some(crate::io::header::RunDirection::Plus) => Some(Direction::Positive),
                        Some(crate::io::header::RunDirection::Minus) => Some(Direction::Negative),
                        None => {
                            return Err(invalid(format!(
                                "line {line}: column dir:{}: `{other}` is not +, - or empty",
                                machine.axes()[*a].letter
                            )))
                        }
                    },
                };
            }
            directions.extend(row);
        }
    }
    Ok(table_out)
}
