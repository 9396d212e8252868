//! A program corrected as a stream: read in parts of whole lines ([`trueaxis_nc::parts`]), each
//! part run, corrected and written before the next is read, so that memory does not grow with the
//! program's length. The interpreter's state, the corrector's (directions of motion, the
//! correction the controller holds) and the writer's (the corrected position, the canned-cycle
//! words the controller remembers) go on from part to part; the summary numbers are running
//! maxima and sums. The corrected lines go to a spool (memory, or an unnamed temporary file)
//! because the notes at the top of the corrected program (what was expanded, the tools taken at
//! an assumed length) are known only at the end; the output is the spool with the notes put in.
//!
//! What a part cannot decide alone falls back to the whole program, read again and corrected in
//! memory ([`super::correct_whole`]): control flow (O-words, `GOTO`, `WHILE`, calls and returns),
//! a line kept as text that reads the current position, a control structure that spans parts.
//! A program of one part is the whole program: everything runs as it would in memory.

use super::correct::{Corrections, Rounding};
use super::{header, input_error, machine_axes, plan, write, CompensateError, NcOptions, NcResult, Trace};
use crate::compensate::correction::Corrector;
use std::io::{Read, Seek, Write};
use trueaxis_nc::parts::{Part, PartReader};
use trueaxis_nc::program::{PartState, Program, SourceFile};
use trueaxis_nc::source::Ending;
use trueaxis_nc::trace::Warning;
use trueaxis_nc::{Controller, Progress, Runner};

/// Lines the dialect detection reads (`Dialect::detect`): it is given as many from the start of
/// the file, so that it sees what it sees on the whole text.
const DETECTION_LINES: usize = 20_000;

/// Where the corrected lines wait for the notes at the top.
pub enum Spool {
    Memory(Vec<u8>),
    /// An unnamed temporary file (nothing to remove, whatever ends the run), and its length.
    File(std::io::BufWriter<std::fs::File>, u64),
}

impl Spool {
    /// An unnamed temporary file in the system's temporary directory (`TMPDIR`).
    pub fn file() -> std::io::Result<Spool> {
        Ok(Spool::File(std::io::BufWriter::with_capacity(1 << 16, tempfile::tempfile()?), 0))
    }

    fn len(&self) -> u64 {
        match self {
            Spool::Memory(v) => v.len() as u64,
            Spool::File(_, n) => *n,
        }
    }

    fn push(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        match self {
            Spool::Memory(v) => v.extend_from_slice(bytes),
            Spool::File(f, n) => {
                f.write_all(bytes)?;
                *n += bytes.len() as u64;
            }
        }
        Ok(())
    }

    /// Writes the spooled bytes to `out` with `notes` put in at byte `at`.
    fn drain(self, at: u64, notes: &[u8], out: &mut dyn Write) -> std::io::Result<()> {
        match self {
            Spool::Memory(v) => {
                out.write_all(&v[..at as usize])?;
                out.write_all(notes)?;
                out.write_all(&v[at as usize..])
            }
            Spool::File(f, _) => {
                let mut file = f.into_inner().map_err(|e| e.into_error())?;
                file.rewind()?;
                std::io::copy(&mut (&mut file).take(at), out)?;
                out.write_all(notes)?;
                std::io::copy(&mut file, out).map(drop)
            }
        }
    }
}

/// What a streamed correction gave: the summary (its `program` empty: the text went to the
/// output), or the need of the whole program and why.
pub enum Streamed {
    Done(Box<NcResult>),
    NeedsWhole(String),
}

/// The program's parts with what reading them needs across parts.
struct Source<R> {
    reader: PartReader<R>,
    part_lines: usize,
    state: PartState,
    origin: String,
}

/// A part that could not be read alone: an error of the part (with the line in the file), or the
/// need of the whole program (a control structure across parts).
enum PartError {
    Input(CompensateError),
    Whole,
}

impl<R: Read> Source<R> {
    fn next(&mut self, lines: usize) -> Result<Option<Part>, CompensateError> {
        self.reader.next_part(lines).map_err(|source| crate::data::DataError::Read { path: self.origin.clone(), source }.into())
    }

    /// Reads `part` as the next part of the main file.
    fn load(&mut self, part: &Part, controller: Controller) -> Result<SourceFile, PartError> {
        let first = self.state.lines == 0;
        let before = self.state;
        SourceFile::load_part(&self.origin, &part.bytes, controller, &mut self.state, part.last).map_err(|e| {
            // a line the byte reader refuses is refused wherever it stands; an unmatched structure
            // may be matched in another part
            let whole = first && part.last;
            if whole || trueaxis_nc::source::decode_part(&part.bytes, first).is_err() {
                PartError::Input(input_error(trueaxis_nc::NcError { line: before.lines + e.line, ..e }))
            } else {
                PartError::Whole
            }
        })
    }
}

/// Corrects the program `reader` gives, as a stream, writing the corrected program to `out`.
/// Falls back on [`Streamed::NeedsWhole`] (nothing written to `out`) when a part cannot be
/// corrected alone.
pub fn correct_streamed(
    corrector: &Corrector,
    reader: impl Read,
    origin: &str,
    options: &NcOptions,
    temperatures: &[f64],
    mut spool: Spool,
    out: &mut dyn Write,
) -> Result<Streamed, CompensateError> {
    let mut source =
        Source { reader: PartReader::new(reader), part_lines: options.part_lines, state: PartState::default(), origin: origin.to_string() };
    // the dialect is detected on the first lines ended by LF, as on the whole text (a file with
    // other line ends is detected as one text)
    let read_error = |source| crate::data::DataError::Read { path: origin.to_string(), source };
    let (head, rest) = source.reader.peek(DETECTION_LINES).map_err(read_error)?;
    let detected = rest || head.iter().filter(|&&b| b == b'\n').count() >= DETECTION_LINES;
    if options.dialect.is_none() && !detected {
        return Ok(Streamed::NeedsWhole(format!("the dialect is detected on {DETECTION_LINES} lines ended by LF")));
    }
    // a corrected program is refused before anything runs (its header is in the first 100 lines
    // that are not empty, which 20,000 lines hold but in a file of blank lines)
    if !options.force {
        header::check_uncorrected(head, origin).map_err(input_error)?;
    }
    let controller = options.dialect.unwrap_or_else(|| Controller::detect(&String::from_utf8_lossy(head)));
    let dialect = controller.family();
    let Some(first) = source.next(options.part_lines)? else { unreachable!("a first part, empty or not") };
    let file = match source.load(&first, controller) {
        Ok(f) => f,
        Err(PartError::Input(e)) => return Err(e),
        Err(PartError::Whole) => return Ok(Streamed::NeedsWhole("a control structure spans parts".into())),
    };
    let setup = super::setup_for(options, controller);
    let mut program = Program { dialect, controller, files: vec![file], search: setup.search_path.clone() };
    let axes = machine_axes(corrector.machine);
    let mut runner = Runner::new(&axes, &program, &setup).map_err(input_error)?;
    runner.in_parts = !first.last;
    let tight = Tight::new(corrector, options, controller);
    let mut run = PartsRun::new(&tight, options, temperatures, controller);
    let mut part = first;
    let mut ended = false;
    loop {
        if program.files[0].continues && source.state.leading_percent.is_none() {
            return Ok(Streamed::NeedsWhole("a part of empty lines only".into()));
        }
        if !ended {
            match runner.advance(&mut program).map_err(input_error)? {
                Progress::Ended => ended = true,
                Progress::PartDone => {}
                Progress::NeedsWhole(line) => {
                    return Ok(Streamed::NeedsWhole(format!("control flow, or a NURBS across parts, at line {line}")))
                }
            }
        }
        let trace = runner.take_trace();
        if let Some(why) = run.part(&program, &trace, runner.in_parts, &mut spool)? {
            return Ok(Streamed::NeedsWhole(why));
        }
        if part.last {
            break;
        }
        part = source.next(source.part_lines)?.expect("a part after one that is not the last");
        program.files[0] = match source.load(&part, controller) {
            Ok(f) => f,
            Err(PartError::Input(e)) => return Err(e),
            Err(PartError::Whole) => return Ok(Streamed::NeedsWhole("a control structure spans parts".into())),
        };
        runner.start_part(&program);
    }
    let last_open = program.files[0].endings.last() == Some(&Ending::None);
    let result = run.finish(&source.origin, spool, last_open, out)?;
    Ok(Streamed::Done(Box::new(result)))
}

/// The correction of a program part by part: the corrector's state, the writer's, the totals.
struct PartsRun<'a, 'b> {
    corrections: Corrections<'a, 'b>,
    options: &'a NcOptions,
    controller: Controller,
    decimals: (usize, usize),
    resolution: f64,
    axes: trueaxis_nc::MachineAxes,
    carry: Option<write::Carry>,
    /// Where the notes go in the spool, once a part has placed them.
    notes_at: Option<u64>,
    moves: usize,
    blocks: usize,
    /// The run's warnings (each message once, counted) with the name of their file.
    warnings: Vec<(Warning, String)>,
    assumed_tools: Vec<u32>,
}

impl<'a, 'b> PartsRun<'a, 'b> {
    fn new(tight: &'a Tight<'b>, options: &'a NcOptions, temperatures: &[f64], controller: Controller) -> Self {
        PartsRun {
            corrections: Corrections::new(&tight.corrector, options.limits, temperatures, tight.rounding),
            options,
            controller,
            decimals: tight.decimals,
            resolution: tight.resolution,
            axes: machine_axes(tight.corrector.machine),
            carry: None,
            notes_at: None,
            moves: 0,
            blocks: 0,
            warnings: Vec::new(),
            assumed_tools: Vec::new(),
        }
    }

    /// Corrects and writes the trace of one part (`in_parts`: the program is read in parts);
    /// why the part needs the whole program, if it does.
    fn part(&mut self, program: &Program, trace: &Trace, in_parts: bool, spool: &mut Spool) -> Result<Option<String>, CompensateError> {
        let plan = plan::plan(program, trace);
        if in_parts && (plan.flattened.is_some() || !plan.regions.is_empty()) {
            return Ok(Some(plan.flattened.unwrap_or_else(|| "a part is expanded".into())));
        }
        let main = &program.files[0];
        let mut writer = write::Writer::new(&self.axes, program, trace, &plan, self.decimals.0, self.decimals.1);
        writer.machine_inch = self.options.setup.machine_inch;
        writer.line_offset = main.first_line as u32;
        writer.move_offset = self.moves as u32;
        if let Some(c) = self.carry.take() {
            writer.resume(c);
        }
        let c = &mut self.corrections;
        let mut file = usize::MAX;
        let mut pieces = Vec::new();
        for (i, step) in trace.steps.iter().enumerate() {
            if step.file as usize != file {
                file = step.file as usize;
                c.origin.clone_from(&program.files[file].name);
            }
            c.line = step.line as usize + 1 + if file == 0 { main.first_line } else { 0 };
            pieces.clear();
            for m in trace.step_moves(step) {
                let frame = trace.frames[m.frame as usize];
                pieces.push(c.pieces(m, &frame, self.options)?);
                c.finish(m);
            }
            writer.step(i, &pieces);
        }
        let mut bytes = Vec::with_capacity(main.text.len() + main.line_count() + 64);
        if main.bom {
            bytes.extend_from_slice(b"\xEF\xBB\xBF");
        }
        if let Some(at) = writer.write_lines(&mut bytes, self.notes_at.is_some()) {
            self.notes_at = Some(spool.len() + at as u64);
        }
        spool.push(&bytes).map_err(spool_error)?;
        self.moves += trace.moves.len();
        self.blocks += trace.steps.len();
        for w in &trace.warnings {
            match self.warnings.iter_mut().find(|(seen, _)| seen.message == w.message) {
                Some((seen, _)) => seen.count += w.count,
                None => self.warnings.push((w.clone(), program.files[w.file as usize].name.clone())),
            }
        }
        for t in &trace.assumed_tools {
            if !self.assumed_tools.contains(t) {
                self.assumed_tools.push(*t);
            }
        }
        self.carry = Some(writer.carry());
        Ok(None)
    }

    /// The notes put in at the top (after the leading `%` and program-number lines) and the
    /// spool written to `out` (`last_open`: the program's last line has no line end); the summary.
    fn finish(self, origin: &str, spool: Spool, last_open: bool, out: &mut dyn Write) -> Result<NcResult, CompensateError> {
        let carry = self.carry.expect("a part was written");
        let e = self.corrections.extremes;
        let (controller, dialect) = (self.controller, self.controller.family());
        let tool_length_um_per_100mm = (!self.assumed_tools.is_empty()).then_some(e.max_uncorrectable_urad * 0.1);
        let mut notes = self.options.header.as_ref().map_or_else(Vec::new, |h| h.lines(dialect));
        if self.options.header.is_some() {
            notes.push(header::dialect_line(controller, self.options.dialect.is_none()));
        }
        if let Some(per_100) = tool_length_um_per_100mm {
            notes.push(header::assumed_tools_line(&self.assumed_tools, &self.options.setup, per_100, dialect));
        }
        notes.extend(write::notes(&carry.notes, dialect));
        if controller == Controller::Siemens {
            // a SINUMERIK comment runs from `;` to the end of the block (parentheses group values)
            notes.iter_mut().for_each(|n| *n = format!(";{}", n.trim_start_matches('(').trim_end_matches(')')));
        }
        let mut text = Vec::new();
        if self.notes_at.is_none() && last_open && !notes.is_empty() {
            text.extend_from_slice(carry.eol.bytes());
        }
        for n in &notes {
            text.extend_from_slice(n.as_bytes());
            text.extend_from_slice(carry.eol.bytes());
        }
        let at = self.notes_at.unwrap_or(spool.len());
        spool.drain(at, &text, out).map_err(|source| crate::data::DataError::Write { path: "the corrected program".into(), source })?;
        let mut warnings: Vec<String> = self
            .warnings
            .iter()
            .map(|(w, name)| {
                let more = if w.count > 1 { format!(" (and {} more lines)", w.count - 1) } else { String::new() };
                format!("{name}: line {}: {}{more}", w.line, w.message)
            })
            .collect();
        warnings.extend(super::hole_warnings(&carry.holes, origin, self.resolution * 1e3));
        Ok(NcResult {
            program: Vec::new(),
            dialect: controller,
            moves: self.moves,
            blocks: self.blocks,
            corrected_points: e.corrected_points,
            changed_lines: carry.changed_lines,
            inserted_lines: carry.inserted_lines,
            expanded: carry.notes,
            warnings,
            assumed_tools: self.assumed_tools,
            tool_length_um_per_100mm,
            clamped_points: carry.clamped,
            max_correction_um: e.max_correction_um,
            max_correction_urad: e.max_correction_urad,
            max_residual_um: e.max_residual_um,
            max_uncorrectable_urad: e.max_uncorrectable_urad,
            holes: carry.holes,
        })
    }
}

fn spool_error(source: std::io::Error) -> CompensateError {
    crate::data::DataError::Write { path: "the temporary file of the corrected program".into(), source }.into()
}

/// The corrector with its solve stopping well inside the written resolution (a fifth of its last
/// digit), and that resolution.
pub(super) struct Tight<'b> {
    corrector: Corrector<'b>,
    rounding: Rounding,
    resolution: f64,
    decimals: (usize, usize),
}

impl<'b> Tight<'b> {
    fn new(corrector: &Corrector<'b>, options: &NcOptions, controller: Controller) -> Tight<'b> {
        let (decimals, decimals_inch) = options.decimals_for(controller);
        let resolution = 10f64.powi(-(decimals as i32)).min(super::MM_PER_INCH * 10f64.powi(-(decimals_inch as i32)));
        let mut tight = *corrector;
        tight.options.tolerance_mm = tight.options.tolerance_mm.min(0.2 * resolution);
        Tight {
            corrector: tight,
            rounding: Rounding::of_decimals(decimals, decimals_inch),
            resolution,
            decimals: (decimals, decimals_inch),
        }
    }
}
