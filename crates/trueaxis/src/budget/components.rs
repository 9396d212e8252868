//! The component errors of a budget: ISO 230 parameters of the machine (motion errors of every axis,
//! squareness of the linear axes, location errors of the rotary axes), each with its kind and the
//! length that homogenises it (Zhu 2008 eqs. B.1-B.2 and the paragraph after them).

use crate::machine::{AxisKind, Component, Machine, ParameterId};
use serde::Serialize;

/// The three kinds of component error of Zhu 2008 appendix B: linear errors `D_i(j)` (every
/// translation: positioning, straightness, radial and axial motion, position of a rotary axis),
/// angular errors `E_i(j)` (rotational motion errors and the zero offset of a rotary axis) and
/// squareness errors `S_ij` (orientation of an axis: squareness of linear axes, parallelism of
/// rotary axes; appendix A counts both as link errors after ASME B5.54).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ErrorKind {
    Linear,
    Angular,
    Squareness,
}

impl ErrorKind {
    pub const ALL: [ErrorKind; 3] = [ErrorKind::Linear, ErrorKind::Angular, ErrorKind::Squareness];

    /// The kind of an ISO 230 parameter (setup errors are linear).
    pub fn of(id: &ParameterId) -> ErrorKind {
        let component = id.component();
        match *id {
            _ if !component.is_rotation() => ErrorKind::Linear,
            ParameterId::Motion { .. } => ErrorKind::Angular,
            ParameterId::Location { axis, component } if component.letter() == axis => ErrorKind::Angular,
            _ => ErrorKind::Squareness,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            ErrorKind::Linear => "linear",
            ErrorKind::Angular => "angular",
            ErrorKind::Squareness => "squareness",
        }
    }

    /// Unit of a tolerance of this kind.
    pub fn unit(self) -> &'static str {
        match self {
            ErrorKind::Linear => "um",
            _ => "urad",
        }
    }
}

/// One component error of a budget.
#[derive(Clone, Debug, PartialEq)]
pub struct BudgetComponent {
    pub id: ParameterId,
    /// Position in the machine's parameter vector.
    pub index: usize,
    pub kind: ErrorKind,
    /// The axis the error belongs to.
    pub axis: char,
    /// Homogenisation length (mm) of a linear error: a tolerance of `e` um counts as `e / (L / 1000)`
    /// um/m, comparable with urad (Zhu 2008: "1 um over a 1 m axis is about 1 um/m angular error in
    /// manufacturing difficulty and cost"). 1000 mm for angular and squareness errors (no change).
    pub length_mm: f64,
}

impl BudgetComponent {
    /// Factor from the homogenised tolerance (um/m or urad) to the tolerance in its own unit.
    pub fn scale(&self) -> f64 {
        match self.kind {
            ErrorKind::Linear => self.length_mm / 1000.0,
            _ => 1.0,
        }
    }
}

/// The default homogenisation length of the linear errors of each axis (mm, canonical axis order): a
/// linear axis's travel; for a rotary axis (whose radial and axial errors have no travel of their
/// own) the longest linear travel of the machine, or 1000 mm if it has none.
pub fn default_lengths(machine: &Machine) -> Vec<f64> {
    let travel = |k: usize| machine.axes()[k].range.map(|[lo, hi]| hi - lo);
    let longest =
        (0..machine.axis_count()).filter(|&k| machine.axes()[k].kind == AxisKind::Linear).filter_map(travel).fold(0.0_f64, f64::max);
    let reference = if longest > 0.0 { longest } else { 1000.0 };
    (0..machine.axis_count())
        .map(|k| match machine.axes()[k].kind {
            AxisKind::Linear => travel(k).unwrap_or(reference),
            AxisKind::Rotary => reference,
        })
        .collect()
}

/// The standard component set of a machine:
/// - the six motion errors of every axis (linear axis X: `EXX EYX EZX EAX EBX ECX`; rotary axis C:
///   `EXC EYC EZC EAC EBC ECC`), the 18 motion errors of a three-axis machine of Zhu 2008 B.2;
/// - the squareness errors of the linear axes X, Y, Z that the machine has, one per pair: `EC0X`
///   (X to Y), `EA0Z` (Y to Z), `EB0Z` (X to Z), the three of Zhu 2008 B.2 and ISO 230-1;
/// - the location errors of every rotary axis (ISO 230-7): the position of its line (C: `EX0C EY0C`)
///   and its orientation (C: `EA0C EB0C`).
pub fn default_components(machine: &Machine) -> Vec<ParameterId> {
    let mut ids = Vec::new();
    for axis in machine.axes() {
        for component in Component::ALL {
            ids.push(ParameterId::Motion { axis: axis.letter, component });
        }
    }
    let has = |c: char| machine.axis_index(c).is_some();
    for (axis, component, other) in [('X', Component::C, 'Y'), ('Z', Component::A, 'Y'), ('Z', Component::B, 'X')] {
        if has(axis) && has(other) {
            ids.push(ParameterId::Location { axis, component });
        }
    }
    for axis in machine.axes().iter().filter(|a| a.kind == AxisKind::Rotary) {
        let own = Component::ALL.iter().position(|c| c.letter() == axis.letter).map(|i| i % 3);
        for component in Component::ALL {
            if Some(component.direction()) != own {
                ids.push(ParameterId::Location { axis: axis.letter, component });
            }
        }
    }
    ids
}

/// Binds parameter ids to a machine: index, kind, axis and homogenisation length (`lengths_mm`, one
/// per axis in canonical order). Setup errors (`TX`, `WZ`) are not components of a machine and are
/// refused, as are repeated names.
pub fn bind(machine: &Machine, ids: &[ParameterId], lengths_mm: &[f64]) -> crate::error::Result<Vec<BudgetComponent>> {
    let mut out: Vec<BudgetComponent> = Vec::with_capacity(ids.len());
    for id in ids {
        let index = machine.parameter_index(id)?;
        let Some(letter) = id.axis() else {
            crate::bail!(input, "{id} is a setup error, not a component of the machine; list motion, squareness and location errors");
        };
        crate::ensure!(out.iter().all(|c| c.index != index), input, "{id} is listed twice");
        let k = machine.axis_index(letter).expect("parameter_index checked the axis");
        let kind = ErrorKind::of(id);
        let length_mm = if kind == ErrorKind::Linear { lengths_mm[k] } else { 1000.0 };
        out.push(BudgetComponent { id: *id, index, kind, axis: letter, length_mm });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_follow_appendix_b() {
        for (name, kind) in [
            ("EXX", ErrorKind::Linear),
            ("EYC", ErrorKind::Linear),
            ("EX0C", ErrorKind::Linear),
            ("EBX", ErrorKind::Angular),
            ("ECC", ErrorKind::Angular),
            ("EC0C", ErrorKind::Angular),
            ("EC0X", ErrorKind::Squareness),
            ("EA0C", ErrorKind::Squareness),
        ] {
            assert_eq!(ErrorKind::of(&ParameterId::parse(name).unwrap()), kind, "{name}");
        }
    }

    #[test]
    fn default_set_of_a_three_axis_machine_has_21_components() {
        let m = Machine::from_toml_str(include_str!("../../../../examples/machines/vmc3.toml"), "vmc3").unwrap();
        let ids = default_components(&m);
        assert_eq!(ids.len(), 21);
        let c600u = Machine::from_toml_str(include_str!("../../../../examples/machines/c600u.toml"), "c600u").unwrap();
        let names: Vec<String> = default_components(&c600u).iter().map(|i| i.to_string()).collect();
        assert_eq!(names.len(), 30 + 3 + 8);
        for n in ["EY0A", "EZ0A", "EB0A", "EC0A", "EX0C", "EY0C", "EA0C", "EB0C"] {
            assert!(names.contains(&n.to_string()), "{n}");
        }
    }
}
