//! The unknowns of an indirect identification: error parameters of the machine (constants, or the
//! coefficient of one power of a motion error's polynomial), and nuisance parameters of the
//! measurements (the unknown length of a gauge, the misalignment of a hole plate).
//!
//! Every unknown has a user unit (um, urad, um/mm, ...); columns of the design matrix are in um of
//! reading per user unit of the unknown.

use crate::errors::{ErrorFunction, ErrorModel};
use crate::machine::{Machine, ParameterId};

/// What an unknown is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum UnknownKind {
    /// An error parameter: `power = 0` a constant (`EC0Y`, `TX`, or a constant motion error `EXX`),
    /// `power = k > 0` the coefficient of `q^k` of a motion error's polynomial (`EXX[1]`, um/mm),
    /// `q` the own axis position in mm or deg.
    Model { id: ParameterId, index: usize, power: u32, own_axis: Option<usize> },
    /// The unknown constant offset (um) of every reading of length measurement `measurement`: an
    /// uncalibrated gauge (seed 000 §4.2, §5.2.2: the artefact length appended to the parameters).
    LengthOffset { measurement: usize },
    /// One of the six components (`tx ty tz` um, `wx wy wz` urad) of the rigid misalignment of the
    /// artefact of probe measurement `measurement`.
    Plate { measurement: usize, component: usize },
}

/// One unknown with its name and unit.
#[derive(Clone, Debug, PartialEq)]
pub struct Unknown {
    /// `EC0Y`, `EXX[1]`, `offset:<measurement>`, `plate:<measurement>:tx`.
    pub name: String,
    pub unit: String,
    pub kind: UnknownKind,
}

const PLATE_COMPONENTS: [&str; 6] = ["tx", "ty", "tz", "wx", "wy", "wz"];

impl Unknown {
    /// Parses an error-parameter name for `machine`: an ISO name (`EC0Y`, `EXOC`, `WX`) or a motion
    /// error with a power in brackets (`EXX[1]`, `EBC[2]`).
    pub fn parse(machine: &Machine, text: &str) -> Result<Unknown, String> {
        let (stem, power) = match text.trim().split_once('[') {
            Some((stem, rest)) => {
                let digits = rest.strip_suffix(']').ok_or_else(|| format!("`{text}`: expected NAME[POWER], e.g. EXX[1]"))?;
                let power: u32 = digits.trim().parse().map_err(|_| format!("`{text}`: the power must be an integer 0..8"))?;
                if power > 8 {
                    return Err(format!("`{text}`: the power must be an integer 0..8"));
                }
                (stem, power)
            }
            None => (text.trim(), 0),
        };
        let (id, index) = machine.parse_parameter(stem)?;
        let own_axis = match id {
            ParameterId::Motion { axis, .. } => machine.axis_index(axis),
            _ if power > 0 => {
                return Err(format!("`{text}`: only motion errors (EXX, EBC, ...) are functions of a position; {id} is a constant"))
            }
            _ => None,
        };
        let unit = match (power, own_axis) {
            (0, _) => id.unit().to_string(),
            (k, Some(a)) => {
                let per = machine.axes()[a].position_unit();
                if k == 1 {
                    format!("{}/{per}", id.unit())
                } else {
                    format!("{}/{per}^{k}", id.unit())
                }
            }
            _ => unreachable!("power > 0 only for motion errors"),
        };
        let name = if power == 0 { id.to_string() } else { format!("{id}[{power}]") };
        Ok(Unknown { name, unit, kind: UnknownKind::Model { id, index, power, own_axis } })
    }

    /// The gauge offset of measurement `measurement` named `label`.
    pub fn length_offset(measurement: usize, label: &str) -> Unknown {
        Unknown { name: format!("offset:{label}"), unit: "um".into(), kind: UnknownKind::LengthOffset { measurement } }
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
            })
            .collect()
    }

    /// Whether this is an error parameter of the machine (not a nuisance of one measurement).
    pub fn is_model(&self) -> bool {
        matches!(self.kind, UnknownKind::Model { .. })
    }

    /// For a model unknown: the derivative of its parameter (internal units, mm or rad) with
    /// respect to the unknown (user units) at pose `q` (mm, rad): `q_user^power * to_internal`.
    pub fn parameter_factor(&self, machine: &Machine, q: &[f64]) -> f64 {
        match self.kind {
            UnknownKind::Model { id, power, own_axis, .. } => {
                let position = own_axis.map_or(1.0, |a| machine.axes()[a].position_to_user(q[a]));
                position.powi(power as i32) * id.component().to_internal()
            }
            _ => 0.0,
        }
    }

    /// The value of a model unknown in `nominal` (user units): a constant, or the coefficient of a
    /// polynomial; an error when the nominal function of that parameter is a table or a basis, or is
    /// given per direction of motion.
    pub fn nominal_value(&self, nominal: &ErrorModel) -> Result<f64, String> {
        let UnknownKind::Model { id, power, .. } = self.kind else { return Ok(0.0) };
        if nominal.directional_entries().any(|(i, d, _)| *i == id && d.is_some()) {
            return Err(format!(
                "{}: the nominal errors give {id} per direction of motion; it cannot be identified as one function",
                self.name
            ));
        }
        match nominal.entries().find(|(i, _)| **i == id).map(|(_, f)| f) {
            None => Ok(0.0),
            Some(ErrorFunction::Constant(v)) => Ok(if power == 0 { *v } else { 0.0 }),
            Some(ErrorFunction::Polynomial { coefficients }) => Ok(coefficients.get(power as usize).copied().unwrap_or(0.0)),
            Some(_) => Err(format!(
                "{}: the nominal errors give {id} as a table or basis; identify it as constants or polynomial powers only when it is a constant or a polynomial there",
                self.name
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_units_and_factors() {
        let m = Machine::from_toml_str(include_str!("../../examples/machines/kx8five.toml"), "kx8five").unwrap();
        let u = Unknown::parse(&m, "EXX[2]").unwrap();
        assert_eq!((u.name.as_str(), u.unit.as_str()), ("EXX[2]", "um/mm^2"));
        let q = [10.0, 0.0, 0.0, 0.0, 0.0];
        assert!((u.parameter_factor(&m, &q) - 100.0 * 1e-3).abs() < 1e-15);
        assert_eq!(Unknown::parse(&m, "EBC[1]").unwrap().unit, "urad/deg");
        assert_eq!(Unknown::parse(&m, "exoc").unwrap().name, "EX0C");
        assert!(Unknown::parse(&m, "EX0C[1]").unwrap_err().contains("constant"));
        assert!(Unknown::parse(&m, "EXX[1").unwrap_err().contains("NAME[POWER]"));
        assert!(Unknown::parse(&m, "EXB").unwrap_err().contains("axis B"));
    }
}
