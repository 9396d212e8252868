//! A canned cycle written as a cycle again. A cycle block carries one hole position and one level
//! per word, so it is corrected at two points (program units, absolute, G90):
//!
//! - the bottom `P_b = (x, y, z)`: the hole position and `Z` are those of the corrected bottom,
//!   `x' y' z' = P_b + c(P_b)`, exact there;
//! - the R level: `R' = R + c_z(x, y, R)`, exact along the cycle axis at R.
//!
//! The controller then plunges straight from `(x', y', R')` to `(x', y', z')`, whereas the
//! correction at R asks for `(x, y) + c_xy(x, y, R)`: the plunge leans by `|c_xy(R) - c_xy(P_b)|`
//! across the hole (reported per hole as `lean`), and the moves at the clearance levels stand off
//! their corrected points by what the kept hole position and levels leave (`clearance`, the
//! largest over the hole's other points: peck depths keep their distance from R, the initial level
//! is the one the program stood at). Tapping follows the spindle and is always written so; a
//! drilling or boring cycle whose corrected levels would change its moves (a peck more or less,
//! a level crossing R), or whose hole needs a rotary axis corrected otherwise than the controller
//! holds it (a cycle moves none), is expanded into plain moves instead.

use super::Writer;
use crate::cycles::pecks;
use crate::modal::{Frame, Vec9};
use crate::path::Pieces;
use crate::tools::AXIS_LETTERS;
use crate::trace::{Axes, CycleHole, Step};
use std::ops::Range;

/// What a hole kept as a cycle leaves, for the report.
#[derive(Clone, Debug, PartialEq)]
pub struct HoleReport {
    /// Line of the main file (1-based) and the cycle's G code (x 10).
    pub line: u32,
    pub code: u16,
    /// The axis it drills along: 0 X (G19), 1 Y (G18), 2 Z (G17).
    pub axis: usize,
    /// The moves of the hole in the trace, and those that end at R and at the bottom.
    pub moves: Range<u32>,
    pub r_move: u32,
    pub bottom_move: u32,
    /// How far the written R point stands across the hole from its corrected point (um): the
    /// correction's change between R and the bottom.
    pub lean_um: f64,
    /// The largest distance of the hole's other written points (clearance levels, pecks, R) from
    /// their corrected points (um).
    pub clearance_um: f64,
}

/// The corrected hole: position and levels as the controller will take them (program units).
struct Levels {
    frame: Frame,
    /// Corrected (unrounded) hole position in the plane, bottom and R.
    exact: [f64; 4],
    /// Where the controller is before the block (program point).
    before: Vec9,
    /// The original level before the block.
    before_original: f64,
    /// Corrected points of the hole's moves (machine).
    targets: Vec<Axes>,
}

impl Writer<'_> {
    /// The corrected hole position and levels of a kept cycle.
    fn levels(&self, hole: &CycleHole, step: &Step, pieces: &[Pieces]) -> Levels {
        let moves = self.trace.step_moves(step);
        let [a, b, c] = hole.plane.axes();
        let (rm, bm) = (&moves[hole.r_move as usize], &moves[hole.bottom_move as usize]);
        let frame = self.frame(bm);
        let targets: Vec<Axes> = moves.iter().zip(pieces).map(|(m, p)| self.targets(m, p).last().expect("a piece").0).collect();
        let bottom = self.program_of(&frame, &targets[hole.bottom_move as usize], &bm.program_end);
        let r = self.program_of(&frame, &targets[hole.r_move as usize], &rm.program_end);
        // the level the controller stands at, counted as it counts it (a Fanuc after `G43` alone)
        let first = self.frame(&moves[0]).held();
        let before = self.program_of(&first, &self.written, &moves[0].program_end);
        let before_original = self.program_of(&first, &moves[0].start, &moves[0].program_end)[c];
        Levels { frame, exact: [bottom[a], bottom[b], bottom[c], r[c]], before, before_original, targets }
    }

    /// The line of a cycle block kept as a cycle, its words corrected in place; `None` when it
    /// must be expanded instead (a drilling or boring cycle whose corrected levels change its moves,
    /// or one that continues a cycle the corrected program has expanded).
    pub(super) fn kept_cycle(&mut self, hole: &CycleHole, step: &Step, pieces: &[Pieces]) -> Option<Vec<String>> {
        let file = &self.program.files[step.file as usize];
        let k = step.line as usize;
        let text = file.line_text(k).to_string();
        let Ok(line) = &file.lines[k] else { unreachable!("an executed line was read") };
        let names_cycle = line
            .words
            .iter()
            .any(|w| w.letter == b'G' && matches!(w.value, crate::lexer::Operand::Number(v) if (v * 10.0).round() as u16 == hole.code));
        if !self.cycle_valid && !names_cycle {
            return hole.tapping().then(|| self.cycle_block(hole, step, pieces));
        }
        let levels = self.levels(hole, step, pieces);
        // a cycle moves no rotary axis: their corrections at the hole must be the ones held
        let half_deg = 0.5 * 10f64.powi(-(self.decimals as i32));
        let rotary_held = (0..self.machine.axis_count())
            .filter(|&i| self.machine.axes()[i].rotary)
            .all(|i| levels.targets.iter().all(|t| (t[i] - self.written[i]).abs() < half_deg));
        let [a, b, c] = hole.plane.axes();
        let resolved = self.trace.words_of(&step.motion_words);
        let value_of = |l: u8| resolved.iter().find(|(x, _)| *x == l).map(|(_, v)| *v);
        let modal = if self.cycle_valid { self.cycle_words } else { None };
        let current = [Some(levels.before[a]), Some(levels.before[b]), modal.map(|m| m.1), modal.map(|m| m.0)];
        let letters = [AXIS_LETTERS[a], AXIS_LETTERS[b], AXIS_LETTERS[c], b'R'];
        let axes = [a, b, c, c];
        let frame = levels.frame;
        // per word: the value the controller takes, and the edit or the added word that gives it
        let mut taken = [0.0; 4];
        let mut edits: Vec<(Range<usize>, String)> = Vec::new();
        let mut appended: Vec<String> = Vec::new();
        for d in 0..4 {
            let (v, half) = (levels.exact[d], self.half(&frame, axes[d]));
            let written = self.axis_text(&frame, axes[d], v);
            let rounded = written.parse::<f64>().unwrap_or(v);
            taken[d] = match (line.word(letters[d]), value_of(letters[d]), current[d]) {
                (Some(w), Some(old), _) if (v - old).abs() >= half => {
                    edits.push((w.span.clone(), written));
                    rounded
                }
                (Some(_), Some(old), _) => old,
                (None, _, Some(cur)) if (v - cur).abs() < half => cur,
                _ => {
                    appended.push(format!("{}{written}", letters[d] as char));
                    rounded
                }
            };
        }
        let [ha, hb, z, r] = taken;
        let initial = self.initial_level(hole, &levels);
        // where the original positions and retracts at R (it stands at R, G99 or an initial level
        // at R), the corrected levels may add or drop a rapid of the size of the correction's
        // change along the cycle axis; otherwise a move more or less (or a peck) would change the
        // cycle's path
        let at_r = (levels.before_original - hole.r).abs() < 1e-9 && (hole.clear - hole.r).abs() < 1e-9;
        let moves_kept = at_r
            || positioning(levels.before_original, hole.initial, hole.r, hole.retract_to_r)
                == positioning(levels.before[c], initial, r, hole.retract_to_r);
        let peck = self.peck_word(hole, line, &frame, r, z, &mut edits, &mut appended);
        if !(hole.tapping() || moves_kept && rotary_held && peck.is_some()) {
            return None;
        }
        let clear = if hole.retract_to_r { r } else { initial.max(r) };
        self.report_hole(hole, step, &levels, [ha, hb, z, r, clear, peck.unwrap_or(hole.peck)]);
        self.cycle_ends(hole, &levels, [ha, hb, r, z, clear], initial, peck);
        let new = super::edited_line(&text, line, &appended, edits);
        if new != text {
            self.changed_lines += 1;
        }
        Some(vec![new])
    }

    /// A tapping block inside an expanded part: written whole as a cycle (G90, its retraction,
    /// hole position, levels and dwell), its modal words before it.
    pub(super) fn cycle_block(&mut self, hole: &CycleHole, step: &Step, pieces: &[Pieces]) -> Vec<String> {
        let levels = self.levels(hole, step, pieces);
        let [a, b, c] = hole.plane.axes();
        let frame = levels.frame;
        let axes = [a, b, c, c];
        let mut words = vec![
            "G90".to_string(),
            if hole.retract_to_r { "G99" } else { "G98" }.to_string(),
            format!("G{}", crate::dialects::gcode_text(hole.code)),
        ];
        let mut taken = [0.0; 4];
        for (d, letter) in [AXIS_LETTERS[a], AXIS_LETTERS[b], AXIS_LETTERS[c], b'R'].into_iter().enumerate() {
            let written = self.axis_text(&frame, axes[d], levels.exact[d]);
            taken[d] = written.parse::<f64>().unwrap_or(levels.exact[d]);
            words.push(format!("{}{written}", letter as char));
        }
        if hole.dwell > 0.0 {
            words.push(format!("P{}", super::fine(hole.dwell)));
        }
        let [ha, hb, z, r] = taken;
        let initial = self.initial_level(hole, &levels);
        let clear = if hole.retract_to_r { r } else { initial.max(r) };
        self.report_hole(hole, step, &levels, [ha, hb, z, r, clear, hole.peck]);
        self.cycle_ends(hole, &levels, [ha, hb, r, z, clear], initial, None);
        let setup: Vec<String> = self.trace.words_of(&step.setup).iter().map(|&(l, v)| self.word_text(l, v, &frame)).collect();
        let mut out = Vec::new();
        if !setup.is_empty() {
            out.push(setup.join(" "));
        }
        out.push(words.join(" "));
        out
    }

    /// The initial level of the run of cycles in the corrected program (program units): where it
    /// stood before the first cycle the controller runs of it (an expanded cycle before does not
    /// count).
    fn initial_level(&self, hole: &CycleHole, levels: &Levels) -> f64 {
        let [_, _, c] = hole.plane.axes();
        match self.cycle_initial {
            Some(i) if !hole.first && self.cycle_valid => i,
            _ => levels.before[c],
        }
    }

    /// After a kept cycle: the controller at the hole (`taken`: hole position, R, bottom and the
    /// clearance level), remembering R, the bottom, the initial level and the peck depth.
    fn cycle_ends(&mut self, hole: &CycleHole, levels: &Levels, taken: [f64; 5], initial: f64, peck: Option<f64>) {
        let [a, b, c] = hole.plane.axes();
        let [ha, hb, r, z, clear] = taken;
        let mut end = levels.before;
        (end[a], end[b], end[c]) = (ha, hb, clear);
        self.written = self.machine_of(&levels.frame, &end);
        self.cycle_words = Some((r, z));
        self.cycle_initial = Some(initial);
        self.cycle_valid = true;
        if let Some(q) = peck {
            self.cycle_q = Some((hole.peck, q));
        }
    }

    /// The peck depth of a G73/G83 kept as a cycle: the one the controller holds, or one scaled with
    /// the corrected depth `r - z` (written in place or added) so that it makes as many pecks as
    /// the original; `Some(Q)` the peck depth the controller runs with (any for other cycles),
    /// `None` when no written Q does.
    #[allow(clippy::too_many_arguments)]
    fn peck_word(
        &self,
        hole: &CycleHole,
        line: &crate::lexer::Line,
        frame: &Frame,
        r: f64,
        z: f64,
        edits: &mut Vec<(Range<usize>, String)>,
        appended: &mut Vec<String>,
    ) -> Option<f64> {
        if hole.peck == 0.0 {
            return Some(0.0);
        }
        let [_, _, c] = hole.plane.axes();
        let word = line.word(b'Q');
        let held = match (word, self.cycle_q) {
            (Some(_), _) => Some(hole.peck),
            (None, Some((original, written))) if self.cycle_valid && original == hole.peck => Some(written),
            (None, None) if self.cycle_valid => Some(hole.peck),
            _ => None,
        };
        let wanted = pecks(hole.r, hole.bottom, hole.peck);
        if let Some(q) = held.filter(|&q| pecks(r, z, q) == wanted) {
            return Some(q);
        }
        let unit = 2.0 * self.half(frame, c);
        let scaled = hole.peck * (r - z) / (hole.r - hole.bottom);
        let q = [0.0, unit, -unit, 2.0 * unit]
            .iter()
            .map(|d| ((scaled / unit).round() + d / unit) * unit)
            .find(|&q| q > 0.0 && pecks(r, z, q) == wanted)?;
        let text = self.axis_text(frame, c, q);
        match word {
            Some(w) => edits.push((w.span.clone(), text.clone())),
            None => appended.push(format!("Q{text}")),
        }
        Some(text.parse().unwrap_or(q))
    }

    /// The hole's lean and clearance: each written point of the hole (the kept position and
    /// `taken` levels: bottom, R, clearance) against its corrected point.
    fn report_hole(&mut self, hole: &CycleHole, step: &Step, levels: &Levels, taken: [f64; 6]) {
        let [ha, hb, z, r, clear, q] = taken;
        let [a, b, c] = hole.plane.axes();
        let level = |l: f64| {
            if (l - hole.bottom).abs() < 1e-9 {
                z
            } else if (l - hole.r).abs() < 1e-9 {
                r
            } else if (l - hole.clear).abs() < 1e-9 {
                clear
            } else if l < hole.r && l > hole.bottom {
                // pecks keep their distance from R, in peck depths
                r + (l - hole.r) * q / hole.peck.max(f64::MIN_POSITIVE)
            } else {
                levels.before[c]
            }
        };
        let moves = self.trace.step_moves(step);
        let hole_at = moves[hole.bottom_move as usize].program_end;
        let mut lean = 0.0;
        let mut clearance: f64 = 0.0;
        for (i, m) in moves.iter().enumerate() {
            let mut p = self.program_of(&levels.frame, &levels.targets[i], &m.program_end);
            // a rise to R before the first hole is where the program stood
            let at_hole = (m.program_end[a] - hole_at[a]).abs() < 1e-9 && (m.program_end[b] - hole_at[b]).abs() < 1e-9;
            let (pa, pb) = if at_hole { (ha, hb) } else { (levels.before[a], levels.before[b]) };
            (p[a], p[b], p[c]) = (pa, pb, level(m.program_end[c]));
            let off = self.stand_off_um(&levels.frame, &p, &levels.targets[i]);
            if i as u32 == hole.r_move {
                lean = off;
            }
            if i as u32 != hole.bottom_move {
                clearance = clearance.max(off);
            }
        }
        let first = step.moves.start + self.move_offset;
        self.holes.push(HoleReport {
            line: step.line + 1 + self.line_offset,
            code: hole.code,
            axis: c,
            moves: first..step.moves.end + self.move_offset,
            r_move: first + hole.r_move,
            bottom_move: first + hole.bottom_move,
            lean_um: lean,
            clearance_um: clearance,
        });
    }
}

/// The positioning moves of a cycle from level `current` with the initial level `initial`: whether
/// it first rises to R, whether it comes down from above R at the hole, whether it retracts above R.
fn positioning(current: f64, initial: f64, r: f64, retract_to_r: bool) -> [bool; 3] {
    let rise = initial < r;
    let (current, initial) = if rise { (r, r) } else { (current, initial) };
    let clear = if retract_to_r { r } else { initial };
    [rise, current > r, clear > r]
}
