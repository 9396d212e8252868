//! Machine descriptions: axes, the structure code, ISO 230 parameter names, and the machine TOML
//! of docs/design.md, Files.

mod axis;
mod error;
mod file;
mod independence;
mod limits;
mod parameter;
mod structure;

pub use axis::{Axis, AxisKind, Side};
pub use error::MachineError;
pub(crate) use file::one_line;
pub use file::DIRECTION_NORM_TOLERANCE;
pub use independence::MIN_INDEPENDENCE;
pub use limits::{
    check_limit_value, CorrectionLimits, DEFAULT_CORRECTION_UM, DEFAULT_CORRECTION_URAD, MAX_CORRECTION_UM, MAX_CORRECTION_URAD,
};
pub use parameter::{is_axis_letter, is_rotary_letter, Component, ParameterId, SetupSide};
pub use structure::Structure;

use crate::error::{Error, Result};
use crate::geometry::Vec3;

/// Number of error components per axis block (motion or location).
const SIX: usize = 6;

/// An immutable machine description. Built once; evaluations borrow it.
///
/// Axes are stored in the canonical ISO order X Y Z U V W A B C; a pose is a slice of axis positions
/// in that order. The parameter vector holds, per axis in that order, the six motion errors
/// `EX? EY? EZ? EA? EB? EC?` then the six location errors `EX0? .. EC0?`, followed by the setup
/// errors `TX TY TZ WX WY WZ`.
#[derive(Clone, Debug)]
pub struct Machine {
    pub name: String,
    /// Where the description comes from (a seed, a manual), free text.
    pub source: Option<String>,
    pub structure: Structure,
    axes: Vec<Axis>,
    /// Tool point at home, in M (mm).
    pub tool_point: Vec3,
    /// The largest corrections trueaxis may write (`[limits]`, defaults when absent).
    pub correction_limits: CorrectionLimits,
    tool_chain: Vec<usize>,
    work_chain: Vec<usize>,
}

impl Machine {
    /// Parses and validates a machine TOML; `origin` (a file name) prefixes every error message.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Machine, MachineError> {
        file::parse(text, origin)
    }

    /// Reads a machine TOML file.
    pub fn load(path: impl AsRef<std::path::Path>) -> Result<Machine, MachineError> {
        let path = path.as_ref();
        let text =
            crate::files::inputs::read_to_string(path).map_err(|source| MachineError::Read { path: path.display().to_string(), source })?;
        Self::from_toml_str(&text, &path.display().to_string())
    }

    fn assemble(name: String, source: Option<String>, structure: Structure, mut axes: Vec<Axis>, tool_point: Vec3) -> Machine {
        const ORDER: &str = "XYZUVWABC";
        axes.sort_by_key(|a| ORDER.find(a.letter));
        let index = |c: &char| axes.iter().position(|a| a.letter == *c).expect("validated structure");
        let tool_chain = structure.tool_side.iter().map(index).collect();
        let work_chain = structure.workpiece_side.iter().map(index).collect();
        Machine { name, source, structure, axes, tool_point, correction_limits: CorrectionLimits::default(), tool_chain, work_chain }
    }

    /// Axes in canonical order (the order of pose vectors).
    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    pub fn axis_count(&self) -> usize {
        self.axes.len()
    }

    pub fn axis_index(&self, letter: char) -> Option<usize> {
        self.axes.iter().position(|a| a.letter == letter)
    }

    /// Tool-side axis indices, base outward.
    pub fn tool_chain(&self) -> &[usize] {
        &self.tool_chain
    }

    /// Workpiece-side axis indices, base outward.
    pub fn work_chain(&self) -> &[usize] {
        &self.work_chain
    }

    /// Axis letters in canonical order, e.g. `"XYZAC"`.
    pub fn axis_letters(&self) -> String {
        self.axes.iter().map(|a| a.letter).collect()
    }

    /// Length of the parameter vector: 12 per axis plus 6 setup errors.
    pub fn parameter_count(&self) -> usize {
        2 * SIX * self.axes.len() + SIX
    }

    /// Index of the motion error `component` of axis number `axis`.
    pub fn motion_index(&self, axis: usize, component: Component) -> usize {
        2 * SIX * axis + component.index()
    }

    /// Index of the location error `component` of axis number `axis`.
    pub fn location_index(&self, axis: usize, component: Component) -> usize {
        2 * SIX * axis + SIX + component.index()
    }

    /// Index of a setup error (translations only).
    pub fn setup_index(&self, side: SetupSide, component: Component) -> usize {
        let base = 2 * SIX * self.axes.len() + if side == SetupSide::Tool { 0 } else { 3 };
        base + component.direction()
    }

    /// Position of a parameter in the parameter vector; an error names the unknown axis.
    pub fn parameter_index(&self, id: &ParameterId) -> Result<usize> {
        let axis_of = |letter: char| {
            self.axis_index(letter).ok_or_else(|| {
                let axes = self.axis_letters();
                Error::input(format!("{id} refers to axis {letter}, which machine `{}` does not have (axes: {axes})", self.name))
            })
        };
        Ok(match *id {
            ParameterId::Motion { axis, component } => self.motion_index(axis_of(axis)?, component),
            ParameterId::Location { axis, component } => self.location_index(axis_of(axis)?, component),
            ParameterId::Setup { side, component } => self.setup_index(side, component),
        })
    }

    /// Parses an ISO name and checks it against this machine.
    pub fn parse_parameter(&self, name: &str) -> Result<(ParameterId, usize)> {
        let id = ParameterId::parse(name)?;
        let index = self.parameter_index(&id)?;
        Ok((id, index))
    }

    /// The id of the parameter at `index` (inverse of [`Machine::parameter_index`]).
    pub fn parameter_id(&self, index: usize) -> ParameterId {
        let n = self.axes.len();
        if index >= 2 * SIX * n {
            let k = index - 2 * SIX * n;
            let side = if k < 3 { SetupSide::Tool } else { SetupSide::Workpiece };
            return ParameterId::Setup { side, component: Component::from_index(k % 3) };
        }
        let axis = self.axes[index / (2 * SIX)].letter;
        let component = Component::from_index(index % SIX);
        if index % (2 * SIX) < SIX {
            ParameterId::Motion { axis, component }
        } else {
            ParameterId::Location { axis, component }
        }
    }

    /// All parameter ids in vector order.
    pub fn parameter_ids(&self) -> Vec<ParameterId> {
        (0..self.parameter_count()).map(|i| self.parameter_id(i)).collect()
    }

    /// Converts a pose from user units (mm, deg) to internal units (mm, rad).
    pub fn pose_to_internal(&self, user: &[f64], internal: &mut [f64]) {
        for ((axis, u), q) in self.axes.iter().zip(user).zip(internal.iter_mut()) {
            *q = axis.position_to_internal(*u);
        }
    }

    /// Refuses a pose (user units) with an axis outside its travel: the first such axis, as bad input.
    pub fn check_range(&self, user: &[f64]) -> Result<()> {
        for (axis, &u) in self.axes.iter().zip(user) {
            crate::ensure!(u.is_finite(), input, "axis {} position is not a finite number", axis.letter);
            if !axis.in_range(u) {
                let [lo, hi] = axis.range.expect("in_range is true without a range");
                let unit = axis.position_unit();
                crate::bail!(input, "axis {} at {u} {unit} is outside its range [{lo}, {hi}] {unit}", axis.letter);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const C600U: &str = include_str!("../../../../examples/machines/c600u.toml");

    #[test]
    fn parameter_indices_round_trip() {
        let m = Machine::from_toml_str(C600U, "c600u").unwrap();
        assert_eq!(m.axis_letters(), "XYZAC");
        assert_eq!(m.parameter_count(), 66);
        for i in 0..m.parameter_count() {
            let id = m.parameter_id(i);
            assert_eq!(m.parameter_index(&id).unwrap(), i, "{id}");
        }
        assert_eq!(m.parameter_id(m.location_index(4, Component::X)).to_string(), "EX0C");
        assert!(m.parse_parameter("EX0B").unwrap_err().to_string().contains("axis B"));
    }

    #[test]
    fn chains_follow_the_structure_code() {
        let m = Machine::from_toml_str(C600U, "c600u").unwrap();
        let letters = |chain: &[usize]| chain.iter().map(|&i| m.axes()[i].letter).collect::<String>();
        assert_eq!(letters(m.work_chain()), "AC");
        assert_eq!(letters(m.tool_chain()), "YXZ");
    }
}
