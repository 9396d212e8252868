//! Pose CSV files (DESIGN.md section 3): one row per sample, axis columns named by letter
//! (`X,Y,Z` in mm, `A,B,C` in deg); other columns are ignored here.

use super::DataError;
use crate::errors::Direction;
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
/// be a finite number within the axis range.
pub fn read_poses(path: impl AsRef<std::path::Path>, machine: &Machine) -> Result<PoseTable, DataError> {
    let path = path.as_ref();
    let file = std::fs::File::open(path).map_err(|source| DataError::Read { path: path.display().to_string(), source })?;
    read_poses_from(file, &path.display().to_string(), machine)
}

/// As [`read_poses`], from any reader; `origin` names the source in messages.
pub fn read_poses_from(reader: impl Read, origin: &str, machine: &Machine) -> Result<PoseTable, DataError> {
    let invalid = |message: String| DataError::Invalid { origin: origin.to_string(), message };
    let mut csv = csv::ReaderBuilder::new().trim(csv::Trim::All).comment(Some(b'#')).flexible(false).from_reader(reader);
    let headers = csv.headers().map_err(|e| invalid(format!("cannot read the header line: {e}")))?.clone();
    let mut columns = Vec::new();
    for axis in machine.axes() {
        let name = axis.letter.to_string();
        let column = headers.iter().position(|h| h == name).ok_or_else(|| {
            invalid(format!(
                "missing column `{}` for axis {} ({}) of machine `{}`; the header has: {}",
                name,
                axis.letter,
                axis.position_unit(),
                machine.name,
                headers.iter().collect::<Vec<_>>().join(",")
            ))
        })?;
        columns.push(column);
    }
    let dir_columns: Vec<(usize, usize)> = machine
        .axes()
        .iter()
        .enumerate()
        .filter_map(|(a, axis)| headers.iter().position(|h| h == format!("dir:{}", axis.letter)).map(|c| (a, c)))
        .collect();
    let temperature_columns: Vec<(String, usize)> =
        headers.iter().enumerate().filter(|(_, h)| h.starts_with("T:") && h.len() > 2).map(|(c, h)| (h.to_string(), c)).collect();
    let mut table = PoseTable {
        user: Vec::new(),
        lines: Vec::new(),
        directions: (!dir_columns.is_empty()).then(Vec::new),
        temperatures: temperature_columns.iter().map(|(n, _)| (n.clone(), Vec::new())).collect(),
    };
    for record in csv.records() {
        let record = record.map_err(|e| invalid(one_line_csv(&e)))?;
        let line = record.position().map_or(0, |p| p.line());
        let start = table.user.len();
        for (axis, &column) in machine.axes().iter().zip(&columns) {
            let text = &record[column];
            let value: f64 = text.parse().map_err(|_| invalid(format!("line {line}: column {}: `{text}` is not a number", axis.letter)))?;
            table.user.push(value);
        }
        machine.check_range(&table.user[start..]).map_err(|m| invalid(format!("line {line}: {m}")))?;
        if let Some(directions) = table.directions.as_mut() {
            let mut row = vec![None; machine.axis_count()];
            for (a, c) in &dir_columns {
                row[*a] = match &record[*c] {
                    "+" => Some(Direction::Positive),
                    "-" => Some(Direction::Negative),
                    "" | "0" => None,
                    other => {
                        return Err(invalid(format!(
                            "line {line}: column dir:{}: `{other}` is not +, - or empty",
                            machine.axes()[*a].letter
                        )))
                    }
                };
            }
            directions.extend(row);
        }
        for ((name, c), (_, values)) in temperature_columns.iter().zip(table.temperatures.iter_mut()) {
            let text = &record[*c];
            let t: f64 = text
                .parse()
                .ok()
                .filter(|t: &f64| t.is_finite())
                .ok_or_else(|| invalid(format!("line {line}: column {name}: `{text}` is not a temperature")))?;
            values.push(t);
        }
        table.lines.push(line);
    }
    if table.is_empty() {
        return Err(invalid("no poses: the file has a header but no data rows".into()));
    }
    Ok(table)
}

fn one_line_csv(e: &csv::Error) -> String {
    match e.position() {
        Some(p) => format!("line {}: {}", p.line(), e.to_string().replace('\n', " ")),
        None => e.to_string().replace('\n', " "),
    }
}
