//! Renishaw laser files (`.rtl`): the plain-text result files of Renishaw's laser calibration
//! software, which many other programs read and write.
//!
//! Layout (Renishaw publishes no specification; read from public programs on GitHub that read or
//! write the format, found by a code search: a C# laser-measurement program that writes it, and a
//! Python plotting tool, a C++ pitch-compensation tool and a JavaScript viewer that read it; see
//! docs/user-guide.md, "Instrument files"):
//!
//! ```text
//! HEADER::
//! File type  : rtl
//! TARGET DATA::
//! Filetype  : ISO
//! Target-count: 11
//! Targets :
//! 0.000000 50.000000 100.000000 150.000000 200.000000     (five per line, wrapped)
//! ...
//! Flags: 0 0 2 0
//! USER-TEXT::
//! Machine: ...        Serial No: ...   Date: ...   By: ...   Axis: ...   Location: ...   TITLE: ...
//! RUNS::
//! Run-count: 10
//! DEVIATIONS::
//! Run Target Data:
//! 1   1      0.000000     (run number, target number, deviation)
//! ...
//! ENVIRONMENT::       (optional: Air temp, Air Press, Air Humid, Mat temp 1..3, Exp coeff, ...)
//! EQUIPMENT::         (optional)
//! EOF::
//! ```
//!
//! Lines end in CRLF or LF. Target positions and deviations are in mm, for a rotary axis in deg
//! (taken as rotary when the `Axis` of `USER-TEXT::` is A, B or C or names a rotary axis). A run's
//! direction of approach follows the order its target numbers are listed in: towards increasing
//! positions is `+`. The readings are actual minus target (the laser's reading minus the target).

use super::header::RunDirection;
use super::metadata::Metadata;
use super::text::{clip, key_value, numbered_lines, parse_number};
use super::IoError;
use std::fmt::Write;

/// One reading of a run: the target number (1-based, as in the file), the deviation in the file's
/// unit (mm, or deg for a rotary axis) and the line it was read from.
#[derive(Clone, Debug, PartialEq)]
pub struct RtlReading {
    pub target: usize,
    pub deviation: f64,
    pub line: u64,
}

/// One run: its number, direction of approach and readings in file order.
#[derive(Clone, Debug, PartialEq)]
pub struct RtlRun {
    pub number: i64,
    pub direction: RunDirection,
    pub readings: Vec<RtlReading>,
}

/// A Renishaw laser file held in memory.
#[derive(Clone, Debug, PartialEq)]
pub struct RtlFile {
    /// Target positions by target number - 1 (mm, or deg for a rotary axis).
    pub targets: Vec<f64>,
    pub runs: Vec<RtlRun>,
    /// True when the axis is rotary: positions and deviations in deg.
    pub rotary: bool,
    pub metadata: Metadata,
    /// Suspicious but usable content (a run count that differs from the runs given, a run whose
    /// targets are not listed in order).
    pub warnings: Vec<String>,
}

/// True when `text` looks like a Renishaw laser file: a `TARGET DATA::` or `DEVIATIONS::` section.
pub fn looks_like(text: &str) -> bool {
    text.lines().take(400).any(|l| {
        let t = l.trim().to_ascii_uppercase();
        t == "TARGET DATA::" || t == "DEVIATIONS::"
    })
}

fn section_of(line: &str) -> Option<String> {
    let t = line.trim();
    let name = t.strip_suffix("::")?;
    (!name.is_empty() && !name.contains(':') && name.len() <= 40).then(|| name.trim().to_ascii_uppercase())
}

/// True when the `Axis` text names a rotary axis (`C`, `A axis`, `rotary table`).
fn rotary_axis(axis: &str) -> bool {
    let a = axis.trim().to_ascii_lowercase();
    let first = a.split(|c: char| !c.is_alphanumeric()).next().unwrap_or("");
    matches!(first, "a" | "b" | "c") || a.contains("rotary") || a.contains("rot")
}

/// Parses the text of a `.rtl` file; `origin` names it in messages. Every error names the line.
pub fn parse(text: &str, origin: &str) -> Result<RtlFile, IoError> {
    let text = super::text::strip_bom(text);
    let bad = |line: u64, message: String| IoError::Invalid { origin: origin.to_string(), message: format!("line {line}: {message}") };
    let mut section = String::new();
    let mut target_count: Option<(usize, u64)> = None;
    let mut run_count: Option<(i64, u64)> = None;
    let mut targets: Vec<(f64, u64)> = Vec::new();
    let mut collecting_targets = false;
    let mut in_deviations = false;
    let mut pairs: Vec<(String, String)> = Vec::new();
    let mut readings: Vec<(i64, usize, f64, u64)> = Vec::new();
    let mut seen_deviations = false;
    for (number, raw) in numbered_lines(text) {
        let line = raw.trim();
        if line.is_empty() || line.starts_with("//") {
            continue;
        }
        if let Some(s) = section_of(line) {
            section = s;
            collecting_targets = false;
            in_deviations = false;
            if section == "DEVIATIONS" {
                seen_deviations = true;
            }
            if section == "EOF" {
                break;
            }
            continue;
        }
        match section.as_str() {
            "TARGET DATA" => {
                if let Some((key, value)) = key_value(line) {
                    let key = key.to_ascii_lowercase().replace(' ', "");
                    collecting_targets = key == "targets";
                    match key.as_str() {
                        "target-count" | "targetcount" => {
                            let n =
                                value.parse::<usize>().ok().filter(|n| *n >= 1 && *n <= 100_000).ok_or_else(|| {
                                    bad(number, format!("Target-count `{value}` is not a count of targets (1 to 100000)"))
                                })?;
                            target_count = Some((n, number));
                        }
                        "targets" => push_numbers(value, number, &mut targets, &bad)?,
                        // Filetype, Flags: internals of the laser software
                        _ => {}
                    }
                } else if collecting_targets {
                    push_numbers(line, number, &mut targets, &bad)?;
                } else {
                    return Err(bad(number, format!("unexpected `{}` in TARGET DATA:: (expected Target-count, Targets)", clip(line))));
                }
            }
            "RUNS" => {
                if let Some((key, value)) = key_value(line) {
                    if key.to_ascii_lowercase().replace(' ', "").starts_with("run-count") {
                        let n = value
                            .parse::<i64>()
                            .ok()
                            .filter(|n| *n >= 1 && *n <= 100_000)
                            .ok_or_else(|| bad(number, format!("Run-count `{value}` is not a count of runs (1 to 100000)")))?;
                        run_count = Some((n, number));
                    }
                }
            }
            "DEVIATIONS" => {
                if line.to_ascii_lowercase().starts_with("run target data") {
                    in_deviations = true;
                    continue;
                }
                if !in_deviations {
                    return Err(bad(number, format!("unexpected `{}` before `Run Target Data:` in DEVIATIONS::", clip(line))));
                }
                let fields: Vec<&str> = line.split_whitespace().collect();
                if fields.len() != 3 {
                    return Err(bad(
                        number,
                        format!("expected three fields `run target deviation`, found {} in `{}`", fields.len(), clip(line)),
                    ));
                }
                let run = fields[0]
                    .parse::<i64>()
                    .ok()
                    .filter(|r| *r >= 0 && *r <= 1_000_000)
                    .ok_or_else(|| bad(number, format!("run number `{}` is not a whole number", fields[0])))?;
                let target = fields[1]
                    .parse::<usize>()
                    .ok()
                    .filter(|t| *t >= 1)
                    .ok_or_else(|| bad(number, format!("target number `{}` is not a whole number from 1", fields[1])))?;
                let dev = parse_number(fields[2], true).ok_or_else(|| bad(number, format!("deviation `{}` is not a number", fields[2])))?;
                if !dev.is_finite() {
                    return Err(bad(number, format!("deviation `{}` is not a finite number", fields[2])));
                }
                readings.push((run, target, dev, number));
            }
            "USER-TEXT" | "ENVIRONMENT" | "EQUIPMENT" => {
                if let Some((key, value)) = key_value(line) {
                    let key = if section == "EQUIPMENT" { format!("Equipment {key}") } else { key.into() };
                    pairs.push((key, value.to_string()));
                }
            }
            _ => {}
        }
    }
    let Some((count, count_line)) = target_count else {
        return Err(IoError::Invalid { origin: origin.into(), message: "no `Target-count:` in a TARGET DATA:: section".into() });
    };
    if targets.len() != count {
        let line = targets.last().map_or(count_line, |t| t.1);
        return Err(bad(line, format!("Target-count is {count} (line {count_line}) but {} target positions are listed", targets.len())));
    }
    if !seen_deviations || readings.is_empty() {
        return Err(IoError::Invalid {
            origin: origin.into(),
            message: "no readings: the file has no `DEVIATIONS::` with `Run Target Data:` rows".into(),
        });
    }
    let metadata = Metadata::from_pairs(pairs.iter().map(|(k, v)| (k.as_str(), v.as_str())));
    let rotary = metadata.axis.as_deref().is_some_and(rotary_axis);
    let positions: Vec<f64> = targets.iter().map(|t| t.0).collect();
    let mut runs: Vec<RtlRun> = Vec::new();
    let mut warnings = Vec::new();
    for &(run, target, deviation, line) in &readings {
        if target > count {
            return Err(bad(line, format!("target number {target}, but Target-count is {count}")));
        }
        let r = match runs.iter().position(|r| r.number == run) {
            Some(i) => &mut runs[i],
            None => {
                runs.push(RtlRun { number: run, direction: RunDirection::Plus, readings: Vec::new() });
                runs.last_mut().expect("pushed")
            }
        };
        if let Some(earlier) = r.readings.iter().find(|x| x.target == target) {
            return Err(bad(line, format!("run {run}, target {target} is given twice (first on line {})", earlier.line)));
        }
        r.readings.push(RtlReading { target, deviation, line });
    }
    for r in &mut runs {
        let (first, last) = (&r.readings[0], &r.readings[r.readings.len() - 1]);
        let (p0, p1) = (positions[first.target - 1], positions[last.target - 1]);
        if r.readings.len() < 2 || p0 == p1 {
            return Err(bad(first.line, format!("run {} reads only target position {p0}; its direction of approach is unknown", r.number)));
        }
        r.direction = if p1 > p0 { RunDirection::Plus } else { RunDirection::Minus };
        let sign = if p1 > p0 { 1.0 } else { -1.0 };
        if r.readings.windows(2).any(|w| sign * (positions[w[1].target - 1] - positions[w[0].target - 1]) <= 0.0) {
            warnings.push(format!(
                "run {} (from line {}) does not list its targets in order of position; its direction {} is that of its first and last target",
                r.number,
                first.line,
                r.direction.symbol()
            ));
        }
    }
    if let Some((n, line)) = run_count {
        if n as usize != runs.len() {
            warnings.push(format!("line {line}: Run-count is {n} but {} runs have readings", runs.len()));
        }
    }
    Ok(RtlFile { targets: positions, runs, rotary, metadata, warnings })
}

fn push_numbers(text: &str, line: u64, out: &mut Vec<(f64, u64)>, bad: &dyn Fn(u64, String) -> IoError) -> Result<(), IoError> {
    for field in text.split_whitespace() {
        let v =
            parse_number(field, true).filter(|v| v.is_finite()).ok_or_else(|| bad(line, format!("target `{field}` is not a number")))?;
        if out.len() >= 100_000 {
            return Err(bad(line, "more than 100000 targets".into()));
        }
        out.push((v, line));
    }
    Ok(())
}

impl RtlFile {
    /// The unit of positions and deviations in the file: mm, or deg for a rotary axis.
    pub fn unit(&self) -> &'static str {
        if self.rotary {
            "deg"
        } else {
            "mm"
        }
    }

    /// Writes the file in the layout [`parse`] reads (CRLF line ends, targets five per line,
    /// deviations with 6 decimals: 1 nm or 1e-6 deg), e.g. to hand readings to software that reads
    /// `.rtl` files, and for round-trip tests.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let nl = "\r\n";
        let _ = write!(s, "HEADER::{nl}File type  : rtl{nl}Owner      : trueaxis{nl}Version no : 1{nl}{nl}");
        let _ = write!(s, "TARGET DATA::{nl}Filetype  : ISO{nl}Target-count: {}{nl}Targets :{nl}", self.targets.len());
        for chunk in self.targets.chunks(5) {
            let row: Vec<String> = chunk.iter().map(|t| format!("{t:.6}")).collect();
            let _ = write!(s, "{}{nl}", row.join(" "));
        }
        let _ = write!(s, "Flags: 0 0 2 0{nl}{nl}USER-TEXT::{nl}");
        let m = &self.metadata;
        for (key, value) in [
            ("Machine", &m.machine),
            ("Serial No", &m.serial),
            ("Date", &m.date),
            ("By", &m.operator),
            ("Axis", &m.axis),
            ("Location", &m.location),
            ("TITLE", &m.title),
        ] {
            let _ = write!(s, "{key}: {}{nl}", value.as_deref().unwrap_or(""));
        }
        let _ = write!(s, "{nl}RUNS::{nl}Run-count: {}{nl}{nl}DEVIATIONS::{nl}Run Target Data:{nl}", self.runs.len());
        for r in &self.runs {
            for x in &r.readings {
                let _ = write!(s, "{}   {}      {:.6}{nl}", r.number, x.target, x.deviation);
            }
        }
        let e = &m.environment;
        if !e.is_empty() {
            let _ = write!(s, "{nl}ENVIRONMENT::{nl}");
            if let Some(t) = e.air_temperature_degc {
                let _ = write!(s, "Air temp   : {t}{nl}");
            }
            for (i, t) in e.material_temperatures_degc.iter().enumerate() {
                let _ = write!(s, "Mat temp {} : {t}{nl}", i + 1);
            }
            if let Some(a) = e.expansion_coefficient_um_per_m_k {
                let _ = write!(s, "Exp coeff  : {a}{nl}");
            }
        }
        let _ = write!(s, "{nl}EOF::{nl}");
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "HEADER::\r\nFile type  : rtl\r\n\r\nTARGET DATA::\r\nFiletype  : ISO\r\nTarget-count: 3\r\nTargets :\r\n\
0.000000 100.000000\r\n200.000000\r\nFlags: 0 0 2 0\r\n\r\nUSER-TEXT::\r\nMachine: VMC 3\r\nAxis: X\r\n\r\nRUNS::\r\nRun-count: 2\r\n\r\n\
DEVIATIONS::\r\nRun Target Data:\r\n1   1      0.000000\r\n1   2      0.001500\r\n1   3      0.002500\r\n\
2   3      0.003000\r\n2   2      0.002000\r\n2   1      0.000400\r\n\r\nEOF::\r\n";

    #[test]
    fn reads_targets_wrapped_over_lines_runs_and_directions() {
        let f = parse(SMALL, "x.rtl").unwrap();
        assert_eq!(f.targets, vec![0.0, 100.0, 200.0]);
        assert_eq!(f.runs.len(), 2);
        assert_eq!(f.runs[0].direction, RunDirection::Plus);
        assert_eq!(f.runs[1].direction, RunDirection::Minus);
        assert_eq!(f.runs[1].readings[0], RtlReading { target: 3, deviation: 0.003, line: 24 });
        assert_eq!(f.metadata.machine.as_deref(), Some("VMC 3"));
        assert!(!f.rotary);
        assert!(f.warnings.is_empty(), "{:?}", f.warnings);
        let again = parse(&f.to_text(), "again.rtl").unwrap();
        assert_eq!(again.targets, f.targets);
        // (run, direction, target, deviation) of every reading
        let numbers = |g: &RtlFile| -> Vec<(i64, RunDirection, usize, f64)> {
            g.runs.iter().flat_map(|r| r.readings.iter().map(move |x| (r.number, r.direction, x.target, x.deviation))).collect()
        };
        assert_eq!(numbers(&again), numbers(&f));
        assert_eq!(again.metadata, f.metadata);
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse(&SMALL.replace("2   2      0.002000", "2   7      0.002000"), "x.rtl").unwrap_err().to_string();
        assert!(e.contains("x.rtl: line 25: target number 7, but Target-count is 3"), "{e}");
        let e = parse(&SMALL.replace("Target-count: 3", "Target-count: 4"), "x.rtl").unwrap_err().to_string();
        assert!(e.contains("Target-count is 4") && e.contains("3 target positions"), "{e}");
        let e = parse(&SMALL.replace("0.001500", "abc"), "x.rtl").unwrap_err().to_string();
        assert!(e.contains("line 22: deviation `abc` is not a number"), "{e}");
    }
}
