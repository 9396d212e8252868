//! The modal state of an NC interpreter and the coordinate frames it moves in.
//!
//! As LinuxCNC 2.9 keeps it (`interp_internal.hh`, `emccanon.cc`): the current position in program
//! coordinates and program units; the work offset of the active coordinate system (`G54`-`G59.3`,
//! with its XY rotation), the `G92` offset and the tool length offset in program units. The
//! machine position of a program point `p` is
//!
//! ```text
//! machine = rotate_xy(p + g92, rotation) + g5x + tool_offset     (program units; x 25.4 in inch)
//! ```
//!
//! Interpreter axes are X Y Z A B C U V W (LinuxCNC's order), rotary A B C in degrees.

use crate::tools::AXIS_LETTERS;

/// Interpreter axes: X Y Z A B C U V W.
pub const AXES: usize = 9;
/// A vector over the interpreter axes.
pub type Vec9 = [f64; AXES];
/// Millimetres per inch.
pub const MM_PER_INCH: f64 = 25.4;

/// Whether interpreter axis `k` is linear (X Y Z U V W) rather than rotary (A B C).
pub fn is_linear(k: usize) -> bool {
    !(3..6).contains(&k)
}

/// The interpreter axis of an axis letter.
pub fn axis_of_letter(letter: u8) -> Option<usize> {
    AXIS_LETTERS.iter().position(|&l| l == letter)
}

/// The plane of arcs and canned cycles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PlaneSelect {
    /// G17: arcs in X Y (centre words I J), cycles along Z.
    #[default]
    Xy,
    /// G18: arcs in Z X (K I), cycles along Y.
    Xz,
    /// G19: arcs in Y Z (J K), cycles along X.
    Yz,
}

impl PlaneSelect {
    /// Interpreter axes of the first and second plane coordinates and of the normal.
    pub fn axes(self) -> [usize; 3] {
        match self {
            PlaneSelect::Xy => [0, 1, 2],
            PlaneSelect::Xz => [2, 0, 1],
            PlaneSelect::Yz => [1, 2, 0],
        }
    }

    /// Letters of the centre words of the first and second plane coordinates.
    pub fn centre_letters(self) -> [u8; 2] {
        match self {
            PlaneSelect::Xy => *b"IJ",
            PlaneSelect::Xz => *b"KI",
            PlaneSelect::Yz => *b"JK",
        }
    }

    pub fn gcode(self) -> f64 {
        match self {
            PlaneSelect::Xy => 17.0,
            PlaneSelect::Xz => 18.0,
            PlaneSelect::Yz => 19.0,
        }
    }
}

/// The motion mode (group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Motion {
    /// G80 (or none yet).
    #[default]
    None,
    Rapid,
    Feed,
    Arc {
        clockwise: bool,
    },
    /// A canned cycle: G73, G74, G81-G89 (the number times 10: 730, 810, ...).
    Cycle(u16),
    /// A LinuxCNC spline: G5 (50) or G5.1 (51).
    Spline(u16),
}

/// Feed rate mode (group 5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FeedMode {
    /// G94.
    #[default]
    PerMinute,
    /// G93: F is the inverse of the move's time (1/min).
    InverseTime,
    /// G95.
    PerRevolution,
}

/// Spindle state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Spindle {
    #[default]
    Stopped,
    Clockwise,
    CounterClockwise,
}

/// The transformation between program coordinates and machine positions, and the modes that
/// decide how a written number becomes a coordinate. Plain data, copied into every move.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Frame {
    /// G20.
    pub inch: bool,
    /// G91.
    pub incremental: bool,
    /// G90.1: arc centres absolute.
    pub ijk_absolute: bool,
    /// G7: X words are diameters.
    pub diameter: bool,
    /// Active coordinate system, 1 (G54) to 9 (G59.3).
    pub system: u8,
    /// Work offset, G92 offset, tool offset (program units, deg).
    pub g5x: Vec9,
    pub g92: Vec9,
    pub tool: Vec9,
    /// XY rotation of the coordinate system (deg).
    pub rotation: f64,
    /// The tool offset the controller still counts its program position with (`None`: `tool`). A
    /// Fanuc applies a tool length offset by moving (`G43`/`G44`/`G49`, parameter TOS = 0): its
    /// program position stays and the next move takes the machine there with the new offset.
    pub held_tool: Option<Vec9>,
}

impl Frame {
    /// Program units per millimetre of a linear axis.
    pub fn scale(&self) -> f64 {
        if self.inch {
            MM_PER_INCH
        } else {
            1.0
        }
    }

    /// External (machine) position in program units of program point `p`.
    pub fn external(&self, p: &Vec9) -> Vec9 {
        let mut e: Vec9 = std::array::from_fn(|k| p[k] + self.g92[k]);
        if self.rotation != 0.0 {
            let (s, c) = self.rotation.to_radians().sin_cos();
            let (x, y) = (e[0], e[1]);
            e[0] = x * c - y * s;
            e[1] = x * s + y * c;
        }
        std::array::from_fn(|k| e[k] + self.g5x[k] + self.tool[k])
    }

    /// Program point of the external position `e` (program units).
    pub fn program(&self, e: &Vec9) -> Vec9 {
        let mut p: Vec9 = std::array::from_fn(|k| e[k] - self.g5x[k] - self.tool[k]);
        if self.rotation != 0.0 {
            let (s, c) = self.rotation.to_radians().sin_cos();
            let (x, y) = (p[0], p[1]);
            p[0] = x * c + y * s;
            p[1] = -x * s + y * c;
        }
        std::array::from_fn(|k| p[k] - self.g92[k])
    }

    /// Machine position (mm, deg) of the external position `e` (program units).
    pub fn to_mm(&self, e: &Vec9) -> Vec9 {
        let s = self.scale();
        std::array::from_fn(|k| if is_linear(k) { e[k] * s } else { e[k] })
    }

    /// External position (program units) of a machine position (mm, deg).
    pub fn from_mm(&self, m: &Vec9) -> Vec9 {
        let s = self.scale();
        std::array::from_fn(|k| if is_linear(k) { m[k] / s } else { m[k] })
    }

    /// Machine position (mm, deg) of program point `p`.
    pub fn machine(&self, p: &Vec9) -> Vec9 {
        self.to_mm(&self.external(p))
    }

    /// Program point of a machine position (mm, deg).
    pub fn program_of_machine(&self, m: &Vec9) -> Vec9 {
        self.program(&self.from_mm(m))
    }

    /// The frame the controller's program position is counted in before this frame's move: its
    /// tool offset the held one (a Fanuc's after `G43` without a move).
    pub fn held(&self) -> Frame {
        Frame { tool: self.held_tool.unwrap_or(self.tool), held_tool: None, ..*self }
    }
}

/// What canned cycles remember between blocks (program units).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct CycleMemory {
    pub r: f64,
    pub q: f64,
    pub p: f64,
    /// The bottom (Z in G17) of the last cycle.
    pub bottom: f64,
    pub i: f64,
    pub j: f64,
    pub k: f64,
    /// The initial level of a run of cycles (G98 returns to it).
    pub initial: Option<f64>,
}

/// The modal state of the interpreter.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct State {
    pub frame: Frame,
    /// Current point, program coordinates (program units, deg).
    pub position: Vec9,
    pub plane: PlaneSelect,
    pub motion: Motion,
    /// The last of G00-G03 (a Fanuc's group 01, which its canned cycles in group 09 leave as it was).
    pub group01: Motion,
    pub feed_mode: FeedMode,
    /// F (program units per minute, per revolution, or 1/min).
    pub feed: f64,
    pub speed: f64,
    pub spindle: Spindle,
    /// G99: canned cycles retract to R (else G98: to the initial level).
    pub retract_to_r: bool,
    pub cycle: CycleMemory,
    /// Tool in the spindle, tool selected by T.
    pub tool: u32,
    pub selected_tool: Option<u32>,
    /// A tool change happened (`G43` without `H` then takes the spindle's tool).
    pub tool_changed: bool,
    /// G43 active (tool length offset from the table).
    pub tool_offset_on: bool,
    /// G96 constant surface speed.
    pub css: bool,
    /// G61 / G61.1 / G64 (path control), kept as the G-code times 10, and the tolerances P Q of
    /// G64.
    pub path_mode: u16,
    pub path_tolerance: Option<f64>,
    pub naive_tolerance: Option<f64>,
    /// G92 offsets applied (#5210).
    pub g92_applied: bool,
    /// Flood / mist coolant.
    pub flood: bool,
    pub mist: bool,
}

/// The modes M70 saves and M72 restores (LinuxCNC "save/restore modal state").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SavedModes {
    pub inch: bool,
    pub incremental: bool,
    pub ijk_absolute: bool,
    pub diameter: bool,
    pub plane: PlaneSelect,
    pub motion: Motion,
    pub feed_mode: FeedMode,
    pub feed: f64,
    pub speed: f64,
    pub spindle: Spindle,
    pub retract_to_r: bool,
    pub css: bool,
    pub path_mode: u16,
    pub system: u8,
    pub flood: bool,
    pub mist: bool,
}

impl State {
    pub fn saved_modes(&self) -> SavedModes {
        SavedModes {
            inch: self.frame.inch,
            incremental: self.frame.incremental,
            ijk_absolute: self.frame.ijk_absolute,
            diameter: self.frame.diameter,
            plane: self.plane,
            motion: self.motion,
            feed_mode: self.feed_mode,
            feed: self.feed,
            speed: self.speed,
            spindle: self.spindle,
            retract_to_r: self.retract_to_r,
            css: self.css,
            path_mode: self.path_mode,
            system: self.frame.system,
            flood: self.flood,
            mist: self.mist,
        }
    }

    /// Changes the length units, converting the position and the offsets like LinuxCNC
    /// (`convert_length_units`).
    pub fn set_inch(&mut self, inch: bool) {
        if self.frame.inch == inch {
            return;
        }
        let factor = if inch { 1.0 / MM_PER_INCH } else { MM_PER_INCH };
        for k in (0..AXES).filter(|&k| is_linear(k)) {
            self.position[k] *= factor;
            self.frame.g5x[k] *= factor;
            self.frame.g92[k] *= factor;
            self.frame.tool[k] *= factor;
        }
        self.frame.inch = inch;
        self.feed *= factor;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_round_trip_with_rotation_and_offsets() {
        let frame = Frame {
            inch: true,
            rotation: 30.0,
            g5x: [1.0, 2.0, 3.0, 10.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            g92: [0.5, -0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            tool: [0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            ..Frame::default()
        };
        let p = [1.0, 0.0, -1.0, 45.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let m = frame.machine(&p);
        // x + g92 = 1.5, y + g92 = -0.5 rotated by 30 deg, then the offsets; inch to mm
        let (s, c) = (0.5f64, 3f64.sqrt() / 2.0);
        assert!((m[0] - (1.5 * c + 0.5 * s + 1.0) * 25.4).abs() < 1e-12);
        assert!((m[1] - (1.5 * s - 0.5 * c + 2.0) * 25.4).abs() < 1e-12);
        assert!((m[2] - 4.0 * 25.4).abs() < 1e-12);
        assert_eq!(m[3], 55.0);
        let back = frame.program_of_machine(&m);
        for k in 0..AXES {
            assert!((back[k] - p[k]).abs() < 1e-12);
        }
    }
}
