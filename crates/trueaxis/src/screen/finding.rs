//! The one result type of screening: a [`Finding`] names the kind of damage, the file, where in it
//! (run, column, rows), what was seen, and what it means for the result. A finding either flags the
//! data (the command goes on and prints it, and `--json` carries it under `data_quality`) or
//! refuses it as bad input (a result from it would be meaningless).

use serde_json::{json, Value};

/// The kind of damage a check looks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// A run or column whose size is that of another unit (mm among um, degF among degC, m among mm).
    Unit,
    /// A run or column whose values do not agree with the others (another axis, another test).
    Inconsistent,
    /// Identical readings repeated where noise is expected: a stuck sensor or a frozen logger.
    Stuck,
    /// Rows recorded twice: counted as independent they shrink every uncertainty.
    Duplicate,
    /// Readings beyond the robust limit from their neighbours or from the fit.
    Outlier,
    /// A jump of one channel that its neighbours in time do not explain (a re-seated sensor).
    Step,
    /// A pause in a time series much longer than its sampling interval.
    Gap,
    /// A temperature outside what its sensor's role allows, or one that looks like degF.
    Temperature,
    /// The temperature changed during a test by enough to matter for the result.
    Drift,
    /// A ballbar file whose axis positions do not describe the circle it is evaluated as.
    Geometry,
    /// Cells missing (a logger dropout), skipped on request.
    Missing,
}

impl Kind {
    /// The name used in messages and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Unit => "unit",
            Kind::Inconsistent => "inconsistent",
            Kind::Stuck => "stuck sensor",
            Kind::Duplicate => "duplicate rows",
            Kind::Outlier => "outlier",
            Kind::Step => "step",
            Kind::Gap => "gap",
            Kind::Temperature => "temperature",
            Kind::Drift => "temperature drift",
            Kind::Geometry => "geometry",
            Kind::Missing => "missing cells",
        }
    }
}

/// One suspect part of a file.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    pub kind: Kind,
    /// The file (as given on the command line or in the campaign).
    pub file: String,
    /// Where in the file: `run 4 (+)`, `column dz`, `column T:p1, lines 120-198`.
    pub place: String,
    /// What was seen, with numbers and their units.
    pub message: String,
    /// What it means for the result (e.g. "R would be 4.1 um without run 4"); may be empty.
    pub consequence: String,
    /// True when the data cannot give a meaningful result (the command refuses it).
    pub refuse: bool,
    /// 1-based file lines of the suspect readings (for listings and exclusion), may be empty.
    pub lines: Vec<u64>,
}

impl Finding {
    pub fn flag(kind: Kind, file: &str, place: impl Into<String>, message: impl Into<String>) -> Finding {
        Finding {
            kind,
            file: file.into(),
            place: place.into(),
            message: message.into(),
            consequence: String::new(),
            refuse: false,
            lines: Vec::new(),
        }
    }

    pub fn refusing(mut self) -> Finding {
        self.refuse = true;
        self
    }

    pub fn with_lines(mut self, lines: Vec<u64>) -> Finding {
        self.lines = lines;
        self
    }

    pub fn with_consequence(mut self, consequence: impl Into<String>) -> Finding {
        self.consequence = consequence.into();
        self
    }

    /// One line: `file: place: kind: message; consequence`.
    pub fn line(&self) -> String {
        let consequence = if self.consequence.is_empty() { String::new() } else { format!("; {}", self.consequence) };
        format!("{}: {}: {}: {}{consequence}", self.file, self.place, self.kind.name(), self.message)
    }

    pub fn to_json(&self) -> Value {
        json!({
            "kind": self.kind.name(),
            "file": self.file,
            "place": self.place,
            "message": self.message,
            "consequence": self.consequence,
            "refused": self.refuse,
            "lines": self.lines,
        })
    }
}

/// The `data_quality` member of a command's JSON document: the findings, empty when none.
pub fn findings_json(findings: &[Finding]) -> Value {
    Value::Array(findings.iter().map(Finding::to_json).collect())
}

/// Lines as a short text: `12, 14, 20-35` (at most 8 ranges, then `and N more`).
pub fn lines_text(lines: &[u64]) -> String {
    let mut sorted = lines.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let mut ranges: Vec<(u64, u64)> = Vec::new();
    for l in sorted {
        match ranges.last_mut() {
            Some((_, hi)) if *hi + 1 == l => *hi = l,
            _ => ranges.push((l, l)),
        }
    }
    let more = ranges.len().saturating_sub(8);
    let mut parts: Vec<String> =
        ranges.iter().take(8).map(|&(lo, hi)| if lo == hi { lo.to_string() } else { format!("{lo}-{hi}") }).collect();
    if more > 0 {
        parts.push(format!("and {more} more"));
    }
    parts.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_ranges() {
        assert_eq!(lines_text(&[5, 3, 4, 9, 12, 11]), "3-5, 9, 11-12");
    }
}
