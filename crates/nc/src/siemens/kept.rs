//! A SINUMERIK drilling cycle written as a cycle again, as the other dialects' canned cycles are
//! (`crate::write` "cycle"): each hole is corrected at two points (program units, G17, along Z):
//!
//! - the bottom `P_b = (x, y, DP)`: the hole position is that of the corrected bottom,
//!   `x' y' = (P_b + c(P_b))_xy`, and the depth `DP' = (P_b + c(P_b))_z` (or `DPR' = RFP' - DP'`);
//! - the start of the feed, RFP + SDIS: `RFP' = RFP + SDIS + c_z(x, y, RFP + SDIS) - SDIS`; the
//!   retraction plane `RTP' = RTP + c_z(x, y, RTP)`.
//!
//! CYCLE83 keeps its infeed `RFP - FDEP` (FDEP moves with RFP; FDPR stays) when the corrected
//! levels give as many infeeds, else the infeed is scaled with the corrected depth `RFP' - DP'`
//! (on the written increment, the nearest that gives as many): its drilling depths keep their
//! distance from RFP, as G83's pecks keep theirs from R. The hole position is the `X Y` of the block that
//! positions it under `MCALL` (changed in place or added), or, for a direct call at the current
//! position, a block `X.. Y..` of its own before the call (in the modal G0 or G1 it stands in).
//! The levels are parameters of one call: a direct call gets its parameters changed in place;
//! under `MCALL`, where a hole needs other parameters than the call the corrected program has in
//! force, `MCALL CYCLE8x(...)` is written again before the hole block with them (Programming
//! Manual Fundamentals, "Modal subprogram call (MCALL)": a new modal call replaces the one in
//! force). With no correction at the written resolution nothing changes.
//!
//! What is left is reported per hole as for the other dialects: the plunge from RFP + SDIS leans
//! across the hole by the correction's change between there and the bottom (`lean`), and the
//! other points of the hole (the positioning at the level before, the infeeds and retractions,
//! RTP) stand off their corrected points by what the kept position and parameters leave
//! (`clearance`), each computed from the strokes the controller runs with the written values.
//! A hole whose rotary axes need another correction than the controller holds, whose block moves
//! another axis than X and Y, or whose infeeds cannot keep their number, is expanded into plain
//! moves instead, `MCALL` (off) written before them while a modal call is in force.

use super::cycles::{Drilling, Hole, Stroke, SIEMENS_CODE};
use crate::cycles::pecks;
use crate::lexer::Line;
use crate::modal::{Frame, Vec9};
use crate::path::Pieces;
use crate::trace::{flags, Axes, CycleHole, Step};
use crate::write::{edited_line, HoleReport, Writer};
use std::ops::Range;

/// The modal cycle call the corrected program has in force, as written.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Mcall {
    #[default]
    Off,
    /// `MCALL CYCLE<number>(...)` with these parameter texts.
    On(u16, Vec<String>),
    /// Not known: a part written as it was sets or ends one.
    Unknown,
}

/// Where the call in `text` starts (`MCALL` or `CYCLE`), where it ends (after `)`), and the byte
/// ranges of its parameters (blanks around them left out).
pub fn call_spans(text: &str) -> Option<(usize, usize, Vec<Range<usize>>)> {
    let code = &text[..text.find(';').unwrap_or(text.len())];
    let upper = code.to_ascii_uppercase();
    let name = upper.find("CYCLE8")?;
    let start = upper[..name].rfind("MCALL").unwrap_or(name);
    let open = name + upper[name..].find('(')?;
    let (mut depth, mut from, mut spans) = (0, open + 1, Vec::new());
    for (i, b) in code.bytes().enumerate().skip(open + 1) {
        match b {
            b'(' => depth += 1,
            b')' if depth > 0 => depth -= 1,
            b',' | b')' if depth == 0 => {
                let arg = &code[from..i];
                let lead = arg.len() - arg.trim_start().len();
                spans.push(from + lead..from + lead + arg.trim().len());
                if b == b')' {
                    return Some((start, i + 1, spans));
                }
                from = i + 1;
            }
            _ => {}
        }
    }
    None
}

/// The corrected hole: its exact points (program units) and the corrected targets of its moves.
struct Exact {
    frame: Frame,
    /// Hole position, bottom, start of the feed (RFP + SDIS) and RTP.
    position: [f64; 2],
    bottom: f64,
    start: f64,
    rtp: f64,
    /// Where the controller stands before the block (program point).
    before: Vec9,
    targets: Vec<Axes>,
}

impl Writer<'_> {
    /// Follows the `MCALL` lines written as they are (a line of a part expanded or left as it
    /// was: not known).
    pub(crate) fn siemens_track(&mut self, index: usize) {
        let step = &self.trace.steps[index];
        let Some(Ok(line)) = self.program.files[step.file as usize].lines.get(step.line as usize) else { return };
        let in_part = self.plan.region_of[index].is_some() || step.file != 0;
        self.siemens_mcall = match line.siemens_call.as_deref() {
            Some(super::Call::ModalOff | super::Call::Cycle { modal: true, .. }) if in_part => Mcall::Unknown,
            Some(super::Call::ModalOff) => Mcall::Off,
            Some(super::Call::Cycle { number, modal: true, .. }) if !step.has(flags::EXPAND) => {
                let text = self.program.files[step.file as usize].line_text(step.line as usize);
                let spans = call_spans(text).map_or(Vec::new(), |(_, _, s)| s);
                Mcall::On(*number, spans.into_iter().map(|r| text[r].to_string()).collect())
            }
            _ => return,
        };
    }

    /// `MCALL` to write before the expanded moves of `step` while a modal call is in force.
    pub(crate) fn siemens_call_off(&mut self, step: &Step) -> Option<String> {
        if step.moves.is_empty() || self.siemens_mcall == Mcall::Off {
            return None;
        }
        self.siemens_mcall = Mcall::Off;
        Some("MCALL".into())
    }

    /// A block replaced by its moves, after `MCALL` while a modal call is in force.
    pub(crate) fn siemens_single(&mut self, index: usize, pieces: &[Pieces], k: usize) {
        let step = &self.trace.steps[index];
        let off = self.siemens_call_off(step);
        self.single(step, pieces, k);
        if let (Some(off), Some(lines)) = (off, self.out[k].as_mut()) {
            lines.insert(0, off);
            self.inserted_lines += 1;
        }
    }

    /// A SINUMERIK hole of a line kept in place: written as a cycle, or expanded.
    pub(crate) fn siemens_hole(&mut self, index: usize, pieces: &[Pieces], k: usize) {
        let trace = self.trace;
        let step = &trace.steps[index];
        let hole = trace.hole_of(index).expect("a hole");
        let at = trace.siemens_holes.binary_search_by_key(&(index as u32), |h| h.step).expect("a SINUMERIK hole");
        match self.kept_siemens(hole, &trace.siemens_holes[at], step, pieces, k) {
            Some(lines) => self.out[k] = Some(lines),
            None => self.siemens_single(index, pieces, k),
        }
    }

    /// The corrected points of the hole.
    fn exact(&self, hole: &CycleHole, step: &Step, pieces: &[Pieces]) -> Exact {
        let moves = self.trace.step_moves(step);
        let frame = self.frame(&moves[hole.bottom_move as usize]);
        let targets: Vec<Axes> = moves.iter().zip(pieces).map(|(m, p)| self.targets(m, p).last().expect("a piece").0).collect();
        let at = |i: usize| self.program_of(&frame, &targets[i], &moves[i].program_end);
        let bottom = at(hole.bottom_move as usize);
        Exact {
            frame,
            position: [bottom[0], bottom[1]],
            bottom: bottom[2],
            start: at(hole.r_move as usize)[2],
            rtp: at(moves.len() - 1)[2],
            before: self.program_of(&frame, &self.written, &moves[0].program_end),
            targets,
        }
    }

    /// The lines of a hole kept as a cycle, or `None` when it must be expanded.
    fn kept_siemens(&mut self, hole: &CycleHole, sh: &Hole, step: &Step, pieces: &[Pieces], k: usize) -> Option<Vec<String>> {
        let e = self.exact(hole, step, pieces);
        let half_deg = 0.5 * 10f64.powi(-(self.decimals as i32));
        let rotary_held = (0..self.machine.axis_count())
            .filter(|&i| self.machine.axes()[i].rotary)
            .all(|i| e.targets.iter().all(|t| (t[i] - self.written[i]).abs() < half_deg));
        if !rotary_held {
            return None;
        }
        let file = &self.program.files[step.file as usize];
        let text = file.line_text(k).to_string();
        let Ok(line) = &file.lines[k] else { unreachable!("an executed line was read") };
        let (position, block, nudge) = if sh.modal {
            let (position, block) = self.hole_words(step, line, &text, &e)?;
            (position, Some(block), None)
        } else {
            let (position, nudge) = self.hole_nudge(&e, sh.linear_motion)?;
            (position, None, nudge)
        };
        let (d, edits) = self.corrected_parameters(&sh.drilling, &e)?;
        // the call with its parameters changed: the modal call as written, or the direct call's line
        let (call, wanted) = with_parameters(if sh.modal { &sh.drilling.call } else { &text }, &edits)?;
        // nothing can fail from here on
        self.report_siemens(hole, sh, step, &e, position, &d)?;
        let mut out = Vec::new();
        let new = match block {
            Some(block) => {
                if self.siemens_mcall != Mcall::On(d.number, wanted.clone()) {
                    out.push(call);
                    self.siemens_mcall = Mcall::On(d.number, wanted);
                }
                block
            }
            None => {
                if nudge.is_some() && self.siemens_mcall != Mcall::Off {
                    // the modal call in force would drill at the block that positions the hole
                    out.push("MCALL".to_string());
                    self.siemens_mcall = Mcall::Off;
                }
                out.extend(nudge);
                call
            }
        };
        if new != text {
            self.changed_lines += 1;
        }
        self.inserted_lines += out.len();
        out.push(new);
        Some(out)
    }

    /// The hole block under `MCALL` with its X Y corrected (changed in place or added), and the
    /// hole position the controller takes; `None` when the block moves another axis.
    fn hole_words(&self, step: &Step, line: &Line, text: &str, e: &Exact) -> Option<([f64; 2], String)> {
        let resolved = self.trace.words_of(&step.motion_words);
        if resolved.iter().any(|(l, _)| !matches!(l, b'X' | b'Y')) {
            return None;
        }
        let mut edits = Vec::new();
        let mut appended = Vec::new();
        let mut taken = [0.0; 2];
        for (d, letter) in [b'X', b'Y'].into_iter().enumerate() {
            let (v, half) = (e.position[d], self.half(&e.frame, d));
            let written = self.axis_text(&e.frame, d, v);
            let rounded = written.parse::<f64>().unwrap_or(v);
            let old = resolved.iter().find(|(l, _)| *l == letter).map(|(_, v)| *v);
            taken[d] = match (line.word(letter), old) {
                (Some(w), Some(old)) if (v - old).abs() >= half => {
                    edits.push((w.span.clone(), written));
                    rounded
                }
                (Some(_), Some(old)) => old,
                _ if (v - e.before[d]).abs() < half => e.before[d],
                _ => {
                    appended.push(format!("{}{written}", letter as char));
                    rounded
                }
            };
        }
        Some((taken, edited_line(text, line, &appended, edits)))
    }

    /// For a direct call: the block `X.. Y..` that puts the controller at the corrected hole
    /// position (none when it stands there at the written resolution); `None` when the modal
    /// motion is not G0 or G1.
    fn hole_nudge(&self, e: &Exact, linear_motion: bool) -> Option<([f64; 2], Option<String>)> {
        let mut taken = [e.before[0], e.before[1]];
        let mut words = Vec::new();
        for (d, letter) in ['X', 'Y'].into_iter().enumerate() {
            if (e.position[d] - e.before[d]).abs() >= self.half(&e.frame, d) {
                let written = self.axis_text(&e.frame, d, e.position[d]);
                taken[d] = written.parse::<f64>().unwrap_or(e.position[d]);
                words.push(format!("{letter}{written}"));
            }
        }
        if words.is_empty() {
            return Some((taken, None));
        }
        linear_motion.then(|| (taken, Some(words.join(" "))))
    }

    /// The cycle's values the controller takes with the corrected parameters, and the parameters
    /// to write (index, text); `None` when the infeeds cannot keep their number.
    fn corrected_parameters(&self, d: &Drilling, e: &Exact) -> Option<(Drilling, Vec<(usize, String)>)> {
        let half = self.half(&e.frame, 2);
        let mut edits = Vec::new();
        let level = |index: usize, old: f64, exact: f64, edits: &mut Vec<(usize, String)>| {
            if (exact - old).abs() < half {
                return old;
            }
            let text = self.axis_text(&e.frame, 2, exact);
            let taken = text.parse().unwrap_or(exact);
            edits.push((index, text));
            taken
        };
        let mut c = d.clone();
        c.rtp = level(0, d.rtp, e.rtp, &mut edits);
        c.rfp = level(1, d.rfp, e.start - d.sdis, &mut edits);
        c.depth = if d.relative {
            c.rfp - level(4, d.rfp - d.depth, c.rfp - e.bottom, &mut edits)
        } else {
            level(3, d.depth, e.bottom, &mut edits)
        };
        if let (Some(p), Some(q)) = (d.pecking, c.pecking.as_mut()) {
            // the infeed kept (FDEP moved with RFP), or scaled with the depth when the number of
            // infeeds would change
            let unit = 2.0 * half;
            let scaled = p.infeed * (c.rfp - c.depth) / (d.rfp - d.depth);
            let infeed = [p.infeed]
                .into_iter()
                .chain([0.0, 1.0, -1.0, 2.0].iter().map(|s| ((scaled / unit).round() + s) * unit))
                .find(|&f| f > 0.0 && pecks(c.rfp, c.depth, f) == d.pecks())?;
            q.infeed = if p.relative {
                level(6, p.infeed, infeed, &mut edits)
            } else {
                c.rfp - level(5, d.rfp - p.infeed, c.rfp - infeed, &mut edits)
            };
        }
        edits.sort_by_key(|(i, _)| *i);
        Some((c, edits))
    }

    /// The hole's lean and clearance from the strokes the controller runs with the written values
    /// (`d`, the hole position `position`); the controller left at RTP.
    fn report_siemens(&mut self, hole: &CycleHole, sh: &Hole, step: &Step, e: &Exact, position: [f64; 2], d: &Drilling) -> Option<()> {
        let moves = self.trace.step_moves(step);
        let levels: Vec<f64> = d
            .strokes()
            .into_iter()
            .filter_map(|s| match s {
                Stroke::Rapid(l) | Stroke::Feed(l) => Some(l),
                Stroke::Dwell(_) => None,
            })
            .collect();
        if levels.len() + sh.first as usize != moves.len() {
            return None;
        }
        let (mut lean, mut clearance) = (0.0, 0.0f64);
        let mut end = e.before;
        for (i, m) in moves.iter().enumerate() {
            let mut p = m.program_end;
            (p[0], p[1]) = (position[0], position[1]);
            p[2] = if i < sh.first as usize { e.before[2] } else { levels[i - sh.first as usize] };
            let off = self.stand_off_um(&e.frame, &p, &e.targets[i]);
            if i as u32 == hole.r_move {
                lean = off;
            }
            if i as u32 != hole.bottom_move {
                clearance = clearance.max(off);
            }
            end = p;
        }
        self.written = self.machine_of(&e.frame, &end);
        let first = step.moves.start + self.move_offset;
        self.holes.push(HoleReport {
            line: step.line + 1 + self.line_offset,
            code: hole.code,
            axis: 2,
            moves: first..step.moves.end + self.move_offset,
            r_move: first + hole.r_move,
            bottom_move: first + hole.bottom_move,
            lean_um: lean,
            clearance_um: clearance,
        });
        Some(())
    }
}

/// `text` with the parameters of its cycle call replaced by `edits` (index, text), and the
/// parameters it then has; `None` when it has no such parameter.
fn with_parameters(text: &str, edits: &[(usize, String)]) -> Option<(String, Vec<String>)> {
    let (_, _, spans) = call_spans(text)?;
    let mut out = text.to_string();
    let mut wanted: Vec<String> = spans.iter().map(|r| text[r.clone()].to_string()).collect();
    for (i, value) in edits.iter().rev() {
        out.replace_range(spans.get(*i)?.clone(), value);
        wanted[*i] = value.clone();
    }
    Some((out, wanted))
}

/// The name of a kept cycle's code: `CYCLE81` for a SINUMERIK one, else `G81`, `G73`...
pub fn cycle_name(code: u16) -> String {
    match code.checked_sub(SIEMENS_CODE) {
        Some(n) => format!("CYCLE{}", n / 10),
        None => format!("G{}", crate::dialects::gcode_text(code)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_parameters_of_a_call_are_found_with_blanks_and_expressions() {
        let text = "N70 MCALL CYCLE81(15, 0, 2 , -12) ; holes (1, 2)";
        let (start, end, spans) = call_spans(text).unwrap();
        assert_eq!(&text[start..end], "MCALL CYCLE81(15, 0, 2 , -12)");
        let args: Vec<&str> = spans.iter().map(|r| &text[r.clone()]).collect();
        assert_eq!(args, ["15", "0", "2", "-12"]);
        let text = "CYCLE83(R1+2,0,(R2*2),-20,,-4,,0,,,1,0,,,,,)";
        let (start, _, spans) = call_spans(text).unwrap();
        let args: Vec<&str> = spans.iter().map(|r| &text[r.clone()]).collect();
        assert_eq!((start, args.len(), args[0], args[2], args[4]), (0, 17, "R1+2", "(R2*2)", ""));
        assert_eq!(call_spans("G0 X1 ; CYCLE81(1,2)"), None);
        assert_eq!((cycle_name(10830), cycle_name(830), cycle_name(731)), ("CYCLE83".into(), "G83".into(), "G73.1".into()));
    }
}
