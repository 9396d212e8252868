//! Writing error functions into an error-values TOML, keeping the rest of the file (comments
//! included) as it was.

use super::function::ErrorFunction;
use super::model::Direction;
use crate::error::{Error, Result};
use crate::machine::ParameterId;
use toml_edit::{value, Array, ArrayOfTables, DocumentMut, Item, Table};

const SECTIONS: [&str; 4] = ["constant", "table", "polynomial", "basis"];

/// Sets `id` to `function` in the error-values document `text` (empty for a new file), as
/// `[constant]`, `[table.NAME]`, `[polynomial.NAME]` or `[basis.NAME]`, and returns the new text.
/// With a `direction` the function is that of one direction of motion only (`NAME+` / `NAME-`,
/// Soons 1993 §3.2.5): the undirected entry and the entry of the same direction are replaced, the
/// other direction is kept. Without, every entry of the parameter is replaced.
pub fn set_error_function(text: &str, id: &ParameterId, direction: Option<Direction>, function: &ErrorFunction) -> Result<String> {
    let mut doc: DocumentMut = text.parse().map_err(|e: toml_edit::TomlError| Error::input(crate::machine::one_line(&e.to_string())))?;
    let suffix = |d: Option<Direction>| match d {
        Some(Direction::Positive) => "+",
        Some(Direction::Negative) => "-",
        None => "",
    };
    let name = format!("{id}{}", suffix(direction));
    let replaced = |key: &str| {
        let key = key.trim();
        let (stem, own) = match key.chars().last() {
            Some('+') => (&key[..key.len() - 1], Some(Direction::Positive)),
            Some('-') => (&key[..key.len() - 1], Some(Direction::Negative)),
            _ => (key, None),
        };
        ParameterId::parse(stem).ok() == Some(*id) && (direction.is_none() || own.is_none() || own == direction)
    };
    for section in SECTIONS {
        if let Some(table) = doc.get_mut(section).and_then(Item::as_table_like_mut) {
            let keys: Vec<String> = table.iter().map(|(k, _)| k.to_string()).filter(|k| replaced(k)).collect();
            for k in keys {
                table.remove(&k);
            }
        }
    }
    let section = |doc: &mut DocumentMut, s: &str| -> Result<Table> {
        match doc.remove(s) {
            Some(Item::Table(t)) => Ok(t),
            None => {
                let mut t = Table::new();
                t.set_implicit(s != "constant");
                Ok(t)
            }
            Some(_) => Err(Error::input(format!("`{s}` is not a table in the existing file"))),
        }
    };
    let floats = |v: &[f64]| v.iter().copied().collect::<Array>();
    let (key, item) = match function {
        ErrorFunction::Constant(v) => ("constant", value(*v)),
        ErrorFunction::Table { positions, values, .. } => {
            let mut t = Table::new();
            t.insert("position", value(floats(positions)));
            t.insert("value", value(floats(values)));
            ("table", Item::Table(t))
        }
        ErrorFunction::Polynomial { coefficients } => {
            let mut t = Table::new();
            t.insert("coefficients", value(floats(coefficients)));
            ("polynomial", Item::Table(t))
        }
        ErrorFunction::Basis { basis, coefficients } => {
            let s = &basis.spec;
            let mut t = Table::new();
            t.insert("family", value(s.family.as_str()));
            t.insert("degree", value(s.degree as i64));
            t.insert("knots", value(floats(&s.knots)));
            t.insert("continuity", value(s.continuity.iter().map(|c| *c as i64).collect::<Array>()));
            t.insert("constant", value(s.constant));
            t.insert("constraint", value(s.constraint.as_str()));
            t.insert("domain", value(floats(&s.domain)));
            t.insert("coefficients", value(floats(coefficients)));
            if !s.periodic.is_empty() {
                let mut periodic = ArrayOfTables::new();
                for p in &s.periodic {
                    let mut pt = Table::new();
                    pt.insert("wavelength", value(p.wavelength));
                    pt.insert("phase", value(p.phase));
                    pt.insert("degree", value(p.degree as i64));
                    pt.insert("knots", value(floats(&p.knots)));
                    pt.insert("continuity", value(p.continuity as i64));
                    periodic.push(pt);
                }
                t.insert("periodic", Item::ArrayOfTables(periodic));
            }
            ("basis", Item::Table(t))
        }
    };
    let mut table = section(&mut doc, key)?;
    table.insert(&name, item);
    doc.insert(key, Item::Table(table));
    Ok(doc.to_string())
}

/// Sets the standard uncertainty (k = 1, um or urad) of `id` in the `[uncertainty]` table of the
/// error-values document `text`, and returns the new text.
pub fn set_uncertainty(text: &str, id: &ParameterId, u: f64) -> Result<String> {
    let mut doc: DocumentMut = text.parse().map_err(|e: toml_edit::TomlError| Error::input(crate::machine::one_line(&e.to_string())))?;
    let table = doc
        .entry("uncertainty")
        .or_insert(Item::Table(Table::new()))
        .as_table_mut()
        .ok_or_else(|| Error::input("`uncertainty` is not a table in the existing file"))?;
    table.insert(&id.to_string(), value(u));
    Ok(doc.to_string())
}
