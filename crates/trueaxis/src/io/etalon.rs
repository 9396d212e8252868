//! The Etalon exchange format: error parameters of a volumetric calibration with an Etalon
//! LaserTRACER and TRAC-CAL, as the ISG kernel and Beckhoff TwinCAT TF5280 (Volumetric
//! Compensation) read them, "Vendor" variant (Beckhoff Information System, TF5280, "Etalon Exchange
//! Format", "Units of measure", "List of parameters supported"):
//!
//! ```text
//! // comment
//! [C0B]                       position (location) error: one value
//! VALUE = 0.000022355737
//! [EXY]                       component (motion) error: a lookup table of (argument, value)
//! Gridpoints = {
//!    -280.0 -0.001358635132
//!    ...
//! }  // end of EXY
//! ```
//!
//! Values are in mm (translations) and rad (rotations); arguments in mm (linear axes) and deg
//! (rotary axes). Position errors are named `X0C`, `A0B`, `C0Y` (ISO 230-1 `EX0C`, `EA0B`, `EC0Y`
//! without the leading `E`), component errors `EXX` ... `ECC` as in ISO 230-1. Assumed (no public
//! statement found): the sign is that of ISO 230-1 (actual minus nominal), the one trueaxis uses,
//! as for the ISG CSV format of the same controller. ISG's own kinematic parameters (`P0X`, `N0X`,
//! `PXA`, `VXX`, ...) are nominal geometry, not errors, and are not converted.

use super::text::{clip, numbered_lines, parse_number};
use super::IoError;

/// The value of one parameter block.
#[derive(Clone, Debug, PartialEq)]
pub enum EtalonValue {
    /// `VALUE = v` (mm or rad).
    Constant(f64),
    /// `Gridpoints = { argument value ... }` (argument mm or deg, value mm or rad), in file order.
    Table(Vec<(f64, f64)>),
}

/// One `[NAME]` block.
#[derive(Clone, Debug, PartialEq)]
pub struct EtalonParameter {
    /// The name as written (`C0B`, `EXY`).
    pub name: String,
    /// Line of the `[NAME]`.
    pub line: u64,
    pub value: EtalonValue,
}

/// An Etalon exchange file held in memory.
#[derive(Clone, Debug, PartialEq)]
pub struct EtalonFile {
    pub parameters: Vec<EtalonParameter>,
    /// Keys the format does not define, as `line N: ...`.
    pub warnings: Vec<String>,
}

/// True when `text` looks like an Etalon exchange file: a `[NAME]` block followed by `VALUE =` or
/// `Gridpoints =`.
pub fn looks_like(text: &str) -> bool {
    let mut block = false;
    for line in text.lines().take(2000) {
        let t = strip_comment(line).trim();
        if t.starts_with('[') && t.ends_with(']') {
            block = true;
        } else if block {
            let key = t.split('=').next().unwrap_or("").trim().to_ascii_lowercase();
            if t.contains('=') && (key == "value" || key == "gridpoints") {
                return true;
            }
        }
    }
    false
}

fn strip_comment(line: &str) -> &str {
    line.find("//").map_or(line, |i| &line[..i])
}

/// Parses an Etalon exchange file; `origin` names it in messages, which name the line.
pub fn parse(text: &str, origin: &str) -> Result<EtalonFile, IoError> {
    let bad = |line: u64, message: String| IoError::Invalid { origin: origin.to_string(), message: format!("line {line}: {message}") };
    let mut parameters: Vec<EtalonParameter> = Vec::new();
    let mut warnings = Vec::new();
    let mut current: Option<(String, u64, Option<EtalonValue>)> = None;
    // an open `Gridpoints = {`: its numbers and the line it started on
    let mut grid: Option<(Vec<f64>, u64)> = None;
    let finish = |current: &mut Option<(String, u64, Option<EtalonValue>)>, parameters: &mut Vec<EtalonParameter>| -> Result<(), IoError> {
        if let Some((name, line, value)) = current.take() {
            let value = value.ok_or_else(|| bad(line, format!("[{name}] has neither `VALUE =` nor `Gridpoints = {{ ... }}`")))?;
            if let Some(p) = parameters.iter().find(|p| p.name.eq_ignore_ascii_case(&name)) {
                return Err(bad(line, format!("[{name}] is given twice (first on line {})", p.line)));
            }
            parameters.push(EtalonParameter { name, line, value });
        }
        Ok(())
    };
    for (number, raw) in numbered_lines(super::text::strip_bom(text)) {
        let line = strip_comment(raw).trim();
        if let Some((values, start)) = grid.as_mut() {
            let (body, closed) = match line.find('}') {
                Some(i) => (&line[..i], true),
                None => (line, false),
            };
            for field in body.split_whitespace() {
                let v = parse_number(field, true).ok_or_else(|| bad(number, format!("`{field}` in Gridpoints is not a number")))?;
                if !v.is_finite() {
                    return Err(bad(number, format!("`{field}` in Gridpoints is not a finite number")));
                }
                if values.len() >= 200_000 {
                    return Err(bad(number, "more than 100000 grid points".into()));
                }
                values.push(v);
            }
            if closed {
                let start = *start;
                let (values, _) = grid.take().expect("open grid");
                if values.len() % 2 != 0 {
                    return Err(bad(start, format!("Gridpoints has {} numbers; expected pairs `argument value`", values.len())));
                }
                let pairs: Vec<(f64, f64)> = values.chunks(2).map(|c| (c[0], c[1])).collect();
                if let Some((_, _, slot)) = current.as_mut() {
                    *slot = Some(EtalonValue::Table(pairs));
                }
            }
            continue;
        }
        if line.is_empty() {
            continue;
        }
        if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            finish(&mut current, &mut parameters)?;
            let name = name.trim();
            if name.is_empty() || name.len() > 16 {
                return Err(bad(number, format!("`[{name}]` is not a parameter name")));
            }
            current = Some((name.to_string(), number, None));
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            return Err(bad(number, format!("expected `[NAME]`, `VALUE = number` or `Gridpoints = {{`, found `{}`", clip(line))));
        };
        let key = key.trim().to_ascii_lowercase();
        let Some((name, _, slot)) = current.as_mut() else {
            warnings.push(format!("line {number}: `{}` outside a [NAME] block is ignored", clip(line)));
            continue;
        };
        if slot.is_some() && (key == "value" || key == "gridpoints") {
            return Err(bad(number, format!("[{name}] has a second value")));
        }
        match key.as_str() {
            "value" => {
                let v =
                    parse_number(value, true).ok_or_else(|| bad(number, format!("[{name}] VALUE `{}` is not a number", value.trim())))?;
                if !v.is_finite() {
                    return Err(bad(number, format!("[{name}] VALUE `{}` is not a finite number", value.trim())));
                }
                *slot = Some(EtalonValue::Constant(v));
            }
            "gridpoints" => {
                let rest = value.trim();
                let Some(after) = rest.strip_prefix('{') else {
                    return Err(bad(number, format!("[{name}] Gridpoints must start with `{{`")));
                };
                grid = Some((Vec::new(), number));
                // numbers (and the closing brace) on the same line are handled as a grid line
                let (values, _) = grid.as_mut().expect("just set");
                let (body, closed) = match after.find('}') {
                    Some(i) => (&after[..i], true),
                    None => (after, false),
                };
                for field in body.split_whitespace() {
                    let v = parse_number(field, true)
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| bad(number, format!("`{field}` in Gridpoints is not a finite number")))?;
                    values.push(v);
                }
                if closed {
                    let (values, start) = grid.take().expect("open grid");
                    if values.len() % 2 != 0 {
                        return Err(bad(start, format!("Gridpoints has {} numbers; expected pairs `argument value`", values.len())));
                    }
                    *slot = Some(EtalonValue::Table(values.chunks(2).map(|c| (c[0], c[1])).collect()));
                }
            }
            other => warnings.push(format!("line {number}: [{name}] key `{other}` is not part of the exchange format; ignored")),
        }
    }
    if let Some((_, start)) = grid {
        return Err(bad(start, "Gridpoints `{` is never closed by `}`".into()));
    }
    finish(&mut current, &mut parameters)?;
    if parameters.is_empty() {
        return Err(IoError::Invalid { origin: origin.into(), message: "no [NAME] parameter blocks".into() });
    }
    Ok(EtalonFile { parameters, warnings })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_values_and_grids() {
        let text = "// Etalon\n[C0B]\nVALUE = 0.000022355737\n[EXY]\nGridpoints = {\n -280.0 -0.001358635132\n -270.0 -0.000240680764\n}  // end\n\
                    [EYY]\nGridpoints = { 0 0.001 10 0.002 }\n[P0X]\nVALUE = 100\n";
        let f = parse(text, "e.exc").unwrap();
        assert_eq!(f.parameters.len(), 4);
        assert_eq!(f.parameters[0].value, EtalonValue::Constant(0.000022355737));
        assert_eq!(f.parameters[1].value, EtalonValue::Table(vec![(-280.0, -0.001358635132), (-270.0, -0.000240680764)]));
        assert_eq!(f.parameters[2].value, EtalonValue::Table(vec![(0.0, 0.001), (10.0, 0.002)]));
        assert!(looks_like(text));
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse("[EXX]\nGridpoints = {\n 0 1\n 10\n}\n", "e.exc").unwrap_err().to_string();
        assert!(e.contains("e.exc: line 2: Gridpoints has 3 numbers"), "{e}");
        let e = parse("[EXX]\nVALUE = x\n", "e.exc").unwrap_err().to_string();
        assert!(e.contains("line 2: [EXX] VALUE `x` is not a number"), "{e}");
        let e = parse("[EXX]\nGridpoints = {\n 0 1\n", "e.exc").unwrap_err().to_string();
        assert!(e.contains("line 2: Gridpoints `{` is never closed"), "{e}");
    }
}
