//! The error-values TOML of docs/design.md, Files:
//! `[constant]` (um, urad), `[table.NAME]` with `position`/`value`, `[polynomial.NAME]` with
//! `coefficients` in ascending powers of the own axis position (mm or deg), `[basis.NAME]` with a
//! parametric basis (Soons 1993 ch. 3) and its `coefficients`, `[uncertainty]` with the standard
//! uncertainties (k = 1, um or urad) of constant values.

use super::basis::{Basis, BasisSpec};
use super::function::ErrorFunction;
use super::model::Direction;
use super::model::ErrorModel;
use super::ErrorModelError;
use crate::error::Error;
use crate::io::ranges::{line_of_key, ANGULAR_ERROR_URAD, LINEAR_ERROR_UM, MACHINE_LENGTH_MM, ROTARY_POSITION_DEG};
use crate::machine::{one_line, Machine, ParameterId};
use serde::Deserialize;
use std::collections::BTreeMap;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ErrorValuesFile {
    /// Free-text description and provenance, accepted and not interpreted.
    #[serde(default, rename = "name")]
    _name: Option<String>,
    #[serde(default, rename = "source")]
    _source: Option<String>,
    #[serde(default)]
    constant: BTreeMap<String, f64>,
    #[serde(default)]
    table: BTreeMap<String, TableFile>,
    #[serde(default)]
    polynomial: BTreeMap<String, PolynomialFile>,
    /// `[basis.NAME]`: a [`BasisSpec`] and its `coefficients`.
    #[serde(default)]
    basis: BTreeMap<String, toml::Table>,
    /// `[[term.NAME]]`: product terms (cross-coupling, temperature, spindle speed, load).
    #[serde(default)]
    term: BTreeMap<String, Vec<TermFile>>,
    /// `[load.NAME]`: workpiece-load errors (Soons 1993 eq. 3.20).
    #[serde(default)]
    load: BTreeMap<String, LoadFile>,
    /// `[[drift.NAME]]`: drift models at tested axis positions (Soons 1993 §3.4.4).
    #[serde(default)]
    drift: BTreeMap<String, Vec<DriftFile>>,
    /// `[uncertainty]`: standard uncertainties (k = 1, um or urad) of constant values, as an
    /// identification states them.
    #[serde(default)]
    uncertainty: BTreeMap<String, f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TermFile {
    coefficient: f64,
    /// Axis letters and inputs (`T:<sensor>`, `S:<spindle>`, `F:<load>`, `P:<name>`) with their powers.
    factors: BTreeMap<String, i32>,
    /// `[lo, hi]`: the term holds for `lo <= q < hi` of the own axis (mm or deg).
    #[serde(default)]
    range: Option<[f64; 2]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LoadFile {
    /// The load (N) the change was measured under.
    reference_n: f64,
    /// The load input (`F:<name>`, N).
    #[serde(default = "default_load")]
    load: String,
    /// The change under the reference load: a table of the own axis position, a polynomial, or a
    /// constant (location errors).
    #[serde(default)]
    position: Option<Vec<f64>>,
    #[serde(default)]
    value: Option<Vec<f64>>,
    #[serde(default)]
    coefficients: Option<Vec<f64>>,
    #[serde(default)]
    constant: Option<f64>,
    /// The lever arm (mm) at the reference load position, and the position input that shortens it.
    #[serde(default)]
    lever_mm: Option<f64>,
    #[serde(default)]
    lever_at: Option<String>,
}

fn default_load() -> String {
    "F:workpiece".into()
}

/// One tested position of a drift model: the fields of a `trueaxis thermal fit --model
/// state-space` file (`kind` and `error` accepted and not interpreted) plus `axis` and `position`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DriftFile {
    axis: String,
    position: f64,
    sensors: Vec<String>,
    time_constants_s: Vec<f64>,
    gains_um_per_degc: Vec<Vec<f64>>,
    #[serde(default, rename = "kind")]
    _kind: Option<String>,
    #[serde(default, rename = "error")]
    _error: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TableFile {
    position: Vec<f64>,
    value: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PolynomialFile {
    coefficients: Vec<f64>,
}

/// Parses an error-values TOML for `machine`; `origin` names the file in every message.
pub fn parse(text: &str, origin: &str, machine: &Machine) -> Result<ErrorModel, ErrorModelError> {
    crate::io::toml_numbers::refuse_underflow(text)
        .map_err(|e| ErrorModelError::Syntax { origin: origin.into(), message: e.to_string() })?;
    let file: ErrorValuesFile =
        toml::from_str(text).map_err(|e| ErrorModelError::Syntax { origin: origin.into(), message: one_line(&e.to_string()) })?;
    let mut model = ErrorModel::zero(machine);
    let invalid = |section: &str, name: &str, message: String| ErrorModelError::Invalid {
        origin: origin.into(),
        message: format!("[{section}] {name}: {message}"),
    };
    // a name may end in + or - : the function of one direction of motion (Soons 1993 §3.2.5)
    let id_of = |section: &str, name: &str| -> Result<(ParameterId, Option<Direction>), ErrorModelError> {
        let (stem, direction) = match name.trim().chars().last() {
            Some('+') => (&name.trim()[..name.trim().len() - 1], Some(Direction::Positive)),
            Some('-') => (&name.trim()[..name.trim().len() - 1], Some(Direction::Negative)),
            _ => (name, None),
        };
        Ok((ParameterId::parse(stem).map_err(|m| invalid(section, name, m.to_string()))?, direction))
    };
    for (name, &u) in &file.uncertainty {
        let id = ParameterId::parse(name).map_err(|m| invalid("uncertainty", name, m.to_string()))?;
        machine.parameter_index(&id).map_err(|m| invalid("uncertainty", name, m.to_string()))?;
        model.set_uncertainty(id, u).map_err(|m| invalid("uncertainty", name, m.to_string()))?;
    }
    let mut set = |section: &str, name: &str, f: crate::error::Result<ErrorFunction>| -> Result<(), ErrorModelError> {
        let (id, direction) = id_of(section, name)?;
        let f = f.map_err(|m| invalid(section, name, m.to_string()))?;
        model.set_directional(machine, id, direction, f).map_err(|m| invalid(section, name, m.to_string()))
    };
    for (name, &value) in &file.constant {
        let f = if value.is_finite() { Ok(ErrorFunction::Constant(value)) } else { Err(Error::input("value must be a finite number")) };
        set("constant", name, f)?;
    }
    for (name, t) in &file.table {
        let section = format!("table.{name}");
        // positions of the own axis within the physical range of a position of its kind
        let (id, _) = id_of(&section, name)?;
        let rotary = id.axis().is_some_and(crate::machine::is_rotary_letter);
        if let Some((i, m)) = (if rotary { ROTARY_POSITION_DEG } else { MACHINE_LENGTH_MM }).first_outside(&t.position) {
            let line = line_of_key(text, name).map_or(String::new(), |l| format!("line {l}: "));
            return Err(invalid(&section, name, format!("{line}position, entry {}: {m}", i + 1)));
        }
        set(&section, name, ErrorFunction::table(t.position.clone(), t.value.clone(), None))?;
    }
    for (name, p) in &file.polynomial {
        set(&format!("polynomial.{name}"), name, ErrorFunction::polynomial(p.coefficients.clone()))?;
    }
    for (name, table) in &file.basis {
        set(&format!("basis.{name}"), name, basis_function(table.clone()))?;
    }
    for (name, terms) in &file.term {
        let section = format!("term.{name}");
        // a name ending in + or - : the term holds for that direction of motion (NISTIR 5236 §3.6)
        let (id, direction) = id_of(&section, name)?;
        for t in terms {
            let mut axes = Vec::new();
            let mut sensors = Vec::new();
            for (factor, power) in &t.factors {
                let mut chars = factor.chars();
                match (chars.next(), chars.next()) {
                    (Some(c), None) => axes.push((c, *power)),
                    _ if factor.contains(':') => sensors.push((factor.as_str(), *power)),
                    _ => {
                        return Err(invalid(
                            &section,
                            name,
                            format!(
                                "factor `{factor}` is neither an axis letter nor an input (T:<sensor>, S:<spindle>, F:<load>, P:<name>)"
                            ),
                        ))
                    }
                }
            }
            let range = t.range.map(|[lo, hi]| (lo, hi));
            model
                .add_segment_term(machine, id, direction, range, t.coefficient, &axes, &sensors)
                .map_err(|m| invalid(&section, name, m.to_string()))?;
        }
    }
    for (name, l) in &file.load {
        let section = format!("load.{name}");
        let id = ParameterId::parse(name).map_err(|m| invalid(&section, name, m.to_string()))?;
        let function = match (&l.position, &l.value, &l.coefficients, l.constant) {
            (Some(p), Some(v), None, None) => ErrorFunction::table(p.clone(), v.clone(), None),
            (None, None, Some(c), None) => ErrorFunction::polynomial(c.clone()),
            (None, None, None, Some(c)) if c.is_finite() => Ok(ErrorFunction::Constant(c)),
            _ => Err(Error::input(
                "give the change under the reference load as `position` and `value` (a table), `coefficients` (a polynomial) \
                 or `constant`, exactly one of them",
            )),
        }
        .map_err(|m| invalid(&section, name, m.to_string()))?;
        let lever = match (l.lever_mm, &l.lever_at) {
            (Some(mm), Some(at)) => Some((mm, at.as_str())),
            (None, None) => None,
            _ => return Err(invalid(&section, name, "`lever_mm` and `lever_at` go together".into())),
        };
        model.add_load(machine, id, function, l.reference_n, &l.load, lever).map_err(|m| invalid(&section, name, m.to_string()))?;
    }
    for (name, entries) in &file.drift {
        let section = format!("drift.{name}");
        let id = ParameterId::parse(name).map_err(|m| invalid(&section, name, m.to_string()))?;
        for d in entries {
            let mut letters = d.axis.trim().chars();
            let axis = match (letters.next(), letters.next()) {
                (Some(c), None) => c,
                _ => return Err(invalid(&section, name, format!("`axis` = `{}` is not an axis letter", d.axis))),
            };
            model
                .add_drift(machine, id, axis, d.position, &d.sensors, &d.time_constants_s, &d.gains_um_per_degc)
                .map_err(|m| invalid(&section, name, m.to_string()))?;
        }
    }
    model.check_directions().map_err(|m| ErrorModelError::Invalid { origin: origin.into(), message: m.to_string() })?;
    check_physical_ranges(&model, machine, text, origin)?;
    Ok(model)
}

/// Refuses an error function whose value leaves the physical range of its quantity
/// (`io::ranges`: linear errors in um, angular errors in urad) anywhere on its axis travel: 65
/// equally spaced positions over the travel of the own axis of a motion error (one turn of a
/// rotary axis without a range), the value itself for a location or setup error. The message
/// names the file, the line, the parameter and the position.
fn check_physical_ranges(model: &ErrorModel, machine: &Machine, text: &str, origin: &str) -> Result<(), ErrorModelError> {
    const SAMPLES: usize = 65;
    for (id, direction, function) in model.directional_entries() {
        let range = if id.component().is_rotation() { ANGULAR_ERROR_URAD } else { LINEAR_ERROR_UM };
        let travel = match id {
            ParameterId::Motion { axis, .. } => machine.axis_index(*axis).map(|k| machine.axes()[k].range.unwrap_or([0.0, 360.0])),
            _ => None,
        };
        let positions: Vec<f64> = match travel {
            Some([lo, hi]) => (0..SAMPLES).map(|i| lo + (hi - lo) * i as f64 / (SAMPLES - 1) as f64).collect(),
            None => vec![0.0],
        };
        for q in positions {
            if let Some(m) = range.check(function.evaluate(q)) {
                let name = format!("{id}{}", direction.map_or(String::new(), |d| d.symbol().to_string()));
                let line = line_of_key(text, &name).map_or(String::new(), |l| format!("line {l}: "));
                let at = travel.map_or(String::new(), |_| format!(" at {}{q}", id.axis().unwrap_or(' ')));
                return Err(ErrorModelError::Invalid { origin: origin.into(), message: format!("{line}{name}{at}: {m}") });
            }
        }
    }
    Ok(())
}

/// A `[basis.NAME]` table: the fields of [`BasisSpec`] plus `coefficients`.
fn basis_function(mut table: toml::Table) -> crate::error::Result<ErrorFunction> {
    let coefficients: Vec<f64> = match table.remove("coefficients") {
        Some(v) => v.try_into().map_err(|e: toml::de::Error| Error::input(format!("`coefficients`: {}", one_line(&e.to_string()))))?,
        None => return Err(Error::input("missing field `coefficients`")),
    };
    let spec: BasisSpec = toml::Value::Table(table).try_into().map_err(|e: toml::de::Error| Error::input(one_line(&e.to_string())))?;
    ErrorFunction::basis(Basis::new(spec)?, coefficients)
}
