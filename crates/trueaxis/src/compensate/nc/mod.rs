//! NC-program correction (NISTIR 5236 section 4, "editing NC programs"): run an RS274/NGC program as
//! LinuxCNC 2.9 does (parameters, expressions, O-word subroutines and control flow, tool length
//! offsets, work offsets, canned cycles...) or a Fanuc program as a Fanuc control does (macro
//! variables, `IF`/`GOTO`/`WHILE`, `M98`/`M99`/`G65`), correct every point it moves to by the pose
//! correction of [`crate::compensate::Corrector`], split moves along which the correction varies
//! more than a tolerance, and write a program that differs from the input only where it must:
//! changed numbers in place, added words, added lines for the pieces of split moves; what a
//! correction cannot stay inside (a loop, a subroutine called from several places, a canned cycle)
//! is expanded into plain moves and said so at the top of the program.
//!
//! Machine positions: `machine = rotate_xy(program + G92, rotation) + work offset + tool offset`
//! (LinuxCNC `emccanon.cc`), in mm (program units x 25.4 in G20). The correction at a point uses
//! the directions of motion there (for bidirectional error models), the direction of an axis that
//! does not move being the one it last moved in, and the tool point of the active tool length
//! offset (the machine's tool point is the controlled point without offset).
//!
//! The program is read and run by the crate `trueaxis-nc` (re-exported here: [`Dialect`],
//! [`Move`], [`Trace`], [`ToolTable`], [`params`]...), which knows nothing of machine errors;
//! [`correct`] computes the corrections along its moves and the pieces a move is split into.

pub mod correct;
pub mod header;
pub mod stream;

pub use header::{FileId, Header};

use super::correction::Corrector;
use super::export::Limits;
use super::CompensateError;
use crate::machine::AxisKind;
use crate::machine::Machine;
pub use trueaxis_nc::{
    dialect, dialects, fadal, lexer, modal, params, path, plan, program, tools, trace, write, AxisSpec, Controller, Dialect, FanucSettings,
    MachineAxes, Move, MoveKind, NcError, ProgramSetup, Role, SearchPath, ToolTable, Trace, UnknownTools, MM_PER_INCH,
};

/// The axes of `machine` as the NC interpreter needs them: letters, linear or rotary, travel.
pub fn machine_axes(machine: &Machine) -> MachineAxes {
    let axes = machine.axes().iter().map(|a| AxisSpec { letter: a.letter, rotary: a.kind == AxisKind::Rotary, range: a.range }).collect();
    MachineAxes { name: machine.name.clone(), axes }
}

/// Options of the NC correction.
#[derive(Clone, Debug, PartialEq)]
pub struct NcOptions {
    /// Split a feed or arc move when the correction of a linear axis departs from the straight
    /// blend of its end values by more than this (mm).
    pub tolerance_mm: f64,
    /// The same for rotary axes (deg).
    pub rotary_tolerance_deg: f64,
    /// Decimals of written numbers in mm and deg, and in inch; `None`: LinuxCNC 5 and 6, Fanuc 3
    /// and 4 (the IS-B increment system: a number with more digits raises an alarm).
    pub decimals: Option<usize>,
    pub decimals_inch: Option<usize>,
    /// Most pieces per move.
    pub max_pieces: usize,
    /// Start position, parameters, tool table, search path.
    pub setup: ProgramSetup,
    /// Refuse the program when a correction exceeds these (um, urad; the machine's by default).
    pub limits: Limits,
    /// The dialect (the controller's); `None`: detected from the program.
    pub dialect: Option<Controller>,
    /// The header naming the machine and error files the program is corrected for (none: no
    /// header written).
    pub header: Option<Header>,
    /// Correct a program that says it was corrected already (default: refused).
    pub force: bool,
    /// Lines read, run, corrected and written at a time ([`stream`]): what the memory of a long
    /// program is bounded by (default 4096: about 8 MB).
    pub part_lines: usize,
}

impl NcOptions {
    /// Defaults: split tolerance 1 um (and 1 urad expressed in deg), the dialect's decimals, at
    /// most 10000 pieces per move, start at 0, zero offsets, the machine's correction limits, detection.
    pub fn new(machine: &Machine) -> NcOptions {
        NcOptions {
            tolerance_mm: 1e-3,
            rotary_tolerance_deg: 1e-6f64.to_degrees(),
            decimals: None,
            decimals_inch: None,
            max_pieces: 10_000,
            setup: ProgramSetup::zero(&machine_axes(machine)),
            limits: Limits::of_machine(machine),
            dialect: None,
            header: None,
            force: false,
            part_lines: 4096,
        }
    }

    /// The decimals in mm/deg and in inch for `controller` (its table's, unless given).
    pub fn decimals_for(&self, controller: Controller) -> (usize, usize) {
        let numbers = controller.table().numbers;
        let (mm, inch) = (numbers.decimals_mm, numbers.decimals_inch);
        let mm = self.decimals.unwrap_or(mm);
        (mm, self.decimals_inch.unwrap_or(if self.decimals.is_some() { mm + 1 } else { inch }))
    }
}

/// The corrected program and what happened.
#[derive(Clone, Debug, PartialEq)]
pub struct NcResult {
    /// The corrected program's bytes (line ends and bytes of the input kept).
    pub program: Vec<u8>,
    /// The dialect it was read in (detected, or as given).
    pub dialect: Controller,
    /// Moves of the run corrected.
    pub moves: usize,
    /// Blocks executed.
    pub blocks: usize,
    /// Poses corrected on the way (end points, split checks, pieces).
    pub corrected_points: usize,
    /// Lines whose text changed and lines added.
    pub changed_lines: usize,
    pub inserted_lines: usize,
    /// What was expanded into plain moves (also noted at the top of the program).
    pub expanded: Vec<String>,
    /// What was passed over (codes the dialect does not know, passed through unchanged; a
    /// program without its end), each with its file and first line.
    pub warnings: Vec<String>,
    /// Tools that were not in the tool table and took the assumed length, and how far each 100 mm
    /// of a real tool's length from it can move that tool's corrected points (um): the largest
    /// orientation error left along the program times 100 mm.
    pub assumed_tools: Vec<u32>,
    pub tool_length_um_per_100mm: Option<f64>,
    /// Corrected points that would leave the machine's travel, kept at its end (uncorrected by
    /// what lies beyond: a move to the end of the travel, e.g. `G53 G0 Z0` at the top).
    pub clamped_points: usize,
    /// Largest correction of a linear axis (um) and of a rotary axis (urad).
    pub max_correction_um: f64,
    pub max_correction_urad: f64,
    /// Largest position residual after correction and largest uncorrectable orientation (um, urad).
    pub max_residual_um: f64,
    pub max_uncorrectable_urad: f64,
    /// The canned cycles kept as cycles, per hole: its line, its moves in the run, how far the
    /// plunge leans between R and the bottom and how far its clearance moves stand off (um); the
    /// bottom and R of every hole are exact.
    pub holes: Vec<write::HoleReport>,
}

impl NcResult {
    /// The corrected program as text (bytes that are not UTF-8, from comments read byte for
    /// byte, shown as U+FFFD).
    pub fn text(&self) -> std::borrow::Cow<'_, str> {
        String::from_utf8_lossy(&self.program)
    }
}

/// A program the interpreter cannot run is bad input, at its file and line.
impl From<NcError> for crate::Error {
    fn from(e: NcError) -> crate::Error {
        crate::Error::input(e.message).in_file(e.file).at_line(e.line)
    }
}

pub(super) fn input_error(e: NcError) -> CompensateError {
    CompensateError::Input(e.to_string())
}

/// Runs a program without correcting it: its trace (moves in machine positions) and the loaded
/// program. `origin` (the file name) prefixes messages.
pub fn run_program(
    machine: &Machine,
    bytes: impl AsRef<[u8]>,
    origin: &str,
    options: &NcOptions,
) -> Result<(Trace, program::Program), CompensateError> {
    let bytes = bytes.as_ref();
    let controller = options.dialect.unwrap_or_else(|| Controller::detect(&String::from_utf8_lossy(bytes)));
    trueaxis_nc::run(&machine_axes(machine), bytes, origin, Some(controller), &setup_for(options, controller)).map_err(input_error)
}

/// The program setup of `options` for `controller`: a Fanuc reads a number without a decimal point
/// in units of the last written decimal.
fn setup_for(options: &NcOptions, controller: Controller) -> ProgramSetup {
    let mut setup = options.setup.clone();
    if controller.table().numbers.integers_are_increments {
        if let Some(d) = options.decimals {
            setup.fanuc.increment_mm = 10f64.powi(-(d as i32));
        }
    }
    setup
}

/// The moves of a program in machine positions (mm, deg).
pub fn program_moves(machine: &Machine, bytes: impl AsRef<[u8]>, origin: &str, options: &NcOptions) -> Result<Vec<Move>, CompensateError> {
    Ok(run_program(machine, bytes, origin, options)?.0.moves)
}

/// Corrects a program (its bytes, as read from the file: any line ends, a byte-order mark,
/// comments in Latin-1; see `trueaxis_nc::source`). `origin` (the file name) prefixes messages; `temperatures` are the error
/// model's sensor temperatures (degC) for the whole program (empty: 20 degC). The program is
/// corrected in parts of [`NcOptions::part_lines`] lines, or whole when it needs to be ([`stream`]).
pub fn correct_program(
    corrector: &Corrector,
    bytes: impl AsRef<[u8]>,
    origin: &str,
    options: &NcOptions,
    temperatures: &[f64],
) -> Result<NcResult, CompensateError> {
    let bytes = bytes.as_ref();
    let mut out = Vec::new();
    match stream::correct_streamed(corrector, bytes, origin, options, temperatures, stream::Spool::Memory(Vec::new()), &mut out)? {
        stream::Streamed::Done(r) => Ok(NcResult { program: out, ..*r }),
        stream::Streamed::NeedsWhole(_) => correct_whole(corrector, bytes, origin, options, temperatures),
    }
}

/// Corrects a program held whole in memory (one part: every construct of the language).
pub fn correct_whole(
    corrector: &Corrector,
    bytes: &[u8],
    origin: &str,
    options: &NcOptions,
    temperatures: &[f64],
) -> Result<NcResult, CompensateError> {
    let whole = NcOptions { part_lines: usize::MAX, ..options.clone() };
    let mut out = Vec::new();
    match stream::correct_streamed(corrector, bytes, origin, &whole, temperatures, stream::Spool::Memory(Vec::new()), &mut out)? {
        stream::Streamed::Done(r) => Ok(NcResult { program: out, ..*r }),
        stream::Streamed::NeedsWhole(_) => unreachable!("a program of one part is whole"),
    }
}

/// Corrects the program of file `path` into `out` (the returned summary's `program` is empty):
/// a regular file is read in parts, its corrected lines spooled in an unnamed temporary file, so
/// that memory does not grow with the program's length; a program that needs its whole text
/// (control flow), and a stream that cannot be read twice (a FIFO, standard input), are read whole.
pub fn correct_file(
    corrector: &Corrector,
    path: &std::path::Path,
    origin: &str,
    options: &NcOptions,
    temperatures: &[f64],
    out: &mut dyn std::io::Write,
) -> Result<NcResult, CompensateError> {
    let read_error = |source| crate::data::DataError::Read { path: origin.to_string(), source };
    let mut file = std::fs::File::open(path).map_err(read_error)?;
    if file.metadata().map_err(read_error)?.is_file() {
        let spool = stream::Spool::file().map_err(read_error)?;
        if let stream::Streamed::Done(r) = stream::correct_streamed(corrector, &mut file, origin, options, temperatures, spool, out)? {
            return Ok(*r);
        }
        file = std::fs::File::open(path).map_err(read_error)?;
    }
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(&mut file, &mut bytes).map_err(read_error)?;
    let r = if file.metadata().map_err(read_error)?.is_file() {
        correct_whole(corrector, &bytes, origin, options, temperatures)?
    } else {
        correct_program(corrector, &bytes, origin, options, temperatures)?
    };
    out.write_all(&r.program).map_err(|source| crate::data::DataError::Write { path: "the corrected program".into(), source })?;
    Ok(NcResult { program: Vec::new(), ..r })
}

/// A warning per hole kept as a cycle whose plunge leans, or whose clearance moves stand off,
/// by more than the written resolution (`resolution_um`): the bottom and R are exact, a cycle
/// carries one hole position.
pub(super) fn hole_warnings(holes: &[write::HoleReport], origin: &str, resolution_um: f64) -> Vec<String> {
    holes
        .iter()
        .filter(|h| h.lean_um.max(h.clearance_um) > resolution_um)
        .map(|h| {
            format!(
                "{origin}: line {}: {} kept as a cycle, its bottom and R corrected at the hole; the plunge from R leans {:.2} um across the hole (the correction's change between R and the bottom), its clearance moves stand up to {:.2} um off",
                h.line,
                trueaxis_nc::siemens::kept::cycle_name(h.code),
                h.lean_um,
                h.clearance_um
            )
        })
        .collect()
}
