//! The error-values TOML of DESIGN.md section 3:
//! `[constant]` (um, urad), `[table.NAME]` with `position`/`value`, `[polynomial.NAME]` with
//! `coefficients` in ascending powers of the own axis position (mm or deg), `[basis.NAME]` with a
//! parametric basis (seed 000 ch. 3) and its `coefficients`.

use super::basis::{Basis, BasisSpec};
use super::function::ErrorFunction;
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
    let id_of = |section: &str, name: &str| ParameterId::parse(name).map_err(|m| invalid(section, name, m));
    for (name, &value) in &file.constant {
        if !value.is_finite() {
            return Err(invalid("constant", name, "value must be a finite number".into()));
        }
        let id = id_of("constant", name)?;
        model.set(machine, id, ErrorFunction::Constant(value)).map_err(|m| invalid("constant", name, m))?;
    }
    for (name, t) in &file.table {
        let section = format!("table.{name}");
        let id = id_of(&section, name)?;
        let f = ErrorFunction::table(t.position.clone(), t.value.clone(), None).map_err(|m| invalid(&section, name, m))?;
        model.set(machine, id, f).map_err(|m| invalid(&section, name, m))?;
    }
    for (name, p) in &file.polynomial {
        let section = format!("polynomial.{name}");
        let id = id_of(&section, name)?;
        let f = ErrorFunction::polynomial(p.coefficients.clone()).map_err(|m| invalid(&section, name, m))?;
        model.set(machine, id, f).map_err(|m| invalid(&section, name, m))?;
    }
    for (name, table) in &file.basis {
        let section = format!("basis.{name}");
        let id = id_of(&section, name)?;
        let f = basis_function(table.clone()).map_err(|m| invalid(&section, name, m))?;
        model.set(machine, id, f).map_err(|m| invalid(&section, name, m))?;
    }
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
