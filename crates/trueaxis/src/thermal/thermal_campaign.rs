//! Thermal measurement campaigns (CSV, docs/design.md, Files): one row per sample with the time `t`
//! (s), optionally `run` (the duty cycle or test the row belongs to), temperature columns
//! `T:<sensor>` (degC), error columns (um, e.g. `dz` or `EZZ`) and axis positions (mm, deg).

use crate::error::Error;
use crate::io::ranges;
use std::collections::BTreeMap;

/// The physical range of a campaign column (`io::ranges`): temperatures `T:<sensor>`, the time
/// `t`, axis positions (one axis letter), else an error or drift (um).
fn physical_range_of(name: &str) -> ranges::PhysicalRange {
    let mut letters = name.chars();
    match (letters.next(), letters.next()) {
        _ if name.starts_with("T:") => ranges::TEMPERATURE_DEGC,
        (Some('t'), None) => ranges::TIME_S,
        (Some(c), None) if crate::machine::is_rotary_letter(c) => ranges::ROTARY_POSITION_DEG,
        (Some(c), None) if crate::machine::is_axis_letter(c) => ranges::MACHINE_LENGTH_MM,
        _ => ranges::THERMAL_DRIFT_UM,
    }
}

/// A campaign held in memory.
#[derive(Clone, Debug)]
pub struct Campaign {
    pub origin: String,
    /// Run name per row (empty when the file has no `run` column).
    pub runs: Vec<String>,
    /// Direction of motion per row (`+`, `-`, or empty; column `dir`, for segmented G-T models).
    pub dirs: Vec<String>,
    /// Numeric columns by name, in file order of `names`.
    pub names: Vec<String>,
    /// The 1-based file line of each row (for messages of screening).
    pub lines: Vec<u64>,
    columns: BTreeMap<String, Vec<f64>>,
}

impl Campaign {
    /// Reads a campaign CSV (`#` comments allowed).
    pub fn read(path: impl AsRef<std::path::Path>) -> Result<Campaign, Error> {
        let path = path.as_ref();
        let text = crate::files::inputs::read_to_string(path).map_err(|e| Error::input(format!("{}: cannot read: {e}", path.display())))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses campaign CSV text (forgivingly: `crate::data::CsvTable`, units in headers converted
    /// to degC, s, um, mm, deg); `origin` names it in messages.
    pub fn parse(text: &str, origin: &str) -> Result<Campaign, Error> {
        let table = crate::data::CsvTable::from_text(text, origin)
            .map_err(|e| Error::input(e.to_string().replace("no data: the file has a header but no rows", "no data rows")))?;
        Self::from_table(&table, origin)
    }

    /// As [`Campaign::read`], leaving out the rows with a blank cell (a logger dropout): the
    /// campaign and the file lines left out (`--skip-missing`).
    pub fn read_skipping_missing(path: impl AsRef<std::path::Path>) -> Result<(Campaign, Vec<u64>), Error> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        let text = crate::files::inputs::read_to_string(path).map_err(|e| Error::input(format!("{origin}: cannot read: {e}")))?;
        let table = crate::data::CsvTable::from_text(&text, &origin).map_err(|e| Error::input(e.to_string()))?;
        let (kept, dropped) = table.without_blank_rows();
        Ok((Self::from_table(&kept, &origin)?, dropped))
    }

    fn from_table(table: &crate::data::CsvTable, origin: &str) -> Result<Campaign, Error> {
        let named = |name: &str| table.headers().iter().find(|h| h.name.eq_ignore_ascii_case(name)).map(|h| h.name.clone());
        let runs = match named("run") {
            Some(h) => table.texts(&h).map_err(|e| Error::input(e.to_string()))?,
            None => vec![String::new(); table.len()],
        };
        // direction of motion per row, for segmented G-T models: `+`, `-` or empty
        let dirs = match named("dir") {
            Some(h) => {
                let texts = table.texts(&h).map_err(|e| Error::input(e.to_string()))?;
                if let Some(i) = texts.iter().position(|d| !["+", "-", ""].contains(&d.as_str())) {
                    return Err(Error::input(table.row_error(i, &format!("column dir: `{}` is not +, - or empty", texts[i])).to_string()));
                }
                texts
            }
            None => vec![String::new(); table.len()],
        };
        let names: Vec<String> = table
            .headers()
            .iter()
            .filter(|h| !h.name.eq_ignore_ascii_case("run") && !h.name.eq_ignore_ascii_case("dir"))
            .map(|h| h.name.clone())
            .collect();
        let mut columns = BTreeMap::new();
        for name in &names {
            let values = table.numbers(name).map_err(|e| Error::input(e.to_string()))?;
            crate::data::checks::physical_range(table, name, &values, &physical_range_of(name)).map_err(|e| Error::input(e.to_string()))?;
            columns.insert(name.clone(), values);
        }
        Ok(Campaign { origin: origin.into(), runs, dirs, names, lines: table.lines().to_vec(), columns })
    }

    /// Whether the file has the direction column `dir`.
    pub fn has_directions(&self) -> bool {
        self.dirs.iter().any(|d| !d.is_empty())
    }

    pub fn len(&self) -> usize {
        self.runs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// A numeric column.
    pub fn column(&self, name: &str) -> Result<&[f64], Error> {
        self.columns
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| Error::input(format!("{}: missing column `{name}`; the header has: {}", self.origin, self.names.join(","))))
    }

    /// The temperature columns `T:<sensor>`, in file order.
    pub fn sensors(&self) -> Vec<String> {
        self.names.iter().filter(|n| n.starts_with("T:")).cloned().collect()
    }

    /// The distinct run names in order of first appearance.
    pub fn run_names(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for r in &self.runs {
            if !out.contains(r) {
                out.push(r.clone());
            }
        }
        out
    }

    /// Row indices of the named runs (with the segments of a run split at its gaps,
    /// `thermal::thermal_screening::split_at_gaps`).
    pub fn rows_of(&self, runs: &[String]) -> Result<Vec<usize>, Error> {
        for r in runs {
            if !self.runs.iter().any(|x| Self::is_of_run(x, r)) {
                return Err(Error::input(format!("{}: no rows of run `{r}` (runs: {})", self.origin, self.run_names().join(", "))));
            }
        }
        Ok((0..self.len()).filter(|&i| runs.iter().any(|r| Self::is_of_run(&self.runs[i], r))).collect())
    }

    /// Whether the rows of run `row_run` belong to the run named `name`: the same name, or a
    /// segment of it after a gap (`name [after gap k]`).
    pub fn is_of_run(row_run: &str, name: &str) -> bool {
        row_run == name || row_run.strip_prefix(name).is_some_and(|rest| rest.starts_with(crate::thermal::thermal_screening::AFTER_GAP))
    }

    /// The named columns restricted to `rows`: `[column][row]`.
    pub fn select(&self, names: &[String], rows: &[usize]) -> Result<Vec<Vec<f64>>, Error> {
        names.iter().map(|n| self.column(n).map(|c| rows.iter().map(|&i| c[i]).collect())).collect()
    }
}
