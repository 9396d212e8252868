//! The budget file (TOML): which components, their tolerances, homogenisation lengths and costs.
//!
//! ```toml
//! components = ["EXX", "EYX", "EC0X"]   # optional: the default is the standard set
//! exclude = ["EZC"]                     # optional: names left out of the set
//!
//! [tolerance]        # um for linear errors, urad for angular and squareness errors
//! linear = 5.0       # every linear error not named below
//! angular = 10.0
//! squareness = 10.0
//! EXX = 3.0          # one component
//!
//! [length]           # homogenisation length (mm) of the linear errors of an axis
//! C = 400
//!
//! [cost]             # cost = a / e^k of the homogenised tolerance e (um/m or urad)
//! a = 1.0
//! k = 2.0
//! [cost.lower]       # lower limits by kind (um, urad)
//! linear = 0.1
//! angular = 0.5
//! squareness = 0.5
//! [cost.table]       # per component: a, k, lower (each optional)
//! EXX = { a = 2.0, k = 1.5, lower = 0.2 }
//! ```

use super::components::{bind, default_components, default_lengths, BudgetComponent, ErrorKind};
use super::cost::{CostModel, CostTerm, DEFAULT_A, DEFAULT_K, DEFAULT_LOWER};
use crate::error::Error;
use crate::machine::{Machine, ParameterId};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt::Write;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SpecFile {
    components: Option<Vec<String>>,
    exclude: Option<Vec<String>>,
    tolerance: Option<BTreeMap<String, f64>>,
    length: Option<BTreeMap<String, f64>>,
    cost: Option<CostFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CostFile {
    a: Option<f64>,
    k: Option<f64>,
    lower: Option<BTreeMap<String, f64>>,
    table: Option<BTreeMap<String, CostRow>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CostRow {
    a: Option<f64>,
    k: Option<f64>,
    lower: Option<f64>,
}

/// Tolerances by kind: linear (um), angular (urad), squareness (urad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KindValues(pub [f64; 3]);

impl KindValues {
    /// Default tolerances of a machining centre: 5 um, 10 urad, 10 urad.
    pub const DEFAULT: KindValues = KindValues([5.0, 10.0, 10.0]);

    pub fn of(&self, kind: ErrorKind) -> f64 {
        self.0[ErrorKind::ALL.iter().position(|k| *k == kind).expect("three kinds")]
    }
}

/// A budget bound to a machine: components, their tolerances (um, urad) and their costs.
#[derive(Clone, Debug)]
pub struct BudgetSpec {
    pub components: Vec<BudgetComponent>,
    /// Tolerance of each component in its own unit (um or urad): a standard uncertainty for the
    /// root-sum-square stack-up, a limit for the worst case.
    pub tolerances: Vec<f64>,
    pub cost: CostModel,
}

impl BudgetSpec {
    /// The standard component set with the same tolerance per kind and the default cost model.
    pub fn standard(machine: &Machine, tolerances: KindValues) -> BudgetSpec {
        let components = bind(machine, &default_components(machine), &default_lengths(machine)).expect("the standard set binds");
        let tolerances = components.iter().map(|c| tolerances.of(c.kind)).collect();
        let cost = CostModel::uniform(&components, DEFAULT_A, DEFAULT_K, DEFAULT_LOWER);
        BudgetSpec { components, tolerances, cost }
    }

    /// Reads a budget file; `defaults` fills the tolerances the file does not give.
    pub fn load(path: impl AsRef<std::path::Path>, machine: &Machine, defaults: KindValues) -> Result<BudgetSpec, Error> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        let text =
            crate::files::inputs::read_to_string(path).map_err(|e| Error::input(format!("{origin}: cannot read budget file: {e}")))?;
        Self::from_toml_str(&text, &origin, machine, defaults)
    }

    /// Parses a budget file; every error names `origin` and the key at fault.
    pub fn from_toml_str(text: &str, origin: &str, machine: &Machine, defaults: KindValues) -> Result<BudgetSpec, Error> {
        let fail = |message: String| Error::input(format!("{origin}: {message}"));
        crate::io::toml_numbers::refuse_underflow(text).map_err(|e| e.in_file(origin))?;
        let file: SpecFile = toml::from_str(text).map_err(|e| fail(crate::machine::one_line(&e.to_string())))?;
        let parse = |name: &str, key: &str| -> Result<ParameterId, Error> {
            machine.parse_parameter(name).map(|(id, _)| id).map_err(|e| e.context(key).in_file(origin))
        };
        let mut ids = match &file.components {
            Some(names) => names.iter().map(|n| parse(n, "components")).collect::<Result<Vec<_>, _>>()?,
            None => default_components(machine),
        };
        for name in file.exclude.iter().flatten() {
            let id = parse(name, "exclude")?;
            let before = ids.len();
            ids.retain(|i| *i != id);
            if ids.len() == before {
                return Err(fail(format!("exclude: {id} is not in the component set")));
            }
        }
        if ids.is_empty() {
            return Err(fail("the component set is empty".into()));
        }
        let mut lengths = default_lengths(machine);
        for (key, value) in file.length.iter().flatten() {
            let k = single_letter(key).and_then(|c| machine.axis_index(c)).ok_or_else(|| {
                fail(format!("[length] {key}: machine `{}` has no axis {key} (axes: {})", machine.name, machine.axis_letters()))
            })?;
            if !(value.is_finite() && *value > 0.0) {
                return Err(fail(format!("[length] {key} = {value}: a homogenisation length must be a positive number of mm")));
            }
            lengths[k] = *value;
        }
        let components = bind(machine, &ids, &lengths).map_err(|e| e.in_file(origin))?;

        let mut by_kind = defaults;
        let mut named = BTreeMap::new();
        for (key, value) in file.tolerance.iter().flatten() {
            if !(value.is_finite() && *value > 0.0) {
                return Err(fail(format!("[tolerance] {key} = {value}: a tolerance must be a positive number (um or urad)")));
            }
            match kind_key(key) {
                Some(kind) => by_kind.0[kind] = *value,
                None => {
                    let id = parse(key, "[tolerance]")?;
                    let index = components.iter().position(|c| c.id == id).ok_or_else(|| {
                        fail(format!("[tolerance] {id} is not in the component set (add it to `components` or remove it)"))
                    })?;
                    named.insert(index, *value);
                }
            }
        }
        let tolerances = (0..components.len()).map(|i| named.get(&i).copied().unwrap_or_else(|| by_kind.of(components[i].kind))).collect();

        let cost_file = file.cost.unwrap_or(CostFile { a: None, k: None, lower: None, table: None });
        let mut lower = DEFAULT_LOWER;
        for (key, value) in cost_file.lower.iter().flatten() {
            let kind = kind_key(key).ok_or_else(|| fail(format!("[cost.lower] {key}: expected linear, angular or squareness")))?;
            lower[kind] = *value;
        }
        let mut cost = CostModel::uniform(&components, cost_file.a.unwrap_or(DEFAULT_A), cost_file.k.unwrap_or(DEFAULT_K), lower);
        for (key, row) in cost_file.table.iter().flatten() {
            let id = parse(key, "[cost.table]")?;
            let index =
                components.iter().position(|c| c.id == id).ok_or_else(|| fail(format!("[cost.table] {id} is not in the component set")))?;
            let term: &mut CostTerm = &mut cost.terms[index];
            term.a = row.a.unwrap_or(term.a);
            term.k = row.k.unwrap_or(term.k);
            term.lower = row.lower.unwrap_or(term.lower);
        }
        cost.check(&components).map_err(|m| fail(format!("[cost] {m}")))?;
        Ok(BudgetSpec { components, tolerances, cost })
    }

    /// Indices of the components of one kind.
    pub fn of_kind(&self, kind: ErrorKind) -> impl Iterator<Item = usize> + '_ {
        (0..self.components.len()).filter(move |&j| self.components[j].kind == kind)
    }

    /// The same budget with other tolerances (um, urad), e.g. an allocation.
    pub fn with_tolerances(&self, tolerances: Vec<f64>) -> BudgetSpec {
        BudgetSpec { components: self.components.clone(), tolerances, cost: self.cost.clone() }
    }

    /// A budget file holding these components, tolerances, lengths and costs, which
    /// [`BudgetSpec::from_toml_str`] reads back to the same budget. `header` is written as comments.
    pub fn to_toml(&self, machine: &Machine, header: &str) -> String {
        let mut out = String::new();
        for line in header.lines() {
            let _ = writeln!(out, "# {line}");
        }
        let names: Vec<String> = self.components.iter().map(|c| format!("\"{}\"", c.id)).collect();
        let _ = writeln!(
            out,
            "components = [{}]\n\n[tolerance]   # um for linear errors, urad for angular and squareness errors",
            names.join(", ")
        );
        for (c, t) in self.components.iter().zip(&self.tolerances) {
            let _ = writeln!(out, "{} = {}", c.id, round_sig(*t));
        }
        let _ = writeln!(out, "\n[length]      # homogenisation length of the linear errors of each axis (mm)");
        for (axis, length) in machine.axes().iter().zip(self.lengths(machine)) {
            let _ = writeln!(out, "{} = {}", axis.letter, length);
        }
        let _ = writeln!(out, "\n[cost.table]  # cost = a / e^k of the homogenised tolerance; lower limit in um or urad");
        for (c, term) in self.components.iter().zip(&self.cost.terms) {
            let _ = writeln!(out, "{} = {{ a = {}, k = {}, lower = {} }}", c.id, term.a, term.k, term.lower);
        }
        out
    }

    /// The homogenisation length of each axis (mm): the one of its linear components, else the default.
    pub fn lengths(&self, machine: &Machine) -> Vec<f64> {
        let mut lengths = default_lengths(machine);
        for c in self.components.iter().filter(|c| c.kind == ErrorKind::Linear) {
            lengths[machine.axis_index(c.axis).expect("bound to this machine")] = c.length_mm;
        }
        lengths
    }
}

fn single_letter(key: &str) -> Option<char> {
    let mut chars = key.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) => Some(c.to_ascii_uppercase()),
        _ => None,
    }
}

fn kind_key(key: &str) -> Option<usize> {
    ErrorKind::ALL.iter().position(|k| k.name() == key)
}

/// Nine significant digits: enough to read back the same allocation to 1e-8, short enough to read.
fn round_sig(x: f64) -> String {
    format!("{}", format!("{x:.8e}").parse::<f64>().unwrap_or(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vmc3() -> Machine {
        Machine::from_toml_str(include_str!("../../../../examples/machines/vmc3.toml"), "vmc3").unwrap()
    }

    #[test]
    fn file_overrides_defaults_and_round_trips() {
        let m = vmc3();
        let text =
            "exclude = [\"EZX\"]\n[tolerance]\nlinear = 2\nEXX = 1.5\n[length]\nX = 500\n[cost]\nk = 1\n[cost.table]\nEBX = { a = 3 }\n";
        let spec = BudgetSpec::from_toml_str(text, "b.toml", &m, KindValues::DEFAULT).unwrap();
        assert_eq!(spec.components.len(), 20);
        let at = |name: &str| spec.components.iter().position(|c| c.id.to_string() == name).unwrap();
        assert_eq!(spec.tolerances[at("EXX")], 1.5);
        assert_eq!(spec.tolerances[at("EYX")], 2.0);
        assert_eq!(spec.tolerances[at("EBX")], 10.0);
        assert_eq!(spec.components[at("EXX")].length_mm, 500.0);
        assert_eq!(spec.cost.terms[at("EBX")].a, 3.0);
        assert_eq!(spec.cost.terms[at("EXX")].k, 1.0);
        let again = BudgetSpec::from_toml_str(&spec.to_toml(&m, "round trip"), "again", &m, KindValues([9.0; 3])).unwrap();
        assert_eq!(again.components, spec.components);
        assert_eq!(again.tolerances, spec.tolerances);
        assert_eq!(again.cost, spec.cost);
    }

    #[test]
    fn errors_name_the_file_and_the_key() {
        let m = vmc3();
        for (text, needle) in [
            ("[tolerance]\nEXC = 1\n", "axis C"),
            ("[tolerance]\nEXX = -1\n", "EXX = -1"),
            ("[length]\nQ = 1\n", "[length] Q"),
            ("exclude = [\"EX0C\"]\n", "exclude"),
            ("[cost]\nk = 0\n", "[cost]"),
            ("[cost]\nfoo = 1\n", "foo"),
            ("components = [\"TX\"]\n", "setup error"),
        ] {
            let e = BudgetSpec::from_toml_str(text, "b.toml", &m, KindValues::DEFAULT).unwrap_err().to_string();
            assert!(e.starts_with("b.toml: ") && e.contains(needle), "{text}: {e}");
        }
    }
}
