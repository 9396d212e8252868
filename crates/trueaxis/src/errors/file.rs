//! The error-values TOML of DESIGN.md section 3:
//! `[constant]` (um, urad), `[table.NAME]` with `position`/`value`, `[polynomial.NAME]` with
//! `coefficients` in ascending powers of the own axis position (mm or deg), `[basis.NAME]` with a
//! parametric basis (seed 000 ch. 3) and its `coefficients`.

use super::basis::{Basis, BasisSpec};
use super::function::ErrorFunction;
use super::model::Direction;
use super::model::ErrorModel;
use super::ErrorsError;
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
    /// `[[term.NAME]]`: product terms (cross-coupling, temperature).
    #[serde(default)]
    term: BTreeMap<String, Vec<TermFile>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TermFile {
    coefficient: f64,
    /// Axis letters and sensor names (`T:<sensor>`) with their powers.
    factors: BTreeMap<String, i32>,
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
pub fn parse(text: &str, origin: &str, machine: &Machine) -> Result<ErrorModel, ErrorsError> {
    let file: ErrorValuesFile =
        toml::from_str(text).map_err(|e| ErrorsError::Syntax { origin: origin.into(), message: one_line(&e.to_string()) })?;
    let mut model = ErrorModel::zero(machine);
    let invalid = |section: &str, name: &str, message: String| ErrorsError::Invalid {
        origin: origin.into(),
        message: format!("[{section}] {name}: {message}"),
    };
    // a name may end in + or - : the function of one direction of motion (seed 000 §3.2.5)
    let id_of = |section: &str, name: &str| -> Result<(ParameterId, Option<Direction>), ErrorsError> {
        let (stem, direction) = match name.trim().chars().last() {
            Some('+') => (&name.trim()[..name.trim().len() - 1], Some(Direction::Positive)),
            Some('-') => (&name.trim()[..name.trim().len() - 1], Some(Direction::Negative)),
            _ => (name, None),
        };
        Ok((ParameterId::parse(stem).map_err(|m| invalid(section, name, m))?, direction))
    };
    let mut set = |section: &str, name: &str, f: Result<ErrorFunction, String>| -> Result<(), ErrorsError> {
        let (id, direction) = id_of(section, name)?;
        let f = f.map_err(|m| invalid(section, name, m))?;
        model.set_directional(machine, id, direction, f).map_err(|m| invalid(section, name, m))
    };
    for (name, &value) in &file.constant {
        let f = if value.is_finite() { Ok(ErrorFunction::Constant(value)) } else { Err("value must be a finite number".to_string()) };
        set("constant", name, f)?;
    }
    for (name, t) in &file.table {
        set(&format!("table.{name}"), name, ErrorFunction::table(t.position.clone(), t.value.clone(), None))?;
    }
    for (name, p) in &file.polynomial {
        set(&format!("polynomial.{name}"), name, ErrorFunction::polynomial(p.coefficients.clone()))?;
    }
    for (name, table) in &file.basis {
        set(&format!("basis.{name}"), name, basis_function(table.clone()))?;
    }
    for (name, terms) in &file.term {
        let section = format!("term.{name}");
        // product terms hold for both directions of motion (the model has no directional terms)
        if let (_, Some(d)) = id_of(&section, name)? {
            let stem = name.trim().trim_end_matches(['+', '-']);
            return Err(invalid(
                &section,
                name,
                format!(
                    "product terms hold for both directions of motion; a term of the {s} direction only is not supported: give it \
                     under [[term.{stem}]], or put the direction's difference into [table.\"{stem}{s}\"] / [basis.\"{stem}{s}\"]",
                    s = d.symbol()
                ),
            ));
        }
        let id = ParameterId::parse(name).map_err(|m| invalid(&section, name, m))?;
        for t in terms {
            let mut axes = Vec::new();
            let mut sensors = Vec::new();
            for (factor, power) in &t.factors {
                match factor.strip_prefix("T:") {
                    Some(sensor) if !sensor.is_empty() => sensors.push((factor.as_str(), *power)),
                    _ => {
                        let mut chars = factor.chars();
                        match (chars.next(), chars.next()) {
                            (Some(c), None) => axes.push((c, *power)),
                            _ => {
                                return Err(invalid(
                                    &section,
                                    name,
                                    format!("factor `{factor}` is neither an axis letter nor a sensor `T:<name>`"),
                                ))
                            }
                        }
                    }
                }
            }
            model.add_term(machine, id, t.coefficient, &axes, &sensors).map_err(|m| invalid(&section, name, m))?;
        }
    }
    model.check_directions().map_err(|m| ErrorsError::Invalid { origin: origin.into(), message: m })?;
    Ok(model)
}

/// A `[basis.NAME]` table: the fields of [`BasisSpec`] plus `coefficients`.
fn basis_function(mut table: toml::Table) -> Result<ErrorFunction, String> {
    let coefficients: Vec<f64> = match table.remove("coefficients") {
        Some(v) => v.try_into().map_err(|e: toml::de::Error| format!("`coefficients`: {}", one_line(&e.to_string())))?,
        None => return Err("missing field `coefficients`".into()),
    };
    let spec: BasisSpec = toml::Value::Table(table).try_into().map_err(|e: toml::de::Error| one_line(&e.to_string()))?;
    ErrorFunction::basis(Basis::new(spec)?, coefficients)
}
