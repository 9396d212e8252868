//! Where a machine's rotary axes are, in the terms the controllers' five-axis functions use: on the
//! table (the part rotates), on the head (the tool rotates), or one of each; the first rotary axis
//! is the one nearer the machine base (its motion carries the second), except for the mixed case,
//! where the controllers make the head axis the first (Siemens CYCLE800 "rotary axis 1 is always the
//! axis for the tool orientation" with mixed kinematics; Fanuc parameter 19680 = 21).

use crate::machine::{AxisKind, Machine};

/// The controllers' classes of rotary-axis layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RotaryKind {
    /// Every rotary axis carries the workpiece (Siemens kinematic type P, Fanuc 12).
    Table,
    /// Every rotary axis carries the tool (Siemens T, Fanuc 2).
    Head,
    /// One rotary axis on each side (Siemens M, Fanuc 21).
    Mixed,
}

/// The rotary axes of a machine with one or two of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RotaryLayout {
    pub kind: RotaryKind,
    /// Axis indices (canonical order) of the first and second rotary axis.
    pub first: usize,
    pub second: Option<usize>,
}

impl RotaryLayout {
    /// The layout of `machine`; `None` without a rotary axis or with more than two.
    pub fn of(machine: &Machine) -> Option<RotaryLayout> {
        let rotary =
            |chain: &[usize]| -> Vec<usize> { chain.iter().copied().filter(|&k| machine.axes()[k].kind == AxisKind::Rotary).collect() };
        let (work, tool) = (rotary(machine.work_chain()), rotary(machine.tool_chain()));
        match (work.as_slice(), tool.as_slice()) {
            (&[], &[]) => None,
            (&[a], &[]) => Some(RotaryLayout { kind: RotaryKind::Table, first: a, second: None }),
            (&[a, b], &[]) => Some(RotaryLayout { kind: RotaryKind::Table, first: a, second: Some(b) }),
            (&[], &[a]) => Some(RotaryLayout { kind: RotaryKind::Head, first: a, second: None }),
            (&[], &[a, b]) => Some(RotaryLayout { kind: RotaryKind::Head, first: a, second: Some(b) }),
            (&[w], &[t]) => Some(RotaryLayout { kind: RotaryKind::Mixed, first: t, second: Some(w) }),
            _ => None,
        }
    }

    /// The rotary axes, first then second.
    pub fn axes(&self) -> Vec<usize> {
        std::iter::once(self.first).chain(self.second).collect()
    }
}
