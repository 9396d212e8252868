//! What running a program leaves: every executed line (a step) in execution order with what it
//! did: its moves in machine positions, its words with their values, the parameters it wrote, the
//! frame each move was programmed in. The writer turns a trace back into program text, line by
//! line in place or expanded into plain moves.

use crate::modal::{Frame, PlaneSelect, Vec9};
use crate::params::ParamKey;
use crate::MAX_AXES;
use std::ops::Range;

/// A machine position: mm and deg, in the machine's canonical axis order (the first
/// `Machine::axis_count` entries are used).
pub type Axes = [f64; MAX_AXES];

/// The plane of an arc in machine axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plane {
    /// Machine axis indices of the plane's first and second coordinates and of its normal.
    pub first: usize,
    pub second: usize,
    pub normal: usize,
    /// The program plane (its centre words: I J, K I, J K).
    pub select: PlaneSelect,
}

/// What a move does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MoveKind {
    /// Only the end point matters.
    Rapid,
    /// A straight line in axis space.
    Feed,
    /// A circular (helical) arc of less than one turn, or a full turn when start and end coincide
    /// in the plane; `centre` in machine positions (mm) of the plane's first and second axes.
    Arc { clockwise: bool, plane: Plane, centre: [f64; 2] },
}

/// Where a move comes from in its block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// The block's own motion, from its axis words (written in place by changing them).
    Words,
    /// The intermediate point of `G28`/`G30` (also from the block's axis words).
    Intermediate { g30: bool },
    /// The return of `G28`/`G30` to the stored position: not corrected (a reference position,
    /// often at the end of the travel).
    Home,
    /// One of the moves a canned cycle, a multi-turn arc or another expansion makes.
    Generated,
}

/// One move in machine positions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// The step that made it.
    pub step: u32,
    pub kind: MoveKind,
    pub start: Axes,
    pub end: Axes,
    /// The end in program coordinates (program units, deg), interpreter axes X Y Z A B C U V W.
    pub program_end: Vec9,
    /// Index of the frame in [`Trace::frames`].
    pub frame: u32,
    pub role: Role,
    /// Programmed in machine coordinates (`G53`).
    pub machine_coordinates: bool,
    /// Inverse-time feed of the move (G93, 1/min).
    pub inverse_time: Option<f64>,
    /// Interpreter axes with words in the block (bit 0 = X).
    pub words: u16,
}

/// A block whose words set something from the current position (the corrected program sits
/// elsewhere by the correction, so the written values must move with it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Relative {
    /// `G92`: the axis words are the new coordinates of the current point.
    G92,
    /// `G10 L20 P<system>`: the work offset such that the current point has the given coordinates
    /// in `system`, whose XY rotation is `rotation` (deg).
    G10L20 { system: u8, rotation: f64 },
    /// `G10 L10` / `L11`: the tool offset such that the current point has the given coordinates.
    G10Tool,
    /// `G28.1` / `G30.1`: the current machine position is stored in `#5161`/`#5181`...
    Store { first: u32 },
}

/// Step flags.
pub mod flags {
    /// The block read a parameter whose value differs in the corrected program (the current
    /// position, a subroutine's return value, the line number).
    pub const READS_UNSAFE: u16 = 1;
    /// The block's moves cannot be written by changing its words (a canned cycle, a multi-turn
    /// arc, a tapping cycle): the block must be expanded.
    pub const EXPAND: u16 = 2;
    /// A control statement (O-word, Fanuc IF/GOTO/WHILE/END): nothing to write when expanded.
    pub const CONTROL: u16 = 4;
    /// A subroutine call (`o.. call`, `M98`, `G65`).
    pub const CALL: u16 = 8;
    /// A backward `GOTO` was taken (Fanuc): the program is expanded as a whole.
    pub const JUMP_BACK: u16 = 16;
    /// A spline (`G5`, `G5.1`) run as chords.
    pub const SPLINE: u16 = 32;
    /// A line of a NURBS (`G5.2` control points, `G5.3` running it as chords): always written
    /// as its chords.
    pub const NURBS: u16 = 64;
    /// A SINUMERIK cycle call (`CYCLE81(...)`, `MCALL CYCLE81(...)`) or a block drilling under
    /// `MCALL`: always written as its moves, the call taken out.
    pub const SIEMENS_CYCLE: u16 = 128;
}

/// One executed line.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    pub file: u32,
    /// Line index in the file.
    pub line: u32,
    /// Call depth (0: the main program).
    pub depth: u16,
    /// Level of local parameters (calls that opened a new one).
    pub level: u16,
    pub moves: Range<u32>,
    /// Words for an expanded copy of the block, in [`Trace::words`]: what to set before its moves
    /// (modal codes, F S T, M codes, dwell, `G43 H`), the axis-setting command (`G10`, `G92`, `G52`,
    /// `G43.1`) with its words, and the stop codes after the moves.
    pub setup: Range<u32>,
    pub setting: Range<u32>,
    /// The block's axis, polar and arc words as they were evaluated (for rewriting them in place).
    pub motion_words: Range<u32>,
    pub stops: Range<u32>,
    /// Parameters the block wrote, in [`Trace::writes`], with their values (resolved assignments).
    pub writes: Range<u32>,
    pub flags: u16,
    /// A block setting something from the current position, and that position (mm, deg).
    pub relative: Option<(Relative, Axes)>,
    /// Frame before the block's moves (index in [`Trace::frames`]).
    pub frame: u32,
    /// Comments of an expanded copy, with parameters replaced by their values.
    pub messages: Range<u32>,
    /// Codes to write between the moves of an expanded copy, in [`Trace::actions`].
    pub actions: Range<u32>,
    /// After the block, the controller believes itself moved by this (mm, deg; the rs274 tool
    /// change reading of [`crate::ProgramSetup::rs274_tool_change`]).
    pub jump: Option<Axes>,
}

impl Step {
    pub fn has(&self, flag: u16) -> bool {
        self.flags & flag != 0
    }
}

/// The record of one run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    pub steps: Vec<Step>,
    pub moves: Vec<Move>,
    pub frames: Vec<Frame>,
    /// Resolved words `(letter, value)`.
    pub words: Vec<(u8, f64)>,
    pub writes: Vec<(ParamKey, f64)>,
    pub messages: Vec<String>,
    /// Codes between generated moves (a dwell or spindle codes inside a canned cycle): the index of
    /// the step's move they precede (the number of its moves: after the last) and their words.
    pub actions: Vec<(u32, Range<u32>)>,
    /// The machine position where the program starts (mm, deg).
    pub start: Axes,
    /// What the run passed over with a warning: each message once, with the file and line where
    /// it first came and how many times it came.
    pub warnings: Vec<Warning>,
    /// Tools the table lacks that took the assumed length ([`crate::UnknownTools::Assume`]).
    pub assumed_tools: Vec<u32>,
    /// The canned-cycle blocks to be written as cycles (in step order).
    pub holes: Vec<CycleHole>,
    /// The SINUMERIK holes among them, with their cycles' values (in step order).
    pub siemens_holes: Vec<crate::siemens::cycles::Hole>,
}

/// A canned-cycle block kept as a cycle in the corrected program: one hole position in the plane
/// and the levels along the cycle axis (Z in G17), in program units, absolute (the block was run in
/// G90). The corrected block carries the hole position and the bottom of the correction at the
/// bottom, and the R level of the correction at R.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleHole {
    pub step: u32,
    /// The cycle's G code times 10 (810, 840...).
    pub code: u16,
    pub plane: PlaneSelect,
    /// R level, bottom, and the level it retracts to (R with G99, the initial level with G98).
    pub r: f64,
    pub bottom: f64,
    pub clear: f64,
    /// The initial level of the run of cycles (the level before its first block).
    pub initial: f64,
    pub retract_to_r: bool,
    /// The first cycle block of a run of cycles (its initial level is the current position).
    pub first: bool,
    /// Peck depth (G73, G83; 0 otherwise) and dwell at the bottom (s; 0: none).
    pub peck: f64,
    pub dwell: f64,
    /// The moves of the step (from its first) that end at R at the hole and at the bottom (first
    /// repeat).
    pub r_move: u32,
    pub bottom_move: u32,
}

impl CycleHole {
    /// Tapping follows the spindle: its moves cannot be written as plain moves.
    pub fn tapping(&self) -> bool {
        matches!(self.code, 740 | 840)
    }
}

/// A warning of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    pub file: u32,
    /// 1-based.
    pub line: u32,
    pub message: String,
    pub count: u32,
}

impl Trace {
    /// The index of `frame`, adding it when it differs from the last one.
    pub fn frame_index(&mut self, frame: &Frame) -> u32 {
        if self.frames.last() != Some(frame) {
            self.frames.push(*frame);
        }
        (self.frames.len() - 1) as u32
    }

    /// The kept cycle of step `index`, if it is one.
    pub fn hole_of(&self, index: usize) -> Option<&CycleHole> {
        self.holes.binary_search_by_key(&(index as u32), |h| h.step).ok().map(|k| &self.holes[k])
    }

    pub fn step_moves(&self, step: &Step) -> &[Move] {
        &self.moves[step.moves.start as usize..step.moves.end as usize]
    }

    pub fn words_of(&self, range: &Range<u32>) -> &[(u8, f64)] {
        &self.words[range.start as usize..range.end as usize]
    }
}
