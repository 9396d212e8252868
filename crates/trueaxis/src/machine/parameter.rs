//! ISO 230-1 / ISO 230-7 parameter names: motion errors (`EXX`, `ECC`), location errors (`EX0C`,
//! `EB0X`) and setup errors (`TX`, `WZ`). docs/design.md, Conventions.

use std::fmt;

use crate::error::{Error, Result};

/// One of the six components of a small displacement: translations along x, y, z and rotations
/// about x, y, z (the `X Y Z A B C` of the ISO names). Translations first, unlike Soons 1993.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Component {
    X,
    Y,
    Z,
    A,
    B,
    C,
}

impl Component {
    pub const ALL: [Component; 6] = [Component::X, Component::Y, Component::Z, Component::A, Component::B, Component::C];

    /// 0..6: x, y, z translations then rotations about x, y, z.
    pub fn index(self) -> usize {
        self as usize
    }

    pub fn from_index(i: usize) -> Component {
        Self::ALL[i]
    }

    pub fn is_rotation(self) -> bool {
        self.index() >= 3
    }

    /// The coordinate direction (0 = x, 1 = y, 2 = z) the component acts along or about.
    pub fn direction(self) -> usize {
        self.index() % 3
    }

    pub fn letter(self) -> char {
        ['X', 'Y', 'Z', 'A', 'B', 'C'][self.index()]
    }

    pub fn from_letter(c: char) -> Option<Component> {
        Self::ALL.iter().copied().find(|k| k.letter() == c)
    }

    /// The unit small displacement of this component: `(eps, e)`, rotation vector and translation.
    pub fn unit_displacement(self) -> (crate::geometry::Vec3, crate::geometry::Vec3) {
        let mut axis = crate::geometry::Vec3::zeros();
        axis[self.direction()] = 1.0;
        if self.is_rotation() {
            (axis, crate::geometry::Vec3::zeros())
        } else {
            (crate::geometry::Vec3::zeros(), axis)
        }
    }

    /// User-facing unit of a value of this component: um for translations, urad for rotations.
    pub fn unit(self) -> &'static str {
        if self.is_rotation() {
            "urad"
        } else {
            "um"
        }
    }

    /// Factor from the user unit (um, urad) to the internal unit (mm, rad).
    pub fn to_internal(self) -> f64 {
        if self.is_rotation() {
            1e-6
        } else {
            1e-3
        }
    }
}

/// Which side of the machine a setup error belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SetupSide {
    /// `TX TY TZ`: offset of the tool point, in the tool body frame.
    Tool,
    /// `WX WY WZ`: offset of the workpiece point, in the workpiece body frame.
    Workpiece,
}

/// The canonical id of an error parameter (docs/design.md, Conventions, "Names").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ParameterId {
    /// Motion error of an axis, a function of its own position: `EXX`, `EBC`, ...
    Motion { axis: char, component: Component },
    /// Location error of an axis, constant: `EX0C`, `EB0X`, ...
    Location { axis: char, component: Component },
    /// Setup error, constant: `TX`, `WZ`, ... (translations only)
    Setup { side: SetupSide, component: Component },
}

impl ParameterId {
    pub fn component(&self) -> Component {
        match *self {
            ParameterId::Motion { component, .. } | ParameterId::Location { component, .. } | ParameterId::Setup { component, .. } => {
                component
            }
        }
    }

    pub fn axis(&self) -> Option<char> {
        match *self {
            ParameterId::Motion { axis, .. } | ParameterId::Location { axis, .. } => Some(axis),
            ParameterId::Setup { .. } => None,
        }
    }

    /// um or urad.
    pub fn unit(&self) -> &'static str {
        self.component().unit()
    }

    /// Parses an ISO name; accepts lower case and the letter `O` for the zero of location errors
    /// (`EXOC`). Whether the axis exists is checked by [`crate::machine::Machine::parameter_index`].
    pub fn parse(name: &str) -> Result<ParameterId> {
        let upper = name.trim().to_ascii_uppercase();
        let chars: Vec<char> = upper.chars().collect();
        let bad = |why: &str| Err(Error::input(format!("`{name}` is not an ISO 230 parameter name: {why}")));
        match chars.as_slice() {
            [side @ ('T' | 'W'), c] => match Component::from_letter(*c) {
                Some(component) if !component.is_rotation() => {
                    Ok(ParameterId::Setup { side: if *side == 'T' { SetupSide::Tool } else { SetupSide::Workpiece }, component })
                }
                _ => bad("setup errors are TX TY TZ (tool point) and WX WY WZ (workpiece point)"),
            },
            ['E', c, axis] => match Component::from_letter(*c) {
                Some(component) if is_axis_letter(*axis) => Ok(ParameterId::Motion { axis: *axis, component }),
                _ => bad("motion errors are E<direction><axis>, e.g. EXX, EYX, ECC"),
            },
            ['E', c, '0' | 'O', axis] => match Component::from_letter(*c) {
                Some(component) if is_axis_letter(*axis) => Ok(ParameterId::Location { axis: *axis, component }),
                _ => bad("location errors are E<direction>0<axis>, e.g. EX0C, EB0X"),
            },
            _ => bad("expected a motion error (EXX), a location error (EX0C) or a setup error (TX, WX)"),
        }
    }
}

impl fmt::Display for ParameterId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ParameterId::Motion { axis, component } => write!(f, "E{}{}", component.letter(), axis),
            ParameterId::Location { axis, component } => write!(f, "E{}0{}", component.letter(), axis),
            ParameterId::Setup { side, component } => {
                let s = if side == SetupSide::Tool { 'T' } else { 'W' };
                write!(f, "{}{}", s, component.letter())
            }
        }
    }
}

/// Axis letters of ISO 841: linear X Y Z and secondary U V W, rotary A B C.
pub fn is_axis_letter(c: char) -> bool {
    "XYZUVWABC".contains(c)
}

/// Whether ISO 841 reserves the letter for a rotary axis.
pub fn is_rotary_letter(c: char) -> bool {
    "ABC".contains(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_accept_the_letter_o() {
        for name in ["EXX", "ECC", "EX0C", "EB0X", "TX", "WZ", "EZ0A"] {
            assert_eq!(ParameterId::parse(name).unwrap().to_string(), name);
        }
        assert_eq!(ParameterId::parse("exoc").unwrap().to_string(), "EX0C");
    }

    #[test]
    fn malformed_names_are_rejected_with_a_reason() {
        for name in ["EQX", "TA", "E", "EXQ", "EX1C", "XX"] {
            let err = ParameterId::parse(name).unwrap_err().to_string();
            assert!(err.contains(name), "{err}");
        }
    }
}
