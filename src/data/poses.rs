//! Pose CSV files (DESIGN.md section 3): one row per sample, axis columns named by letter
//! (`X,Y,Z` in mm, `A,B,C` in deg); other columns are ignored here.

use super::DataError;
use crate::machine::Machine;
use std::io::Read;

/// Axis positions read from a CSV, in the machine's canonical axis order and in user units.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseTable {
    /// `machine.axis_count()` positions per pose (mm, deg).
    pub user: Vec<f64>,
    /// 1-based line number in the file of each pose, for messages.
    pub lines: Vec<u64>,
}

impl PoseTable {
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
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
    let mut table = PoseTable { user: Vec::new(), lines: Vec::new() };
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
