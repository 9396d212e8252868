//! ISO 230-2:2014 evaluation of the accuracy and repeatability of positioning of a numerically
//! controlled axis from bidirectional runs (typically laser-interferometer readings).
//!
//! Symbols follow the standard (clause 3, terms and definitions; clause 8, presentation of the
//! results), with `plus` for the up arrow (approach in the `+` direction) and `minus` for the down
//! arrow. Target positions `P_i` are in mm; positional deviations `x_ij = P_ij - P_i` (actual minus
//! target) and every result are in um; for a rotary axis targets are in deg and deviations and
//! results in urad. The coverage factor is 2 throughout, as in the 2014 edition.
//!
//! The standard test cycle approaches every target five times in each direction; this evaluation
//! accepts any number `n >= 2` per target and direction (the estimator `s` needs two readings) and
//! reports the smallest count used in [`Iso2302Result::runs`].

use crate::data::CsvTable;
use crate::error::{Error, Result};
use crate::io::header::RunDirection;
use crate::io::units::Dimension;
use serde_json::{json, Value};
use std::collections::HashMap;

/// Two readings whose targets differ by at most this (mm) belong to the same target position.
pub const TARGET_TOLERANCE_MM: f64 = 1e-6;

/// Direction of approach to a target: `+` (ISO 230-2 up arrow) or `-` (down arrow).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    Plus,
    Minus,
}

impl Direction {
    /// `+` or `-`, as in the `dir` column.
    pub fn symbol(self) -> &'static str {
        match self {
            Direction::Plus => "+",
            Direction::Minus => "-",
        }
    }

    /// Parses the `dir` column: exactly `+` or `-`.
    pub fn parse(text: &str) -> Option<Direction> {
        match text {
            "+" => Some(Direction::Plus),
            "-" => Some(Direction::Minus),
            _ => None,
        }
    }
}

/// One reading `x_ij` of one run at one target.
#[derive(Clone, Debug, PartialEq)]
pub struct Reading {
    /// Target position `P_i` (mm).
    pub target: f64,
    /// Positional deviation `x_ij = P_ij - P_i`, actual minus target (um).
    pub dev: f64,
    /// Direction of approach.
    pub direction: Direction,
    /// Run number `j` (any integers; unique per target and direction).
    pub run: i64,
    /// 1-based line of the reading in its file, used in messages (for data built in code: any
    /// number that identifies the reading).
    pub line: u64,
}

/// The readings of one positioning test, with the name of their origin (file) for messages.
#[derive(Clone, Debug)]
pub struct PositioningData {
    pub origin: String,
    pub readings: Vec<Reading>,
    /// True for a rotary axis: targets in deg, deviations and results in urad (else mm and um).
    pub rotary: bool,
    /// What the file says about the test (machine, date, environment, ...).
    pub metadata: crate::io::Metadata,
}

impl PositioningData {
    /// The unit of the targets: mm, or deg for a rotary axis.
    pub fn position_unit(&self) -> &'static str {
        if self.rotary {
            "deg"
        } else {
            "mm"
        }
    }

    /// The unit of the deviations and results: um, or urad for a rotary axis.
    pub fn unit(&self) -> &'static str {
        if self.rotary {
            "urad"
        } else {
            "um"
        }
    }
}

/// Reads a positioning test (docs/design.md sections 3-4) from a table or a Renishaw `.rtl` file, read
/// forgivingly by [`CsvTable`]: columns `target` (mm; deg for a rotary axis), `dev` (um, actual
/// minus target; urad for a rotary axis), `dir` (`+` or `-`; `up`, `down` ...), `run` (integer), or
/// the wide layout of one column per run and direction; units in the headers honoured; other
/// columns ignored. Errors name the file, line and column. The grouping into target positions and
/// the checks of the run counts are done by [`evaluate`].
pub fn read_runs(path: impl AsRef<std::path::Path>) -> Result<PositioningData> {
    runs_of(&CsvTable::read(path)?)
}

/// As [`read_runs`], from any reader; `origin` names the data in messages.
pub fn read_runs_from(reader: impl std::io::Read, origin: &str) -> Result<PositioningData> {
    runs_of(&CsvTable::from_reader(reader, origin)?)
}

/// As [`read_runs`], from text; `origin` names the data in messages.
pub fn read_runs_from_str(text: &str, origin: &str) -> Result<PositioningData> {
    runs_of(&CsvTable::from_text(text, origin)?)
}

/// The readings of a table already read (see [`read_runs`]). A `target` column in an angle unit
/// (`target [deg]`, or a Renishaw file of a rotary axis) makes the test rotary.
pub fn runs_of(table: &CsvTable) -> Result<PositioningData> {
    let origin = table.origin();
    // Check all four columns before any value, so that a missing column is reported as such.
    for name in ["target", "dev", "dir", "run"] {
        table.find(name)?;
    }
    let rotary = table.unit_of("target").is_some_and(|u| u.dimension == Dimension::Angle);
    let dimension = if rotary { Dimension::Angle } else { Dimension::Length };
    let targets = table.numbers_as("target", dimension)?;
    let devs = table.numbers_as("dev", dimension)?;
    let dirs = table.directions("dir")?;
    let runs = table.texts("run")?;
    let invalid = |line: u64, message: String| Error::input(message).in_file(origin).at_line(line as usize);
    let run_column = table.column_text("run").unwrap_or("run").to_string();
    let mut readings = Vec::with_capacity(table.len());
    for (k, &line) in table.lines().iter().enumerate() {
        let direction = match dirs[k] {
            RunDirection::Plus => Direction::Plus,
            RunDirection::Minus => Direction::Minus,
        };
        let run =
            parse_run(&runs[k]).ok_or_else(|| invalid(line, format!("column {run_column}: `{}` is not an integer run number", runs[k])))?;
        readings.push(Reading { target: targets[k], dev: devs[k], direction, run, line });
    }
    Ok(PositioningData { origin: origin.to_string(), readings, rotary, metadata: table.metadata().clone() })
}

/// Findings of the plausibility checks of a positioning table (`io::plausibility`): the size of the
/// deviations and the targets of every run.
pub fn plausibility(table: &CsvTable, data: &PositioningData) -> Result<Vec<crate::io::Finding>> {
    let devs: Vec<f64> = data.readings.iter().map(|r| r.dev).collect();
    let targets: Vec<f64> = data.readings.iter().map(|r| r.target).collect();
    let mut out: Vec<crate::io::Finding> = crate::data::checks::deviation_finding(table, "dev", &devs).into_iter().collect();
    out.extend(crate::data::checks::target_finding(table, &targets, TARGET_TOLERANCE_MM)?);
    Ok(out)
}

fn parse_run(text: &str) -> Option<i64> {
    let t = text.trim();
    // `3`, `3.0` (spreadsheets), `Run 3`
    let t = t.strip_prefix("Run").or_else(|| t.strip_prefix("run")).unwrap_or(t).trim();
    if let Ok(r) = t.parse::<i64>() {
        return Some(r);
    }
    t.parse::<f64>().ok().filter(|v| v.is_finite() && v.fract() == 0.0 && v.abs() < 1e15).map(|v| v as i64)
}

/// Statistics at one target position `P_i` (um unless stated).
#[derive(Clone, Debug, PartialEq)]
pub struct PositionResult {
    /// Target position `P_i` (mm): the value first given in the file among those grouped into it.
    pub target: f64,
    /// Number of runs in the `+` and `-` directions.
    pub n_plus: usize,
    pub n_minus: usize,
    /// Mean unidirectional positional deviations `x̄_i↑`, `x̄_i↓`.
    pub mean_plus: f64,
    pub mean_minus: f64,
    /// Mean bidirectional positional deviation `x̄_i = (x̄_i↑ + x̄_i↓) / 2`.
    pub mean: f64,
    /// Estimators of the unidirectional standard uncertainty of positioning `s_i↑`, `s_i↓`
    /// (sample standard deviations, divisor `n - 1`).
    pub s_plus: f64,
    pub s_minus: f64,
    /// Reversal value `B_i = x̄_i↑ - x̄_i↓`.
    pub reversal: f64,
    /// Unidirectional repeatability of positioning `R_i↑ = 4 s_i↑`, `R_i↓ = 4 s_i↓`.
    pub r_plus: f64,
    pub r_minus: f64,
    /// Bidirectional repeatability `R_i = max(2 s_i↑ + 2 s_i↓ + |B_i|, R_i↑, R_i↓)`.
    pub r: f64,
}

/// The ISO 230-2:2014 results of an axis (um), coverage factor 2.
#[derive(Clone, Debug, PartialEq)]
pub struct Iso2302Result {
    /// Per target position, sorted by increasing target.
    pub positions: Vec<PositionResult>,
    /// Smallest number of runs at any target in either direction.
    pub runs: usize,
    /// Bidirectional accuracy of positioning `A`; unidirectional `A↑`, `A↓`.
    pub a: f64,
    pub a_plus: f64,
    pub a_minus: f64,
    /// Reversal value of the axis `B = max |B_i|`.
    pub b: f64,
    /// Mean reversal value `B̄ = mean of B_i` (signed).
    pub b_mean: f64,
    /// Bidirectional systematic positional deviation `E`; unidirectional `E↑`, `E↓`.
    pub e: f64,
    pub e_plus: f64,
    pub e_minus: f64,
    /// Range of the mean bidirectional positional deviation `M = max x̄_i - min x̄_i`.
    pub m: f64,
    /// Bidirectional repeatability of positioning `R = max R_i`; unidirectional `R↑`, `R↓`.
    pub r: f64,
    pub r_plus: f64,
    pub r_minus: f64,
    /// Unit of the results and deviations: um, or urad for a rotary axis.
    pub unit: &'static str,
    /// Unit of the targets: mm, or deg for a rotary axis.
    pub position_unit: &'static str,
}

/// Evaluates a bidirectional positioning test (ISO 230-2:2014 clause 3 definitions, as used in its
/// clause 8 presentation of results; coverage factor 2): groups the readings by target (within
/// [`TARGET_TOLERANCE_MM`]), checks that no (target, direction, run) is given twice and that every
/// target has at least 2 runs in each direction, and computes, with i the target and j the run:
/// - `x̄_i↑ = mean_j x_ij↑`, `x̄_i↓` likewise, `x̄_i = (x̄_i↑ + x̄_i↓)/2`;
/// - `B_i = x̄_i↑ - x̄_i↓`, `B = max_i |B_i|`, `B̄ = mean_i B_i`;
/// - `s_i↑ = sqrt(Σ_j (x_ij↑ - x̄_i↑)² / (n - 1))`, `s_i↓` likewise;
/// - `R_i↑ = 4 s_i↑`, `R_i↓ = 4 s_i↓`, `R_i = max(2 s_i↑ + 2 s_i↓ + |B_i|, R_i↑, R_i↓)`, and
///   `R↑`, `R↓`, `R` their maxima over i;
/// - `E↑ = max x̄_i↑ - min x̄_i↑`, `E↓` likewise, `E = max(x̄_i↑, x̄_i↓) - min(x̄_i↑, x̄_i↓)` over all i;
/// - `M = max x̄_i - min x̄_i`;
/// - `A↑ = max(x̄_i↑ + 2 s_i↑) - min(x̄_i↑ - 2 s_i↑)`, `A↓` likewise,
///   `A = max(x̄_i↑ + 2 s_i↑, x̄_i↓ + 2 s_i↓) - min(x̄_i↑ - 2 s_i↑, x̄_i↓ - 2 s_i↓)` over all i.
///
/// Inputs: targets in mm, deviations in um; all results in um (deg, urad, urad for a rotary axis).
pub fn evaluate(data: &PositioningData) -> Result<Iso2302Result> {
    let invalid = |message: String| Error::input(message).in_file(&data.origin);
    if data.readings.is_empty() {
        return Err(invalid("no readings".into()));
    }
    if let Some(r) = data.readings.iter().find(|r| !r.target.is_finite() || !r.dev.is_finite()) {
        return Err(invalid(format!("line {}: target and dev must be finite numbers", r.line)));
    }
    let pu = data.position_unit();
    let groups = group_targets(data).map_err(|e| invalid(e.to_string()))?;
    let mut positions = Vec::with_capacity(groups.len());
    for group in &groups {
        // The target as first written in the file (the others are within the tolerance).
        let mut in_file_order = group.clone();
        in_file_order.sort_by_key(|r| r.line);
        let Some(first) = in_file_order.first() else { continue };
        let target = first.target;
        let mut seen: HashMap<(Direction, i64), u64> = HashMap::new();
        for r in &in_file_order {
            if let Some(earlier) = seen.insert((r.direction, r.run), r.line) {
                return Err(invalid(format!(
                    "line {}: target {target} {pu}, dir {}, run {} is given twice (first on line {earlier})",
                    r.line,
                    r.direction.symbol(),
                    r.run
                )));
            }
        }
        let values = |d: Direction| group.iter().filter(|r| r.direction == d).map(|r| r.dev).collect::<Vec<f64>>();
        let (plus, minus) = (values(Direction::Plus), values(Direction::Minus));
        for (d, v) in [(Direction::Plus, &plus), (Direction::Minus, &minus)] {
            if v.len() < 2 {
                return Err(invalid(format!(
                    "line {}: target {target} {pu} has {} run(s) in the {} direction; ISO 230-2 needs at least 2 in each direction (5 in the standard test)",
                    first.line,
                    v.len(),
                    d.symbol()
                )));
            }
        }
        let (mean_plus, s_plus) = mean_and_s(&plus);
        let (mean_minus, s_minus) = mean_and_s(&minus);
        let reversal = mean_plus - mean_minus;
        let (r_plus, r_minus) = (4.0 * s_plus, 4.0 * s_minus);
        positions.push(PositionResult {
            target,
            n_plus: plus.len(),
            n_minus: minus.len(),
            mean_plus,
            mean_minus,
            mean: 0.5 * (mean_plus + mean_minus),
            s_plus,
            s_minus,
            reversal,
            r_plus,
            r_minus,
            r: (2.0 * s_plus + 2.0 * s_minus + reversal.abs()).max(r_plus).max(r_minus),
        });
    }
    let mut result = axis_results(positions);
    result.unit = data.unit();
    result.position_unit = data.position_unit();
    let all = [
        result.a,
        result.a_plus,
        result.a_minus,
        result.b,
        result.b_mean,
        result.e,
        result.e_plus,
        result.e_minus,
        result.m,
        result.r,
        result.r_plus,
        result.r_minus,
    ];
    let positions_finite = result.positions.iter().all(|q| {
        [q.mean_plus, q.mean_minus, q.mean, q.s_plus, q.s_minus, q.reversal, q.r_plus, q.r_minus, q.r].iter().all(|v| v.is_finite())
    });
    if !positions_finite || all.iter().any(|v| !v.is_finite()) {
        return Err(Error::computation(format!(
            "{}: the evaluation overflowed (deviations too large to evaluate in {})",
            data.origin,
            data.unit()
        )));
    }
    Ok(result)
}

/// Groups the readings by target value: sorted, a reading joins the group of the previous one when
/// the targets differ by at most [`TARGET_TOLERANCE_MM`]; a group spanning more than that is refused.
fn group_targets(data: &PositioningData) -> crate::error::Result<Vec<Vec<&Reading>>> {
    let mut sorted: Vec<&Reading> = data.readings.iter().collect();
    sorted.sort_by(|a, b| a.target.total_cmp(&b.target).then(a.line.cmp(&b.line)));
    let mut groups: Vec<Vec<&Reading>> = Vec::new();
    for r in sorted {
        match groups.last_mut() {
            Some(g) if r.target - g.last().map_or(r.target, |p| p.target) <= TARGET_TOLERANCE_MM => {
                if r.target - g[0].target > TARGET_TOLERANCE_MM {
                    return Err(crate::Error::input(format!(
                        "line {}: targets {} mm (line {}) to {} mm chain together within {TARGET_TOLERANCE_MM} mm; give each target position one value",
                        r.line, g[0].target, g[0].line, r.target
                    )));
                }
                g.push(r);
            }
            _ => groups.push(vec![r]),
        }
    }
    Ok(groups)
}

/// Mean and sample standard deviation (divisor n - 1) of at least two values.
fn mean_and_s(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let ss = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>();
    (mean, (ss / (n - 1.0)).sqrt())
}

fn max_of(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(f64::NEG_INFINITY, f64::max)
}

fn min_of(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(f64::INFINITY, f64::min)
}

fn axis_results(positions: Vec<PositionResult>) -> Iso2302Result {
    let p = &positions;
    let range = |f: &dyn Fn(&PositionResult) -> (f64, f64)| max_of(p.iter().map(|q| f(q).1)) - min_of(p.iter().map(|q| f(q).0));
    let e_plus = range(&|q| (q.mean_plus, q.mean_plus));
    let e_minus = range(&|q| (q.mean_minus, q.mean_minus));
    let e = range(&|q| (q.mean_plus.min(q.mean_minus), q.mean_plus.max(q.mean_minus)));
    let m = range(&|q| (q.mean, q.mean));
    let band_plus = |q: &PositionResult| (q.mean_plus - 2.0 * q.s_plus, q.mean_plus + 2.0 * q.s_plus);
    let band_minus = |q: &PositionResult| (q.mean_minus - 2.0 * q.s_minus, q.mean_minus + 2.0 * q.s_minus);
    let a_plus = range(&band_plus);
    let a_minus = range(&band_minus);
    let a = range(&|q| {
        let (u, d) = (band_plus(q), band_minus(q));
        (u.0.min(d.0), u.1.max(d.1))
    });
    Iso2302Result {
        runs: p.iter().map(|q| q.n_plus.min(q.n_minus)).min().unwrap_or(0),
        a,
        a_plus,
        a_minus,
        b: max_of(p.iter().map(|q| q.reversal.abs())),
        b_mean: p.iter().map(|q| q.reversal).sum::<f64>() / p.len() as f64,
        e,
        e_plus,
        e_minus,
        m,
        r: max_of(p.iter().map(|q| q.r)),
        r_plus: max_of(p.iter().map(|q| q.r_plus)),
        r_minus: max_of(p.iter().map(|q| q.r_minus)),
        positions,
        unit: "um",
        position_unit: "mm",
    }
}

impl Iso2302Result {
    /// The JSON document of `trueaxis iso230-2 --json` (docs/design.md, Command line): the axis results `A`,
    /// `A_plus`, `A_minus`, `B`, `B_mean`, `E`, `E_plus`, `E_minus`, `M`, `R`, `R_plus`, `R_minus`
    /// (um), `unit`, `targets`, `runs` and the per-position values in `positions` (target in mm).
    pub fn to_json(&self) -> Value {
        let positions: Vec<Value> = self
            .positions
            .iter()
            .map(|q| {
                json!({
                    "target": q.target,
                    "n_plus": q.n_plus,
                    "n_minus": q.n_minus,
                    "mean_plus": q.mean_plus,
                    "mean_minus": q.mean_minus,
                    "mean": q.mean,
                    "s_plus": q.s_plus,
                    "s_minus": q.s_minus,
                    "B_i": q.reversal,
                    "R_i_plus": q.r_plus,
                    "R_i_minus": q.r_minus,
                    "R_i": q.r,
                })
            })
            .collect();
        json!({
            "A": self.a,
            "A_plus": self.a_plus,
            "A_minus": self.a_minus,
            "B": self.b,
            "B_mean": self.b_mean,
            "E": self.e,
            "E_plus": self.e_plus,
            "E_minus": self.e_minus,
            "M": self.m,
            "R": self.r,
            "R_plus": self.r_plus,
            "R_minus": self.r_minus,
            "unit": self.unit,
            "position_unit": self.position_unit,
            "targets": self.positions.len(),
            "runs": self.runs,
            "positions": positions,
        })
    }

    /// The axis results as (symbol, name, value in um), in the order of ISO 230-2 clause 8.
    pub fn axis_table(&self) -> [(&'static str, &'static str, f64); 12] {
        [
            ("A", "bidirectional accuracy of positioning", self.a),
            ("A+", "unidirectional accuracy of positioning, + direction", self.a_plus),
            ("A-", "unidirectional accuracy of positioning, - direction", self.a_minus),
            ("R", "bidirectional repeatability of positioning", self.r),
            ("R+", "unidirectional repeatability of positioning, + direction", self.r_plus),
            ("R-", "unidirectional repeatability of positioning, - direction", self.r_minus),
            ("E", "bidirectional systematic positional deviation", self.e),
            ("E+", "unidirectional systematic positional deviation, + direction", self.e_plus),
            ("E-", "unidirectional systematic positional deviation, - direction", self.e_minus),
            ("M", "range of mean bidirectional positional deviation", self.m),
            ("B", "reversal value of the axis", self.b),
            ("B_mean", "mean reversal value of the axis", self.b_mean),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(target: f64, dev: f64, direction: Direction, run: i64, line: u64) -> Reading {
        Reading { target, dev, direction, run, line }
    }

    #[test]
    fn two_runs_at_one_target() {
        // + : 1, 3 (mean 2, s = sqrt(2)); - : 0, 0 (mean 0, s = 0); B = 2.
        let data = PositioningData {
            origin: "t".into(),
            readings: vec![
                reading(0.0, 1.0, Direction::Plus, 1, 2),
                reading(0.0, 3.0, Direction::Plus, 2, 3),
                reading(0.0, 0.0, Direction::Minus, 1, 4),
                reading(1e-7, 0.0, Direction::Minus, 2, 5),
            ],
            rotary: false,
            metadata: Default::default(),
        };
        let r = evaluate(&data).unwrap();
        assert_eq!(r.positions.len(), 1);
        let s = 2f64.sqrt();
        assert!((r.positions[0].s_plus - s).abs() < 1e-12);
        assert!((r.b - 2.0).abs() < 1e-12 && (r.b_mean - 2.0).abs() < 1e-12);
        assert!((r.r - (2.0 * s + 2.0).max(4.0 * s)).abs() < 1e-12);
        assert_eq!((r.e_plus, r.e_minus, r.m), (0.0, 0.0, 0.0));
        assert!((r.e - 2.0).abs() < 1e-12);
        // A = max(2 + 2 s, 0) - min(2 - 2 s, 0) = 4 s since 2 - 2 s < 0
        assert!((r.a - 4.0 * s).abs() < 1e-12);
    }

    #[test]
    fn chained_targets_are_refused() {
        let readings = (0..4).map(|k| reading(k as f64 * 0.9e-6, 0.0, Direction::Plus, k, k as u64 + 2)).collect();
        let e = evaluate(&PositioningData { origin: "f.csv".into(), readings, rotary: false, metadata: Default::default() })
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("f.csv: line") && e.contains("chain together"), "{e}");
    }

    #[test]
    fn run_numbers_may_be_written_as_reals() {
        assert_eq!(parse_run("3"), Some(3));
        assert_eq!(parse_run("3.0"), Some(3));
        assert_eq!(parse_run("3.5"), None);
        assert_eq!(parse_run("x"), None);
    }
}
