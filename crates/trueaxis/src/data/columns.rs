//! Tables with named columns (laser, level, ballbar and other instrument data, poses; docs/design.md
//! section 3), read forgivingly: every CSV input of trueaxis goes through [`CsvTable`].
//!
//! - `#` (or `//`) comment lines and blank lines anywhere; the header is the first line whose
//!   field count the next line repeats; `Key: value` lines before it, and `# Key: value` comments
//!   with a key of the file's metadata (`Machine`, `Date`, `Mat temp 1`, `Radius` ...), become the
//!   file's [`Metadata`];
//! - `,`, `;` or tab as the separator (from the header line); with `;` or tab a decimal comma
//!   (`-0,0123`); a UTF-8 byte-order mark; CRLF, LF or CR line ends; fields trimmed and unquoted;
//! - header names matched without regard to case, spaces and underscores, with synonyms
//!   (`deviation` for `dev`, `position` for `target`, `direction` for `dir`, `io::header`), and a
//!   unit in the header (`dev [mm]`, `Dev_um`, `Position (mm)`) honoured: a column read as a
//!   position comes in mm or deg, a deviation or reading in um or urad, a temperature in degC, a
//!   time in s (docs/design.md, Conventions);
//! - the wide laser layout (one row per target, one column per run and direction: `Run 1 +`,
//!   `Run 1 -`, ...) turned into the long one (`target, dev, dir, run`);
//! - a Renishaw `.rtl` laser file read as the table `target, dev, dir, run` of its readings.
//!
//! Errors name the file, the line and the column.

use super::table_head::{find_column, header_index, TableHead};
use super::value_column::ValueColumn;
use super::DataError;
use crate::io::header::{normalised, run_column, synonyms, Header, RunDirection};
use crate::io::metadata::Metadata;
use crate::io::rtl::RtlFile;
use crate::io::text::{numbered_lines, parse_number};
use crate::io::units::{canonical, Dimension, Unit};
use crate::io::Format;

/// How the readings were laid out in the file.
#[derive(Clone, Debug, PartialEq)]
pub enum Layout {
    /// One row per reading.
    Long,
    /// One row per target and one column per run and direction (the header texts), turned into
    /// one row per reading.
    Wide { run_columns: Vec<String> },
}

/// A table held in memory, with accessors for named columns.
#[derive(Clone, Debug)]
pub struct CsvTable {
    origin: String,
    headers: Vec<Header>,
    pub(crate) rows: Vec<Vec<String>>,
    lines: Vec<u64>,
    decimal_comma: bool,
    separator: u8,
    layout: Layout,
    format: Format,
    metadata: Metadata,
    /// Suspicious but readable content found while reading (from a Renishaw file: a run count that
    /// differs from the runs given), each naming the line.
    warnings: Vec<String>,
}

/// True for the names of columns that hold positions (mm, deg) rather than error values or readings
/// (um, urad): `target`, `position`, `angle` and axis letters (`X`, `C`, `X2`).
pub(crate) fn is_position_column(name: &str) -> bool {
    let n = name.trim();
    let mut c = n.chars();
    let axis = match (c.next(), c.as_str()) {
        (Some(a), rest) => "XYZUVWABC".contains(a) && (rest.is_empty() || rest.chars().all(|d| d.is_ascii_digit())),
        _ => false,
    };
    axis || matches!(n, "target" | "position" | "angle")
}

impl CsvTable {
    /// Reads a table file, or a Renishaw `.rtl` laser file as the table of its readings; an Etalon
    /// exchange file (error parameters, not readings) is refused with the command that converts it.
    pub fn read(path: impl AsRef<std::path::Path>) -> Result<CsvTable, DataError> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        let text = crate::io::read_text(path)?;
        Self::from_text(&text, &origin)
    }

    /// Reads a table from any reader; `origin` names it in messages.
    pub fn from_reader(mut reader: impl std::io::Read, origin: &str) -> Result<CsvTable, DataError> {
        let mut bytes = Vec::new();
        reader.read_to_end(&mut bytes).map_err(|source| DataError::Read { path: origin.to_string(), source })?;
        let text = crate::io::text_of(bytes, origin)?;
        Self::from_text(&text, origin)
    }

    /// Reads a table (or a Renishaw file) from its text; `origin` names it in messages.
    pub fn from_text(text: &str, origin: &str) -> Result<CsvTable, DataError> {
        let text = crate::io::text::strip_bom(text);
        match crate::io::detect(text) {
            Format::Rtl => Ok(Self::from_rtl(&crate::io::rtl::parse(text, origin)?, origin)),
            Format::Etalon => Err(DataError::Invalid {
                origin: origin.into(),
                message: "this is an Etalon exchange file (error parameters, not readings): convert it into an error-values file with \
                          `trueaxis convert FILE --to errors --machine M.toml --out errors.toml`"
                    .into(),
            }),
            Format::Table => Self::parse_table(text, origin),
        }
    }

    fn parse_table(text: &str, origin: &str) -> Result<CsvTable, DataError> {
        let lines = numbered_lines(text);
        let h = header_index(&lines)
            .ok_or_else(|| DataError::Invalid { origin: origin.to_string(), message: "no data: the file is empty".into() })?;
        let head = TableHead::parse(&lines[..=h], origin)?;
        let mut rows = Vec::new();
        let mut row_lines = Vec::new();
        for &(number, line) in &lines[h + 1..] {
            if let Some(row) = head.fields(number, line)? {
                rows.push(row);
                row_lines.push(number);
            }
        }
        if rows.is_empty() {
            return Err(head.invalid("no data: the file has a header but no rows".into()));
        }
        let TableHead { headers, separator, decimal_comma, metadata, .. } = head;
        let table = CsvTable {
            origin: origin.to_string(),
            headers,
            rows,
            lines: row_lines,
            decimal_comma,
            separator,
            layout: Layout::Long,
            format: Format::Table,
            metadata,
            warnings: Vec::new(),
        };
        table.long_from_wide()
    }

    /// The table of the readings of a Renishaw file: `target` and `dev` in the file's unit (mm, or
    /// deg for a rotary axis), `dir` (`+` / `-`, from the order of the run's targets), `run`; each
    /// row's line is that of its reading in the file.
    pub fn from_rtl(file: &RtlFile, origin: &str) -> CsvTable {
        let unit = if file.rotary { Unit::DEG } else { Unit::MM };
        let header = |name: &str, unit: Option<Unit>| Header {
            text: unit.map_or(name.to_string(), |u| format!("{name} [{u}]")),
            name: name.to_string(),
            unit,
        };
        let mut rows = Vec::new();
        let mut lines = Vec::new();
        for run in &file.runs {
            for r in &run.readings {
                rows.push(vec![
                    format!("{}", file.targets[r.target - 1]),
                    format!("{}", r.deviation),
                    run.direction.symbol().to_string(),
                    run.number.to_string(),
                ]);
                lines.push(r.line);
            }
        }
        CsvTable {
            origin: origin.to_string(),
            headers: vec![header("target", Some(unit)), header("dev", Some(unit)), header("dir", None), header("run", None)],
            rows,
            lines,
            decimal_comma: false,
            separator: b',',
            layout: Layout::Long,
            format: Format::Rtl,
            metadata: file.metadata.clone(),
            warnings: file.warnings.iter().map(|w| format!("{origin}: {w}")).collect(),
        }
    }

    /// Wide laser layout -> long: when the table has a target column, no deviation column and at
    /// least two run-and-direction columns, each non-empty cell of those becomes a row
    /// `target, dev, dir, run` (other columns copied), on the line of its row.
    fn long_from_wide(self) -> Result<CsvTable, DataError> {
        if self.find("dev").is_ok() {
            return Ok(self);
        }
        let Ok(target) = self.find("target") else { return Ok(self) };
        let runs: Vec<(usize, i64, RunDirection)> =
            self.headers.iter().enumerate().filter_map(|(i, h)| run_column(&h.name).map(|(r, d)| (i, r, d))).collect();
        if runs.len() < 2 {
            return Ok(self);
        }
        let unit = self.headers[runs[0].0].unit;
        if let Some(&(i, _, _)) = runs.iter().find(|(i, _, _)| self.headers[*i].unit != unit) {
            return Err(self.invalid(format!(
                "the run columns `{}` and `{}` have different units; give all runs in one unit",
                self.headers[runs[0].0].text, self.headers[i].text
            )));
        }
        let others: Vec<usize> = (0..self.headers.len()).filter(|i| *i != target && !runs.iter().any(|r| r.0 == *i)).collect();
        let mut headers = vec![
            self.headers[target].clone(),
            Header { text: unit.map_or("dev".into(), |u| format!("dev [{u}]")), name: "dev".into(), unit },
            Header { text: "dir".into(), name: "dir".into(), unit: None },
            Header { text: "run".into(), name: "run".into(), unit: None },
        ];
        headers.extend(others.iter().map(|&i| self.headers[i].clone()));
        let mut rows = Vec::new();
        let mut lines = Vec::new();
        // run by run, so that a run's readings stay together as in the long layout
        for &(column, run, direction) in &runs {
            for (row, &line) in self.rows.iter().zip(&self.lines) {
                let cell = &row[column];
                if cell.is_empty() {
                    continue;
                }
                let v = parse_number(cell, self.decimal_comma)
                    .ok_or_else(|| self.invalid(format!("line {line}: column {}: `{cell}` is not a number", self.headers[column].text)))?;
                let mut out = vec![row[target].clone(), format!("{v}"), direction.symbol().to_string(), run.to_string()];
                out.extend(others.iter().map(|&i| row[i].clone()));
                rows.push(out);
                lines.push(line);
            }
        }
        let layout = Layout::Wide { run_columns: runs.iter().map(|r| self.headers[r.0].text.clone()).collect() };
        Ok(CsvTable { headers, rows, lines, layout, ..self })
    }

    fn invalid(&self, message: String) -> DataError {
        DataError::Invalid { origin: self.origin.clone(), message }
    }

    pub fn len(&self) -> usize {
        self.rows.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The name of the file (or of the data) in messages.
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// The metadata of the file's header (`# Key: value` comments, a `Key: value` preamble, the
    /// user text and environment of a Renishaw file).
    pub fn metadata(&self) -> &Metadata {
        &self.metadata
    }

    /// Suspicious but readable content found while reading, each naming the file and line.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The file's format: a table or a Renishaw file.
    pub fn format(&self) -> Format {
        self.format
    }

    /// `,`, `;` or tab.
    pub fn separator(&self) -> char {
        self.separator as char
    }

    /// True when numbers may have a decimal comma (the separator is not a comma).
    pub fn decimal_comma(&self) -> bool {
        self.decimal_comma
    }

    /// The columns: header text as written, name and unit.
    pub fn headers(&self) -> &[Header] {
        &self.headers
    }

    /// True when a column answers to `name` (or one of its synonyms).
    pub fn has_column(&self, name: &str) -> bool {
        self.find(name).is_ok()
    }

    /// 1-based file line of each row.
    pub fn lines(&self) -> &[u64] {
        &self.lines
    }

    /// The index of the column that answers to `name`: the same name, else the same name without
    /// regard to case, spaces and underscores, else a synonym; two columns answering at the same
    /// level are an error.
    pub fn find(&self, name: &str) -> Result<usize, DataError> {
        find_column(&self.headers, name, &self.origin)
    }

    /// The header of the column that answers to `name`, as written (for messages).
    pub fn column_text(&self, name: &str) -> Option<&str> {
        self.find(name).ok().map(|i| self.headers[i].text.as_str())
    }

    /// The unit written in the header of column `name`, if any.
    pub fn unit_of(&self, name: &str) -> Option<Unit> {
        self.find(name).ok().and_then(|i| self.headers[i].unit)
    }

    /// The unit the values of column `name` are returned in by [`CsvTable::numbers`]: the header's
    /// unit converted to mm / deg for positions (`target`, `position`, `angle`, axis letters), um /
    /// urad for other values, degC, s; `None` when the header has no unit (the values as written).
    pub fn unit_returned(&self, name: &str) -> Option<Unit> {
        self.unit_of(name).map(|u| canonical(u.dimension, is_position_column(name)))
    }

    fn column_in(&self, column: usize, to: Option<Unit>) -> Result<Vec<f64>, DataError> {
        // a header without a unit: the values as written
        let reader = ValueColumn::new(&self.headers, column, to);
        self.rows.iter().zip(&self.lines).map(|(row, &line)| reader.value(row, line, self.decimal_comma, &self.origin)).collect()
    }

    /// A column of finite numbers, converted from the header's unit to the unit of
    /// [`CsvTable::unit_returned`] (as written when the header names no unit).
    pub fn numbers(&self, name: &str) -> Result<Vec<f64>, DataError> {
        let i = self.find(name)?;
        let to = self.headers[i].unit.map(|u| canonical(u.dimension, is_position_column(name)));
        self.column_in(i, to)
    }

    /// As [`CsvTable::numbers`], refusing a column whose header names a unit of another dimension
    /// than `dimension` (e.g. `dev [mm]` where an angle in urad is expected).
    pub fn numbers_as(&self, name: &str, dimension: Dimension) -> Result<Vec<f64>, DataError> {
        let i = self.find(name)?;
        ValueColumn::of_dimension(&self.headers, i, dimension, canonical(dimension, is_position_column(name)), &self.origin)?;
        self.numbers(name)
    }

    /// A column of finite numbers in `unit`: converted from the header's unit (which must be of the
    /// same dimension), taken as `unit` when the header names none.
    pub fn numbers_in(&self, name: &str, unit: Unit) -> Result<Vec<f64>, DataError> {
        let i = self.find(name)?;
        ValueColumn::of_dimension(&self.headers, i, unit.dimension, unit, &self.origin)?;
        self.column_in(i, Some(unit))
    }

    /// The table without its rows that have a blank cell (a logger dropout), with the file lines of
    /// the rows left out (for `--skip-missing`, reported by the caller).
    pub fn without_blank_rows(&self) -> (CsvTable, Vec<u64>) {
        let blank = |row: &Vec<String>| row.iter().any(|c| c.trim().is_empty());
        let dropped: Vec<u64> = self.rows.iter().zip(&self.lines).filter(|(r, _)| blank(r)).map(|(_, l)| *l).collect();
        let mut out = self.clone();
        let kept: Vec<(Vec<String>, u64)> =
            self.rows.iter().zip(&self.lines).filter(|(r, _)| !blank(r)).map(|(r, l)| (r.clone(), *l)).collect();
        (out.rows, out.lines) = kept.into_iter().unzip();
        (out, dropped)
    }

    /// A column of text.
    pub fn texts(&self, name: &str) -> Result<Vec<String>, DataError> {
        let i = self.find(name)?;
        Ok(self.rows.iter().map(|row| row[i].clone()).collect())
    }

    /// Column `name` of row `row`, as written.
    pub fn cell(&self, row: usize, name: &str) -> Result<&str, DataError> {
        let i = self.find(name)?;
        Ok(&self.rows[row][i])
    }

    /// An error about row `row` of this table.
    pub fn row_error(&self, row: usize, message: &str) -> DataError {
        self.invalid(format!("line {}: {message}", self.lines[row]))
    }

    /// The `+` / `-` directions of a `dir` column, read forgivingly (`up`, `down`, `fwd`, `bwd`,
    /// ...; `io::header::RunDirection`); an error names the line.
    pub fn directions(&self, name: &str) -> Result<Vec<RunDirection>, DataError> {
        let i = self.find(name)?;
        (0..self.rows.len())
            .map(|r| {
                RunDirection::parse(&self.rows[r][i]).ok_or_else(|| {
                    self.invalid(format!(
                        "line {}: column {}: `{}` is not a direction (+ or -, up or down)",
                        self.lines[r], self.headers[i].text, self.rows[r][i]
                    ))
                })
            })
            .collect()
    }

    /// The canonical CSV of this table (docs/design.md, Files): the metadata as `# Key: value`
    /// comments, a header of the column names with their units as returned by
    /// [`CsvTable::numbers`], `,` as separator and `.` as decimal mark; numeric columns converted,
    /// text columns as written. Columns of mixed text and numbers are written as text.
    pub fn to_canonical_csv(&self) -> Result<String, DataError> {
        let mut out = String::new();
        for (k, v) in self.metadata.comment_pairs() {
            out.push_str(&format!("# {k}: {v}\n"));
        }
        let mut columns: Vec<(String, Vec<String>)> = Vec::new();
        for (i, h) in self.headers.iter().enumerate() {
            let numeric = (0..self.rows.len()).all(|r| parse_number(&self.rows[r][i], self.decimal_comma).is_some_and(f64::is_finite));
            let name = canonical_name(&h.name);
            if numeric {
                let to = h.unit.map(|u| canonical(u.dimension, is_position_column(&name)));
                let values = self.column_in(i, to)?;
                let header = to.map_or(name.clone(), |u| format!("{name} [{u}]"));
                columns.push((header, values.iter().map(|v| format!("{v}")).collect()));
            } else {
                let header = if name.contains(',') { format!("\"{name}\"") } else { name.clone() };
                let texts = self.rows.iter().map(|r| quote(&r[i])).collect();
                columns.push((header, texts));
            }
        }
        out.push_str(&columns.iter().map(|c| c.0.as_str()).collect::<Vec<_>>().join(","));
        out.push('\n');
        for r in 0..self.rows.len() {
            out.push_str(&columns.iter().map(|c| c.1[r].as_str()).collect::<Vec<_>>().join(","));
            out.push('\n');
        }
        Ok(out)
    }
}

/// The trueaxis name of a column written under a synonym (`Deviation` -> `dev`).
fn canonical_name(name: &str) -> String {
    let n = normalised(name);
    for canonical in ["target", "dev", "dir", "run", "angle", "dL", "t"] {
        if normalised(canonical) == n || synonyms(canonical).iter().any(|s| normalised(s) == n) {
            return canonical.to_string();
        }
    }
    name.to_string()
}

fn quote(text: &str) -> String {
    if text.contains([',', '"', '#']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forgiving_variants_read_alike() {
        let canonical = CsvTable::from_text("target,dev,dir,run\n0,1.5,+,1\n100,-2.25,-,1\n", "a.csv").unwrap();
        let semicolon =
            CsvTable::from_text("\u{feff}Position (mm);Dev [mm];Direction;Run\r\n0;0,0015;+;1\r\n100;-0,00225;-;1\r\n", "b.csv").unwrap();
        assert_eq!(semicolon.numbers("target").unwrap(), canonical.numbers("target").unwrap());
        let a = canonical.numbers("dev").unwrap();
        let b = semicolon.numbers("dev").unwrap();
        assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12), "{a:?} {b:?}");
        assert_eq!(semicolon.unit_returned("dev"), Some(Unit::UM));
        let wide = CsvTable::from_text("Target\tRun 1 +\tRun 1 -\n0\t1.5\t\n100\t\t-2.25\n", "c.tsv").unwrap();
        assert_eq!(wide.numbers("dev").unwrap(), vec![1.5, -2.25]);
        assert_eq!(wide.texts("dir").unwrap(), vec!["+", "-"]);
        assert_eq!(wide.lines(), &[2, 3]);
    }

    #[test]
    fn errors_name_file_line_and_column() {
        let t = CsvTable::from_text("# c\ntarget,dev\n\n# c\n0,x\n", "f.csv").unwrap();
        let e = t.numbers("dev").unwrap_err().to_string();
        assert_eq!(e, "f.csv: line 5: column dev: `x` is not a number");
        let e = CsvTable::from_text("a,b\n1,2,3\n", "f.csv").unwrap_err().to_string();
        assert!(e.contains("line 2: 3 fields, but the header (line 1) has 2"), "{e}");
        let t = CsvTable::from_text("dev [mm],b\n1,2\n", "f.csv").unwrap();
        let e = t.numbers_as("dev", Dimension::Angle).unwrap_err().to_string();
        assert!(e.contains("column dev [mm]: mm is a length, but an angle (urad) is expected"), "{e}");
    }

    #[test]
    fn metadata_from_comments_and_preamble() {
        let t = CsvTable::from_text("Machine: DMU 50\nRadius (mm): 100\n# Operator: A. B.\nangle;dL\n0;1\n", "f.csv").unwrap();
        assert_eq!(t.metadata().machine.as_deref(), Some("DMU 50"));
        assert_eq!(t.metadata().operator.as_deref(), Some("A. B."));
        assert_eq!(t.metadata().other_value("radius (mm)"), Some("100"));
    }
}
