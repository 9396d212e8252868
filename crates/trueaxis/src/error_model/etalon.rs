//! Error-values files from the parameters of an Etalon exchange file (`io::etalon`, which reads the
//! file into plain records): position errors become `[constant]` entries, component errors
//! `[table.NAME]` (docs/design.md, Files). The file's values are in mm (translations) and rad
//! (rotations), the error-values file's in um and urad: translations are scaled by 1e3, rotations
//! by 1e6, then rounded to 1e-9 um or urad (the file's 1e-12 mm or rad) to drop the binary noise of
//! the scaling. Arguments stay as in the file (mm for linear axes, deg for rotary axes).

use super::{set_error_function, ErrorFunction, ErrorModel};
use crate::error::{Error, Result};
use crate::io::etalon::{EtalonFile, EtalonParameter, EtalonValue};
use crate::io::{plausibility, Severity};
use crate::machine::{Machine, ParameterId};

/// The result of converting an exchange file into an error-values file.
#[derive(Clone, Debug)]
pub struct Conversion {
    /// The error-values TOML (um, urad; positions mm, deg), checked against the machine.
    pub toml: String,
    /// The parameters written, by ISO name.
    pub written: Vec<String>,
    /// Blocks not converted and suspicious values, each naming the line.
    pub warnings: Vec<String>,
}

/// Converts the parameters of `file` into an error-values file for `machine`; `origin` names the
/// file in messages. A parameter of an axis the machine does not have, a lookup table of a
/// position error, and values far outside what a machine tool can have (a sign of another unit)
/// are refused as bad input, with the line named.
pub fn from_etalon(file: &EtalonFile, machine: &Machine, origin: &str) -> Result<Conversion> {
    let mut text = format!(
        "# Converted by trueaxis from the Etalon exchange file {origin} for machine `{}`.\n\
         # Values: mm and rad in the file, um and urad here; positions in mm (linear) and deg (rotary).\n",
        machine.name
    );
    let mut written = Vec::new();
    let mut warnings: Vec<String> = file.warnings.clone();
    for p in &file.parameters {
        let bad = |message: String| Error::input(message).in_file(origin).at_line(p.line as usize);
        let id = match parameter_id(&p.name) {
            Ok(Some(id)) => id,
            Ok(None) => {
                warnings.push(format!(
                    "line {}: [{}] is a kinematic parameter of the ISG model (nominal geometry), not converted",
                    p.line, p.name
                ));
                continue;
            }
            Err(e) => return Err(bad(format!("[{}]: {e}", p.name))),
        };
        machine.parameter_index(&id).map_err(|e| bad(format!("[{}]: {e}; give the machine the file was measured on", p.name)))?;
        let function = error_function(p, id, &mut warnings).map_err(|e| bad(e.to_string()))?;
        text = set_error_function(&text, &id, None, &function).map_err(|e| bad(e.to_string()))?;
        written.push(id.to_string());
    }
    if written.is_empty() {
        return Err(Error::input("no error parameter to convert").in_file(origin));
    }
    ErrorModel::from_toml_str(&text, origin, machine).map_err(|e| Error::input(e.to_string()).in_file(origin))?;
    Ok(Conversion { toml: text, written, warnings })
}

/// The error function of one parameter block (um or urad), its scale checked (a refusal is the
/// error, a warning is pushed onto `warnings` naming the line); messages without the line.
fn error_function(p: &EtalonParameter, id: ParameterId, warnings: &mut Vec<String>) -> Result<ErrorFunction> {
    let rotation = id.component().is_rotation();
    let factor = if rotation { 1e6 } else { 1e3 };
    let scale = |v: f64| (v * factor * 1e9).round() / 1e9;
    let values: Vec<f64> = match &p.value {
        EtalonValue::Constant(v) => vec![*v],
        EtalonValue::Table(pairs) => pairs.iter().map(|x| x.1).collect(),
    };
    let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if let Some(f) = plausibility::error_parameter_scale(largest, rotation, &format!("[{}]", p.name)) {
        match f.severity {
            Severity::Refuse => return Err(Error::input(f.message)),
            Severity::Warn => warnings.push(format!("line {}: {}", p.line, f.message)),
        }
    }
    match (&p.value, id) {
        (EtalonValue::Constant(v), _) => Ok(ErrorFunction::Constant(scale(*v))),
        (EtalonValue::Table(pairs), ParameterId::Motion { .. }) => {
            let mut sorted = pairs.clone();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            if let Some(w) = sorted.windows(2).find(|w| w[0].0 == w[1].0) {
                return Err(Error::input(format!("[{}]: the argument {} is given twice", p.name, w[0].0)));
            }
            let positions = sorted.iter().map(|x| x.0).collect();
            let values = sorted.iter().map(|x| scale(x.1)).collect();
            ErrorFunction::table(positions, values, None).map_err(|e| e.context(format!("[{}]", p.name)))
        }
        (EtalonValue::Table(_), _) => {
            Err(Error::input(format!("[{}] ({id}) is a position error, a constant: give it as `VALUE =`", p.name)))
        }
    }
}

/// ISG's kinematic parameters (nominal geometry, not errors): `P0X`, `N0X`, `PXA`, `VXX`.
fn is_isg_geometry(name: &str) -> bool {
    let c: Vec<char> = name.chars().collect();
    match c.as_slice() {
        ['P' | 'N', '0', a] => "XYZ".contains(*a),
        ['P', d, a] => "XYZ".contains(*d) && "ABC".contains(*a),
        ['V', d, a] => "XYZ".contains(*d) && "XYZABC".contains(*a),
        _ => false,
    }
}

/// The ISO 230-1 id of an exchange-format name: `X0C` -> `EX0C`, `EXY` -> `EXY`; `None` for ISG's
/// kinematic parameters.
pub fn parameter_id(name: &str) -> crate::error::Result<Option<ParameterId>> {
    let upper = name.trim().to_ascii_uppercase();
    if is_isg_geometry(&upper) {
        return Ok(None);
    }
    let iso = if upper.len() == 3 && upper.as_bytes()[1] == b'0' { format!("E{upper}") } else { upper };
    ParameterId::parse(&iso).map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exchange_names_are_iso_names() {
        assert_eq!(parameter_id("C0B").unwrap().unwrap().to_string(), "EC0B");
        assert_eq!(parameter_id("P0X").unwrap(), None);
    }
}
