//! The columns of a pose table (docs/design.md, Files) and the reading of one row, shared by the
//! table read whole ([`super::poses_of`]) and the table read as a stream ([`super::PoseStream`]):
//! one column per axis of the machine (`X Y Z U V W` in mm, `A B C` in deg, a unit in the header
//! converted), `dir:<axis>` directions of motion (`+`, `-`, empty = at rest) and `T:<sensor>`
//! temperatures (degC, within the physical range). A column of an axis the machine does not have
//! is refused, as `nc` refuses a word of such an axis: the poses are for another machine.

use super::PoseTable;
use crate::data::value_column::ValueColumn;
use crate::data::DataError;
use crate::error_model::Direction;
use crate::io::header::{normalised, Header, RunDirection};
use crate::io::ranges::TEMPERATURE_DEGC;
use crate::io::units::{canonical, Dimension};
use crate::machine::{AxisKind, Machine};

/// Where the values of a pose are in a row.
#[derive(Clone, Debug)]
pub(super) struct PoseColumns {
    origin: String,
    decimal_comma: bool,
    /// One per axis of the machine, in its order.
    axes: Vec<ValueColumn>,
    /// `(axis, column)` of each `dir:<axis>` column.
    directions: Vec<(usize, usize)>,
    /// `T:<sensor>` columns.
    temperatures: Vec<(String, ValueColumn)>,
}

impl PoseColumns {
    /// The columns of a table with `headers` for `machine`; `origin` names the table in messages.
    pub(super) fn new(headers: &[Header], origin: &str, decimal_comma: bool, machine: &Machine) -> Result<PoseColumns, DataError> {
        let invalid = |message: String| DataError::Invalid { origin: origin.to_string(), message };
        let find = |name: &str| crate::data::table_head::find_column(headers, name, origin);
        for h in headers {
            let name = normalised(&h.name);
            let name = name.strip_prefix("dir:").unwrap_or(&name);
            let mut chars = name.chars();
            if let (Some(c), None) = (chars.next().map(|c| c.to_ascii_uppercase()), chars.next()) {
                if "XYZUVWABC".contains(c) && machine.axis_index(c).is_none() {
                    return Err(invalid(format!(
                        "column `{}`: axis {c} is not an axis of machine `{}` (axes: {}); these poses are for another machine",
                        h.text,
                        machine.name,
                        machine.axis_letters()
                    )));
                }
            }
        }
        let mut axes = Vec::new();
        for axis in machine.axes() {
            let name = axis.letter.to_string();
            let column = find(&name).map_err(|_| {
                invalid(format!(
                    "missing column `{name}` for axis {} ({}) of machine `{}`; the header has: {}",
                    axis.letter,
                    axis.position_unit(),
                    machine.name,
                    headers.iter().map(|h| h.text.as_str()).collect::<Vec<_>>().join(",")
                ))
            })?;
            let dimension = if axis.kind == AxisKind::Rotary { Dimension::Angle } else { Dimension::Length };
            axes.push(
                ValueColumn::of_dimension(headers, column, dimension, canonical(dimension, true), origin)?
                    .named(format!("axis {} at ", axis.letter)),
            );
        }
        let directions = (0..machine.axis_count())
            .filter_map(|a| {
                let name = format!("dir:{}", machine.axes()[a].letter);
                headers.iter().any(|h| normalised(&h.name) == normalised(&name)).then(|| find(&name).map(|c| (a, c)))
            })
            .collect::<Result<_, _>>()?;
        let mut temperatures = Vec::new();
        for (i, h) in headers.iter().enumerate() {
            if h.name.len() > 2 && h.name.get(..2).is_some_and(|p| p.eq_ignore_ascii_case("T:")) {
                let column =
                    ValueColumn::of_dimension(headers, i, Dimension::Temperature, canonical(Dimension::Temperature, false), origin)?;
                temperatures.push((format!("T:{}", &h.name[2..]), column));
            }
        }
        Ok(PoseColumns { origin: origin.to_string(), decimal_comma, axes, directions, temperatures })
    }

    /// An empty table of these columns (no rows), with room for `rows`.
    pub(super) fn table(&self, rows: usize, machine: &Machine) -> PoseTable {
        PoseTable {
            user: Vec::with_capacity(rows * machine.axis_count()),
            lines: Vec::with_capacity(rows),
            directions: (!self.directions.is_empty()).then(Vec::new),
            temperatures: self.temperatures.iter().map(|(n, _)| (n.clone(), Vec::new())).collect(),
        }
    }

    /// Appends the pose of `row` (line `line`) to `poses`: positions within the axis ranges,
    /// directions, temperatures within their physical range.
    pub(super) fn push_row(&self, row: &[String], line: u64, machine: &Machine, poses: &mut PoseTable) -> Result<(), DataError> {
        let invalid = |message: String| DataError::Invalid { origin: self.origin.clone(), message: format!("line {line}: {message}") };
        let start = poses.user.len();
        for c in &self.axes {
            poses.user.push(c.value(row, line, self.decimal_comma, &self.origin)?);
        }
        machine.check_range(&poses.user[start..]).map_err(|e| invalid(e.to_string()))?;
        if let Some(directions) = poses.directions.as_mut() {
            let first = directions.len();
            directions.resize(first + machine.axis_count(), None);
            for &(a, column) in &self.directions {
                directions[first + a] = match row[column].as_str() {
                    "" | "0" => None,
                    other => Some(match RunDirection::parse(other) {
                        Some(RunDirection::Plus) => Direction::Positive,
                        Some(RunDirection::Minus) => Direction::Negative,
                        None => return Err(invalid(format!("column dir:{}: `{other}` is not +, - or empty", machine.axes()[a].letter))),
                    }),
                };
            }
        }
        for ((name, column), (_, values)) in self.temperatures.iter().zip(&mut poses.temperatures) {
            let t = column
                .value(row, line, self.decimal_comma, &self.origin)
                .map_err(|_| invalid(format!("column {name}: `{}` is not a temperature", row[column.column])))?;
            if let Some(m) = TEMPERATURE_DEGC.check(t) {
                return Err(invalid(format!("column `{}`: {m}", column.text())));
            }
            values.push(t);
        }
        poses.lines.push(line);
        Ok(())
    }
}
