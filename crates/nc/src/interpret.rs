//! Running a program: the program counter over the lines of its files, the control flow (LinuxCNC
//! O-words: `sub`/`endsub`/`call`/`return`, `if`/`elseif`/`else`, `while`/`do`/`repeat`,
//! `break`/`continue`; Fanuc `GOTO`, `IF`, `WHILE ... DO`/`END`, `M98`/`M99`, `G65`), the parameters
//! an expression reads (stored, or computed from the modal state), and the [`Trace`] it leaves.
//! The blocks themselves are executed in [`crate::execute`].

use crate::axes::MachineAxes;
use crate::dialect::Dialect;
use crate::expr::{evaluate, ExprId, ParamRef};
use crate::lexer::{Label, OKind, Statement};
use crate::modal::{is_linear, FeedMode, Motion, PlaneSelect, SavedModes, Spindle, State, Vec9, AXES, MM_PER_INCH};
use crate::params::{ParamKey, Params};
use crate::program::{Link, Program, SourceFile};
use crate::system::is_predefined;
use crate::tools::{ToolTable, AXIS_LETTERS};
use crate::trace::{flags, Axes, Step, Trace};
use crate::{NcError, ProgramSetup, UnknownTools};

/// Most blocks one run may execute (a guard against endless loops).
pub const MAX_STEPS: usize = 20_000_000;

/// Deepest nesting of subroutine and subprogram calls: LinuxCNC's `INTERP_SUB_ROUTINE_LEVELS`
/// (10, `src/emc/rs274ngc/interp_internal.hh`), and the 10 levels of `M98` nesting of Fanuc
/// controls. Deeper nesting is refused as both controllers refuse it; without the bound a program
/// that calls itself ran until `MAX_STEPS` (found by the `nc_fanuc` fuzz target).
pub const MAX_CALL_LEVELS: usize = 10;

/// What happens after a line.
pub(crate) enum Flow {
    Next,
    /// Continue at this line of the same file.
    Jump(usize),
    /// The program ends (M2, M30, or a closing `%`).
    End,
    /// LinuxCNC `o.. call`.
    Call(Label, Vec<f64>),
    /// Fanuc `M98 P.. L..` (shares the locals) or `G65 P.. L.. args` (a new local level).
    CallProgram {
        number: u32,
        repeat: u32,
        args: Option<Vec<f64>>,
    },
    /// SINUMERIK `L10 P3`, `NAME`, `CALL "NAME"`: the subprogram file run `passes` times (the R
    /// parameters are global: no new level).
    CallFile {
        name: String,
        passes: u32,
    },
    /// Haas `M97 P<label> L<repeats>`: the block `N<label>` of the same program (shares the locals).
    CallLocal {
        label: u32,
        repeat: u32,
    },
    /// `endsub`/`return` (with a value) or Fanuc `M99` (with a `P` sequence number to return to).
    Return {
        value: Option<f64>,
        sequence: Option<u32>,
    },
}

/// An active call.
#[derive(Clone, Debug)]
pub(crate) struct Call {
    /// File and line to continue at after the return.
    return_to: (usize, usize),
    /// First line of the body and how many more times to run it (Fanuc `L`).
    body: (usize, usize),
    repeat: u32,
    /// A new level of local parameters.
    locals: bool,
    /// M73: modes to restore on return.
    pub(crate) autorestore: Option<SavedModes>,
}

/// Dialect-specific settings of the interpreter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FanucSettings {
    /// Clearance of the rapid back into a `G83` hole above the last depth, and retraction of a
    /// `G73` peck (Fanuc parameters 5115 and 5114; LinuxCNC uses 0.010 inch for both), mm.
    pub peck_clearance_mm: f64,
    /// Least input increment of a dimension word without a decimal point (mm; inch: one tenth
    /// of it in inch): 0.001 for the IS-B increment system.
    pub increment_mm: f64,
}

impl Default for FanucSettings {
    fn default() -> Self {
        FanucSettings { peck_clearance_mm: 0.254, increment_mm: 0.001 }
    }
}

/// The interpreter's state beside the program text.
pub(crate) struct Exec<'m> {
    pub machine: &'m MachineAxes,
    /// P Q of the last `G5` (a `G5` without I J after it mirrors them).
    pub spline_pq: Option<(f64, f64)>,
    /// The NURBS being collected between `G5.2` and `G5.3`.
    pub nurbs: Option<crate::nurbs::Pending>,
    /// The SINUMERIK drilling cycle called modally (`MCALL CYCLE81(...)`) with its values.
    pub siemens_mcall: Option<crate::siemens::cycles::Drilling>,
    pub dialect: Dialect,
    /// The controller's codes.
    pub table: &'static crate::dialects::DialectTable,
    pub params: Params,
    pub tools: ToolTable,
    /// Fanuc tool length wear (`G10 L11`), by offset number.
    pub wear: Vec<(u32, f64)>,
    pub state: State,
    /// Parameters, tool table: inch (else mm).
    pub machine_inch: bool,
    /// Machine axis of each interpreter axis.
    pub axis_map: [Option<usize>; AXES],
    pub trace: Trace,
    pub calls: Vec<Call>,
    /// Active `repeat` loops: (file, first line, runs left).
    repeats: Vec<(usize, usize, i64)>,
    /// The block being read read a parameter that differs in the corrected program.
    pub unsafe_read: bool,
    pub fanuc: FanucSettings,
    /// M70 / M73 modes.
    pub saved_modes: Option<SavedModes>,
    pub return_value: f64,
    pub value_returned: bool,
    /// Machine position of the current point (mm, deg), machine axis order.
    pub position: Axes,
    /// The line being executed (1-based, in its file), for `#<_line>` and messages.
    pub line_number: usize,
    /// The line of the main file that line 0 of the part being run is (a file read in parts).
    pub line_offset: u32,
    /// Words of the block being executed for an expanded copy: before its moves, its axis-setting
    /// command, its stop codes.
    pub setup_words: Vec<(u8, f64)>,
    pub setting_words: Vec<(u8, f64)>,
    pub stop_words: Vec<(u8, f64)>,
    /// rs274's reading of the position after a tool change, and the tool offset of the last move
    /// (mm, deg).
    pub rs274_tool_change: bool,
    pub tool_at_last_move: Vec9,
    pub unknown_tools: UnknownTools,
    pub expand_cycles: bool,
}

/// Runs `program` from `setup`; the trace of the run, or the error with its file and line.
pub fn run(machine: &MachineAxes, mut program: Program, setup: &ProgramSetup) -> Result<(Trace, Program), NcError> {
    let mut runner = Runner::new(machine, &program, setup)?;
    runner.advance(&mut program)?;
    Ok((runner.exec.trace, program))
}

/// The end of a run: a NURBS left without its `G5.3` is refused (LinuxCNC would drop it).
fn ended(exec: &Exec, program: &Program) -> Result<Progress, NcError> {
    match &exec.nurbs {
        Some(nurbs) => Err(NcError {
            file: program.files[0].name.clone(),
            line: nurbs.line,
            message: "the G5.2 NURBS is not ended by G5.3 (LinuxCNC would not run it)".into(),
        }),
        None => Ok(Progress::Ended),
    }
}

/// How far a run got through the part of the program it was given.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Progress {
    /// The program ended (M2, M30, a closing `%`, or its last line).
    Ended,
    /// The lines of this part are done; the body continues in the next part.
    PartDone,
    /// A run in parts ([`Runner::in_parts`]) met what needs the whole program: a control statement,
    /// a call, a return or a jump (at this 1-based line of the file).
    NeedsWhole(usize),
}

/// A run that can be given its main file in parts (a program read as a stream): the interpreter's
/// state and where it stands; the trace of each part is taken before the next part is run.
pub struct Runner<'m> {
    exec: Exec<'m>,
    pc: (usize, usize),
    max_blocks: usize,
    /// Blocks executed in the parts whose traces were taken.
    blocks_before: usize,
    /// Stop with [`Progress::NeedsWhole`] at control flow (the main file is given in parts).
    pub in_parts: bool,
}

impl<'m> Runner<'m> {
    /// A run of `program` (its main file, or the first part of it) from `setup`.
    pub fn new(machine: &'m MachineAxes, program: &Program, setup: &ProgramSetup) -> Result<Runner<'m>, NcError> {
        let main = &program.files[0];
        let mut exec = Exec::new(machine, program.dialect, setup).map_err(|m| NcError { file: main.name.clone(), line: 0, message: m })?;
        exec.table = program.controller.table();
        if program.controller == crate::Controller::Fadal {
            crate::fadal::start(&mut exec.params);
        }
        Ok(Runner { exec, pc: (0, main.body.start), max_blocks: setup.max_blocks, blocks_before: 0, in_parts: false })
    }

    /// Blocks executed so far.
    pub fn blocks(&self) -> usize {
        self.blocks_before + self.exec.trace.steps.len()
    }

    /// The trace of the run since the last call, leaving an empty one that continues it (its start
    /// the current position).
    pub fn take_trace(&mut self) -> Trace {
        let mut next = Trace { start: self.exec.position, ..Trace::default() };
        next.frame_index(&self.exec.state.frame);
        let done = std::mem::replace(&mut self.exec.trace, next);
        self.blocks_before += done.steps.len();
        done
    }

    /// Goes on with the next part of the main file, `program` (whose line 0 follows the last line
    /// of the part before).
    pub fn start_part(&mut self, program: &Program) {
        let main = &program.files[0];
        self.pc = (0, main.body.start);
        self.exec.line_offset = main.first_line as u32;
    }

    /// The trace of the last part.
    pub fn into_trace(self) -> Trace {
        self.exec.trace
    }

    /// Runs from where the run stands until the program ends or leaves the part of the main file
    /// it has; an error names the file and line.
    pub fn advance(&mut self, program: &mut Program) -> Result<Progress, NcError> {
        let dialect = program.dialect;
        let exec = &mut self.exec;
        loop {
            let pc = self.pc;
            let file = &program.files[pc.0];
            if pc.1 >= file.body.end {
                if exec.calls.is_empty() {
                    if file.continues {
                        // a NURBS is written at its G5.3 with its control points: one part holds it
                        return Ok(match &exec.nurbs {
                            Some(nurbs) => Progress::NeedsWhole(nurbs.line),
                            None => Progress::PartDone,
                        });
                    }
                    if !file.leading_percent && dialect == Dialect::LinuxCnc {
                        // rs274 runs the moves and then reports "File ended with no percent sign or
                        // program end"; LinuxCNC's GUIs end the program there
                        let last = (file.first_line + file.lines.len()) as u32;
                        exec.warn_at(pc.0 as u32, last, "the program ends without M2, M30 or a closing %".into());
                    }
                    return ended(exec, program);
                }
                return Err(NcError {
                    file: file.name.clone(),
                    line: file.first_line + file.lines.len(),
                    message: "the subroutine file ends inside a subroutine (no endsub / M99; SINUMERIK: M17, RET, M2 or M30)".into(),
                });
            }
            let here_line = file.first_line + pc.1 + 1;
            let at = |m: String, program: &Program| NcError { file: program.files[pc.0].name.clone(), line: here_line, message: m };
            if self.in_parts && matches!(&file.lines[pc.1], Ok(l) if l.statement.is_some()) {
                return Ok(Progress::NeedsWhole(here_line));
            }
            exec.line_number = here_line;
            let result = match &file.lines[pc.1] {
                Err(m) => Err(m.clone()),
                Ok(_) if self.blocks_before + exec.trace.steps.len() >= self.max_blocks => {
                    Err(format!("more than {} blocks executed: an endless loop?", self.max_blocks))
                }
                Ok(line) if line.is_empty() && line.comments.is_empty() => Ok(Flow::Next),
                Ok(line) => match &line.statement {
                    Some(statement) => exec.statement(file, pc, statement),
                    None => exec.block(file, pc, line),
                },
            };
            let flow = result.map_err(|m| at(m, program))?;
            match flow {
                Flow::Next => self.pc.1 += 1,
                Flow::End => return ended(exec, program),
                _ if self.in_parts => return Ok(Progress::NeedsWhole(here_line)),
                Flow::Jump(k) => self.pc.1 = k,
                Flow::Call(..) | Flow::CallProgram { .. } | Flow::CallFile { .. } | Flow::CallLocal { .. }
                    if exec.calls.len() >= MAX_CALL_LEVELS =>
                {
                    return Err(at(format!("more than {MAX_CALL_LEVELS} nested subroutine calls (a call of itself?)"), program));
                }
                Flow::Call(label, args) => {
                    let (f, start, _) = program.find_sub(&label).map_err(|m| at(m, program))?;
                    exec.enter(pc, (f, start + 1), 0, true, &args);
                    self.pc = (f, start + 1);
                }
                Flow::CallProgram { number, repeat, args } => {
                    let (f, k) = program.find_program(number).map_err(|m| at(m, program))?;
                    if repeat == 0 {
                        self.pc.1 += 1;
                        continue;
                    }
                    let locals = args.is_some();
                    exec.enter(pc, (f, k + 1), repeat - 1, locals, args.as_deref().unwrap_or(&[]));
                    self.pc = (f, k + 1);
                }
                Flow::CallFile { name, passes } => {
                    let (f, k) = program.find_siemens_sub(&name).map_err(|m| at(m, program))?;
                    // the subprogram's DEF variables are its own (the R parameters are global)
                    exec.enter(pc, (f, k), passes - 1, true, &[]);
                    self.pc = (f, k);
                }
                Flow::CallLocal { label, repeat } => {
                    let k = crate::subprograms::local_label(&program.files[pc.0], pc.1, label).map_err(|m| at(m, program))?;
                    if repeat == 0 {
                        self.pc.1 += 1;
                        continue;
                    }
                    exec.enter(pc, (pc.0, k), repeat - 1, false, &[]);
                    self.pc = (pc.0, k);
                }
                Flow::Return { value, sequence } => {
                    let Some(call) = exec.calls.last_mut() else {
                        let m = match dialect {
                            _ if program.controller == crate::Controller::Siemens => "RET or M17 outside a subprogram".into(),
                            Dialect::Fanuc => "M99 in the main program restarts it endlessly".into(),
                            Dialect::LinuxCnc => "return outside a subroutine call".into(),
                        };
                        return Err(at(m, program));
                    };
                    if call.repeat > 0 {
                        call.repeat -= 1;
                        self.pc = call.body;
                        continue;
                    }
                    let call = exec.leave(value);
                    self.pc = call.return_to;
                    if let Some(n) = sequence {
                        let target = program.files[self.pc.0].sequence.get(&n).and_then(|v| v.first().copied());
                        self.pc.1 = target.ok_or_else(|| at(format!("M99 P{n}: no block N{n} in the calling program"), program))?;
                    }
                }
            }
        }
    }
}

impl<'m> Exec<'m> {
    fn new(machine: &'m MachineAxes, dialect: Dialect, setup: &ProgramSetup) -> Result<Exec<'m>, String> {
        let mut axis_map = [None; AXES];
        for (k, slot) in axis_map.iter_mut().enumerate() {
            *slot = machine.axis_index(AXIS_LETTERS[k] as char);
        }
        let mut params = Params::new(dialect);
        for &(n, v) in &setup.parameters {
            params.set_numbered(n, v)?;
        }
        let mut exec = Exec {
            machine,
            dialect,
            table: crate::Controller::of_family(dialect).table(),
            params,
            tools: setup.tools.clone(),
            wear: Vec::new(),
            state: State::default(),
            machine_inch: setup.machine_inch,
            axis_map,
            trace: Trace::default(),
            calls: Vec::new(),
            repeats: Vec::new(),
            unsafe_read: false,
            fanuc: setup.fanuc,
            saved_modes: None,
            return_value: 0.0,
            value_returned: false,
            position: [0.0; crate::MAX_AXES],
            line_number: 0,
            line_offset: 0,
            setup_words: Vec::new(),
            setting_words: Vec::new(),
            stop_words: Vec::new(),
            rs274_tool_change: setup.rs274_tool_change,
            expand_cycles: setup.expand_cycles,
            tool_at_last_move: [0.0; AXES],
            spline_pq: None,
            nurbs: None,
            siemens_mcall: None,
            unknown_tools: setup.unknown_tools,
        };
        let n = machine.axis_count();
        if setup.start.len() != n {
            return Err(format!("the start point has {} values for {n} axes", setup.start.len()));
        }
        machine
            .check_range(&setup.start)
            .map_err(|m| format!("the start point (before the first move) leaves the machine's travel: {m}"))?;
        exec.position[..n].copy_from_slice(&setup.start);
        exec.trace.start = exec.position;
        // the coordinate system of #5220 (LinuxCNC) or G54, its offsets; the start point in it
        let system = match dialect {
            Dialect::LinuxCnc => exec.params.numbered(5220).map_or(1, |v| if (1.0..=9.0).contains(&v) { v as u8 } else { 1 }),
            Dialect::Fanuc => 1,
        };
        exec.state.frame.system = system;
        exec.state.frame.g5x = exec.system_offsets(system)?;
        if dialect == Dialect::LinuxCnc {
            exec.params.set_numbered(5220, f64::from(system))?;
            exec.state.frame.rotation = exec.params.numbered(5210 + 20 * u32::from(system)).unwrap_or(0.0);
            if exec.params.numbered(5210).unwrap_or(0.0) != 0.0 {
                exec.state.frame.g92 =
                    std::array::from_fn(|k| exec.user_to_program(k, exec.params.numbered(5211 + k as u32).unwrap_or(0.0)));
                exec.state.g92_applied = true;
            }
        }
        // canned cycles retract to R (G99) in LinuxCNC until G98 says otherwise (rs274 2.9:
        // checked); a Fanuc starts in G98
        exec.state.retract_to_r = dialect == Dialect::LinuxCnc;
        exec.state.path_mode = 640;
        // a Fanuc control starts in G00 (parameter 3402 bit G01 = 0)
        if dialect == Dialect::Fanuc {
            exec.state.motion = Motion::Rapid;
            exec.state.group01 = Motion::Rapid;
        }
        let start = exec.machine_to_program(&exec.position);
        exec.state.position = start;
        exec.trace.frame_index(&exec.state.frame);
        Ok(exec)
    }

    /// A value stored in machine units (parameters, tool table) in program units.
    pub fn user_to_program(&self, axis: usize, v: f64) -> f64 {
        if !is_linear(axis) {
            return v;
        }
        match (self.machine_inch, self.state.frame.inch) {
            (true, false) => v * MM_PER_INCH,
            (false, true) => v / MM_PER_INCH,
            _ => v,
        }
    }

    /// A value in program units in machine units.
    pub fn program_to_user(&self, axis: usize, v: f64) -> f64 {
        if !is_linear(axis) {
            return v;
        }
        match (self.machine_inch, self.state.frame.inch) {
            (true, false) => v / MM_PER_INCH,
            (false, true) => v * MM_PER_INCH,
            _ => v,
        }
    }

    /// First parameter of the offsets of coordinate system `system` (X; then Y Z A B C U V W).
    pub fn system_base(&self, system: u8) -> u32 {
        match (self.dialect, system) {
            (Dialect::Fanuc, s) if s > 9 => 7001 + 20 * u32::from(s - 10),
            (_, s) => 5201 + 20 * u32::from(s),
        }
    }

    /// The work offsets of `system` (program units; Fanuc: plus the external offset #5201).
    pub(crate) fn system_offsets(&self, system: u8) -> Result<Vec9, String> {
        if system == 0 {
            // none selected: a Fadal's `E0`
            return Ok([0.0; AXES]);
        }
        let base = self.system_base(system);
        let mut out = [0.0; AXES];
        for (k, o) in out.iter_mut().enumerate() {
            let read = |n: u32| self.params.numbered(n).filter(|v| !v.is_nan()).unwrap_or(0.0);
            let mut v = read(base + k as u32);
            if self.dialect == Dialect::Fanuc && k < 6 {
                v += read(5201 + k as u32);
            }
            *o = self.user_to_program(k, v);
        }
        Ok(out)
    }

    /// Program point of a machine position (machine axes not on the interpreter's list keep the
    /// program position).
    pub fn machine_to_program(&self, m: &Axes) -> Vec9 {
        let frame = &self.state.frame;
        let mut ext = frame.external(&self.state.position);
        let s = frame.scale();
        for (k, e) in ext.iter_mut().enumerate() {
            if let Some(i) = self.axis_map[k] {
                *e = if is_linear(k) { m[i] / s } else { m[i] };
            }
        }
        frame.program(&ext)
    }

    /// Machine position (mm, deg; machine axis order) of a program point.
    pub fn program_to_machine(&self, p: &Vec9) -> Axes {
        let m = self.state.frame.machine(p);
        let mut out = self.position;
        for (k, slot) in self.axis_map.iter().enumerate() {
            if let Some(i) = slot {
                out[*i] = m[k];
            }
        }
        out
    }

    /// Starts a step for the line at `pc`; its index.
    pub fn begin_step(&mut self, pc: (usize, usize), extra: u16) -> usize {
        let frame = self.trace.frame_index(&self.state.frame);
        let t = &self.trace;
        let (moves, words, writes, messages, actions) =
            (t.moves.len() as u32, t.words.len() as u32, t.writes.len() as u32, t.messages.len() as u32, t.actions.len() as u32);
        self.trace.steps.push(Step {
            file: pc.0 as u32,
            line: pc.1 as u32,
            depth: self.calls.len() as u16,
            level: self.calls.iter().filter(|c| c.locals).count() as u16,
            moves: moves..moves,
            setup: words..words,
            setting: words..words,
            motion_words: words..words,
            stops: words..words,
            writes: writes..writes,
            flags: extra,
            relative: None,
            frame,
            messages: messages..messages,
            actions: actions..actions,
            jump: None,
        });
        self.trace.steps.len() - 1
    }

    /// Closes the ranges of step `step`.
    pub fn end_step(&mut self, step: usize) {
        let (moves, writes, messages, actions) = (
            self.trace.moves.len() as u32,
            self.trace.writes.len() as u32,
            self.trace.messages.len() as u32,
            self.trace.actions.len() as u32,
        );
        let unsafe_read = std::mem::take(&mut self.unsafe_read);
        let s = &mut self.trace.steps[step];
        s.moves.end = moves;
        s.writes.end = writes;
        s.messages.end = messages;
        s.actions.end = actions;
        if unsafe_read {
            s.flags |= flags::READS_UNSAFE;
        }
    }

    /// Tool `n` of the table; a tool the table lacks takes the assumed length of
    /// [`ProgramSetup::unknown_tools`] (recorded in the trace), or is refused.
    pub(crate) fn tool_entry(&mut self, n: u32) -> Result<crate::tools::Tool, String> {
        if let Some(t) = self.tools.get(n) {
            return Ok(t.clone());
        }
        match self.unknown_tools {
            UnknownTools::Refuse => Err(format!("tool {n} is not in the tool table (--strict-tools)")),
            UnknownTools::Assume(length) => {
                if !self.trace.assumed_tools.contains(&n) {
                    self.trace.assumed_tools.push(n);
                }
                let mut offset = [0.0; 9];
                offset[2] = length;
                Ok(crate::tools::Tool { number: n, offset, diameter: 0.0 })
            }
        }
    }

    /// Records a warning at the line being executed (each message once, counted).
    pub fn warn(&mut self, message: String) {
        let (file, line) = self.trace.steps.last().map_or((0, self.line_number as u32), |s| {
            let offset = if s.file == 0 { self.line_offset } else { 0 };
            (s.file, s.line + 1 + offset)
        });
        self.warn_at(file, line, message);
    }

    /// Records a warning at `line` (1-based) of `file`.
    pub fn warn_at(&mut self, file: u32, line: u32, message: String) {
        match self.trace.warnings.iter_mut().find(|w| w.message == message) {
            Some(w) => w.count += 1,
            None => self.trace.warnings.push(crate::trace::Warning { file, line, message, count: 1 }),
        }
    }

    /// Evaluates expression `id` of `file`.
    pub(crate) fn eval(&mut self, file: &SourceFile, id: ExprId) -> Result<f64, String> {
        let dialect = self.dialect;
        evaluate(&file.arena, id, self, dialect)
    }

    /// Writes a parameter and records it in the trace.
    pub(crate) fn assign(&mut self, target: &ParamRef, index: Option<u32>, value: f64) -> Result<(), String> {
        let value = match target {
            // a SINUMERIK DEF variable takes the value as its type makes it
            ParamRef::Named(name) if self.table.name == "siemens" => crate::siemens::variables::typed(&self.params, name, value)?,
            _ => value,
        };
        let key = match target {
            ParamRef::Named(name) => {
                if self.dialect == Dialect::LinuxCnc && name.starts_with('_') && is_predefined(name) {
                    return Err(format!("#<{name}> is a read-only system parameter"));
                }
                self.params.set_named(name, value);
                ParamKey::Named(name.clone())
            }
            ParamRef::Numbered(n) => self.assign_numbered(*n, value)?,
            ParamRef::Indirect(_) => self.assign_numbered(index.expect("computed index"), value)?,
        };
        self.trace.writes.push((key, value));
        Ok(())
    }

    fn assign_numbered(&mut self, n: u32, value: f64) -> Result<ParamKey, String> {
        match self.dialect {
            Dialect::LinuxCnc if n == 5400 || (5401..=5413).contains(&n) || (5420..=5428).contains(&n) => {
                return Err(format!("#{n} is a read-only system parameter"))
            }
            // #3000: the program stops with an alarm here
            Dialect::Fanuc if n == 3000 => return Err(format!("the program stops with alarm {value} here (#3000 = {value})")),
            // what macros write beside the motion: timers #3001/#3002, single block and feed hold
            // #3003/#3004, the message stop #3006, the part counts #3901/#3902 (no effect on positions)
            Dialect::Fanuc if matches!(n, 3001..=3004 | 3006 | 3901 | 3902) => {}
            Dialect::Fanuc if (1000..2001).contains(&n) || (2401..5201).contains(&n) || (5330..7001).contains(&n) => {
                return Err(format!(
                "system variable #{n} cannot be written by this corrector (supported: #1-#999, work offsets #5201-#5326 and #7001-#7948)"
            ))
            }
            _ => {}
        }
        self.params.set_numbered(n, value)?;
        // a write to the active system's offsets takes effect at once (Fanuc system variables)
        if self.dialect == Dialect::Fanuc && (5201..=5326).contains(&n) || (7001..=7948).contains(&n) {
            let old = self.state.frame;
            self.state.frame.g5x = self.system_offsets(self.state.frame.system)?;
            self.refresh_position(&old);
        }
        Ok(ParamKey::Numbered(n))
    }

    /// After a change of offsets: the program position of the unchanged machine position.
    pub fn refresh_position(&mut self, old: &crate::modal::Frame) {
        let ext = old.external(&self.state.position);
        self.state.position = self.state.frame.program(&ext);
    }

    fn enter(&mut self, from: (usize, usize), body: (usize, usize), repeat: u32, locals: bool, args: &[f64]) {
        self.params.enter(args, locals);
        self.calls.push(Call { return_to: (from.0, from.1 + 1), body, repeat, locals, autorestore: None });
        self.return_value = 0.0;
        self.value_returned = false;
    }

    fn leave(&mut self, value: Option<f64>) -> Call {
        let call = self.calls.pop().expect("an active call");
        self.params.leave();
        if let Some(v) = value {
            self.return_value = v;
            self.value_returned = true;
        }
        if let Some(modes) = call.autorestore {
            self.restore_modes(&modes);
            // an expanded copy of the call sets the restored modes itself
            let words = self.mode_words(&modes);
            self.action(&words);
        }
        call
    }

    /// The codes that set the modes M70/M73 save.
    fn mode_words(&self, m: &SavedModes) -> Vec<(u8, f64)> {
        let g = |v: f64| (b'G', v);
        let mut w = vec![
            g(if m.inch { 20.0 } else { 21.0 }),
            g(if m.incremental { 91.0 } else { 90.0 }),
            g(if m.ijk_absolute { 90.1 } else { 91.1 }),
            g(m.plane.gcode()),
            g(match m.feed_mode {
                FeedMode::InverseTime => 93.0,
                FeedMode::PerMinute => 94.0,
                FeedMode::PerRevolution => 95.0,
            }),
            g(if m.diameter { 7.0 } else { 8.0 }),
            g(if m.retract_to_r { 99.0 } else { 98.0 }),
            g(f64::from(m.path_mode) / 10.0),
            g(if m.css { 96.0 } else { 97.0 }),
        ];
        if m.feed_mode != FeedMode::InverseTime {
            w.push((b'F', m.feed));
        }
        w.push((b'S', m.speed));
        w.push((
            b'M',
            match m.spindle {
                Spindle::Clockwise => 3.0,
                Spindle::CounterClockwise => 4.0,
                Spindle::Stopped => 5.0,
            },
        ));
        w.push((
            b'M',
            if m.flood {
                8.0
            } else if m.mist {
                7.0
            } else {
                9.0
            },
        ));
        w
    }

    /// A control statement.
    fn statement(&mut self, file: &SourceFile, pc: (usize, usize), statement: &Statement) -> Result<Flow, String> {
        let k = pc.1;
        let step = self.begin_step(pc, flags::CONTROL);
        let flow = self.statement_flow(file, pc, statement);
        if matches!(flow, Ok(Flow::Call(..))) {
            self.trace.steps[step].flags |= flags::CALL;
        }
        if let Ok(Flow::Jump(target)) = flow {
            let siemens_jump = matches!(statement, Statement::Siemens(crate::siemens::flow::Control::Jump(_)));
            if target <= k && (siemens_jump || matches!(statement, Statement::Goto(_) | Statement::IfGoto(..))) {
                self.trace.steps[step].flags |= flags::JUMP_BACK;
            }
        }
        self.end_step(step);
        flow
    }

    fn statement_flow(&mut self, file: &SourceFile, pc: (usize, usize), statement: &Statement) -> Result<Flow, String> {
        let k = pc.1;
        let link = file.links[k];
        let truth = |v: f64| !v.is_nan() && v != 0.0;
        Ok(match statement {
            Statement::O(label, kind) => match kind {
                OKind::Sub => match link {
                    Link::Sub { end } => Flow::Jump(end + 1),
                    _ => unreachable!("indexed sub"),
                },
                OKind::EndSub(value) | OKind::Return(value) => {
                    if self.calls.is_empty() {
                        return Err(format!("`{label}` ends a subroutine that was not called"));
                    }
                    let v = match value {
                        Some(e) => Some(self.eval(file, *e)?),
                        None => None,
                    };
                    Flow::Return { value: v, sequence: None }
                }
                OKind::Call(args) => {
                    let values = args.iter().map(|a| self.eval(file, *a)).collect::<Result<Vec<_>, _>>()?;
                    if values.len() > 30 {
                        return Err(format!("{} arguments; a call takes at most 30", values.len()));
                    }
                    Flow::Call(label.clone(), values)
                }
                OKind::If(_) => Flow::Jump(self.branch(file, k)?),
                OKind::ElseIf(_) | OKind::Else => match link {
                    // reached at the end of a taken branch
                    Link::Branch { end, .. } => Flow::Jump(end + 1),
                    _ => unreachable!("indexed branch"),
                },
                OKind::EndIf | OKind::Do => Flow::Next,
                OKind::While(cond) => {
                    let c = truth(self.eval(file, *cond)?);
                    match link {
                        Link::LoopStart { end } => {
                            if c {
                                Flow::Next
                            } else {
                                Flow::Jump(end + 1)
                            }
                        }
                        Link::LoopEnd { start } => {
                            if c {
                                Flow::Jump(start + 1)
                            } else {
                                Flow::Next
                            }
                        }
                        _ => unreachable!("indexed while"),
                    }
                }
                OKind::EndWhile => match link {
                    Link::LoopEnd { start } => Flow::Jump(start),
                    _ => unreachable!("indexed endwhile"),
                },
                OKind::Repeat(count) => {
                    let n = self.eval(file, *count)?.round() as i64;
                    let Link::LoopStart { end } = link else { unreachable!("indexed repeat") };
                    if n <= 0 {
                        Flow::Jump(end + 1)
                    } else {
                        self.repeats.push((pc.0, k, n));
                        Flow::Next
                    }
                }
                OKind::EndRepeat => {
                    let Link::LoopEnd { start } = link else { unreachable!("indexed endrepeat") };
                    self.repeat_end(pc.0, start, k)
                }
                OKind::Break => {
                    let Link::LoopJump { start, end } = link else { unreachable!("indexed break") };
                    if matches!(&file.lines[start], Ok(l) if matches!(l.statement, Some(Statement::O(_, OKind::Repeat(_))))) {
                        self.repeats.retain(|r| !(r.0 == pc.0 && r.1 == start));
                    }
                    Flow::Jump(end + 1)
                }
                OKind::Continue => {
                    let Link::LoopJump { start, end } = link else { unreachable!("indexed continue") };
                    match &file.lines[start] {
                        Ok(l) if matches!(l.statement, Some(Statement::O(_, OKind::While(_)))) => Flow::Jump(start),
                        _ => Flow::Jump(end),
                    }
                }
            },
            Statement::Goto(target) => Flow::Jump(self.sequence(file, pc, *target)?),
            Statement::IfGoto(cond, target) => {
                if truth(self.eval(file, *cond)?) {
                    Flow::Jump(self.sequence(file, pc, *target)?)
                } else {
                    Flow::Next
                }
            }
            Statement::IfThen(cond, assignments) => {
                if truth(self.eval(file, *cond)?) {
                    for a in assignments {
                        let index = match &a.target {
                            ParamRef::Indirect(e) => Some(crate::expr::parameter_number(self.eval(file, *e)?)?),
                            _ => None,
                        };
                        let v = self.eval(file, a.value)?;
                        self.assign(&a.target, index, v)?;
                    }
                }
                Flow::Next
            }
            Statement::While(cond, _) => {
                let Link::LoopStart { end } = link else { unreachable!("indexed WHILE") };
                if truth(self.eval(file, *cond)?) {
                    Flow::Next
                } else {
                    Flow::Jump(end + 1)
                }
            }
            Statement::Do(_) | Statement::Output => Flow::Next,
            Statement::Siemens(c) => crate::siemens::flow::flow(self, file, pc, c)?,
            Statement::End(_) => {
                let Link::LoopEnd { start } = link else { unreachable!("indexed END") };
                match &file.lines[start] {
                    Ok(l) if matches!(l.statement, Some(Statement::Do(_))) => Flow::Jump(start + 1),
                    _ => Flow::Jump(start),
                }
            }
        })
    }

    fn repeat_end(&mut self, file: usize, start: usize, _end: usize) -> Flow {
        let Some(top) = self.repeats.iter_mut().rev().find(|r| r.0 == file && r.1 == start) else {
            return Flow::Next;
        };
        top.2 -= 1;
        if top.2 > 0 {
            Flow::Jump(start + 1)
        } else {
            self.repeats.retain(|r| !(r.0 == file && r.1 == start));
            Flow::Next
        }
    }

    /// The first line of the branch of the `if` at `k` whose condition holds.
    fn branch(&mut self, file: &SourceFile, k: usize) -> Result<usize, String> {
        let mut b = k;
        loop {
            let Link::Branch { next, end } = file.links[b] else { return Ok(b + 1) };
            let statement = file.lines[b].as_ref().ok().and_then(|l| l.statement.as_ref());
            match statement {
                Some(Statement::O(_, OKind::If(c) | OKind::ElseIf(c))) => {
                    let v = self.eval(file, *c)?;
                    if !v.is_nan() && v != 0.0 {
                        return Ok(b + 1);
                    }
                    if next == end {
                        return Ok(end + 1);
                    }
                    b = next;
                }
                _ => return Ok(b + 1),
            }
        }
    }

    /// The line of Fanuc sequence number `target` in the program section containing `pc`.
    fn sequence(&mut self, file: &SourceFile, pc: (usize, usize), target: ExprId) -> Result<usize, String> {
        let n = self.eval(file, target)?;
        if n.is_nan() || n < 0.0 || n.fract() != 0.0 {
            return Err(format!("GOTO {n}: not a sequence number"));
        }
        let n = n as u32;
        if n >= crate::fadal::LABEL_BASE {
            return crate::fadal::jump(file, pc.1, n);
        }
        let section = |k: usize| file.programs.values().filter(|&&p| p <= k).max().copied().unwrap_or(0);
        let here = section(pc.1);
        file.sequence
            .get(&n)
            .and_then(|lines| lines.iter().copied().find(|&k| section(k) == here))
            .ok_or_else(|| format!("GOTO {n}: no block N{n} in this program"))
    }

    /// Restores the modes M70/M73 saved.
    pub fn restore_modes(&mut self, m: &SavedModes) {
        self.state.set_inch(m.inch);
        let f = &mut self.state.frame;
        f.incremental = m.incremental;
        f.ijk_absolute = m.ijk_absolute;
        f.diameter = m.diameter;
        self.state.plane = m.plane;
        self.state.motion = m.motion;
        self.state.feed_mode = m.feed_mode;
        self.state.feed = m.feed;
        self.state.speed = m.speed;
        self.state.spindle = m.spindle;
        self.state.retract_to_r = m.retract_to_r;
        self.state.css = m.css;
        self.state.path_mode = m.path_mode;
        self.state.flood = m.flood;
        self.state.mist = m.mist;
    }
}

impl Exec<'_> {
    /// The plane's axes must be on the machine.
    pub(crate) fn plane_axes(&self, plane: PlaneSelect) -> Result<[usize; 3], String> {
        let axes = plane.axes();
        let mut out = [0; 3];
        for (o, &k) in out.iter_mut().zip(&axes) {
            *o = self.axis_map[k].ok_or_else(|| {
                format!(
                    "the plane G{} needs axis {}, which machine `{}` does not have",
                    plane.gcode(),
                    AXIS_LETTERS[k] as char,
                    self.machine.name
                )
            })?;
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use crate::axes::{AxisSpec, MachineAxes};
    use crate::{Dialect, ProgramSetup};

    fn mill() -> MachineAxes {
        let axis = |letter| AxisSpec { letter, rotary: false, range: None };
        MachineAxes { name: "mill".into(), axes: vec![axis('X'), axis('Y'), axis('Z')] }
    }

    /// A loop whose counter is never advanced (a misspelt parameter, as the `nc_linuxcnc` fuzz
    /// target found) is refused at the block limit, with the line it was on; a loop that ends
    /// below the limit runs.
    #[test]
    fn an_endless_loop_is_refused_at_the_block_limit() {
        let axes = mill();
        let mut setup = ProgramSetup::zero(&axes);
        setup.max_blocks = 1000;
        let endless = b"G21 G90 F100\n#<pass> = 0\no10 while [#<pass> LT 3]\nG1 X1\n#<pasc> = [#<pass> + 1]\no10 endwhile\nM2\n";
        let e = crate::run(&axes, endless, "p.ngc", Some(Dialect::LinuxCnc.into()), &setup).unwrap_err();
        assert_eq!(e.message, "more than 1000 blocks executed: an endless loop?");
        assert!((3..=6).contains(&e.line), "line {}", e.line);
        let ending = b"G21 G90 F100\n#<pass> = 0\no10 while [#<pass> LT 3]\nG1 X1\n#<pass> = [#<pass> + 1]\no10 endwhile\nM2\n";
        let (trace, _) = crate::run(&axes, ending, "p.ngc", Some(Dialect::LinuxCnc.into()), &setup).unwrap();
        assert!(trace.steps.len() < 30, "{} blocks", trace.steps.len());
    }
}
