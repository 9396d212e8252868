//! The axes of the machine a program runs on, as the interpreter needs them: their letters in the
//! machine's canonical order, whether each is linear (mm) or rotary (deg), and their travel. The
//! interpreter knows nothing else of the machine (no kinematics, no errors).

use std::fmt;

/// Most machine axes (X Y Z A B C U V W).
pub const MAX_AXES: usize = 9;

/// One machine axis.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisSpec {
    /// Upper-case letter: X Y Z A B C U V W.
    pub letter: char,
    /// Rotary (positions in deg) rather than linear (mm).
    pub rotary: bool,
    /// Travel `[low, high]` (mm or deg); `None`: unlimited.
    pub range: Option<[f64; 2]>,
}

impl AxisSpec {
    /// Whether `position` is within the travel (1e-9 of slack for rounding).
    pub fn in_range(&self, position: f64) -> bool {
        match self.range {
            None => true,
            Some([lo, hi]) => position >= lo - 1e-9 && position <= hi + 1e-9,
        }
    }

    fn unit(&self) -> &'static str {
        if self.rotary {
            "deg"
        } else {
            "mm"
        }
    }
}

/// The machine's axes in canonical order, and its name for messages.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineAxes {
    pub name: String,
    pub axes: Vec<AxisSpec>,
}

impl MachineAxes {
    /// The index of the axis with `letter`.
    pub fn axis_index(&self, letter: char) -> Option<usize> {
        self.axes.iter().position(|a| a.letter == letter)
    }

    pub fn axis_count(&self) -> usize {
        self.axes.len()
    }

    /// Letters in canonical order, e.g. `"XYZAC"`.
    pub fn axis_letters(&self) -> String {
        self.axes.iter().map(|a| a.letter).collect()
    }

    pub fn axes(&self) -> &[AxisSpec] {
        &self.axes
    }

    /// Whether every position (mm, deg, canonical order) is finite and within its axis's travel;
    /// the first that is not, named.
    pub fn check_range(&self, positions: &[f64]) -> Result<(), OutsideTravel> {
        for (axis, &position) in self.axes.iter().zip(positions) {
            if !position.is_finite() || !axis.in_range(position) {
                return Err(OutsideTravel { axis: axis.clone(), position });
            }
        }
        Ok(())
    }
}

/// A machine position that is not a finite number, or lies outside its axis's travel.
#[derive(Clone, Debug, PartialEq)]
pub struct OutsideTravel {
    pub axis: AxisSpec,
    /// The position asked for (mm or deg; NaN or infinite when not a number).
    pub position: f64,
}

impl fmt::Display for OutsideTravel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (letter, u) = (self.axis.letter, self.position);
        match self.axis.range {
            Some([lo, hi]) if u.is_finite() => {
                let unit = self.axis.unit();
                write!(f, "axis {letter} at {u} {unit} is outside its range [{lo}, {hi}] {unit}")
            }
            _ => write!(f, "axis {letter} position is not a finite number"),
        }
    }
}

impl std::error::Error for OutsideTravel {}
