//! The unknowns of an indirect identification: error parameters of the machine (constants, the
//! coefficient of one power of a motion error's polynomial, or the coefficient of one function of a
//! motion error's parametric basis), and nuisance parameters of the measurements (the unknown length
//! of a gauge, the misalignment of a hole plate).
//!
//! Every unknown has a user unit (um, urad, um/mm, ...); columns of the design matrix are in um of
//! reading per user unit of the unknown. A model unknown `theta_j` enters the machine's parameter
//! vector (mm, rad) at pose `q` as `params[index_j] += factor_j(q) theta_j`, with
//! `factor_j = q_own^power * to_internal` for a power and `p_l(q_own) * to_internal` for basis
//! function `l` (Soons 1993 eq. 3.1 / 4.2: `E(x) = sum_l beta_l p_l(x)`); so the design-matrix column
//! of an unknown is the Jacobian column of its parameter times that factor.

use crate::error::{Error, Result};
use crate::error_model::{Basis, ErrorFunction, ErrorModel};
use crate::machine::{Machine, ParameterId};

/// What an unknown is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum UnknownKind {
    /// An error parameter: `power = 0` a constant (`EC0Y`, `TX`, or a constant motion error `EXX`),
    /// `power = k > 0` the coefficient of `q^k` of a motion error's polynomial (`EXX[1]`, um/mm),
    /// `q` the own axis position in mm or deg.
    Model { id: ParameterId, index: usize, power: u32, own_axis: Option<usize> },
    /// The coefficient of function `function` of the basis `basis` (an index into the campaign's
    /// [`BasisParameter`]s) of motion error `id` (`EXX#3`).
    Basis { id: ParameterId, index: usize, basis: usize, function: usize },
    /// The unknown constant offset (um) of every reading of length measurement `measurement`: an
    /// uncalibrated gauge (Soons 1993 §4.2, §5.2.2: the artefact length appended to the parameters).
    LengthOffset { measurement: usize },
    /// One of the six components (`tx ty tz` um, `wx wy wz` urad) of the rigid misalignment of the
    /// artefact of probe measurement `measurement`.
    Plate { measurement: usize, component: usize },
}

/// One unknown with its name and unit.
#[derive(Clone, Debug, PartialEq)]
pub struct Unknown {
    /// `EC0Y`, `EXX[1]`, `EXX#3`, `offset:<measurement>`, `plate:<measurement>:tx`.
    pub name: String,
    pub unit: String,
    pub kind: UnknownKind,
    /// For a basis coefficient: the function it multiplies, e.g. `(x-50)_+^2` (from
    /// [`Basis::names`]).
    pub function: Option<String>,
}

/// A motion error identified as a parametric function of its own axis position (a campaign's
/// `[basis.NAME]`): its basis and the position of its coefficients among the unknowns.
#[derive(Clone, Debug, PartialEq)]
pub struct BasisParameter {
    pub id: ParameterId,
    /// Index in the machine's parameter vector.
    pub index: usize,
    /// The axis whose position (mm or deg) the basis functions take.
    pub own_axis: usize,
    pub basis: Basis,
    /// Index of the first coefficient among the campaign's unknowns; the others follow.
    pub first: usize,
}

const PLATE_COMPONENTS: [&str; 6] = ["tx", "ty", "tz", "wx", "wy", "wz"];

impl Unknown {
    /// Parses an error-parameter name for `machine`: an ISO name (`EC0Y`, `EXOC`, `WX`) or a motion
    /// error with a power in brackets (`EXX[1]`, `EBC[2]`).
    pub fn parse(machine: &Machine, text: &str) -> Result<Unknown> {
        let (stem, power) = match text.trim().split_once('[') {
            Some((stem, rest)) => {
                let digits = rest.strip_suffix(']').ok_or_else(|| Error::input(format!("`{text}`: expected NAME[POWER], e.g. EXX[1]")))?;
                let power: u32 = digits.trim().parse().map_err(|_| Error::input(format!("`{text}`: the power must be an integer 0..8")))?;
                if power > 8 {
                    return Err(Error::input(format!("`{text}`: the power must be an integer 0..8")));
                }
                (stem, power)
            }
            None => (text.trim(), 0),
        };
        let (id, index) = machine.parse_parameter(stem)?;
        let own_axis = match id {
            ParameterId::Motion { axis, .. } => machine.axis_index(axis),
            _ if power > 0 => {
                return Err(Error::input(format!(
                    "`{text}`: only motion errors (EXX, EBC, ...) are functions of a position; {id} is a constant"
                )))
            }
            _ => None,
        };
        let unit = match (power, own_axis) {
            (0, _) => id.unit().to_string(),
            (k, Some(a)) => per_position(id.unit(), machine.axes()[a].position_unit(), k),
            _ => unreachable!("power > 0 only for motion errors"),
        };
        let name = if power == 0 { id.to_string() } else { format!("{id}[{power}]") };
        Ok(Unknown { name, unit, kind: UnknownKind::Model { id, index, power, own_axis }, function: None })
    }

    /// The coefficients of the basis `basis` of motion error `name` (a campaign's `[basis.NAME]`),
    /// named `NAME#1 ...`; `basis_index` is the position of the [`BasisParameter`] in the campaign.
    /// Returns the unknowns and the parameter (with `first` = 0; the campaign sets it).
    pub fn basis(machine: &Machine, name: &str, basis: Basis, basis_index: usize) -> Result<(Vec<Unknown>, BasisParameter)> {
        let (id, index) = machine.parse_parameter(name)?;
        let ParameterId::Motion { axis, .. } = id else {
            return Err(Error::input(format!(
                "{id} is a constant (location or setup error); only motion errors (EXX, EBC, ...) have a basis"
            )));
        };
        let own_axis =
            machine.axis_index(axis).ok_or_else(|| Error::input(format!("{id}: machine `{}` has no axis {axis}", machine.name)))?;
        if basis.is_empty() {
            return Err(Error::input(format!("{id}: the basis has no functions")));
        }
        let position = machine.axes()[own_axis].position_unit();
        let powers = basis.position_powers();
        let unknowns = basis
            .names()
            .into_iter()
            .enumerate()
            .map(|(function, description)| Unknown {
                name: format!("{id}#{}", function + 1),
                unit: per_position(id.unit(), position, powers[function].max(0) as u32),
                kind: UnknownKind::Basis { id, index, basis: basis_index, function },
                function: Some(description),
            })
            .collect();
        Ok((unknowns, BasisParameter { id, index, own_axis, basis, first: 0 }))
    }

    /// The gauge offset of measurement `measurement` named `label`.
    pub fn length_offset(measurement: usize, label: &str) -> Unknown {
        Unknown { name: format!("offset:{label}"), unit: "um".into(), kind: UnknownKind::LengthOffset { measurement }, function: None }
    }

    /// The six plate-misalignment unknowns of measurement `measurement` named `label`.
    pub fn plate(measurement: usize, label: &str) -> Vec<Unknown> {
        PLATE_COMPONENTS
            .iter()
            .enumerate()
            .map(|(component, c)| Unknown {
                name: format!("plate:{label}:{c}"),
                unit: if component < 3 { "um" } else { "urad" }.into(),
                kind: UnknownKind::Plate { measurement, component },
                function: None,
            })
            .collect()
    }

    /// Whether this is an error parameter of the machine (not a nuisance of one measurement).
    pub fn is_model(&self) -> bool {
        matches!(self.kind, UnknownKind::Model { .. } | UnknownKind::Basis { .. })
    }

    /// The machine parameter (and its index in the parameter vector) of a model unknown.
    pub fn parameter(&self) -> Option<(ParameterId, usize)> {
        match self.kind {
            UnknownKind::Model { id, index, .. } | UnknownKind::Basis { id, index, .. } => Some((id, index)),
            _ => None,
        }
    }

    /// The value of a model unknown in `nominal` (user units): a constant, the coefficient of a
    /// polynomial, or the coefficient of a basis that is the campaign's basis; an error when the
    /// nominal function of that parameter is of another kind, or is given per direction of motion.
    pub fn nominal_value(&self, nominal: &ErrorModel, bases: &[BasisParameter]) -> Result<f64> {
        let Some((id, _)) = self.parameter() else { return Ok(0.0) };
        if nominal.directional_entries().any(|(i, d, _)| *i == id && d.is_some()) {
            return Err(Error::input(format!(
                "{}: the nominal errors give {id} per direction of motion; it cannot be identified as one function",
                self.name
            )));
        }
        let existing = nominal.entries().find(|(i, _)| **i == id).map(|(_, f)| f);
        match (self.kind, existing) {
            (_, None) => Ok(0.0),
            (UnknownKind::Model { power, .. }, Some(ErrorFunction::Constant(v))) => Ok(if power == 0 { *v } else { 0.0 }),
            (UnknownKind::Model { power, .. }, Some(ErrorFunction::Polynomial { coefficients })) => {
                Ok(coefficients.get(power as usize).copied().unwrap_or(0.0))
            }
            (UnknownKind::Basis { basis, function, .. }, Some(ErrorFunction::Basis { basis: b, coefficients })) if *b == bases[basis].basis => {
                Ok(coefficients[function])
            }
            (UnknownKind::Basis { .. }, Some(_)) => Err(Error::input(format!(
                "{}: the nominal errors give {id} as another function than the campaign's [basis.{id}]; give it there with the same basis, or not at all",
                self.name
            ))),
            _ => Err(Error::input(format!(
                "{}: the nominal errors give {id} as a table or basis; identify it as constants or polynomial powers only when it is a constant or a polynomial there",
                self.name
            ))),
        }
    }
}

/// `unit/position^k`: `um/mm`, `urad/deg^2`.
fn per_position(unit: &str, position: &str, k: u32) -> String {
    match k {
        0 => unit.to_string(),
        1 => format!("{unit}/{position}"),
        k => format!("{unit}/{position}^{k}"),
    }
}

/// The factors `d params[index_j] / d theta_j` (internal units per user unit) of every unknown at
/// pose `q` (mm, rad) into `out` (one per unknown; zero for nuisances). Each basis is evaluated once
/// ([`Basis::eval_into`]); no allocation.
pub fn parameter_factors(unknowns: &[Unknown], bases: &[BasisParameter], machine: &Machine, q: &[f64], out: &mut [f64]) {
    let axes = machine.axes();
    for (o, u) in out.iter_mut().zip(unknowns) {
        *o = match u.kind {
            UnknownKind::Model { id, power, own_axis, .. } => {
                let position = own_axis.map_or(1.0, |a| axes[a].position_to_user(q[a]));
                position.powi(power as i32) * id.component().to_internal()
            }
            _ => 0.0,
        };
    }
    for b in bases {
        let values = &mut out[b.first..b.first + b.basis.len()];
        b.basis.eval_into(axes[b.own_axis].position_to_user(q[b.own_axis]), values);
        let to_internal = b.id.component().to_internal();
        values.iter_mut().for_each(|v| *v *= to_internal);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error_model::BasisSpec;

    fn kx8five() -> Machine {
        Machine::from_toml_str(include_str!("../../../../examples/machines/kx8five.toml"), "kx8five").unwrap()
    }

    #[test]
    fn names_units_and_factors() {
        let m = kx8five();
        let u = Unknown::parse(&m, "EXX[2]").unwrap();
        assert_eq!((u.name.as_str(), u.unit.as_str()), ("EXX[2]", "um/mm^2"));
        let q = [10.0, 0.0, 0.0, 0.0, 0.0];
        let mut f = [0.0];
        parameter_factors(std::slice::from_ref(&u), &[], &m, &q, &mut f);
        assert!((f[0] - 100.0 * 1e-3).abs() < 1e-15);
        assert_eq!(Unknown::parse(&m, "EBC[1]").unwrap().unit, "urad/deg");
        assert_eq!(Unknown::parse(&m, "exoc").unwrap().name, "EX0C");
        assert!(Unknown::parse(&m, "EX0C[1]").unwrap_err().to_string().contains("constant"));
        assert!(Unknown::parse(&m, "EXX[1").unwrap_err().to_string().contains("NAME[POWER]"));
        assert!(Unknown::parse(&m, "EXB").unwrap_err().to_string().contains("axis B"));
    }

    #[test]
    fn basis_coefficients_are_named_with_units_and_evaluated_at_the_own_axis() {
        // degree 2, C1 at X = 50: x, x^2, (x-50)_+^2 and a periodic term of 10 mm
        let m = kx8five();
        let spec: BasisSpec =
            toml::from_str("domain = [-400, 400]\nknots = [50]\n[[periodic]]\nwavelength = 10\ndegree = 2\ncontinuity = 0\n").unwrap();
        let basis = Basis::new(spec).unwrap();
        let (unknowns, mut parameter) = Unknown::basis(&m, "EBX", basis.clone(), 0).unwrap();
        let units: Vec<&str> = unknowns.iter().map(|u| u.unit.as_str()).collect();
        assert_eq!(&units[..3], &["urad/mm", "urad/mm^2", "urad/mm^2"]);
        assert!(units[3..].iter().all(|u| *u == "urad"), "{units:?}");
        assert_eq!(unknowns[2].name, "EBX#3");
        assert_eq!(unknowns[2].function.as_deref(), Some("(x-50)_+^2"));
        parameter.first = 1;
        let constant = Unknown::parse(&m, "EC0Y").unwrap();
        let all: Vec<Unknown> = std::iter::once(constant).chain(unknowns).collect();
        let mut f = vec![0.0; all.len()];
        // X = 80 mm in internal units is 80 mm
        parameter_factors(&all, &[parameter], &m, &[80.0, 0.0, 0.0, 0.0, 0.0], &mut f);
        let mut values = vec![0.0; basis.len()];
        basis.eval_into(80.0, &mut values);
        assert!((f[0] - 1e-6).abs() < 1e-20);
        assert!((f[3] - 900.0 * 1e-6).abs() < 1e-15, "(80-50)^2 urad in rad: {}", f[3]);
        for l in 0..basis.len() {
            assert!((f[1 + l] - values[l] * 1e-6).abs() < 1e-18);
        }
        assert!(Unknown::basis(&m, "EX0C", basis, 0).unwrap_err().to_string().contains("only motion errors"));
    }
}
