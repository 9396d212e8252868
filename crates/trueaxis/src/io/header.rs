//! Column headers as instrument software and spreadsheets write them: a name and a unit in
//! brackets, parentheses, after a slash or an underscore (`dev [mm]`, `Position (mm)`, `dev/um`,
//! `Dev_um`, `Deviation um`), names matched without regard to case, spaces or underscores, a few
//! synonyms (`deviation` for `dev`, `direction` for `dir`), and the run-and-direction columns of a
//! wide laser table (`Run 1 +`, `run2_down`, `R3 (-)`).

use super::units::Unit;

/// A parsed column header.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    /// The header as written (trimmed), for messages.
    pub text: String,
    /// The name without its unit.
    pub name: String,
    /// The unit written in the header, if any.
    pub unit: Option<Unit>,
}

/// Units that may follow a name after a space or an underscore without brackets: only those that
/// cannot be read as a word or an axis letter (`C`, `m`, `s`, `min` and `in` need brackets).
const BARE_SUFFIX_UNITS: [&str; 17] =
    ["mm", "um", "µm", "μm", "nm", "deg", "rad", "mrad", "urad", "µrad", "arcsec", "degc", "°c", "°", "um/m", "mm/m", "ms"];

impl Header {
    /// Splits a header into its name and unit (see the module documentation).
    pub fn parse(text: &str) -> Header {
        let text = text.trim().trim_matches('"').trim().to_string();
        let plain = |name: &str, unit: Option<Unit>| Header { text: text.clone(), name: name.trim().to_string(), unit };
        // `name [unit]` or `name (unit)`
        for (open, close) in [('[', ']'), ('(', ')')] {
            if let Some(inner) = text.strip_suffix(close) {
                if let Some(i) = inner.rfind(open) {
                    if let Some(u) = Unit::parse(&inner[i + open.len_utf8()..]) {
                        if !inner[..i].trim().is_empty() {
                            return plain(&inner[..i], Some(u));
                        }
                    }
                }
            }
        }
        // `name/unit` (the unit itself may hold a slash: `dev/um/m`)
        for (i, _) in text.match_indices('/') {
            if let Some(u) = Unit::parse(&text[i + 1..]) {
                if !text[..i].trim().is_empty() {
                    return plain(&text[..i], Some(u));
                }
            }
        }
        // `name_unit` or `name unit`, for units that cannot be mistaken for a word
        if let Some(i) = text.rfind(['_', ' ']) {
            let suffix = text[i + 1..].trim();
            let bare = BARE_SUFFIX_UNITS.iter().any(|b| b.eq_ignore_ascii_case(suffix) || *b == suffix.to_lowercase());
            if bare && !text[..i].trim().is_empty() {
                if let Some(u) = Unit::parse(suffix) {
                    return plain(&text[..i], Some(u));
                }
            }
        }
        plain(&text, None)
    }
}

/// A name reduced for matching: lower case, without spaces, underscores, hyphens and dots.
pub fn normalised(name: &str) -> String {
    name.chars().filter(|c| !matches!(c, ' ' | '_' | '-' | '.' | '\t')).flat_map(char::to_lowercase).collect()
}

/// Other names (normalised) under which instrument software writes a trueaxis column.
pub fn synonyms(name: &str) -> &'static [&'static str] {
    match name {
        "target" => &["position", "targetposition", "nominal", "nominalposition", "setpoint", "commanded", "pos"],
        "position" => &["target", "targetposition", "pos", "nominal", "nominalposition"],
        "dev" => &["deviation", "error", "positionerror", "positionaldeviation", "positioningerror", "err"],
        "dL" => &["dr", "deviation", "radialdeviation", "radiusdeviation", "lengthdeviation", "dev", "error"],
        "dir" => &["direction", "approach", "approachdirection"],
        "run" => &["cycle", "runno", "runnumber", "run#", "lauf"],
        "angle" => &["theta", "angularposition", "phi", "angle(deg)"],
        "t" => &["time"],
        _ => &[],
    }
}

/// Direction of a run in a wide laser table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunDirection {
    Plus,
    Minus,
}

impl RunDirection {
    /// `+` / `-`, `up` / `down`, `fwd` / `bwd`, `forward` / `backward` / `reverse`, `plus` /
    /// `minus`, `pos` / `neg`, `↑` / `↓`, `in` / `out` (German `hin` / `rück`).
    pub fn parse(word: &str) -> Option<RunDirection> {
        match word.trim().to_lowercase().as_str() {
            "+" | "up" | "fwd" | "forward" | "plus" | "pos" | "positive" | "↑" | "in" | "hin" => Some(RunDirection::Plus),
            "-" | "−" | "down" | "dn" | "bwd" | "back" | "backward" | "rev" | "reverse" | "minus" | "neg" | "negative" | "↓" | "out"
            | "rück" | "zurück" => Some(RunDirection::Minus),
            _ => None,
        }
    }

    pub fn symbol(self) -> &'static str {
        match self {
            RunDirection::Plus => "+",
            RunDirection::Minus => "-",
        }
    }
}

/// The run number and direction of a column of a wide laser table (`Run 1 +`, `run1_up`,
/// `R2 (-)`, `+3`, `Run 3 backward`), or `None` when the name is not of that form.
pub fn run_column(name: &str) -> Option<(i64, RunDirection)> {
    let s: String = name
        .chars()
        .map(|c| if matches!(c, '(' | ')' | '[' | ']' | '_' | '#' | ':' | '.' | '/') { ' ' } else { c })
        .collect::<String>()
        .to_lowercase();
    let s: String = s.split_whitespace().collect::<Vec<_>>().join(" ");
    let s = s.trim();
    // strip a prefix word: run, r, cycle, lauf, messung
    let body = ["run", "cycle", "lauf", "messung", "r"]
        .iter()
        .find_map(|p| s.strip_prefix(p).filter(|rest| rest.starts_with(|c: char| c.is_ascii_digit() || c == ' ')))
        .unwrap_or(s)
        .trim();
    let digits_at = |t: &str| t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    // number then direction
    let n = digits_at(body);
    if n > 0 && n <= 6 {
        let run: i64 = body[..n].parse().ok()?;
        let rest = body[n..].trim();
        return RunDirection::parse(rest).map(|d| (run, d));
    }
    // direction then number: `+1`, `up 2`, `fwd run 3`
    let split = body.find(|c: char| c.is_ascii_digit())?;
    let word = body[..split].trim().trim_end_matches("run").trim();
    let number = body[split..].trim();
    if number.is_empty() || number.len() > 6 || !number.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let d = RunDirection::parse(word)?;
    Some((number.parse().ok()?, d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_units_of_headers() {
        let h = Header::parse("dev [mm]");
        assert_eq!((h.name.as_str(), h.unit), ("dev", Some(Unit::MM)));
        let h = Header::parse("Dev_um");
        assert_eq!((h.name.as_str(), h.unit), ("Dev", Some(Unit::UM)));
        let h = Header::parse("Position (mm)");
        assert_eq!((h.name.as_str(), h.unit), ("Position", Some(Unit::MM)));
        let h = Header::parse("T:spindle (°C)");
        assert_eq!((h.name.as_str(), h.unit), ("T:spindle", Some(Unit::DEGC)));
        let h = Header::parse("level/um/m");
        assert_eq!((h.name.as_str(), h.unit), ("level", Some(Unit::URAD)));
        // a bare `C` or `m` is a name, not a unit
        assert_eq!(Header::parse("Axis C").unit, None);
        assert_eq!(Header::parse("C").name, "C");
        assert_eq!(Header::parse("Run 1 (+)").unit, None);
    }

    #[test]
    fn run_columns_of_wide_tables() {
        assert_eq!(run_column("Run 1 +"), Some((1, RunDirection::Plus)));
        assert_eq!(run_column("run2_down"), Some((2, RunDirection::Minus)));
        assert_eq!(run_column("R3 (-)"), Some((3, RunDirection::Minus)));
        assert_eq!(run_column("+4"), Some((4, RunDirection::Plus)));
        assert_eq!(run_column("Run 5 backward"), Some((5, RunDirection::Minus)));
        assert_eq!(run_column("fwd run 6"), Some((6, RunDirection::Plus)));
        assert_eq!(run_column("target"), None);
        assert_eq!(run_column("run"), None);
        assert_eq!(run_column("1"), None);
        assert_eq!(run_column("T:1"), None);
    }
}
