//! Which parts of the main program keep their text (numbers changed in place) and which are
//! expanded into plain moves, from the trace of a run.
//!
//! A line executed once keeps its text; one whose moves its words cannot express (a canned cycle,
//! a multi-turn arc) is replaced by its moves where it stands. A control structure (`if`, a loop)
//! keeps its text when none of its blocks ran more than once; otherwise it is expanded as a whole.
//! A subroutine call keeps its text when the subroutine is in the program, runs only from there and
//! only once, and its body can be kept; otherwise the call is expanded (the subroutine's definition
//! stays, unused or used by calls kept as they were). The whole program is expanded when it jumps backwards (Fanuc
//! `GOTO`) or when a block kept as text reads a value that differs in the corrected program (the
//! current position, a return value, the line number).

use crate::dialect::Dialect;
use crate::lexer::{Label, OKind, Statement};
use crate::program::{Link, Program};
use crate::trace::{flags, Trace};
use std::collections::HashMap;
use std::ops::Range;

/// What the corrected program has at a line of the main file.
#[derive(Clone, Debug, PartialEq)]
pub enum LineOut {
    /// The line as it was (not executed, or executed without anything to change).
    Original,
    /// The line rewritten from its step.
    InPlace(u32),
    /// The step's block replaced by its moves here.
    Single(u32),
    /// The first line of an expanded region.
    Region(usize),
    /// A line inside an expanded region.
    Hidden,
}

/// An expanded part of the program.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// Lines of the main file.
    pub lines: Range<usize>,
    /// Steps of the trace.
    pub steps: Range<usize>,
    /// Local-parameter level of the region (parameters written at it, or global ones, are restored
    /// after it).
    pub level: u16,
    /// Why it is expanded (for the note at the top of the corrected program).
    pub reason: String,
}

/// The plan of the corrected program.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub lines: Vec<LineOut>,
    pub regions: Vec<Region>,
    /// Region of each step, if it is in one.
    pub region_of: Vec<Option<u32>>,
    /// Why the whole program is expanded, if it is.
    pub flattened: Option<String>,
}

struct Planner<'a> {
    program: &'a Program,
    trace: &'a Trace,
    /// Non-control executions per main-file line, and the last step at each.
    count: Vec<u32>,
    step_at: Vec<Option<u32>>,
    /// Calls (executed) per subroutine key of the main file, and their lines.
    calls: HashMap<SubKey, Vec<u32>>,
    lines: Vec<LineOut>,
    regions: Vec<(usize, Range<usize>, u16, String)>,
}

/// A subroutine of the main file: LinuxCNC label, or Fanuc program number.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum SubKey {
    Label(Label),
    Program(u32),
}

/// Plans the corrected program.
pub fn plan(program: &Program, trace: &Trace) -> Plan {
    let main = &program.files[0];
    let n = main.lines.len();
    let mut p = Planner {
        program,
        trace,
        count: vec![0; n],
        step_at: vec![None; n],
        calls: HashMap::new(),
        lines: vec![LineOut::Original; n],
        regions: Vec::new(),
    };
    for (i, s) in trace.steps.iter().enumerate() {
        if s.file == 0 {
            let k = s.line as usize;
            if !s.has(flags::CONTROL) || s.has(flags::CALL) {
                p.count[k] += 1;
            }
            p.step_at[k] = Some(i as u32);
            if s.has(flags::CALL) {
                if let Some(key) = p.callee(i) {
                    p.calls.entry(key).or_default().push(s.line);
                }
            }
        }
    }
    let jumps_back = trace.steps.iter().any(|s| s.has(flags::JUMP_BACK));
    let mut flattened = jumps_back.then(|| "the program jumps backwards (GOTO)".to_string());
    if flattened.is_none() {
        let body = p.main_body();
        p.decide(body, 0);
        flattened = p.unsafe_in_place();
    }
    if let Some(reason) = &flattened {
        p.lines = vec![LineOut::Original; n];
        let body = p.main_body();
        for k in body.clone() {
            p.lines[k] = LineOut::Hidden;
        }
        p.lines[body.start] = LineOut::Region(0);
        p.regions = vec![(0, body, 0, format!("the whole program: {reason}"))];
    }
    p.finish(flattened)
}

impl Planner<'_> {
    /// The body of the main program (after a Fanuc program number line, which stays).
    fn main_body(&self) -> Range<usize> {
        let main = &self.program.files[0];
        let mut body = main.body.clone();
        while body.start < body.end
            && matches!(&main.lines[body.start], Ok(l) if l.is_empty() && l.comments.is_empty() || l.program_number.is_some())
        {
            body.start += 1;
        }
        body
    }

    /// The subroutine of the main file a call step calls, if it is one.
    fn callee(&self, step: usize) -> Option<SubKey> {
        let next = self.trace.steps.get(step + 1)?;
        let s = &self.trace.steps[step];
        if next.depth <= s.depth || next.file != 0 {
            return None;
        }
        let main = &self.program.files[0];
        // the `O` program holding a line (Fanuc family; Mach3/Mach4 subprograms)
        let program_of = |line: u32| main.programs.iter().filter(|(_, &k)| k <= line as usize).max_by_key(|(_, &k)| k).map(|(&o, _)| o);
        let label = match self.program.dialect {
            Dialect::LinuxCnc => main.subs.iter().find(|(_, &(start, end))| (start..=end).contains(&(next.line as usize))),
            Dialect::Fanuc => None,
        };
        match (label, program_of(next.line)) {
            (Some((l, _)), _) => Some(SubKey::Label(l.clone())),
            // a Haas `M97` local call stays in the caller's program: its body has no `O` of its own
            (None, Some(o)) if program_of(s.line) != Some(o) => Some(SubKey::Program(o)),
            _ => None,
        }
    }

    /// The line range of a subroutine of the main file (from its `sub` / `O` line to its end).
    fn sub_range(&self, key: &SubKey) -> Option<Range<usize>> {
        let main = &self.program.files[0];
        match key {
            SubKey::Label(l) => main.subs.get(l).map(|&(s, e)| s..e + 1),
            SubKey::Program(o) => {
                let &start = main.programs.get(o)?;
                let end = main.programs.values().copied().filter(|&k| k > start).min().unwrap_or(main.body.end);
                Some(start..end)
            }
        }
    }

    fn statement(&self, k: usize) -> Option<&Statement> {
        self.program.files[0].lines[k].as_ref().ok().and_then(|l| l.statement.as_ref())
    }

    /// Whether the lines `range` (and the subroutines their calls reach) ran at most once each.
    fn runs_once(&self, range: Range<usize>, seen: &mut Vec<SubKey>) -> bool {
        for k in range {
            if self.count[k] > 1 {
                return false;
            }
            if let Some(step) = self.step_at[k] {
                if self.trace.steps[step as usize].has(flags::CALL) {
                    match self.callee(step as usize) {
                        Some(key) if !seen.contains(&key) && self.calls.get(&key).map_or(0, Vec::len) == 1 => {
                            seen.push(key.clone());
                            let Some(r) = self.sub_range(&key) else { return false };
                            if !self.runs_once(r.start + 1..r.end, seen) {
                                return false;
                            }
                        }
                        _ => return false,
                    }
                }
            }
        }
        true
    }

    /// Decides the lines of `range` (main file) run at local level `level`.
    fn decide(&mut self, range: Range<usize>, level: u16) {
        let mut k = range.start;
        while k < range.end {
            let link = self.program.files[0].links[k];
            match (link, self.statement(k)) {
                (Link::Sub { end }, _) => {
                    k = end + 1;
                    continue;
                }
                (Link::Branch { .. }, Some(Statement::O(_, OKind::ElseIf(_) | OKind::Else)))
                | (Link::Branch { .. }, Some(Statement::Siemens(crate::siemens::flow::Control::Else)))
                | (Link::LoopEnd { .. } | Link::SubEnd { .. }, _) => {
                    k += 1;
                    continue;
                }
                (Link::Branch { end, .. } | Link::LoopStart { end }, _)
                    if self.count[k..=end].iter().any(|&c| c > 0) || self.step_at[k].is_some() =>
                {
                    let mut seen = Vec::new();
                    if self.runs_once(k..end + 1, &mut seen) {
                        self.decide(k + 1..end, level);
                    } else {
                        let what = match self.statement(k) {
                            Some(Statement::O(label, OKind::If(_))) => format!("{label} if"),
                            Some(Statement::O(label, kind)) => format!("{label} {}", loop_name(kind)),
                            Some(Statement::Siemens(c)) => c.name(),
                            _ => "WHILE/DO loop".into(),
                        };
                        self.region(k..end + 1, level, format!("lines {}-{}, {what}: its blocks run more than once", k + 1, end + 1));
                    }
                    k = end + 1;
                    continue;
                }
                (Link::Branch { end, .. } | Link::LoopStart { end }, _) => {
                    k = end + 1;
                    continue;
                }
                _ => {}
            }
            if let Some(step) = self.step_at[k] {
                let s = &self.trace.steps[step as usize];
                if s.has(flags::CALL) {
                    let key = self.callee(step as usize);
                    let mut seen = Vec::new();
                    let keep = self.count[k] == 1
                        && key.as_ref().is_some_and(|key| self.calls.get(key).map_or(0, Vec::len) == 1)
                        && self.runs_once(k..k + 1, &mut seen);
                    if keep {
                        let key = key.expect("checked");
                        if !s.has(flags::CONTROL) {
                            self.lines[k] = LineOut::InPlace(step);
                        }
                        let r = self.sub_range(&key).expect("a sub of the main file");
                        let inner = level + u16::from(self.new_locals(step as usize));
                        self.decide(r.start + 1..r.end, inner);
                    } else {
                        let what = match (key, self.statement(k)) {
                            (Some(key), _) => {
                                let runs = self.runs(&key);
                                match key {
                                    SubKey::Label(l) => format!("{l} call (the subroutine runs {runs} times)"),
                                    SubKey::Program(o) => format!("M98 P{o} (the subprogram runs {runs} times)"),
                                }
                            }
                            (None, Some(Statement::O(label, _))) => format!("{label} call (a subroutine file)"),
                            (None, _) => match self.program.files[0].lines[k].as_ref().ok().and_then(|l| l.siemens_call.as_deref()) {
                                Some(crate::siemens::Call::Sub { name, passes }) => {
                                    format!("{name}, a subprogram file run {passes} time{}", if *passes > 1 { "s" } else { "" })
                                }
                                _ => "a subprogram call".into(),
                            },
                        };
                        self.region(k..k + 1, level, format!("line {}, {what}", k + 1));
                    }
                } else if !s.has(flags::CONTROL) {
                    self.lines[k] = if s.has(flags::EXPAND) { LineOut::Single(step) } else { LineOut::InPlace(step) };
                }
            }
            k += 1;
        }
    }

    /// How many times the body of a subroutine of the main file ran.
    fn runs(&self, key: &SubKey) -> u32 {
        self.sub_range(key).map_or(0, |r| self.count[r.start + 1..r.end].iter().copied().max().unwrap_or(0))
    }

    /// Whether the call at `step` opens a new level of local parameters.
    fn new_locals(&self, step: usize) -> bool {
        let s = &self.trace.steps[step];
        self.trace.steps.get(step + 1).is_some_and(|n| n.level > s.level)
    }

    fn region(&mut self, lines: Range<usize>, level: u16, reason: String) {
        for k in lines.clone() {
            self.lines[k] = LineOut::Hidden;
        }
        let index = self.regions.len();
        self.lines[lines.start] = LineOut::Region(index);
        self.regions.push((index, lines, level, reason));
    }

    /// Why the program must be expanded as a whole: a kept line reads a value the correction
    /// changes.
    fn unsafe_in_place(&self) -> Option<String> {
        for s in &self.trace.steps {
            if s.file != 0 || !s.has(flags::READS_UNSAFE) {
                continue;
            }
            let k = s.line as usize;
            match self.lines[k] {
                LineOut::InPlace(_) => {
                    return Some(format!("line {} reads the current position, a return value or the line number", k + 1))
                }
                // a kept control line (a condition)
                LineOut::Original if s.has(flags::CONTROL) => {
                    return Some(format!("the condition of line {} reads the current position or a return value", k + 1))
                }
                _ => {}
            }
        }
        None
    }

    fn finish(mut self, flattened: Option<String>) -> Plan {
        let steps = &self.trace.steps;
        let regions_found = std::mem::take(&mut self.regions);
        // the steps of each region: from the first step at its lines to the last one at the same
        // depth, and the deeper steps after it (one pass over the trace)
        let mut of_line: Vec<Option<usize>> = vec![None; self.lines.len()];
        for (r, (_, lines, _, _)) in regions_found.iter().enumerate() {
            for slot in &mut of_line[lines.clone()] {
                *slot = Some(r);
            }
        }
        let mut bounds: Vec<Option<(usize, usize, u16)>> = vec![None; regions_found.len()];
        for (i, s) in steps.iter().enumerate() {
            if s.file != 0 {
                continue;
            }
            if let Some(r) = of_line[s.line as usize] {
                match &mut bounds[r] {
                    None => bounds[r] = Some((i, i, s.depth)),
                    Some((_, last, depth)) if *depth == s.depth => *last = i,
                    _ => {}
                }
            }
        }
        let mut regions = Vec::new();
        let mut region_of = vec![None; steps.len()];
        for ((index, lines, level, reason), b) in regions_found.into_iter().zip(bounds) {
            let steps_range = match (flattened.is_some(), b) {
                (true, _) => 0..steps.len(),
                (false, None) => 0..0,
                (false, Some((first, last, depth))) => {
                    let mut end = last + 1;
                    while end < steps.len() && steps[end].depth > depth {
                        end += 1;
                    }
                    first..end
                }
            };
            for r in region_of[steps_range.clone()].iter_mut() {
                *r = Some(index as u32);
            }
            regions.push(Region { lines, steps: steps_range, level, reason });
        }
        Plan { lines: self.lines, regions, region_of, flattened }
    }
}

fn loop_name(kind: &OKind) -> &'static str {
    match kind {
        OKind::While(_) => "while",
        OKind::Do => "do",
        OKind::Repeat(_) => "repeat",
        _ => "",
    }
}
