//! Writing the corrected program: a line kept as text gets only the numbers that must change
//! (replaced where they stand, missing axis words added, the pieces of a split move as new lines
//! after it); an expanded part is written block by block as plain moves with its modal codes,
//! its dwells and spindle codes, and the parameters it changed set at its end. Every value is the
//! one that puts the controller at the corrected point, given where the corrected program has
//! already put it (`written`, machine positions): increments are between corrected points,
//! arc centres move by the mean correction of their ends, a `G92`/`G10 L20` that takes the
//! current position takes the shift of the corrected position into account.

use crate::axes::MachineAxes;
use crate::dialect::{format_number, Dialect};
use crate::dialects::gcode_text;
use crate::lexer::Line;
use crate::modal::{is_linear, Frame, Vec9, AXES};
use crate::path::{arc_geometry, point_at, Pieces};
use crate::plan::{LineOut, Plan};
use crate::program::Program;
use crate::source::{encode_line, Ending};
use crate::tools::AXIS_LETTERS;
use crate::trace::{Axes, Move, MoveKind, Relative, Role, Step, Trace};
use std::collections::BTreeMap;

mod cycle;
pub use cycle::HoleReport;

/// Writes the corrected program.
pub struct Writer<'a> {
    pub machine: &'a MachineAxes,
    pub program: &'a Program,
    pub trace: &'a Trace,
    pub plan: &'a Plan,
    pub dialect: Dialect,
    /// Decimals in mm and deg, in inch.
    pub decimals: usize,
    pub decimals_inch: usize,
    axis_map: [Option<usize>; AXES],
    /// The machine position the corrected program has reached (mm, deg).
    pub written: Axes,
    /// New text per line of the main file.
    pub out: Vec<Option<Vec<String>>>,
    region: Vec<String>,
    region_changed: bool,
    /// Lines of the NURBS being written (its control points), commented out unless it is kept.
    nurbs_lines: Vec<usize>,
    pub changed_lines: usize,
    pub inserted_lines: usize,
    /// Parameters and the tool table are in inch.
    pub machine_inch: bool,
    /// Corrected points kept at the end of the travel.
    pub clamped: std::cell::Cell<usize>,
    /// What was expanded, for the note at the top.
    pub notes: Vec<String>,
    /// The holes of the canned cycles kept as cycles.
    pub holes: Vec<HoleReport>,
    /// The R and bottom levels the controller remembers from the last cycle it ran (program
    /// units), whether it runs the cycle the original runs (no expanded copy since), and the
    /// initial level of the run of cycles (original, corrected).
    cycle_words: Option<(f64, f64)>,
    cycle_valid: bool,
    cycle_initial: Option<f64>,
    /// The peck depth of the original and the one written for it (program units).
    cycle_q: Option<(f64, f64)>,
    /// The SINUMERIK modal cycle call (`MCALL CYCLE8x`) the corrected program has in force.
    pub(crate) siemens_mcall: crate::siemens::kept::Mcall,
    /// The line of the main file that line 0 of the program's main file is, and the moves of the
    /// run before the trace's (a file written in parts); the line end of added lines (the file's
    /// first line's).
    pub line_offset: u32,
    pub move_offset: u32,
    pub eol: Ending,
}

/// What a writer hands to the writer of the next part of a program written in parts: where the
/// corrected program stands, the counts, the notes, the holes, the canned-cycle state.
pub struct Carry {
    written: Axes,
    pub changed_lines: usize,
    pub inserted_lines: usize,
    pub clamped: usize,
    pub notes: Vec<String>,
    pub holes: Vec<HoleReport>,
    cycle_words: Option<(f64, f64)>,
    cycle_valid: bool,
    cycle_initial: Option<f64>,
    cycle_q: Option<(f64, f64)>,
    siemens_mcall: crate::siemens::kept::Mcall,
    pub eol: Ending,
}

impl<'a> Writer<'a> {
    pub fn new(
        machine: &'a MachineAxes,
        program: &'a Program,
        trace: &'a Trace,
        plan: &'a Plan,
        decimals: usize,
        decimals_inch: usize,
    ) -> Self {
        Writer {
            machine,
            program,
            trace,
            plan,
            dialect: program.dialect,
            decimals,
            decimals_inch,
            axis_map: std::array::from_fn(|k| machine.axis_index(AXIS_LETTERS[k] as char)),
            written: trace.start,
            out: vec![None; program.files[0].lines.len()],
            region: Vec::new(),
            region_changed: false,
            nurbs_lines: Vec::new(),
            changed_lines: 0,
            inserted_lines: 0,
            machine_inch: false,
            clamped: std::cell::Cell::new(0),
            notes: Vec::new(),
            holes: Vec::new(),
            cycle_words: None,
            cycle_valid: false,
            cycle_initial: None,
            cycle_q: None,
            siemens_mcall: Default::default(),
            line_offset: 0,
            move_offset: 0,
            eol: match program.files[0].endings.first() {
                Some(Ending::None) | None => Ending::Lf,
                Some(&e) => e,
            },
        }
    }

    /// What the next part's writer continues from.
    pub fn carry(self) -> Carry {
        Carry {
            written: self.written,
            changed_lines: self.changed_lines,
            inserted_lines: self.inserted_lines,
            clamped: self.clamped.get(),
            notes: self.notes,
            holes: self.holes,
            cycle_words: self.cycle_words,
            cycle_valid: self.cycle_valid,
            cycle_initial: self.cycle_initial,
            cycle_q: self.cycle_q,
            siemens_mcall: self.siemens_mcall,
            eol: self.eol,
        }
    }

    /// Continues from the writer of the part before.
    pub fn resume(&mut self, c: Carry) {
        self.written = c.written;
        self.changed_lines = c.changed_lines;
        self.inserted_lines = c.inserted_lines;
        self.clamped.set(c.clamped);
        self.notes = c.notes;
        self.holes = c.holes;
        self.cycle_words = c.cycle_words;
        self.cycle_valid = c.cycle_valid;
        self.cycle_initial = c.cycle_initial;
        self.cycle_q = c.cycle_q;
        self.siemens_mcall = c.siemens_mcall;
        self.eol = c.eol;
    }

    fn decimals_of(&self, frame: &Frame, k: usize) -> usize {
        if frame.inch && is_linear(k) {
            self.decimals_inch
        } else {
            self.decimals
        }
    }

    /// Half a unit of the last written decimal of axis `k` (program units).
    pub(crate) fn half(&self, frame: &Frame, k: usize) -> f64 {
        0.5 * 10f64.powi(-(self.decimals_of(frame, k) as i32))
    }

    pub(crate) fn axis_text(&self, frame: &Frame, k: usize, v: f64) -> String {
        format_number(v, self.decimals_of(frame, k), self.dialect)
    }

    /// Program point of machine position `m` in `frame` (axes the machine lacks: `default`).
    pub(crate) fn program_of(&self, frame: &Frame, m: &Axes, default: &Vec9) -> Vec9 {
        let mut ext = frame.external(default);
        let s = frame.scale();
        for (k, e) in ext.iter_mut().enumerate() {
            if let Some(i) = self.axis_map[k] {
                *e = if is_linear(k) { m[i] / s } else { m[i] };
            }
        }
        frame.program(&ext)
    }

    /// How far (um) the machine position of program point `p` in `frame` stands off the corrected
    /// machine position `target`, over the linear axes: what a kept cycle's written words leave
    /// at one of its points.
    pub(crate) fn stand_off_um(&self, frame: &Frame, p: &Vec9, target: &Axes) -> f64 {
        let written = self.machine_of(frame, p);
        let linear = (0..self.machine.axis_count()).filter(|&k| !self.machine.axes()[k].rotary);
        linear.map(|k| (written[k] - target[k]).powi(2)).sum::<f64>().sqrt() * 1e3
    }

    /// Machine position of program point `p` in `frame`.
    pub(crate) fn machine_of(&self, frame: &Frame, p: &Vec9) -> Axes {
        let m = frame.machine(p);
        let mut out = self.written;
        for (k, slot) in self.axis_map.iter().enumerate() {
            if let Some(i) = slot {
                out[*i] = m[k];
            }
        }
        out
    }

    /// The axis values to write so that the controller reaches `target` (machine) with move `m`:
    /// per interpreter axis, `Some(text)` to write, `None` when `original` (the block's word, or
    /// no word) already gives it to the written resolution; with `all_words`, a value for every
    /// axis with a word in the block. Updates `written`.
    /// Axes in `hold` (bits of interpreter axes) stay where the controller is, without a word: the
    /// plane axes of a full circle, which must end exactly where it starts.
    fn axis_values(
        &mut self,
        m: &Move,
        frame: &Frame,
        target: &Axes,
        original: &[Option<f64>; AXES],
        all_words: bool,
        hold: u16,
    ) -> [Option<String>; AXES] {
        let mut out: [Option<String>; AXES] = Default::default();
        let target_p = self.program_of(frame, target, &m.program_end);
        // where the controller counts itself: a Fanuc after `G43` without a move keeps the program
        // position of the offset before, and this move takes the new one
        let held = frame.held();
        let written_p = self.program_of(&held, &self.written, &m.program_end);
        let target_e = frame.external(&target_p);
        let written_e = held.external(&written_p);
        let g53 = m.machine_coordinates;
        let incremental = frame.incremental && !g53;
        let mut values = [0.0; AXES];
        for k in 0..AXES {
            let diameter = if k == 0 && frame.diameter { 2.0 } else { 1.0 };
            let (desired, current_absent) = if g53 {
                (target_e[k], written_e[k])
            } else if incremental {
                (target_p[k] - written_p[k], 0.0)
            } else {
                (target_p[k], written_p[k])
            };
            let (desired, current_absent) = (desired * diameter, current_absent * diameter);
            if hold & (1 << k) != 0 {
                values[k] = current_absent;
                continue;
            }
            let current = original[k].unwrap_or(current_absent);
            let present = original[k].is_some() || all_words && m.words & (1 << k) != 0;
            values[k] = current;
            if self.axis_map[k].is_none() {
                continue;
            }
            if (desired - current).abs() >= self.half(frame, k) || all_words && present {
                let text = self.axis_text(frame, k, desired);
                values[k] = text.parse::<f64>().unwrap_or(desired);
                if (desired - current).abs() >= self.half(frame, k) || present {
                    out[k] = Some(text);
                }
            }
        }
        // where the controller goes with these values
        let mut new_p = written_p;
        let mut new_e = written_e;
        for k in 0..AXES {
            let diameter = if k == 0 && frame.diameter { 2.0 } else { 1.0 };
            let v = values[k] / diameter;
            if g53 {
                new_e[k] = v;
            } else if incremental {
                new_p[k] = written_p[k] + v;
            } else {
                new_p[k] = v;
            }
        }
        if g53 {
            new_p = frame.program(&new_e);
        }
        self.written = self.machine_of(frame, &new_p);
        out
    }

    /// Centre words of an arc piece whose corrected centre is `centre` (machine), from the written
    /// start `start`.
    fn centre_words(&self, m: &Move, frame: &Frame, centre: [f64; 2], start: &Axes) -> [(u8, f64, String); 2] {
        let MoveKind::Arc { plane, .. } = m.kind else { unreachable!("centre of a line") };
        let [a, b, _] = plane.select.axes();
        let start_p = self.program_of(frame, start, &m.program_end);
        let mut c = *start;
        c[plane.first] = centre[0];
        c[plane.second] = centre[1];
        let centre_p = self.program_of(frame, &c, &m.program_end);
        let letters = plane.select.centre_letters();
        std::array::from_fn(|d| {
            let k = [a, b][d];
            let v = if frame.ijk_absolute { centre_p[k] } else { centre_p[k] - start_p[k] };
            (letters[d], v, self.axis_text(frame, k, v))
        })
    }

    /// The corrected targets of the pieces of `m`, and the arc centres (machine). The
    /// intermediate point of a `G28`/`G30` that does not move (`G28 G91 Z0`) is where the controller
    /// already is: nothing to correct.
    pub(crate) fn targets(&self, m: &Move, pieces: &Pieces) -> Vec<(Axes, Option<[f64; 2]>, f64)> {
        if matches!(m.role, Role::Intermediate { .. }) && m.start == m.end {
            return vec![(self.written, None, 1.0)];
        }
        let n = self.machine.axis_count();
        let arc = arc_geometry(m);
        let mut out = Vec::with_capacity(pieces.len());
        let mut t_prev = 0.0;
        // the shift the controller holds at the start: the written end of the move before
        let mut c_prev: Vec<f64> = (0..n).map(|k| self.written[k] - m.start[k]).collect();
        for (t, c) in pieces {
            let mut p = vec![0.0; n];
            point_at(m, arc.as_ref(), *t, &mut p);
            let mut target = m.end;
            for k in 0..n {
                target[k] = p[k] + c[k];
                // a corrected point beyond the travel (a move to the limit) stays at the limit
                if let Some([lo, hi]) = self.machine.axes()[k].range {
                    if target[k] > hi || target[k] < lo {
                        target[k] = target[k].clamp(lo, hi);
                        self.clamped.set(self.clamped.get() + 1);
                    }
                }
            }
            let centre = match m.kind {
                MoveKind::Arc { .. } if *t == t_prev => None,
                MoveKind::Arc { plane, centre, .. } => Some([
                    centre[0] + 0.5 * (c_prev[plane.first] + c[plane.first]),
                    centre[1] + 0.5 * (c_prev[plane.second] + c[plane.second]),
                ]),
                _ => None,
            };
            out.push((target, centre, t - t_prev));
            t_prev = *t;
            c_prev.clone_from(c);
        }
        out
    }

    /// Whether the move's corrected pieces differ from the original move at the written resolution.
    fn move_changes(&self, m: &Move, frame: &Frame, pieces: &Pieces, from_start: bool) -> bool {
        if pieces.len() > 1 {
            return true;
        }
        let s = frame.scale();
        (0..self.machine.axis_count()).any(|i| {
            let k = self.axis_map.iter().position(|&x| x == Some(i)).unwrap_or(0);
            let unit = if is_linear(k) { s } else { 1.0 };
            pieces[0].1[i].abs() / unit >= self.half(frame, k)
                || (from_start && (self.written[i] - m.start[i]).abs() / unit >= self.half(frame, k))
        })
    }

    pub(crate) fn frame(&self, m: &Move) -> Frame {
        self.trace.frames[m.frame as usize]
    }

    /// The line of a block kept as text, rewritten for its moves (with their pieces) and its
    /// position-relative setting; the pieces as new lines after it.
    pub fn in_place(&mut self, step: &Step, pieces: &[Pieces]) -> Vec<String> {
        let file = &self.program.files[step.file as usize];
        let k = step.line as usize;
        let text = file.line_text(k);
        let Ok(line) = &file.lines[k] else { unreachable!("an executed line was read") };
        let mut edits: Vec<(std::ops::Range<usize>, String)> = Vec::new();
        let mut appended: Vec<String> = Vec::new();
        let mut extra: Vec<String> = Vec::new();
        let mut before: Vec<String> = Vec::new();
        if let Some((relative, position)) = step.relative {
            self.relative(step, relative, &position, line, &mut edits, &mut extra);
        }
        let moves = self.trace.step_moves(step);
        for (m, p) in moves.iter().zip(pieces) {
            let frame = self.frame(m);
            match m.role {
                Role::Home => {
                    self.written = m.end;
                }
                Role::Words | Role::Intermediate { .. } => {
                    let mut targets = self.targets(m, p);
                    // a step at the start goes before the line, in the modes in force there; the
                    // line then needs its motion word
                    let frame_before = self.trace.frames[step.frame as usize];
                    while targets.len() > 1 && targets[0].2 == 0.0 {
                        let (target, _, _) = targets.remove(0);
                        if let Some(l) = self.piece_line(m, &frame_before, &target, None, 0.0, 0) {
                            before.push(l);
                            // (a grbl jog `$J=` is a linear move without one, and refuses one)
                            if !has_motion_word(line) && line.system.is_none() {
                                appended.insert(0, motion_word(m, self.dialect));
                            }
                        }
                    }
                    let start = self.written;
                    let resolved = self.trace.words_of(&step.motion_words);
                    let value_of = |l: u8| resolved.iter().find(|(x, _)| *x == l).map(|(_, v)| *v);
                    let original: [Option<f64>; AXES] = std::array::from_fn(|k| value_of(AXIS_LETTERS[k]));
                    let polar = line.word(b'@').is_some() || line.word(b'^').is_some();
                    let original = if polar { [None; AXES] } else { original };
                    let (first, centre, fraction) = targets[0];
                    let mut hold = if p.len() == 1 { full_circle(m) } else { 0 };
                    if let Role::Intermediate { .. } = m.role {
                        // a word would send that axis to the stored position too: the corrected
                        // intermediate point is reached by a rapid before the line when an axis
                        // without a word needs a correction
                        hold |= !m.words & 0x1ff;
                        if let Some(l) = self.intermediate_line(m, &frame_before, &targets[0].0, hold) {
                            before.push(l);
                        }
                    }
                    for (k, &l) in AXIS_LETTERS.iter().enumerate() {
                        if let (true, Some(w)) = (hold & (1 << k) != 0 && m.role == Role::Words, line.word(l)) {
                            edits.push((blank_before(text, letter_start(text, w.span.start))..w.span.end, String::new()));
                        }
                    }
                    let values = self.axis_values(m, &frame, &first, &original, false, hold);
                    if polar && values.iter().any(Option::is_some) {
                        // polar words rewritten as X Y
                        for l in [b'@', b'^'] {
                            if let Some(w) = line.word(l) {
                                edits.push((blank_before(text, letter_start(text, w.span.start))..w.span.end, String::new()));
                            }
                        }
                        let values = self.polar_values(m, &frame, &start, &first);
                        for (k, v) in values.into_iter().enumerate() {
                            if let Some(v) = v {
                                appended.push(format!("{}{v}", AXIS_LETTERS[k] as char));
                            }
                        }
                    } else {
                        for (kk, v) in values.iter().enumerate() {
                            if let Some(v) = v {
                                match line.word(AXIS_LETTERS[kk]) {
                                    Some(w) => edits.push((w.span.clone(), v.clone())),
                                    None => appended.push(format!("{}{v}", AXIS_LETTERS[kk] as char)),
                                }
                            }
                        }
                    }
                    let endpoints_changed = !edits.is_empty() || !appended.is_empty();
                    if let (Some(c), MoveKind::Arc { plane, .. }) = (centre, m.kind) {
                        let words = self.centre_words(m, &frame, c, &start);
                        // an R arc (SINUMERIK CR=, or AR= with its end point) as I J once its ends move
                        if let Some(r) = line.word(b'R').or_else(|| line.word(crate::siemens::arcs::AR)) {
                            if endpoints_changed || p.len() > 1 {
                                let t = format!("{}{} {}{}", words[0].0 as char, words[0].2, words[1].0 as char, words[1].2);
                                edits.push((letter_start(text, r.span.start)..r.span.end, t));
                            }
                        } else {
                            let [a, b, _] = plane.select.axes();
                            for (d, (letter, v, t)) in words.iter().enumerate() {
                                let word = line.word(*letter);
                                let old = value_of(*letter).unwrap_or(0.0);
                                if (v - old).abs() >= self.half(&frame, [a, b][d]) {
                                    match word {
                                        Some(w) => edits.push((w.span.clone(), t.clone())),
                                        None => appended.push(format!("{}{t}", *letter as char)),
                                    }
                                }
                            }
                        }
                    }
                    if let (Some(f), true) = (m.inverse_time, p.len() > 1) {
                        if let Some(w) = line.word(b'F') {
                            edits.push((w.span.clone(), format_number(f / fraction, 6, Dialect::LinuxCnc)));
                        }
                    }
                    for &(target, centre, fraction) in &targets[1..] {
                        if let Some(l) = self.piece_line(m, &frame, &target, centre, fraction, 0) {
                            extra.push(l);
                        }
                    }
                }
                Role::Generated => unreachable!("generated moves are expanded"),
            }
        }
        let new = edited_line(text, line, &appended, edits);
        if new != text {
            self.changed_lines += 1;
        }
        self.inserted_lines += extra.len() + before.len();
        let mut lines = before;
        lines.push(new);
        lines.extend(extra);
        lines
    }

    /// A rapid to the corrected intermediate point of a `G28`/`G30` when an axis without a word
    /// (`hold`) needs a correction there; `None` otherwise.
    fn intermediate_line(&mut self, m: &Move, frame: &Frame, target: &Axes, hold: u16) -> Option<String> {
        let p = self.program_of(frame, target, &m.program_end);
        let w = self.program_of(frame, &self.written, &m.program_end);
        let needed = (0..AXES).any(|k| hold & (1 << k) != 0 && self.axis_map[k].is_some() && (p[k] - w[k]).abs() >= self.half(frame, k));
        if !needed {
            return None;
        }
        let mut rapid = *m;
        rapid.kind = MoveKind::Rapid;
        rapid.machine_coordinates = false;
        self.piece_line(&rapid, frame, target, None, 0.0, 0)
    }

    /// X Y values for a block written with polar words.
    fn polar_values(&mut self, m: &Move, frame: &Frame, start: &Axes, target: &Axes) -> [Option<String>; AXES] {
        self.written = *start;
        let mut mv = *m;
        mv.words |= 0b11;
        self.axis_values(&mv, frame, target, &[None; AXES], true, 0)
    }

    /// A new line for a piece of a split move; `None` when no axis moves at the written resolution.
    fn piece_line(&mut self, m: &Move, frame: &Frame, target: &Axes, centre: Option<[f64; 2]>, fraction: f64, hold: u16) -> Option<String> {
        let start = self.written;
        let mut words = Vec::new();
        if m.machine_coordinates {
            words.push("G53".to_string());
        }
        // a piece of zero length: the step of the correction where an axis reverses, a short rapid
        // (the lost motion taken up where the original path reverses)
        let step = fraction == 0.0;
        words.push(if step { "G0".to_string() } else { motion_word(m, self.dialect) });
        let values = self.axis_values(m, frame, target, &[None; AXES], false, hold);
        for (k, v) in values.iter().enumerate() {
            if let Some(v) = v {
                words.push(format!("{}{v}", AXIS_LETTERS[k] as char));
            }
        }
        if values.iter().all(Option::is_none) && !(hold != 0 && centre.is_some()) {
            self.written = start;
            return None;
        }
        if let (Some(c), false) = (centre, step) {
            for (letter, _, t) in self.centre_words(m, frame, c, &start) {
                words.push(format!("{}{t}", letter as char));
            }
        }
        if let (Some(f), false) = (m.inverse_time, step) {
            words.push(format!("F{}", format_number(f / fraction, 6, Dialect::LinuxCnc)));
        }
        Some(words.join(" "))
    }

    /// A block that sets something from the current position: its axis words shifted by the shift
    /// of the corrected position (G92, G10 L20), or the stored position set back (G28.1, G30.1).
    fn relative(
        &mut self,
        step: &Step,
        relative: Relative,
        position: &Axes,
        line: &Line,
        edits: &mut Vec<(std::ops::Range<usize>, String)>,
        extra: &mut Vec<String>,
    ) {
        let frame = setting_frame(&self.trace.frames[step.frame as usize], relative);
        let delta = self.shift(&frame, position);
        match relative {
            Relative::G92 | Relative::G10L20 { .. } | Relative::G10Tool => {
                for (k, &l) in AXIS_LETTERS.iter().enumerate() {
                    if let Some(w) = line.word(l) {
                        if delta[k].abs() >= self.half(&frame, k) {
                            let v = self.resolved_setting(step, l).unwrap_or(0.0) + delta[k];
                            edits.push((w.span.clone(), self.axis_text(&frame, k, v)));
                        }
                    }
                }
            }
            Relative::Store { first } => {
                if let Some(l) = self.store_line(&frame, first, position) {
                    extra.push(l);
                }
            }
        }
    }

    /// The shift of the corrected position from the original one, in program coordinates.
    fn shift(&self, frame: &Frame, original: &Axes) -> Vec9 {
        let zero = [0.0; AXES];
        let a = self.program_of(frame, &self.written, &zero);
        let b = self.program_of(frame, original, &zero);
        std::array::from_fn(|k| if self.axis_map[k].is_some() { a[k] - b[k] } else { 0.0 })
    }

    /// `#5161=... ` setting the stored position back to the original one, when it differs.
    fn store_line(&self, frame: &Frame, first: u32, original: &Axes) -> Option<String> {
        let delta = self.shift(frame, original);
        if (0..AXES).all(|k| delta[k].abs() < self.half(frame, k)) {
            return None;
        }
        let s = frame.scale();
        let mut words = Vec::new();
        for (k, slot) in self.axis_map.iter().enumerate() {
            if let Some(i) = slot {
                // machine units of the stored parameters: the step's frame converts from mm
                let v = if is_linear(k) { original[*i] / s } else { original[*i] };
                let user = self.to_user(frame, k, v);
                words.push(format!("#{}={}", first + k as u32, fine(user)));
            }
        }
        Some(words.join(" "))
    }

    /// A stored position value (program units of `frame`) in machine units.
    fn to_user(&self, frame: &Frame, k: usize, v: f64) -> f64 {
        if !is_linear(k) {
            return v;
        }
        match (self.machine_inch, frame.inch) {
            (true, false) => v / crate::modal::MM_PER_INCH,
            (false, true) => v * crate::modal::MM_PER_INCH,
            _ => v,
        }
    }

    /// The value of setting word `letter` of a step (resolved).
    fn resolved_setting(&self, step: &Step, letter: u8) -> Option<f64> {
        self.trace.words_of(&step.setting).iter().rev().find(|(l, _)| *l == letter).map(|(_, v)| *v)
    }

    /// The text of a word of an expanded copy.
    fn word_text(&self, letter: u8, v: f64, frame: &Frame) -> String {
        match letter {
            b'G' => format!("G{}", gcode_text((v * 10.0).round() as u16)),
            b'M' => format!("M{}", v.round() as i64),
            l => {
                let value = match (self.dialect, crate::modal::axis_of_letter(l)) {
                    (Dialect::Fanuc, Some(k)) => self.axis_text(frame, k, v),
                    (Dialect::Fanuc, None) if matches!(l, b'I' | b'J' | b'K' | b'R' | b'Q') => {
                        format_number(v, self.decimals_of(frame, 0), Dialect::Fanuc)
                    }
                    _ => fine(v),
                };
                format!("{}{value}", l as char)
            }
        }
    }

    /// An expanded copy of a step.
    pub fn expanded(&mut self, step: &Step, pieces: &[Pieces], keep_sequence: Option<u32>) -> Vec<String> {
        if !step.moves.is_empty() {
            // the controller no longer runs the cycles the original runs
            self.cycle_valid = false;
        }
        let frame0 = self.trace.frames[step.frame as usize];
        let mut out = Vec::new();
        let mut first: Vec<String> = Vec::new();
        if let Some(n) = keep_sequence {
            first.push(format!("N{n}"));
        }
        for &(l, v) in self.trace.words_of(&step.setup) {
            first.push(self.word_text(l, v, &frame0));
        }
        let messages = &self.trace.messages[step.messages.start as usize..step.messages.end as usize];
        let (semicolons, parens): (Vec<&String>, Vec<&String>) = messages.iter().partition(|m| m.starts_with(';'));
        for m in parens {
            first.push(m.clone());
        }
        if let Some(m) = semicolons.first() {
            match self.program.controller {
                crate::Controller::Siemens => first.push(m.to_string()),
                _ => first.push(format!("({})", m[1..].replace(['(', ')'], ""))),
            }
        }
        if !first.is_empty() {
            out.push(first.join(" "));
        }
        let setting = self.trace.words_of(&step.setting);
        if !setting.is_empty() {
            let delta = match step.relative {
                Some((relative @ (Relative::G92 | Relative::G10L20 { .. } | Relative::G10Tool), position)) => {
                    self.shift(&setting_frame(&frame0, relative), &position)
                }
                _ => [0.0; AXES],
            };
            let words: Vec<String> = setting
                .iter()
                .map(|&(l, v)| match crate::modal::axis_of_letter(l) {
                    Some(k) if delta[k] != 0.0 => self.word_text(l, v + delta[k], &frame0),
                    _ => self.word_text(l, v, &frame0),
                })
                .collect();
            out.push(words.join(" "));
            if let Some((Relative::Store { first }, position)) = step.relative {
                if let Some(l) = self.store_line(&frame0, first, &position) {
                    out.push(l);
                }
            }
        }
        let moves = self.trace.step_moves(step);
        let actions = &self.trace.actions[step.actions.start as usize..step.actions.end as usize];
        for (i, (m, p)) in moves.iter().zip(pieces).enumerate() {
            for (at, words) in actions {
                if *at as usize == i {
                    out.push(self.action_text(words, &frame0));
                }
            }
            let frame = self.frame(m);
            match m.role {
                Role::Home => self.written = m.end,
                Role::Intermediate { g30 } => {
                    let (target, _, _) = self.targets(m, p)[0];
                    if let Some(l) = self.intermediate_line(m, &frame, &target, !m.words & 0x1ff) {
                        out.push(l);
                    }
                    let values = self.axis_values(m, &frame, &target, &[None; AXES], true, 0);
                    let mut words = vec![if g30 { "G30".to_string() } else { "G28".to_string() }];
                    for (k, v) in values.iter().enumerate() {
                        if let (Some(v), true) = (v, m.words & (1 << k) != 0) {
                            words.push(format!("{}{v}", AXIS_LETTERS[k] as char));
                        }
                    }
                    out.push(words.join(" "));
                }
                Role::Words | Role::Generated => {
                    // the chords of a curve start where the rounded chord before ended: only the
                    // first start counts
                    let from_start = i == 0 || !step.has(crate::trace::flags::SPLINE);
                    if self.move_changes(m, &frame, p, from_start) {
                        self.region_changed = true;
                    }
                    let hold = if p.len() == 1 { full_circle(m) } else { 0 };
                    for (target, centre, fraction) in self.targets(m, p) {
                        if let Some(l) = self.piece_line(m, &frame, &target, centre, fraction, hold) {
                            out.push(l);
                        }
                    }
                }
            }
        }
        for (at, words) in actions {
            if *at as usize == moves.len() {
                out.push(self.action_text(words, &frame0));
            }
        }
        let stops = self.trace.words_of(&step.stops);
        if !stops.is_empty() {
            out.push(stops.iter().map(|&(l, v)| self.word_text(l, v, &frame0)).collect::<Vec<_>>().join(" "));
        }
        if step.relative.is_some() {
            self.region_changed = true;
        }
        out
    }

    fn action_text(&self, words: &std::ops::Range<u32>, frame: &Frame) -> String {
        self.trace.words_of(words).iter().map(|&(l, v)| self.word_text(l, v, frame)).collect::<Vec<_>>().join(" ")
    }

    /// Processes a step: in place, replaced where it stands, or into the current region.
    pub fn step(&mut self, index: usize, pieces: &[Pieces]) {
        self.write_step(index, pieces);
        if let Some(jump) = self.trace.steps[index].jump {
            for (w, j) in self.written.iter_mut().zip(&jump) {
                *w += j;
            }
        }
    }

    fn write_step(&mut self, index: usize, pieces: &[Pieces]) {
        let step = &self.trace.steps[index];
        let siemens = self.program.controller == crate::Controller::Siemens;
        if siemens {
            self.siemens_track(index);
        }
        if let Some(r) = self.plan.region_of[index] {
            let region = &self.plan.regions[r as usize];
            if index == region.steps.start {
                self.region.clear();
                self.region_changed = false;
                let entry = self.trace.step_moves(step).first().map(|m| m.start);
                if let Some(start) = entry {
                    if (0..self.machine.axis_count()).any(|i| (self.written[i] - start[i]).abs() > 1e-9) {
                        self.region_changed = true;
                    }
                }
            }
            if let Some(hole) = self.trace.hole_of(index).filter(|h| h.tapping()) {
                let lines = self.cycle_block(hole, step, pieces);
                self.region.extend(lines);
                self.region_changed = true;
            } else if !step.has(crate::trace::flags::CONTROL) || !step.actions.is_empty() {
                // a SINUMERIK modal call in force would drill at each expanded move
                if let Some(off) = self.siemens_call_off(step).filter(|_| siemens) {
                    self.region.push(off);
                    self.region_changed = true;
                }
                let lines = self.expanded(step, pieces, None);
                self.region.extend(lines);
            }
            if index + 1 == region.steps.end {
                self.close_region(r as usize);
            }
            return;
        }
        if step.file != 0 {
            return;
        }
        let k = step.line as usize;
        match self.plan.lines[k] {
            LineOut::InPlace(s) if s as usize == index => match self.trace.hole_of(index) {
                Some(_) if siemens => self.siemens_hole(index, pieces, k),
                Some(hole) => match self.kept_cycle(hole, step, pieces) {
                    Some(lines) => self.out[k] = Some(lines),
                    None => self.single(step, pieces, k),
                },
                None => {
                    let lines = self.in_place(step, pieces);
                    self.out[k] = Some(lines);
                }
            },
            LineOut::Single(s) if s as usize == index && siemens => self.siemens_single(index, pieces, k),
            LineOut::Single(s) if s as usize == index => self.single(step, pieces, k),
            _ => {
                // a step of a line kept as it is (a comment, a block without moves)
                for m in self.trace.step_moves(step) {
                    self.written = m.end;
                }
            }
        }
    }

    /// A block replaced by its moves where it stands (a canned cycle, an arc of several turns, a
    /// spline), or its text when nothing changes at the written resolution.
    pub(crate) fn single(&mut self, step: &Step, pieces: &[Pieces], k: usize) {
        let sequence = self.program.files[0].lines[k].as_ref().ok().and_then(|l| l.sequence);
        self.region_changed = false;
        let mut lines = self.expanded(step, pieces, sequence);
        // a SINUMERIK cycle call never stays: the controller would drill again at the moves
        self.region_changed |= step.has(crate::trace::flags::SIEMENS_CYCLE);
        let text = self.program.files[0].line_text(k).to_string();
        let nurbs = step.has(crate::trace::flags::NURBS);
        if nurbs && !step.has(crate::trace::flags::SPLINE) {
            // a control point: the curve is written as chords at its G5.3 if they change
            lines.push(format!("(NURBS control point, written as lines at G5.3: {})", text.trim().replace(['(', ')'], "")));
            self.out[k] = Some(lines);
            self.nurbs_lines.push(k);
            return;
        }
        let control_points = std::mem::take(&mut self.nurbs_lines);
        if self.region_changed {
            let what = if step.has(crate::trace::flags::SIEMENS_CYCLE) {
                "SINUMERIK drilling cycle as moves"
            } else if nurbs {
                "NURBS (G5.2-G5.3) as lines within 1 um of the curve"
            } else if step.has(crate::trace::flags::SPLINE) {
                "spline as lines within 1 um of the curve"
            } else if matches!(self.trace.step_moves(step), [m] if matches!(m.kind, MoveKind::Arc { .. })) {
                // one arc, expanded: an arc whose end its block does not state
                "SINUMERIK arc by its centre and opening angle AR=, written with its end point"
            } else if self.trace.step_moves(step).iter().all(|m| matches!(m.kind, MoveKind::Arc { .. })) {
                "arc of several turns"
            } else {
                "canned cycle"
            };
            self.notes.push(format!("line {}, {what}", k + 1 + self.line_offset as usize));
            self.changed_lines += 1 + control_points.len();
            self.inserted_lines += lines.len().saturating_sub(1);
            let comment = match self.program.controller {
                crate::Controller::Siemens => text.find(';').map(|i| text[i..].to_string()),
                _ => comment_of(&text),
            };
            if let Some(c) = comment {
                if let Some(first) = lines.first_mut() {
                    if !first.contains(&c) {
                        first.push_str(&format!(" {c}"));
                    }
                }
            }
            self.out[k] = Some(lines);
        } else {
            let moves = self.trace.step_moves(step);
            if let Some(m) = moves.last() {
                self.written = m.end;
            }
            self.out[k] = Some(vec![text]);
            for c in control_points {
                self.out[c] = Some(vec![self.program.files[0].line_text(c).to_string()]);
            }
        }
    }

    /// Ends region `r`: its expanded text with the parameters it changed set at its end, or its
    /// original text when nothing in it changes at the written resolution.
    fn close_region(&mut self, r: usize) {
        let region = &self.plan.regions[r];
        let file = &self.program.files[0];
        if !self.region_changed {
            let last = self.trace.steps[region.steps.clone()].iter().rev().find(|s| !s.moves.is_empty());
            if let Some(s) = last {
                self.written = self.trace.moves[s.moves.end as usize - 1].end;
            }
            let text: Vec<String> = region.lines.clone().map(|k| file.line_text(k).to_string()).collect();
            self.out[region.lines.start] = Some(text);
            return;
        }
        self.notes.push(region.reason.clone());
        let mut lines = std::mem::take(&mut self.region);
        // parameters the region changed, visible after it
        let mut last: BTreeMap<crate::params::ParamKey, f64> = BTreeMap::new();
        for s in &self.trace.steps[region.steps.clone()] {
            for (key, value) in &self.trace.writes[s.writes.start as usize..s.writes.end as usize] {
                let global = match key {
                    crate::params::ParamKey::Numbered(n) => *n as usize > crate::params::local_count(self.dialect),
                    crate::params::ParamKey::Named(n) => n.starts_with('_'),
                };
                if s.level == region.level || global {
                    last.insert(key.clone(), *value);
                }
            }
        }
        let to_end = region.lines.end >= file.body.end;
        if !last.is_empty() && !to_end {
            let words: Vec<String> =
                last.iter().map(|(k, v)| format!("{k}={}", if v.is_nan() { "#0".into() } else { format!("{v}") })).collect();
            lines.push(words.join(" "));
        }
        self.changed_lines += region.lines.len();
        self.inserted_lines += lines.len().saturating_sub(region.lines.len());
        self.out[region.lines.start] = Some(lines);
    }

    /// Appends the lines of the main file (or of the part of it this writer has) to `out`; the
    /// offset in `out` where the notes go, unless `noted` (placed in a part before) or no line of
    /// this part is after the leading `%` and program-number lines.
    pub fn write_lines(&self, out: &mut Vec<u8>, mut noted: bool) -> Option<usize> {
        let file = &self.program.files[0];
        let mut at = None;
        for (k, plan) in self.plan.lines.iter().enumerate() {
            let keep_first =
                |l: &Result<Line, String>| matches!(l, Ok(l) if l.percent || l.program_number.is_some() && self.dialect == Dialect::Fanuc);
            let siemens_head = self.program.controller == crate::Controller::Siemens && crate::siemens::is_file_header(file.line_text(k));
            if !(noted || k < file.body.start || keep_first(&file.lines[k]) || siemens_head) {
                at = Some(out.len());
                noted = true;
            }
            if *plan == LineOut::Hidden {
                continue;
            }
            let bytewise = file.bytewise.binary_search(&k).is_ok();
            let ending = file.endings[k];
            match &self.out[k] {
                Some(lines) => {
                    for (i, l) in lines.iter().enumerate() {
                        match self.program.controller {
                            crate::Controller::Siemens => encode_line(&crate::siemens::write::spell(l), bytewise, out),
                            crate::Controller::Fadal => {
                                for (j, block) in crate::fadal::write::spell(l).iter().enumerate() {
                                    if j > 0 {
                                        out.extend_from_slice(self.eol.bytes());
                                    }
                                    encode_line(block, bytewise, out);
                                }
                            }
                            _ => encode_line(l, bytewise, out),
                        }
                        out.extend_from_slice(if i + 1 == lines.len() { ending.bytes() } else { self.eol.bytes() });
                    }
                }
                None => {
                    encode_line(file.line_text(k), bytewise, out);
                    out.extend_from_slice(ending.bytes());
                }
            }
        }
        at
    }
}

/// The frame the axis words of a position-relative setting are read in: `G10 L20` reads them in
/// the coordinates of its system, with that system's rotation.
/// `text` (the line's source) with the words of `edits` replaced (byte ranges of `text`) and the
/// words of `appended` added after its last item, before any comment.
pub(crate) fn edited_line(text: &str, line: &Line, appended: &[String], mut edits: Vec<(std::ops::Range<usize>, String)>) -> String {
    let mut new = text.to_string();
    if !appended.is_empty() {
        let at = line.end_of_items.min(new.len());
        new.insert_str(at, &format!(" {}", appended.join(" ")));
    }
    edits.sort_by_key(|(r, _)| std::cmp::Reverse(r.start));
    for (range, t) in edits {
        new.replace_range(range, &t);
    }
    new
}

fn setting_frame(frame: &Frame, relative: Relative) -> Frame {
    let mut f = *frame;
    if let Relative::G10L20 { rotation, .. } = relative {
        f.rotation = rotation;
    }
    f
}

/// The plane axes (bits of interpreter axes) of an arc that ends where it starts in its plane: a
/// full circle, which the corrected program must keep (its end words are left out).
fn full_circle(m: &Move) -> u16 {
    match m.kind {
        MoveKind::Arc { plane, .. }
            if (m.start[plane.first] - m.end[plane.first]).abs() < 1e-9 && (m.start[plane.second] - m.end[plane.second]).abs() < 1e-9 =>
        {
            let [a, b, _] = plane.select.axes();
            (1 << a) | (1 << b)
        }
        _ => 0,
    }
}

/// The byte offset of the letter of a word whose value starts at `value_start`.
fn letter_start(text: &str, value_start: usize) -> usize {
    let b = text.as_bytes();
    let mut i = value_start;
    while i > 0 {
        i -= 1;
        if b[i].is_ascii_alphabetic() || matches!(b[i], b'@' | b'^') {
            // a SINUMERIK address of several letters before `=` (`CR=5`)
            while b.get(i + 1) == Some(&b'=') && i > 0 && b[i - 1].is_ascii_alphabetic() {
                i -= 1;
            }
            return i;
        }
    }
    0
}

/// `at`, moved back over one blank before it (so that a removed word takes its separator along).
fn blank_before(text: &str, at: usize) -> usize {
    if at > 0 && matches!(text.as_bytes()[at - 1], b' ' | b'\t') {
        at - 1
    } else {
        at
    }
}

/// The first comment of a line, `(...)`.
fn comment_of(text: &str) -> Option<String> {
    let start = text.find('(')?;
    let end = text[start..].find(')')? + start;
    Some(text[start..=end].to_string())
}

/// A value written with all the digits it needs (10 decimals at most, trailing zeros removed).
fn fine(v: f64) -> String {
    format_number(v, 10, Dialect::LinuxCnc)
}

/// Whether a line has a G0/G1/G2/G3 word (or one computed by an expression, which may be one).
fn has_motion_word(line: &Line) -> bool {
    line.words.iter().any(|w| {
        w.letter == b'G'
            && match w.value {
                crate::lexer::Operand::Number(v) => [0.0, 1.0, 2.0, 3.0].contains(&v),
                crate::lexer::Operand::Expr(_) => true,
            }
    })
}

fn motion_word(m: &Move, dialect: Dialect) -> String {
    let _ = dialect;
    match m.kind {
        MoveKind::Rapid => "G0".into(),
        MoveKind::Feed => "G1".into(),
        MoveKind::Arc { clockwise: true, .. } => "G2".into(),
        MoveKind::Arc { clockwise: false, .. } => "G3".into(),
    }
}

/// The comment lines at the top of a corrected program that say what was expanded (at most 20).
pub fn notes(expanded: &[String], dialect: Dialect) -> Vec<String> {
    if expanded.is_empty() {
        return Vec::new();
    }
    let clean = |s: &str| {
        let s = s.replace(['(', ')'], "");
        match dialect {
            Dialect::Fanuc => s.to_uppercase().replace(['<', '>', '#'], " "),
            Dialect::LinuxCnc => s,
        }
    };
    let mut out = vec![clean("(trueaxis: corrected program; expanded into plain moves because the correction differs where they run:)")];
    out[0] =
        format!("({})", clean("trueaxis: corrected program; expanded into plain moves because the correction differs where they run:"));
    for e in expanded.iter().take(20) {
        out.push(format!("({})", clean(&format!("trueaxis: - {e}"))));
    }
    if expanded.len() > 20 {
        out.push(format!("({})", clean(&format!("trueaxis: - and {} more", expanded.len() - 20))));
    }
    out
}
