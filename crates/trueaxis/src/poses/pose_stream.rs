//! A pose table read as a stream, chunk by chunk, in memory independent of its length
//! (docs/reliability.md: `predict` and `compensate --poses` on 10^7 poses): the same forgiving
//! reading as the table read whole ([`crate::data::CsvTable`], [`super::poses_of`]) through the shared
//! head, row splitting and pose columns, and the inputs of an error model per pose
//! (`error_model::InputRows`: columns `T:` `S:` `F:` `P:`, given values, drift lags over `t` and `run`).
//!
//! The header is the first line of at least two fields that the next content line repeats; the
//! lines before it are kept to find it (at most [`MAX_PREAMBLE`] bytes). A file of another kind (a
//! Renishaw laser file, an Etalon exchange file) is refused from its first lines.

use super::pose_columns::PoseColumns;
use super::PoseTable;
use crate::data::lines::Lines;
use crate::data::table_head::{find_column, header_index, is_content, is_header_pair, TableHead};
use crate::data::value_column::ValueColumn;
use crate::data::DataError;
use crate::error_model::{ErrorModel, InputRows};
use crate::io::units::canonical;
use crate::machine::Machine;
use std::collections::VecDeque;
use std::io::BufRead;
use std::path::Path;

/// Most bytes of comment and preamble lines before the header.
pub const MAX_PREAMBLE: usize = 1 << 20;

/// Poses read so far: a chunk of the table, and the inputs of the error model for each pose
/// (`errors.sensors().len()` per pose; empty without [`PoseStream::with_inputs`]).
#[derive(Clone, Debug)]
pub struct PoseChunk {
    pub poses: PoseTable,
    pub inputs: Vec<f64>,
}

/// The inputs of an error model for each row: the plan, the columns it wants, time and run.
struct RowInputs {
    plan: InputRows,
    wanted: Vec<ValueColumn>,
    time: Option<ValueColumn>,
    run: Option<usize>,
    values: Vec<f64>,
}

/// A pose table read chunk by chunk ([`PoseStream::next_chunk`]).
pub struct PoseStream<'m, R> {
    lines: Lines<R>,
    head: TableHead,
    columns: PoseColumns,
    machine: &'m Machine,
    inputs: Option<RowInputs>,
    /// Data lines read while looking for the header.
    pending: VecDeque<(u64, String)>,
    rows: u64,
}

impl<'m> PoseStream<'m, std::io::BufReader<std::fs::File>> {
    /// Opens the pose file `path` for `machine` (recorded as an input of the run, [`crate::files::inputs`]).
    pub fn open(path: &Path, machine: &'m Machine) -> Result<Self, DataError> {
        let file = crate::files::inputs::open(path).map_err(|source| DataError::Read { path: path.display().to_string(), source })?;
        PoseStream::new(std::io::BufReader::with_capacity(1 << 16, file), &path.display().to_string(), machine)
    }
}

impl<'m, R: BufRead> PoseStream<'m, R> {
    /// Reads the head of the pose table from `reader` (`origin` names it in messages).
    pub fn new(reader: R, origin: &str, machine: &'m Machine) -> Result<Self, DataError> {
        let mut lines = Lines::new(reader, origin);
        let invalid = |message: String| DataError::Invalid { origin: origin.to_string(), message };
        let mut prefix: Vec<(u64, String)> = Vec::new();
        let mut bytes = 0;
        let mut last_content: Option<usize> = None;
        while let Some(line) = lines.next_line()? {
            bytes += line.1.len();
            let content = is_content(&line.1);
            let pair = content && last_content.is_some_and(|k| is_header_pair(&prefix[k].1, &line.1));
            if content {
                last_content = Some(prefix.len());
            }
            prefix.push(line);
            if pair {
                break;
            }
            if bytes > MAX_PREAMBLE {
                return Err(invalid(format!("no header in the first {MAX_PREAMBLE} bytes: not a table of poses")));
            }
        }
        let text: String = prefix.iter().map(|(_, l)| format!("{l}\n")).collect();
        match crate::io::detect(&text) {
            crate::io::Format::Table => {}
            other => return Err(invalid(format!("this is a {}, not a table of poses", other.name()))),
        }
        let refs: Vec<(u64, &str)> = prefix.iter().map(|(n, l)| (*n, l.as_str())).collect();
        let h = header_index(&refs).ok_or_else(|| invalid("no poses: the file is empty".into()))?;
        let head = TableHead::parse(&refs[..=h], origin)?;
        let columns = PoseColumns::new(&head.headers, origin, head.decimal_comma, machine)?;
        let pending = prefix.drain(h + 1..).collect();
        Ok(PoseStream { lines, head, columns, machine, inputs: None, pending, rows: 0 })
    }

    /// Also reads the inputs of `errors` for each pose: columns named like them (in their units),
    /// else `given` (`(name, value)` from `--input`), drift lags from the columns `t` (s) and
    /// `run`. An error names the input that has neither a column nor a value.
    pub fn with_inputs(mut self, errors: &ErrorModel, given: &[(String, f64)]) -> Result<Self, DataError> {
        if errors.sensors().is_empty() {
            return Ok(self);
        }
        let headers = &self.head.headers;
        let origin = self.head.origin.clone();
        let find = |name: &str| find_column(headers, name, &origin).ok();
        // a column of values converted from the header's unit to trueaxis's (`CsvTable::numbers`)
        let numbers = |i: usize| {
            ValueColumn::new(
                headers,
                i,
                headers[i].unit.map(|u| canonical(u.dimension, crate::data::columns::is_position_column(&headers[i].name))),
            )
        };
        let value = |name: &str| given.iter().find(|(n, _)| n == name).map(|(_, v)| *v);
        let (plan, wanted) = InputRows::new(errors.sensors(), &|name| find(name).is_some(), &value, find("t").is_some())
            .map_err(|m| DataError::Invalid { origin: origin.clone(), message: m })?;
        let wanted = wanted.iter().map(|name| numbers(find(name).expect("a column the table has"))).collect();
        self.inputs = Some(RowInputs { plan, wanted, time: find("t").map(numbers), run: find("run"), values: Vec::new() });
        Ok(self)
    }

    fn next_row(&mut self) -> Result<Option<(u64, String)>, DataError> {
        match self.pending.pop_front() {
            Some(line) => Ok(Some(line)),
            None => self.lines.next_line(),
        }
    }

    /// The next chunk of at most `max` poses; `None` after the last. A table without any pose is
    /// refused.
    pub fn next_chunk(&mut self, max: usize) -> Result<Option<PoseChunk>, DataError> {
        let mut chunk = PoseChunk { poses: self.columns.table(max.min(1 << 16), self.machine), inputs: Vec::new() };
        while chunk.poses.len() < max {
            let Some((number, line)) = self.next_row()? else { break };
            let Some(row) = self.head.fields(number, &line)? else { continue };
            self.columns.push_row(&row, number, self.machine, &mut chunk.poses)?;
            if let Some(inputs) = self.inputs.as_mut() {
                inputs.push(&row, number, &self.head, &mut chunk.inputs)?;
            }
        }
        self.rows += chunk.poses.len() as u64;
        if self.rows == 0 {
            return Err(self.head.invalid("no poses: the file has a header but no data rows".into()));
        }
        Ok((!chunk.poses.is_empty()).then_some(chunk))
    }
}

impl RowInputs {
    /// Appends the inputs of `row` (line `line`).
    fn push(&mut self, row: &[String], line: u64, head: &TableHead, out: &mut Vec<f64>) -> Result<(), DataError> {
        let read = |c: &ValueColumn| c.value(row, line, head.decimal_comma, &head.origin);
        self.values.clear();
        for c in &self.wanted {
            self.values.push(read(c)?);
        }
        let time = self.time.as_ref().map(read).transpose()?;
        let run = self.run.map_or("", |i| row[i].as_str());
        self.plan.push(&self.values, time, run, out).map_err(|m| head.invalid(format!("line {line}: {m}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MACHINE: &str = "name = \"m\"\nstructure = \"wCAbYXZt\"\n[axes]\nX = { kind = \"linear\", direction = [1, 0, 0], range = [-300, 300] }\n\
        Y = { kind = \"linear\", direction = [0, 1, 0], range = [-250, 250] }\nZ = { kind = \"linear\", direction = [0, 0, 1], range = [-400, 0] }\n\
        A = { kind = \"rotary\", direction = [1, 0, 0], point = [0, 0, 0], range = [-20, 70] }\nC = { kind = \"rotary\", direction = [0, 0, 1], point = [0, 0, 0] }\n\
        [tool]\npoint = [0, 0, 0]\n";

    fn streamed(text: &str, machine: &Machine, max: usize) -> Result<PoseTable, DataError> {
        let mut stream = PoseStream::new(std::io::BufReader::with_capacity(5, text.as_bytes()), "p.csv", machine)?;
        let mut all = PoseTable { user: Vec::new(), lines: Vec::new(), directions: None, temperatures: Vec::new() };
        while let Some(c) = stream.next_chunk(max)? {
            all.user.extend(c.poses.user);
            all.lines.extend(c.poses.lines);
            all.directions = match (all.directions.take(), c.poses.directions) {
                (None, d) => d,
                (Some(mut a), Some(b)) => {
                    a.extend(b);
                    Some(a)
                }
                (a, None) => a,
            };
            for (k, (name, values)) in c.poses.temperatures.into_iter().enumerate() {
                match all.temperatures.get_mut(k) {
                    Some((_, v)) => v.extend(values),
                    None => all.temperatures.push((name, values)),
                }
            }
        }
        Ok(all)
    }

    #[test]
    fn the_stream_reads_as_the_whole_table_in_every_chunk_size() {
        let machine = Machine::from_toml_str(MACHINE, "m.toml").unwrap();
        let text = "\u{feff}# poses\r\nOperator: A. B.\r\nX [mm];Y;Z;A [rad];C;dir:X;T:spindle\r\n1,5;2;-3;0,5;370;+;21\r\n\r\n# pause\r\n-4;5;-6;-0,1;0;-;22,5\r7;8;-9;0;-10;;20\r\n";
        let whole = super::super::read_poses_from(text.as_bytes(), "p.csv", &machine).unwrap();
        assert_eq!(whole.lines, [4, 7, 8]);
        for max in [1, 2, 1000] {
            assert_eq!(streamed(text, &machine, max).unwrap(), whole, "chunks of {max}");
        }
        // the refusals of the whole reader, from the stream
        for (bad, expect) in [
            ("X,Y,Z,A,C\n0,0,0,0,0\n0,0,0,90,0\n", "line 3: axis A at 90 deg"),
            ("X,Y,Z,A,C\n", "no poses"),
            ("X,Y,Z,A,C,B\n0,0,0,0,0,0\n", "axis B is not an axis of machine `m`"),
            ("X,Y,Z,A,C\n0,0,1e-400,0,0\n", "`1e-400` is below the smallest number"),
        ] {
            let e = streamed(bad, &machine, 10).unwrap_err().to_string();
            let w = super::super::read_poses_from(bad.as_bytes(), "p.csv", &machine).unwrap_err().to_string();
            assert!(e.contains(expect) && w.contains(expect), "{e} / {w}");
        }
    }
}
