//! NC programs as a controller runs them: reading an RS274/NGC program as LinuxCNC 2.9 does
//! (parameters, expressions, O-word subroutines and control flow, tool length offsets, work
//! offsets, canned cycles...) or a Fanuc program as a Fanuc control does (macro variables,
//! `IF`/`GOTO`/`WHILE`, `M98`/`M99`/`G65`), into canonical moves in machine positions (mm, deg);
//! planning which lines of a program can keep their text when its points move, and writing the
//! program again with moved points. It knows the machine's axes and their travel
//! ([`MachineAxes`]) and nothing of machine errors: the correction that moves the points is the
//! core library's (`trueaxis::compensate::nc`).
//!
//! Machine positions: `machine = rotate_xy(program + G92, rotation) + work offset + tool offset`
//! (LinuxCNC `emccanon.cc`), in mm (program units x 25.4 in G20).
//!
//! Files: [`lexer`] (reading a line), [`expr`] (expressions), [`params`] (parameters and their
//! scopes), [`program`] (files and their control structures), [`interpret`] (control flow),
//! [`execute`] (blocks, the modal state of [`modal`]), [`offsets`], [`system`] (computed parameters),
//! [`arcs`], [`splines`] and [`nurbs`] (as chords), [`cycles`], [`tools`] (tool table), [`dialect`] (the two
//! families of grammar), [`dialects`] (each controller's codes, as data), [`siemens`] (the
//! SINUMERIK 840D's own language, read into the same lines), [`trace`] (what a run did),
//! `subprograms` (Mach3/Mach4 `M98` and Haas `M97` calls), `grbl_system` (grbl's `$` lines),
//! [`plan`] (what stays, what is expanded), [`path`] (points along moves, split points),
//! [`write`] (the text with moved points), [`parts`] (a file read in parts, for programs of any
//! length).

pub mod arcs;
pub mod axes;
pub mod cycles;
pub mod dialect;
pub mod dialects;
pub mod execute;
pub mod expr;
pub mod fadal;
mod grbl_system;
pub mod interpret;
pub mod lexer;
pub mod modal;
pub mod nurbs;
pub mod offsets;
pub mod params;
pub mod parts;
pub mod path;
pub mod plan;
pub mod program;
pub mod siemens;
pub mod source;
pub mod splines;
mod subprograms;
pub mod system;
pub mod tools;
pub mod trace;
pub mod write;

pub use axes::{AxisSpec, MachineAxes, MAX_AXES};
pub use dialect::Dialect;
pub use dialects::Controller;
pub use interpret::{FanucSettings, Progress, Runner};
pub use modal::MM_PER_INCH;
pub use program::{Program, SearchPath};
pub use tools::ToolTable;
pub use trace::{CycleHole, Move, MoveKind, Role, Trace, Warning};

use std::fmt;

/// Why a program cannot be run, with its file and line.
#[derive(Debug, Clone, PartialEq)]
pub struct NcError {
    pub file: String,
    pub line: usize,
    pub message: String,
}

impl fmt::Display for NcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: line {}: {}", self.file, self.line, self.message)
    }
}

impl std::error::Error for NcError {}

/// Where and with what a program starts.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramSetup {
    /// Machine position before the first move (mm, deg; machine axis order); rs274 starts at 0.
    pub start: Vec<f64>,
    /// Parameters at the start (LinuxCNC parameter file: work offsets `#5221`..., the `G28`/`G30`
    /// positions `#5161`/`#5181`..., the coordinate system `#5220`), machine units.
    pub parameters: Vec<(u32, f64)>,
    /// The tool table (machine units).
    pub tools: ToolTable,
    /// Machine units are inch (parameters, tool table): LinuxCNC's `rs274` without an INI file
    /// works in inch; default mm.
    pub machine_inch: bool,
    /// Where subroutine files are found.
    pub search_path: SearchPath,
    pub fanuc: FanucSettings,
    /// Re-read the position after a tool change (`M6`, `M61`) the way LinuxCNC's standalone
    /// `rs274` does: from the last move in program coordinates, forgetting tool length offset
    /// changes made since (`T1 M6 G43 H1` then reads the machine as if it had moved by the offset).
    /// For checking corrected programs with rs274; LinuxCNC itself keeps the machine position
    /// (default false).
    pub rs274_tool_change: bool,
    /// What a tool the table lacks (or every tool, without a table) is taken as.
    pub unknown_tools: UnknownTools,
    /// Most blocks the run may execute before it is refused as an endless loop
    /// ([`interpret::MAX_STEPS`] by default; the fuzz targets use far fewer so that a mutated
    /// loop condition costs milliseconds, not minutes).
    pub max_blocks: usize,
    /// Write drilling and boring cycles as plain moves (`--expand-cycles`); by default a canned
    /// cycle run in G90 stays a cycle (its hole position and levels corrected). Tapping is always
    /// kept as a cycle.
    pub expand_cycles: bool,
}

/// What a tool that is not in the tool table is taken as.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum UnknownTools {
    /// Refused with the line (`--strict-tools`).
    Refuse,
    /// A tool of this length offset (Z, machine units): 0 puts its tip at the machine file's tool
    /// point. The moves then hold the error of that assumption, which the corrector states.
    Assume(f64),
}

impl ProgramSetup {
    /// All zero for a machine with `axes`: start at 0, no offsets, an empty tool table, mm.
    pub fn zero(axes: &MachineAxes) -> ProgramSetup {
        ProgramSetup {
            start: vec![0.0; axes.axis_count()],
            parameters: Vec::new(),
            tools: ToolTable::default(),
            machine_inch: false,
            search_path: SearchPath::default(),
            fanuc: FanucSettings::default(),
            rs274_tool_change: false,
            unknown_tools: UnknownTools::Assume(0.0),
            max_blocks: interpret::MAX_STEPS,
            expand_cycles: false,
        }
    }

    /// Sets the work offset of coordinate system `system` (1 = G54 ... 9 = G59.3; in the Fanuc
    /// family 10 + p - 1 = `G54.1 P<p>`, a Fadal's `E7`-`E48` at p = 7-48): the machine position of the program zero, `values` per machine axis (mm, deg).
    pub fn set_work_offset(&mut self, axes: &MachineAxes, system: u8, values: &[f64]) {
        // G54-G59.3 at #5221...; the Fanuc family's additional offsets (G54.1 P, a Fadal's E7-E48)
        // at #7001...
        let base = if system > 9 { 7001 + 20 * u32::from(system - 10) } else { 5201 + 20 * u32::from(system) };
        for (axis, v) in axes.axes().iter().zip(values) {
            let k = tools::AXIS_LETTERS.iter().position(|&l| l as char == axis.letter).expect("a machine axis letter");
            let v = if self.machine_inch && modal::is_linear(k) { v / MM_PER_INCH } else { *v };
            self.parameters.retain(|(n, _)| *n != base + k as u32);
            self.parameters.push((base + k as u32, v));
        }
    }
}

/// Reads and runs a program from its bytes (`controller`: `None` detects it from the text): the
/// trace of the run (moves in machine positions) and the loaded program. `origin` (the file name)
/// prefixes messages.
pub fn run(
    axes: &MachineAxes,
    bytes: &[u8],
    origin: &str,
    controller: Option<Controller>,
    setup: &ProgramSetup,
) -> Result<(Trace, Program), NcError> {
    let controller = controller.unwrap_or_else(|| Controller::detect(&String::from_utf8_lossy(bytes)));
    let main = program::SourceFile::load_part(origin, bytes, controller, &mut Default::default(), true)?;
    let program = Program { dialect: controller.family(), controller, files: vec![main], search: setup.search_path.clone() };
    interpret::run(axes, program, setup)
}
