//! Executing one block: its words evaluated, its parameter assignments (all read before any is
//! written, as in LinuxCNC), then its actions in LinuxCNC's order of execution (comments, feed
//! mode, F, S, T, M codes, dwell, plane, units, cutter compensation, tool length offset, coordinate
//! system, path control, distance modes, retract mode, `G10`/`G28`/`G30`/`G92`, the motion, stops;
//! LinuxCNC 2.9 manual "G-code order of execution", `interp_execute.cc`). Moves go to the trace in
//! machine positions; what the block would need to be written again in expanded form (its modal
//! codes, its axis-setting command, its stop codes) is recorded beside them.
//!
//! Refused with the reason: probing (`G38.x`, Fanuc `G31`), spindle-synchronised motion (`G33`,
//! `G33.1`, `G76` threading), cutter radius compensation (`G41`/`G42`), NURBS, lathe roughing cycles, scaling and coordinate rotation commands (Fanuc
//! `G51`/`G68`), 5-axis tool-centre-point and tilted-plane modes, polar coordinate mode (Fanuc `G16`).

use crate::dialect::Dialect;
use crate::dialects::{gcode_text, Group, Unknown};
use crate::expr::{evaluate, parameter_number, ParamRef};
use crate::interpret::{Exec, Flow};
use crate::lexer::{Line, Operand};
use crate::modal::{FeedMode, Motion, PlaneSelect, Spindle, Vec9, AXES};
use crate::program::SourceFile;
use crate::subprograms;
use crate::tools::AXIS_LETTERS;
use crate::trace::{flags, Move, MoveKind, Plane, Relative, Role};

/// Letters of a block: A-Z, then `@` (polar radius), `^` (polar angle), `$` (spindle), and the
/// SINUMERIK's opening angle `AR=` ([`crate::siemens::arcs::AR`]).
const LETTERS: usize = 30;

fn letter_index(letter: u8) -> usize {
    match letter {
        b'@' => 26,
        b'^' => 27,
        b'$' => 28,
        crate::siemens::arcs::AR => 29,
        l => (l - b'A') as usize,
    }
}

fn index_letter(i: usize) -> u8 {
    match i {
        26 => b'@',
        27 => b'^',
        28 => b'$',
        29 => crate::siemens::arcs::AR,
        i => b'A' + i as u8,
    }
}

/// The evaluated words of a block.
pub(crate) struct Words {
    values: [Option<f64>; LETTERS],
    /// G codes (x 10) and M codes.
    g: [u16; 16],
    ng: usize,
    m: [u16; 8],
    nm: usize,
    /// Letters used by some action (the rest go on the setup line of an expanded copy).
    used: u32,
}

impl Words {
    pub(crate) fn get(&self, letter: u8) -> Option<f64> {
        self.values[letter_index(letter)]
    }

    pub(crate) fn has(&self, letter: u8) -> bool {
        self.get(letter).is_some()
    }

    /// The value of `letter`, marked as used.
    pub(crate) fn take(&mut self, letter: u8) -> Option<f64> {
        let i = letter_index(letter);
        self.used |= 1 << i;
        self.values[i]
    }

    pub(crate) fn gs(&self) -> &[u16] {
        &self.g[..self.ng]
    }

    pub(crate) fn ms(&self) -> &[u16] {
        &self.m[..self.nm]
    }

    /// Axis words (interpreter axes) and whether any is present.
    pub(crate) fn axes(&self) -> ([Option<f64>; AXES], bool) {
        let a: [Option<f64>; AXES] = std::array::from_fn(|k| self.get(AXIS_LETTERS[k]));
        let any = a.iter().any(Option::is_some);
        (a, any)
    }

    pub(crate) fn any_axis_or_polar(&self) -> bool {
        self.axes().1 || self.has(b'@') || self.has(b'^') || self.has(crate::siemens::arcs::AR)
    }

    pub(crate) fn use_axes(&mut self) {
        for &l in AXIS_LETTERS.iter().chain(b"@^") {
            self.take(l);
        }
    }
}

/// Letters of dimension words (a Fanuc number without a decimal point counts in increments).
fn is_dimension(letter: u8) -> bool {
    matches!(letter, b'X' | b'Y' | b'Z' | b'A' | b'B' | b'C' | b'U' | b'V' | b'W' | b'I' | b'J' | b'K' | b'R' | b'Q')
}

impl Exec<'_> {
    /// Executes the block `line` of `file` at `pc`.
    pub(crate) fn block(&mut self, file: &SourceFile, pc: (usize, usize), line: &Line) -> Result<Flow, String> {
        if let (Some(n), Dialect::LinuxCnc) = (line.program_number, self.dialect) {
            if !subprograms::runs_m98(self.table) {
                return Err(crate::lexer::o_word_without_keyword(&crate::lexer::Label::Number(n)));
            }
        }
        let step = self.begin_step(pc, 0);
        let flow = match line.system {
            Some(_) => crate::grbl_system::run(self, file, pc, line, step),
            None => self.block_steps(file, pc, line, step),
        };
        self.end_step(step);
        flow
    }

    pub(crate) fn block_steps(&mut self, file: &SourceFile, pc: (usize, usize), line: &Line, step: usize) -> Result<Flow, String> {
        self.setup_words.clear();
        self.setting_words.clear();
        self.stop_words.clear();
        let mut w = self.resolve(file, line)?;
        // assignments: all values read first, then written
        let dialect = self.dialect;
        if !line.assignments.is_empty() {
            let mut pending = Vec::with_capacity(line.assignments.len());
            for a in &line.assignments {
                let index = match &a.target {
                    ParamRef::Indirect(e) => Some(parameter_number(evaluate(&file.arena, *e, self, dialect)?)?),
                    _ => None,
                };
                let value = evaluate(&file.arena, a.value, self, dialect)?;
                pending.push((&a.target, index, value));
                if self.dialect == Dialect::Fanuc {
                    let (t, i, v) = pending.pop().expect("just pushed");
                    self.assign(t, i, v)?;
                }
            }
            for (t, i, v) in pending {
                self.assign(t, i, v)?;
            }
        }
        self.trace.steps[step].writes.end = self.trace.writes.len() as u32;
        self.comments(file, pc.1, line)?;
        let mut flow = self.actions(&mut w, step)?;
        if let Some(call) = &line.siemens_call {
            if let Some(f) = crate::siemens::cycles::call(self, file, call, step)? {
                flow = f;
            }
        } else if self.siemens_mcall.is_some() && w.any_axis_or_polar() {
            crate::siemens::cycles::modal(self, step)?;
        }
        if self.rs274_tool_change && w.ms().iter().any(|&m| m == 6 || m == 61) {
            self.rs274_resync(step);
        }
        // what an expanded copy writes before its moves: the codes recorded, then the letters no
        // action used (F S T, the words of M codes...)
        let moved = self.trace.steps[step].moves.start < self.trace.moves.len() as u32;
        for i in 0..LETTERS {
            if w.used & (1 << i) == 0 {
                if let Some(v) = w.values[i] {
                    let letter = index_letter(i);
                    if letter == b'F' && self.state.feed_mode == FeedMode::InverseTime && moved {
                        continue;
                    }
                    self.setup_words.push((letter, v));
                }
            }
        }
        let m0 = self.trace.words.len() as u32;
        for &l in b"XYZABCUVW@^IJKR" {
            if let Some(v) = w.get(l) {
                self.trace.words.push((l, v));
            }
        }
        let s0 = self.trace.words.len() as u32;
        self.trace.words.extend_from_slice(&self.setup_words);
        let s1 = self.trace.words.len() as u32;
        self.trace.words.extend_from_slice(&self.setting_words);
        let s2 = self.trace.words.len() as u32;
        self.trace.words.extend_from_slice(&self.stop_words);
        let s3 = self.trace.words.len() as u32;
        let s = &mut self.trace.steps[step];
        (s.motion_words, s.setup, s.setting, s.stops) = (m0..s0, s0..s1, s1..s2, s2..s3);
        Ok(flow)
    }

    /// Evaluates the words of a block and checks them as LinuxCNC does (one word per letter, one G
    /// code per modal group, at most four M codes).
    fn resolve(&mut self, file: &SourceFile, line: &Line) -> Result<Words, String> {
        let mut w = Words { values: [None; LETTERS], g: [0; 16], ng: 0, m: [0; 8], nm: 0, used: 0 };
        let dialect = self.dialect;
        for word in &line.words {
            let mut v = match word.value {
                Operand::Number(v) => v,
                Operand::Expr(e) => evaluate(&file.arena, e, self, dialect)?,
            };
            if v.is_nan() {
                continue; // a vacant Fanuc variable: the word is ignored
            }
            let letter = word.letter;
            if self.table.numbers.integers_are_increments
                && is_dimension(letter)
                && !word.decimal_point
                && matches!(word.value, Operand::Number(_))
            {
                let increment = if self.state.frame.inch { self.fanuc.increment_mm / 10.0 } else { self.fanuc.increment_mm };
                v *= increment;
            }
            match letter {
                b'G' => {
                    let code = (v * 10.0).round();
                    if (v * 10.0 - code).abs() > 1e-6 || !(0.0..10_000.0).contains(&code) {
                        return Err(format!("G{v} is not a G-code"));
                    }
                    if w.ng == w.g.len() {
                        return Err("too many G-codes on one line".into());
                    }
                    w.g[w.ng] = code as u16;
                    w.ng += 1;
                }
                b'M' => {
                    if v.fract() != 0.0 || !(0.0..1000.0).contains(&v) {
                        return Err(format!("M{v} is not an M-code"));
                    }
                    if w.nm == w.m.len() || self.dialect == Dialect::LinuxCnc && w.nm == 4 {
                        return Err("more than four M-codes on one line".into());
                    }
                    w.m[w.nm] = v as u16;
                    w.nm += 1;
                }
                l => {
                    let i = letter_index(l);
                    if w.values[i].is_some() {
                        return Err(format!("two {} words on one line", l as char));
                    }
                    w.values[i] = Some(v);
                }
            }
        }
        if let Some((letter, why)) = self.table.refused_words.iter().find(|(l, _)| w.has(*l)) {
            return Err(format!("{}{} {why}", *letter as char, w.get(*letter).unwrap_or(0.0)));
        }
        // one G-code per modal group
        let mut seen: Vec<(Group, u16)> = Vec::with_capacity(w.ng);
        for &code in w.gs() {
            let g = self.table.group(code)?;
            if g == Group::Unknown {
                self.unknown_code(&w, format!("G{}", gcode_text(code)))?;
            }
            if !matches!(g, Group::NonModal | Group::Other | Group::Unknown) {
                // G80 beside another motion code: a Fanuc's G80 is in a group of its own (09), and
                // LinuxCNC's rs274 runs the other code (checked: `G00 G17 G40 G49 G80 G90`, the first
                // line of most posts, and `G81 G80 ...`)
                let beside_g80 = |a: u16, b: u16| (a == 800) != (b == 800);
                if let Some((_, other)) = seen.iter().find(|(s, c)| *s == g && !(g == Group::Motion && beside_g80(*c, code))) {
                    return Err(format!("G{} and G{} on one line are in the same modal group", gcode_text(*other), gcode_text(code)));
                }
            }
            seen.push((g, code));
        }
        let axis_users = w.gs().iter().filter(|&&c| self.table.uses_axes(c)).count();
        // a Fanuc reads `G00 G91 G28 Z0` (a CAM post's return home): the G00 only sets the mode
        let motion_beside = |c: u16| if self.dialect == Dialect::Fanuc { !matches!(c, 0 | 10 | 20 | 30 | 800) } else { c != 800 };
        if axis_users > 1 || axis_users == 1 && seen.iter().any(|(g, c)| *g == Group::Motion && motion_beside(*c)) {
            return Err("two G-codes on one line both use the axis words".into());
        }
        // the M-code groups
        for grp in self.table.m_groups {
            let found: Vec<u16> = w.ms().iter().copied().filter(|m| grp.contains(m)).collect();
            if found.len() > 1 {
                return Err(format!("M{} and M{} on one line are in the same modal group", found[0], found[1]));
            }
        }
        for &m in w.ms() {
            if !self.table.m_known(m)? {
                self.unknown_code(&w, format!("M{m}"))?;
            }
        }
        if self.dialect == Dialect::LinuxCnc {
            // rs274 (interp_check.cc, check_other_codes): "E word with no G70, G76, M66, M67 or M68
            // to use it"; also what `X1e200` reads as (X1 and E200: RS274/NGC has no exponents)
            let uses_e = w.gs().iter().any(|&c| c == 700 || c == 760) || w.ms().iter().any(|&m| matches!(m, 66..=68));
            if w.values[letter_index(b'E')].is_some() && !uses_e {
                return Err("an E word with no G70, G76, M66, M67 or M68 to use it (RS274/NGC numbers have no exponent:                             write 100000, not 1e5)"
                    .into());
            }
        }
        Ok(w)
    }

    /// A code the dialect does not know: passed through with a warning naming the line, refused
    /// when its line has axis words (what it does with them is not known).
    fn unknown_code(&mut self, w: &Words, code: String) -> Result<(), String> {
        let dialect = self.table.title;
        if let Unknown::Alarm(alarm) = self.table.unknown {
            return Err(format!("{code} is not a code of {dialect}: {alarm}"));
        }
        if w.any_axis_or_polar() {
            return Err(format!("{code} is not a code of {dialect}: with axis words on its line it cannot be passed through"));
        }
        self.warn(format!("{code} is not a code of {dialect}: passed through unchanged, assumed to move nothing"));
        Ok(())
    }

    /// Comments: messages with their parameters replaced (for an expanded copy), `(ABORT,...)` ends
    /// the program with an error.
    fn comments(&mut self, file: &SourceFile, k: usize, line: &Line) -> Result<(), String> {
        let text = file.line_text(k);
        for range in &line.comments {
            let body = &text[range.clone()];
            let semicolon = range.start > 0 && text.as_bytes()[range.start - 1] == b';';
            let lower = body.trim_start().to_ascii_lowercase();
            if self.dialect == Dialect::LinuxCnc && lower.starts_with("abort,") {
                return Err(format!("the program aborts here: {}", body.trim_start()[6..].trim()));
            }
            let substituted = if self.dialect == Dialect::LinuxCnc
                && (lower.starts_with("debug,") || lower.starts_with("print,") || lower.starts_with("log,"))
            {
                self.substitute(body)
            } else {
                body.to_string()
            };
            self.trace.messages.push(if semicolon { format!(";{substituted}") } else { format!("({substituted})") });
        }
        Ok(())
    }

    /// `#n`, `#<name>` in a message replaced by their values (`%lf`, as LinuxCNC prints them).
    fn substitute(&mut self, body: &str) -> String {
        let mut out = String::with_capacity(body.len());
        let b = body.as_bytes();
        let mut i = 0;
        while i < b.len() {
            if b[i] == b'#' {
                let rest = &body[i + 1..];
                let (param, len) = if let Some(stripped) = rest.strip_prefix('<') {
                    match stripped.find('>') {
                        Some(e) => (Some(ParamRef::Named(stripped[..e].to_ascii_lowercase().replace(' ', "").into())), e + 2),
                        None => (None, 0),
                    }
                } else {
                    let digits = rest.bytes().take_while(|c| c.is_ascii_digit()).count();
                    (rest[..digits].parse().ok().map(ParamRef::Numbered), digits)
                };
                if let Some(p) = param {
                    use crate::expr::Environment;
                    let v = self.read(&p, None).unwrap_or(f64::NAN);
                    out.push_str(&format!("{v:.6}"));
                    i += 1 + len;
                    continue;
                }
            }
            out.push(b[i] as char);
            i += 1;
        }
        out
    }

    /// The block's actions in LinuxCNC's order.
    fn actions(&mut self, w: &mut Words, step: usize) -> Result<Flow, String> {
        let fanuc = self.dialect == Dialect::Fanuc;
        let setup = |exec: &mut Self, letter: u8, v: f64| exec.setup_words.push((letter, v));
        // feed mode, F, S, T
        for &code in w.gs() {
            match code {
                930 => self.state.feed_mode = FeedMode::InverseTime,
                940 => self.state.feed_mode = FeedMode::PerMinute,
                950 => self.state.feed_mode = FeedMode::PerRevolution,
                _ => continue,
            }
        }
        if let Some(f) = w.get(b'F') {
            if f < 0.0 {
                return Err(format!("negative feed F{f}"));
            }
            if self.state.feed_mode != FeedMode::InverseTime {
                self.state.feed = f;
            }
        }
        if let Some(s) = w.get(b'S') {
            if s < 0.0 {
                return Err(format!("negative spindle speed S{s}"));
            }
            self.state.speed = s;
        }
        if let Some(t) = w.get(b'T') {
            if t < 0.0 || t.fract() != 0.0 {
                return Err(format!("T{t} is not a tool number"));
            }
            if !fanuc && t > 0.0 {
                self.tool_entry(t as u32)?;
            }
            self.state.selected_tool = Some(t as u32);
        }
        // M codes before the G codes
        let mut flow = Flow::Next;
        let (ms, nm) = (w.m, w.nm);
        for &m in &ms[..nm] {
            match m {
                3 => self.state.spindle = Spindle::Clockwise,
                4 => self.state.spindle = Spindle::CounterClockwise,
                5 => self.state.spindle = Spindle::Stopped,
                6 => {
                    let Some(t) = self.state.selected_tool else {
                        if fanuc {
                            setup(self, b'M', 6.0);
                            continue;
                        }
                        return Err("M6 without a tool selected by T".into());
                    };
                    self.state.tool = t;
                    self.state.tool_changed = true;
                    if !fanuc {
                        self.state.spindle = Spindle::Stopped;
                    }
                }
                61 => {
                    let q = w.take(b'Q').ok_or("M61 needs the tool number Q")?;
                    setup(self, b'Q', q);
                    self.state.tool = q as u32;
                    self.state.tool_changed = true;
                }
                7 => self.state.mist = true,
                8 => self.state.flood = true,
                9 => {
                    self.state.mist = false;
                    self.state.flood = false;
                }
                70 | 73 => {
                    let modes = self.state.saved_modes();
                    if m == 70 {
                        self.saved_modes = Some(modes);
                    } else {
                        let Some(call) = self.calls.last_mut() else {
                            return Err("M73 outside a subroutine".into());
                        };
                        call.autorestore = Some(modes);
                        // an expanded copy restores the modes itself at the return
                        continue;
                    }
                }
                71 => self.saved_modes = None,
                72 => {
                    let modes = self.saved_modes.ok_or("M72 without modes saved by M70")?;
                    self.restore_modes(&modes);
                }
                98 if subprograms::runs_m98(self.table) => {
                    let p = w.take(b'P').ok_or("M98 needs the program number P")?;
                    let (number, repeat) = subprograms::m98_call(p, w.take(b'L'));
                    flow = Flow::CallProgram { number, repeat, args: None };
                    self.trace.steps[step].flags |= flags::CALL;
                    continue;
                }
                // SINUMERIK: M17 ends a subprogram (Fundamentals, "Subprogram technique")
                17 if self.table.name == "siemens" && !self.calls.is_empty() => {
                    flow = Flow::Return { value: None, sequence: None };
                    continue;
                }
                97 if subprograms::runs_m97(self.table) => {
                    let p = w.take(b'P').ok_or("M97 needs the N number of the local subprogram in P")?;
                    let repeat = w.take(b'L').map_or(1, |v| v.round() as u32);
                    flow = Flow::CallLocal { label: p.round() as u32, repeat };
                    self.trace.steps[step].flags |= flags::CALL;
                    continue;
                }
                99 if subprograms::runs_m98(self.table) => {
                    if self.calls.is_empty() {
                        return Err("M99 in the main program restarts it endlessly".into());
                    }
                    let p = w.take(b'P');
                    if let Some(n) = p.filter(|_| !subprograms::m99_returns_to_block(self.table)) {
                        return Err(format!(
                            "M99 P{n}: Mach3's M99 has no P (\"Using Mach3Mill\", 10.7: it returns to the block after the M98): not supported"
                        ));
                    }
                    flow = Flow::Return { value: None, sequence: p.map(|v| v.round() as u32) };
                    continue;
                }
                0 | 1 | 2 | 30 | 60 => continue,
                _ => {}
            }
            setup(self, b'M', f64::from(m));
        }
        // G codes, in the order of execution
        let gs: Vec<u16> = w.gs().to_vec();
        let mut motion_code = None;
        let mut nonmodal = Vec::new();
        for &code in &gs {
            match self.table.group(code)? {
                // G80 beside another motion code cancels the cycle before it
                Group::Motion if code == 800 && gs.iter().any(|&c| c != 800 && self.table.group(c) == Ok(Group::Motion)) => {
                    self.state.motion = self.after_g80();
                    self.setup_words.push((b'G', 80.0));
                }
                Group::Motion => motion_code = Some(code),
                Group::NonModal => nonmodal.push(code),
                _ => {}
            }
        }
        if gs.contains(&40) {
            let t = match self.dialect {
                Dialect::LinuxCnc => w.take(b'P').ok_or("G4 needs the dwell time P (seconds)")?,
                Dialect::Fanuc => {
                    w.take(b'P').or_else(|| w.take(b'X')).or_else(|| w.take(b'U')).ok_or("G04 needs the dwell time P or X")?
                }
            };
            if t < 0.0 {
                return Err(format!("negative dwell time {t}"));
            }
            setup(self, b'G', 4.0);
            let letter = if w.has(b'P') || self.dialect == Dialect::LinuxCnc {
                b'P'
            } else if w.has(b'X') {
                b'X'
            } else {
                b'U'
            };
            setup(self, letter, t);
        }
        for &code in &gs {
            match code {
                170 => self.state.plane = PlaneSelect::Xy,
                180 => self.state.plane = PlaneSelect::Xz,
                190 => self.state.plane = PlaneSelect::Yz,
                _ => continue,
            }
            setup(self, b'G', f64::from(code) / 10.0);
        }
        for &code in &gs {
            match code {
                200 | 210 => {
                    self.state.set_inch(code == 200);
                    setup(self, b'G', f64::from(code) / 10.0);
                }
                // the SINUMERIK's inch and metric: G70/G700, G71/G710
                700 | 710 | 7000 | 7100 if self.table.group(code) == Ok(Group::Units) => {
                    self.state.set_inch(matches!(code, 700 | 7000));
                    setup(self, b'G', f64::from(code) / 10.0);
                }
                400 => setup(self, b'G', 40.0),
                _ => {}
            }
        }
        for &code in &gs {
            if matches!(code, 430 | 431 | 432 | 440 | 490) {
                self.tool_length(code, w)?;
            }
        }
        for &code in &gs {
            if self.table.group(code)? == Group::System {
                let system = match code {
                    540..=590 => ((code - 540) / 10 + 1) as u8,
                    591..=593 => (code - 591 + 7) as u8,
                    _ => {
                        let (name, most) = if code == 1540 { ("G154", 99.0) } else { ("G54.1", 48.0) };
                        let p = w.take(b'P').ok_or_else(|| format!("{name} needs the offset number P1-P{most}"))?;
                        if !(1.0..=most).contains(&p) || p.fract() != 0.0 {
                            return Err(format!("{name} P{p}: P must be 1 to {most}"));
                        }
                        setup(self, b'P', p);
                        10 + p as u8 - 1
                    }
                };
                self.select_system(system)?;
                setup(self, b'G', f64::from(code) / 10.0);
            }
        }
        // a Fadal fixture offset `E1`-`E48`, `E0` (crate::fadal::fixture)
        if self.table.name == "fadal" {
            if let Some(e) = w.take(b'E') {
                self.fadal_fixture(e)?;
                setup(self, b'E', e);
            }
        }
        for &code in &gs {
            match code {
                610 | 611 | 640 | 620 | 630 => {
                    self.state.path_mode = code;
                    setup(self, b'G', f64::from(code) / 10.0);
                    if code == 640 && !fanuc {
                        self.state.path_tolerance = w.take(b'P');
                        self.state.naive_tolerance = w.take(b'Q');
                        for (l, v) in [(b'P', self.state.path_tolerance), (b'Q', self.state.naive_tolerance)] {
                            if let Some(v) = v {
                                setup(self, l, v);
                            }
                        }
                    }
                }
                900 | 910 => {
                    self.state.frame.incremental = code == 910;
                    setup(self, b'G', f64::from(code) / 10.0);
                }
                901 | 911 => {
                    self.state.frame.ijk_absolute = code == 901;
                    setup(self, b'G', f64::from(code) / 10.0);
                }
                980 | 990 => {
                    self.state.retract_to_r = code == 990;
                    setup(self, b'G', f64::from(code) / 10.0);
                }
                70 | 80 => {
                    self.state.frame.diameter = code == 70;
                    setup(self, b'G', f64::from(code) / 10.0);
                }
                960 | 970 => {
                    self.state.css = code == 960;
                    setup(self, b'G', f64::from(code) / 10.0);
                    if let Some(d) = w.take(b'D') {
                        setup(self, b'D', d);
                    }
                }
                930 | 940 | 950 => setup(self, b'G', f64::from(code) / 10.0),
                _ if matches!(self.table.group(code)?, Group::Other | Group::Unknown) => setup(self, b'G', f64::from(code) / 10.0),
                _ => {}
            }
        }
        // G10, G28.1, G30.1, G52, G92.x; G28/G30 move
        let mut home = None;
        let g53 = nonmodal.contains(&530);
        for &code in &nonmodal {
            match code {
                100 => self.g10(w, step)?,
                281 | 301 => {
                    let first = if code == 281 { 5161 } else { 5181 };
                    self.trace.steps[step].relative = Some((Relative::Store { first }, self.position));
                    let ext = self.state.frame.external(&self.state.position);
                    for (k, e) in ext.iter().enumerate() {
                        let v = self.program_to_user(k, *e);
                        self.params.set_numbered(first + k as u32, v)?;
                    }
                    self.setting_words.push((b'G', f64::from(code) / 10.0));
                }
                520 | 920 | 921 | 922 | 923 => self.g92(code, w, step)?,
                280 | 300 => home = Some(code),
                650 if fanuc => {
                    let p = w.take(b'P').ok_or("G65 needs the program number P")?;
                    let l = w.take(b'L').map_or(1, |v| v.round() as u32);
                    // arguments: A B C I J K D E F H M Q R S T U V W X Y Z -> #1 #2 #3 #4 #5 #6 #7 ...
                    const ORDER: &[u8] = b"ABCIJKDEF?H?M???QRSTUVWXYZ";
                    let mut args = vec![f64::NAN; 26];
                    for (slot, &letter) in args.iter_mut().zip(ORDER) {
                        if letter != b'?' {
                            if let Some(v) = w.take(letter) {
                                *slot = v;
                            }
                        }
                    }
                    w.used = u32::MAX;
                    self.trace.steps[step].flags |= flags::CALL;
                    return Ok(Flow::CallProgram { number: p.round() as u32, repeat: l, args: Some(args) });
                }
                _ => {}
            }
        }
        // the motion: a Fanuc G00-G03 beside a code that takes the axis words only sets the mode
        if let (true, Some(code @ (0 | 10 | 20 | 30))) = (fanuc && (home.is_some() || g53_free_setting(&nonmodal)), motion_code) {
            self.state.motion = match code {
                0 => Motion::Rapid,
                10 => Motion::Feed,
                c => Motion::Arc { clockwise: c == 20 },
            };
            self.setup_words.push((b'G', f64::from(code) / 10.0));
            motion_code = None;
        }
        if let Some(code) = home {
            if g53 {
                return Err(format!("G53 cannot be used with G{}", code / 10));
            }
            self.home(code, w)?;
        } else {
            let motion = match motion_code {
                Some(code) => Some(code),
                None if w.any_axis_or_polar() && !w.gs().iter().any(|c| matches!(c, 100 | 520 | 920 | 431 | 432)) => {
                    match self.state.motion {
                        Motion::None => {
                            return Err("axis words without a motion mode (G0, G1, G2, G3 or a canned cycle; G80 cancelled it)".into())
                        }
                        Motion::Rapid => Some(0),
                        Motion::Feed => Some(10),
                        Motion::Arc { clockwise } => Some(if clockwise { 20 } else { 30 }),
                        Motion::Cycle(c) | Motion::Spline(c) => Some(c),
                    }
                }
                None => None,
            };
            if let Some(code) = motion {
                if g53 && !matches!(code, 0 | 10) {
                    return Err("G53 works with G0 and G1 only".into());
                }
                self.motion(code, w, g53, step)?;
            } else if g53 {
                return Err("G53 without a G0 or G1 move".into());
            }
        }
        if !matches!(self.state.motion, Motion::Cycle(_)) {
            self.state.cycle.initial = None;
        }
        if matches!(self.state.motion, Motion::Rapid | Motion::Feed | Motion::Arc { .. }) {
            self.state.group01 = self.state.motion;
        }
        // stops
        for &m in w.ms() {
            if matches!(m, 2 | 30) && self.table.name == "siemens" && !self.calls.is_empty() {
                // SINUMERIK: M2/M30 in a subprogram ends it as M17 does
                flow = Flow::Return { value: None, sequence: None };
            } else if matches!(m, 0 | 1 | 2 | 30 | 60) {
                self.stop_words.push((b'M', f64::from(m)));
                if matches!(m, 2 | 30) {
                    flow = Flow::End;
                }
            }
        }
        Ok(flow)
    }

    /// The end point of a motion from the axis words (absolute, incremental, `G53`, polar).
    pub(crate) fn end_point(&mut self, w: &mut Words, g53: bool) -> Result<Vec9, String> {
        let (axes, _) = w.axes();
        let s = &self.state;
        let mut end = s.position;
        let incremental = s.frame.incremental && !g53;
        for k in 0..AXES {
            if let Some(mut v) = axes[k] {
                if k == 0 && s.frame.diameter {
                    v /= 2.0;
                }
                end[k] = if incremental { s.position[k] + v } else { v };
            }
        }
        if g53 {
            // machine coordinates: the program point that puts the controlled point there
            let mut ext = s.frame.external(&s.position);
            for k in 0..AXES {
                if let Some(v) = axes[k] {
                    ext[k] = v;
                }
            }
            let p = s.frame.program(&ext);
            for k in 0..AXES {
                if axes[k].is_some() || k < 2 && (axes[0].is_some() || axes[1].is_some()) {
                    end[k] = p[k];
                }
            }
            if w.has(b'@') || w.has(b'^') {
                return Err("polar coordinates cannot be used with G53".into());
            }
        }
        let (radius, angle) = (w.get(b'@'), w.get(b'^'));
        if radius.is_some() || angle.is_some() {
            if axes[0].is_some() || axes[1].is_some() {
                return Err("X or Y words together with polar coordinates @ ^".into());
            }
            let (x, y) = (s.position[0], s.position[1]);
            let (r0, t0) = (x.hypot(y), y.atan2(x).to_degrees());
            let (r, t) = if incremental {
                if (radius.is_some() || angle.is_some()) && x == 0.0 && y == 0.0 {
                    return Err("incremental polar coordinates at the origin are indeterminate".into());
                }
                (r0 + radius.unwrap_or(0.0), t0 + angle.unwrap_or(0.0))
            } else {
                if angle.is_none() && x == 0.0 && y == 0.0 {
                    return Err("polar coordinates at the origin need the angle ^".into());
                }
                (radius.unwrap_or(r0), angle.unwrap_or(t0))
            };
            end[0] = r * t.to_radians().cos();
            end[1] = r * t.to_radians().sin();
        }
        w.use_axes();
        Ok(end)
    }

    /// A straight move to program point `end` (rapid or feed).
    pub(crate) fn straight(&mut self, rapid: bool, end: Vec9, role: Role, g53: bool, words: u16) -> Result<(), String> {
        self.push_move(if rapid { MoveKind::Rapid } else { MoveKind::Feed }, end, role, g53, words, None)
    }

    /// Adds a move to the trace, checking that its axes exist and that it stays in the travel.
    pub(crate) fn push_move(
        &mut self,
        kind: MoveKind,
        end: Vec9,
        role: Role,
        g53: bool,
        words: u16,
        inverse_time: Option<f64>,
    ) -> Result<(), String> {
        for k in 0..AXES {
            if self.axis_map[k].is_none() && (end[k] - self.state.position[k]).abs() > 1e-12 {
                return Err(format!(
                    "axis {} is not an axis of machine `{}` (axes: {})",
                    AXIS_LETTERS[k] as char,
                    self.machine.name,
                    self.machine.axis_letters()
                ));
            }
        }
        let machine_end = self.program_to_machine(&end);
        let n = self.machine.axis_count();
        self.machine.check_range(&machine_end[..n]).map_err(|m| format!("the end point leaves the machine's travel: {m}"))?;
        let frame = self.trace.frame_index(&self.state.frame);
        let step = (self.trace.steps.len() - 1) as u32;
        self.trace.moves.push(Move {
            step,
            kind,
            start: self.position,
            end: machine_end,
            program_end: end,
            frame,
            role,
            machine_coordinates: g53,
            inverse_time,
            words,
        });
        self.position = machine_end;
        self.state.position = end;
        self.state.frame.held_tool = None;
        self.tool_at_last_move = self.state.frame.to_mm(&self.state.frame.tool);
        Ok(())
    }

    /// The motion of a block: G0, G1, G2, G3 or a canned cycle.
    fn motion(&mut self, code: u16, w: &mut Words, g53: bool, step: usize) -> Result<(), String> {
        let inverse = self.state.feed_mode == FeedMode::InverseTime;
        let words = axis_mask(w);
        if self.nurbs.is_some() && !matches!(code, 52 | 53) {
            return Err("a G5.2 NURBS must be ended by G5.3 before another motion (LinuxCNC drops an unfinished one)".into());
        }
        match code {
            0 | 10 => {
                self.state.motion = if code == 0 { Motion::Rapid } else { Motion::Feed };
                // a Fanuc G00/G01 without axis words only sets the mode (LinuxCNC moves to the
                // point it is at)
                if self.dialect == Dialect::Fanuc && !w.any_axis_or_polar() {
                    self.setup_words.push((b'G', f64::from(code) / 10.0));
                    return Ok(());
                }
                let f = if code == 10 { self.feed_for_move(w)? } else { None };
                let end = self.end_point(w, g53)?;
                self.push_move(if code == 0 { MoveKind::Rapid } else { MoveKind::Feed }, end, Role::Words, g53, words, f)
            }
            20 | 30 => {
                let f = self.feed_for_move(w)?;
                self.state.motion = Motion::Arc { clockwise: code == 20 };
                self.arc(code == 20, w, f, words, step)
            }
            50 | 51 => {
                if inverse {
                    return Err("splines cannot run in inverse-time feed (G93)".into());
                }
                self.feed_for_move(w)?;
                self.trace.steps[step].flags |= flags::EXPAND | flags::SPLINE;
                crate::splines::spline(self, code, w)
            }
            52 | 53 => {
                if inverse {
                    return Err("a NURBS cannot run in inverse-time feed (G93)".into());
                }
                self.feed_for_move(w)?;
                let curve = if code == 53 { flags::SPLINE } else { 0 };
                self.trace.steps[step].flags |= flags::EXPAND | flags::NURBS | curve;
                if code == 52 {
                    crate::nurbs::control_point(self, w)
                } else {
                    crate::nurbs::finish(self, w)
                }
            }
            800 => {
                self.state.motion = self.after_g80();
                self.setup_words.push((b'G', 80.0));
                if !w.any_axis_or_polar() {
                    return Ok(());
                }
                // a Fanuc moves in its group-01 mode, which a canned cycle (group 09) left as it was
                match self.state.motion {
                    Motion::Rapid => self.motion(0, w, g53, step),
                    Motion::Feed => self.motion(10, w, g53, step),
                    Motion::Arc { clockwise } => self.motion(if clockwise { 20 } else { 30 }, w, g53, step),
                    _ => Err("axis words with G80 (G80 cancels the motion mode)".into()),
                }
            }
            c => {
                if inverse {
                    return Err("canned cycles cannot run in inverse-time feed (G93)".into());
                }
                self.check_feed("a canned cycle")?;
                crate::cycles::cycle(self, c, w, step)
            }
        }
    }

    /// The motion mode after G80: none in LinuxCNC (canned cycles are in group 1); a Fanuc's
    /// group-01 mode as it was before the cycle.
    fn after_g80(&self) -> Motion {
        match self.dialect {
            Dialect::LinuxCnc => Motion::None,
            Dialect::Fanuc => self.state.group01,
        }
    }

    /// A feed move or cycle before any `F` (`what`): refused, as LinuxCNC and a Fanuc refuse it,
    /// unless the controller keeps the feed rate of the program before (grbl): then it is
    /// corrected as written, with a warning.
    fn check_feed(&mut self, what: &str) -> Result<(), String> {
        if self.state.feed != 0.0 {
            return Ok(());
        }
        if self.table.keeps_feed {
            self.warn(format!(
                "{what} before any F: {} runs it at the feed rate the program before left (after a reset it stops: error:22); corrected as written",
                self.table.title
            ));
            return Ok(());
        }
        Err(format!("{what} with zero feed rate ({} stops here; a program written for grbl, which keeps the feed rate of the program before: --dialect grbl)", self.table.title))
    }

    /// The feed of a G1/G2/G3 move: checked like LinuxCNC (not zero; F on the line in G93).
    fn feed_for_move(&mut self, w: &mut Words) -> Result<Option<f64>, String> {
        match self.state.feed_mode {
            FeedMode::InverseTime => {
                let f = w.take(b'F').ok_or("an inverse-time (G93) move needs F on its line")?;
                if f <= 0.0 {
                    return Err(format!("inverse-time feed F{f} must be positive"));
                }
                Ok(Some(f))
            }
            FeedMode::PerMinute | FeedMode::PerRevolution => {
                self.check_feed("a feed move")?;
                if self.state.feed_mode == FeedMode::PerRevolution && self.state.speed == 0.0 {
                    return Err("feed per revolution (G95) with zero spindle speed".into());
                }
                Ok(None)
            }
        }
    }

    /// `G28`/`G30`: rapid to the intermediate point of the axis words, then to the stored position
    /// (`#5161`-`#5169` / `#5181`-`#5189`, machine units) on those axes (all when none is given).
    fn home(&mut self, code: u16, w: &mut Words) -> Result<(), String> {
        let words = axis_mask(w);
        let (axes, any) = w.axes();
        let intermediate = self.end_point(w, false)?;
        self.straight(true, intermediate, Role::Intermediate { g30: code == 300 }, false, words)?;
        let first = if code == 280 { 5161 } else { 5181 };
        let stored: [f64; AXES] = std::array::from_fn(|k| {
            let v = self.params.numbered(first + k as u32).filter(|v| !v.is_nan()).unwrap_or(0.0);
            self.user_to_program(k, v)
        });
        let home_program = self.state.frame.program(&stored);
        // the axes with words (all without words) go to the stored position; axes the machine
        // lacks stay where they are
        let end: Vec9 = std::array::from_fn(|k| {
            if (!any || axes[k].is_some()) && self.axis_map[k].is_some() {
                home_program[k]
            } else {
                self.state.position[k]
            }
        });
        self.push_move(MoveKind::Rapid, end, Role::Home, false, 0, None)
    }

    /// A G2/G3 arc (helical when other axes move), checked like LinuxCNC (radius mismatch, zero
    /// radius, R too small); `P` turns are written as separate full circles.
    fn arc(&mut self, clockwise: bool, w: &mut Words, f: Option<f64>, words: u16, step: usize) -> Result<(), String> {
        let plane = self.state.plane;
        let [a, b, _] = plane.axes();
        let [ca, cb] = plane.centre_letters();
        let (ia, ib) = (w.take(ca), w.take(cb));
        let r = w.take(b'R');
        let turns = match w.take(b'P') {
            None => 1,
            Some(p) if p >= 1.0 && p.fract() == 0.0 => p as u32,
            Some(p) => return Err(format!("P{p}: the number of turns of an arc must be a whole number of at least 1")),
        };
        let normal_letter = [b'K', b'J', b'I'][match plane {
            PlaneSelect::Xy => 0,
            PlaneSelect::Xz => 1,
            PlaneSelect::Yz => 2,
        }];
        if w.has(normal_letter) {
            return Err(format!("{} word with an arc in G{}", normal_letter as char, plane.gcode()));
        }
        let start = self.state.position;
        let mut end = self.end_point(w, false)?;
        if let Some(angle) = w.take(crate::siemens::arcs::AR) {
            // SINUMERIK AR=: the centre from the end point, or the end point from the centre
            let on_plane = w.has(AXIS_LETTERS[a]) || w.has(AXIS_LETTERS[b]);
            let (s, e) = ([start[a], start[b]], [end[a], end[b]]);
            let centre = match (on_plane, ia.is_some() || ib.is_some(), r.is_some()) {
                (_, _, true) => return Err("an arc with both AR= and CR=: give one of them".into()),
                (true, true, _) => return Err("AR= with both the end point and the centre: give one of them".into()),
                (false, false, _) => return Err(format!("AR= needs the end point or the centre ({}{})", ca as char, cb as char)),
                (true, false, _) => crate::siemens::arcs::centre_from_end(clockwise, s, e, angle)?,
                (false, true, _) => {
                    let c = [start[a] + ia.unwrap_or(0.0), start[b] + ib.unwrap_or(0.0)];
                    [end[a], end[b]] = crate::siemens::arcs::end_from_centre(clockwise, s, c, angle)?;
                    // the block has no end point to correct: written as its move
                    self.trace.steps[step].flags |= flags::EXPAND;
                    c
                }
            };
            return self.arc_about(clockwise, start, end, centre, turns, words, f, step);
        }
        if ia.is_none() && ib.is_none() && r.is_none() {
            return Err(format!("an arc needs the centre words {}{} or a radius R", ca as char, cb as char));
        }
        if r.is_some() && (ia.is_some() || ib.is_some()) {
            return Err("an arc with both R and centre words".into());
        }
        let inch = self.state.frame.inch;
        let centre = match r {
            Some(r) => crate::arcs::centre_from_radius(clockwise, [start[a], start[b]], [end[a], end[b]], r, inch)?,
            None => {
                if self.state.frame.ijk_absolute && (ia.is_none() || ib.is_none()) {
                    return Err(format!(
                        "{} word missing in absolute centre arc (G90.1)",
                        if ia.is_none() { ca as char } else { cb as char }
                    ));
                }
                let (i, j) = (ia.unwrap_or(0.0), ib.unwrap_or(0.0));
                let c = if self.state.frame.ijk_absolute { [i, j] } else { [start[a] + i, start[b] + j] };
                crate::arcs::check_centre([start[a], start[b]], [end[a], end[b]], c, inch)?;
                c
            }
        };
        self.arc_about(clockwise, start, end, centre, turns, words, f, step)
    }

    /// The arc from `start` to `end` about `centre` (program coordinates of the plane) with its
    /// `turns`.
    #[allow(clippy::too_many_arguments)]
    fn arc_about(
        &mut self,
        clockwise: bool,
        start: Vec9,
        end: Vec9,
        centre: [f64; 2],
        turns: u32,
        words: u16,
        f: Option<f64>,
        step: usize,
    ) -> Result<(), String> {
        let plane = self.state.plane;
        let [a, b, _] = plane.axes();
        if self.state.frame.rotation != 0.0 && plane != PlaneSelect::Xy {
            return Err(format!("an arc in G{} with a rotated coordinate system is not supported", plane.gcode()));
        }
        let axes = self.plane_axes(plane)?;
        // the centre as a machine position (the other axes at the start)
        let mut c = start;
        c[a] = centre[0];
        c[b] = centre[1];
        let cm = self.state.frame.machine(&c);
        let arc_plane = Plane { first: axes[0], second: axes[1], normal: axes[2], select: plane };
        let kind = MoveKind::Arc { clockwise, plane: arc_plane, centre: [cm[a], cm[b]] };
        if turns == 1 {
            return self.push_move(kind, end, Role::Words, false, words, f);
        }
        // several turns: the arc, then whole turns, the other axes sharing the total angle
        self.trace.steps[step].flags |= flags::EXPAND;
        let sweep = crate::arcs::sweep(clockwise, [start[a], start[b]], [end[a], end[b]], centre);
        let total = sweep.abs() + f64::from(turns - 1) * std::f64::consts::TAU;
        let mut angle = sweep.abs();
        let along =
            |t: f64| -> Vec9 { std::array::from_fn(|k| if k == a || k == b { end[k] } else { start[k] + t * (end[k] - start[k]) }) };
        let first_f = f.map(|f| f * total / sweep.abs());
        let turn_f = f.map(|f| f * total / std::f64::consts::TAU);
        self.push_move(kind, along(angle / total), Role::Generated, false, words, first_f)?;
        for _ in 1..turns {
            angle += std::f64::consts::TAU;
            self.push_move(kind, along(angle / total), Role::Generated, false, words, turn_f)?;
        }
        Ok(())
    }
}

/// Whether the non-modal codes of a block include one that takes the axis words (G10, G52, G92).
fn g53_free_setting(nonmodal: &[u16]) -> bool {
    nonmodal.iter().any(|c| matches!(c, 100 | 520 | 920))
}

/// Bits of the interpreter axes with words in the block (X = bit 0).
fn axis_mask(w: &Words) -> u16 {
    let mut mask = 0;
    for (k, &l) in AXIS_LETTERS.iter().enumerate() {
        if w.has(l) {
            mask |= 1 << k;
        }
    }
    if w.has(b'@') || w.has(b'^') {
        mask |= 0b11;
    }
    mask
}
