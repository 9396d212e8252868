//! Thermal measurement campaigns (CSV, DESIGN.md section 3): one row per sample with the time `t`
//! (s), optionally `run` (the duty cycle or test the row belongs to), temperature columns
//! `T:<sensor>` (degC), error columns (um, e.g. `dz` or `EZZ`) and axis positions (mm, deg).

use super::{input, ThermalError};
use std::collections::BTreeMap;

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
    columns: BTreeMap<String, Vec<f64>>,
}

impl Campaign {
    /// Reads a campaign CSV (`#` comments allowed).
    pub fn read(path: impl AsRef<std::path::Path>) -> Result<Campaign, ThermalError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| input(format!("{}: cannot read: {e}", path.display())))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses campaign CSV text; `origin` names it in messages.
    pub fn parse(text: &str, origin: &str) -> Result<Campaign, ThermalError> {
        let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).comment(Some(b'#')).from_reader(text.as_bytes());
        let headers: Vec<String> =
            reader.headers().map_err(|e| input(format!("{origin}: cannot read the header line: {e}")))?.iter().map(String::from).collect();
        let mut runs = Vec::new();
        let names: Vec<String> = headers.iter().filter(|h| *h != "run" && *h != "dir").cloned().collect();
        let mut dirs = Vec::new();
        let mut columns: BTreeMap<String, Vec<f64>> = names.iter().map(|n| (n.clone(), Vec::new())).collect();
        for record in reader.records() {
            let record = record.map_err(|e| input(format!("{origin}: {}", e.to_string().replace('\n', " "))))?;
            let line = record.position().map_or(0, |p| p.line());
            for (h, field) in headers.iter().zip(record.iter()) {
                if h == "run" {
                    runs.push(field.to_string());
                } else if h == "dir" {
                    if !["+", "-", ""].contains(&field) {
                        return Err(input(format!("{origin}: line {line}: column dir: `{field}` is not +, - or empty")));
                    }
                    dirs.push(field.to_string());
                } else {
                    let v = field
                        .parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| input(format!("{origin}: line {line}: column {h}: `{field}` is not a finite number")))?;
                    columns.get_mut(h).expect("named").push(v);
                }
            }
            if !headers.iter().any(|h| h == "run") {
                runs.push(String::new());
            }
            if !headers.iter().any(|h| h == "dir") {
                dirs.push(String::new());
            }
        }
        if runs.is_empty() {
            return Err(input(format!("{origin}: no data rows")));
        }
        Ok(Campaign { origin: origin.into(), runs, dirs, names, columns })
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
    pub fn column(&self, name: &str) -> Result<&[f64], ThermalError> {
        self.columns
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| input(format!("{}: missing column `{name}`; the header has: {}", self.origin, self.names.join(","))))
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

    /// Row indices of the named runs.
    pub fn rows_of(&self, runs: &[String]) -> Result<Vec<usize>, ThermalError> {
        for r in runs {
            if !self.runs.contains(r) {
                return Err(input(format!("{}: no rows of run `{r}` (runs: {})", self.origin, self.run_names().join(", "))));
            }
        }
        Ok((0..self.len()).filter(|&i| runs.contains(&self.runs[i])).collect())
    }

    /// The named columns restricted to `rows`: `[column][row]`.
    pub fn select(&self, names: &[String], rows: &[usize]) -> Result<Vec<Vec<f64>>, ThermalError> {
        names.iter().map(|n| self.column(n).map(|c| rows.iter().map(|&i| c[i]).collect())).collect()
    }
}
