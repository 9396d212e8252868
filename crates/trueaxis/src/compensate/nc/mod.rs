//! NC-program correction (seed 003 section 4, "editing NC programs"): parse an RS274/NGC program,
//! correct every programmed point by the pose correction of [`crate::compensate::Corrector`], split
//! moves along which the correction varies more than a tolerance, and write a program that differs
//! from the input only where it must (changed numbers in place, added words, added lines for the
//! pieces of split moves).
//!
//! Program coordinates map to machine axis positions through the work offsets G54-G59 (given by the
//! user; G53 blocks are machine coordinates): machine = program (mm, deg) + offset. The correction at
//! a point uses the directions of motion there (for bidirectional error models), the direction of an
//! axis that does not move being the one it last moved in.

pub mod interpret;
pub mod parse;
pub mod path;

use super::correction::{CorrectionWorkspace, Corrector, WarmStart};
use super::export::{check_limit, Limits};
use super::CompensateError;
use crate::errors::{Direction, MachineState};
use crate::machine::{AxisKind, Machine};
use interpret::{interpret, to_machine_units, to_program_units, Move, MoveKind};
pub use interpret::{ProgramSetup, MM_PER_INCH};
use parse::Block;
use path::{arc_geometry, directions_at, point_at, split_points, ArcGeometry, Pieces};

/// Options of the NC correction.
#[derive(Clone, Debug, PartialEq)]
pub struct NcOptions {
    /// Split a feed or arc move when the correction of a linear axis departs from the straight
    /// blend of its end values by more than this (mm).
    pub tolerance_mm: f64,
    /// The same for rotary axes (deg).
    pub rotary_tolerance_deg: f64,
    /// Decimals of written numbers: mm and deg (default 4), inch (default 5).
    pub decimals: usize,
    pub decimals_inch: usize,
    /// Most pieces per move.
    pub max_pieces: usize,
    /// Start position and work offsets.
    pub setup: ProgramSetup,
    /// Refuse the program when a correction exceeds these (um, urad).
    pub limits: Limits,
}

impl NcOptions {
    /// Defaults: split tolerance 1 um (and 1 urad expressed in deg), 4 decimals (5 in inch),
    /// at most 10000 pieces per move, start at 0, zero work offsets, no correction limit.
    pub fn new(machine: &Machine) -> NcOptions {
        NcOptions {
            tolerance_mm: 1e-3,
            rotary_tolerance_deg: 1e-6f64.to_degrees(),
            decimals: 4,
            decimals_inch: 5,
            max_pieces: 10_000,
            setup: ProgramSetup::zero(machine),
            limits: Limits::default(),
        }
    }
}

/// The corrected program and what happened.
#[derive(Clone, Debug, PartialEq)]
pub struct NcResult {
    pub text: String,
    /// Programmed moves corrected.
    pub moves: usize,
    /// Poses corrected on the way (end points, split checks, pieces).
    pub corrected_points: usize,
    /// Lines whose text changed and lines added by splitting.
    pub changed_lines: usize,
    pub inserted_lines: usize,
    /// Largest correction of a linear axis (um) and of a rotary axis (urad).
    pub max_correction_um: f64,
    pub max_correction_urad: f64,
    /// Largest position residual after correction and largest uncorrectable orientation (um, urad).
    pub max_residual_um: f64,
    pub max_uncorrectable_urad: f64,
}

struct Context<'a, 'b> {
    corrector: &'a Corrector<'b>,
    machine: &'a Machine,
    origin: &'a str,
    limits: Limits,
    ws: CorrectionWorkspace,
    warm: WarmStart,
    q: Vec<f64>,
    directions: Vec<Option<Direction>>,
    previous_directions: Vec<Option<Direction>>,
    temperatures: Vec<f64>,
    result: NcResult,
    line: usize,
}

impl Context<'_, '_> {
    /// Correction (mm, deg per axis) at parameter `t` of move `m`, with the directions of motion at
    /// parameter `t_direction` (constant over a piece between direction reversals).
    fn correction(
        &mut self,
        m: &Move,
        arc: Option<&ArcGeometry>,
        t: f64,
        t_direction: f64,
    ) -> Result<(Vec<f64>, Vec<f64>), CompensateError> {
        let n = self.machine.axis_count();
        let mut p = vec![0.0; n];
        point_at(m, arc, t, &mut p);
        directions_at(m, arc, t_direction, &self.previous_directions, &mut self.directions);
        self.machine.pose_to_internal(&p, &mut self.q);
        let state = MachineState { directions: Some(&self.directions), temperatures: &self.temperatures };
        let c = self.corrector.correct_along(&self.q, &state, &mut self.ws, &mut self.warm);
        if !c.converged || c.dq[..n].iter().any(|v| !v.is_finite()) {
            return Err(CompensateError::Computation(format!(
                "{}: line {}: the correction did not converge at {p:?}",
                self.origin, self.line
            )));
        }
        let dq = c.dq_user(self.machine);
        for (k, &d) in dq.iter().enumerate() {
            let place = || {
                let words: Vec<String> =
                    self.machine.axes().iter().zip(&p).map(|(a, v)| format!("{}{}", a.letter, number(*v, 4))).collect();
                format!("the machine position {}", words.join(" "))
            };
            check_limit(self.machine, &self.limits, k, d, &place)
                .map_err(|e| CompensateError::Limit(format!("{}: line {}: {e}", self.origin, self.line)))?;
        }
        let r = &mut self.result;
        r.corrected_points += 1;
        r.max_residual_um = r.max_residual_um.max(c.residual_position.norm() * 1e3);
        r.max_uncorrectable_urad = r.max_uncorrectable_urad.max(c.uncorrectable_orientation.norm() * 1e6);
        for (k, axis) in self.machine.axes().iter().enumerate() {
            match axis.kind {
                AxisKind::Linear => r.max_correction_um = r.max_correction_um.max(c.dq[k].abs() * 1e3),
                AxisKind::Rotary => r.max_correction_urad = r.max_correction_urad.max(c.dq[k].abs() * 1e6),
            }
        }
        Ok((p, dq))
    }

    /// The pieces of move `m`: per piece, the parameter of its end and the correction there. G0: one piece (only the end point matters).
    /// G1: split where the correction departs from the straight blend by more than the tolerance
    /// (its directions of motion are constant). G2/G3: one piece when the correction along the whole
    /// arc (directions as they come) stays within the tolerance; otherwise split between the
    /// reversals (the quadrant points), each stretch with its own constant directions.
    fn pieces(&mut self, m: &Move, arc: Option<&ArcGeometry>, options: &NcOptions) -> Result<Pieces, CompensateError> {
        let (machine, origin, line) = (self.machine, self.origin, self.line);
        let tolerance = |k: usize| match machine.axes()[k].kind {
            AxisKind::Linear => options.tolerance_mm,
            AxisKind::Rotary => options.rotary_tolerance_deg,
        };
        let too_many = || {
            CompensateError::Input(format!(
                "{origin}: line {line}: the correction varies so much along the move that it needs more than {} pieces",
                options.max_pieces
            ))
        };
        if m.kind == MoveKind::Rapid {
            let (_, c) = self.correction(m, arc, 1.0, 1.0)?;
            return Ok(vec![(1.0, c)]);
        }
        let limit = if arc.is_some() { 64 } else { options.max_pieces };
        let mut whole = |t: f64| self.correction(m, arc, t, t).map(|(_, c)| c);
        match (split_points(&mut whole, &tolerance, limit)?, arc) {
            (Some(pieces), None) => return Ok(pieces),
            (None, None) => return Err(too_many()),
            (Some(pieces), Some(_)) if pieces.len() == 1 => return Ok(pieces),
            _ => {}
        }
        let mut pieces = Vec::new();
        for w in reversals(arc).windows(2) {
            let (a, b) = (w[0], w[1]);
            let t_direction = 0.5 * (a + b);
            let mut f = |u: f64| self.correction(m, arc, a + u * (b - a), t_direction).map(|(_, c)| c);
            let stretch = split_points(&mut f, &tolerance, options.max_pieces)?.ok_or_else(too_many)?;
            pieces.extend(stretch.into_iter().map(|(u, c)| (a + u * (b - a), c)));
        }
        Ok(pieces)
    }
}

/// Corrects a program text. `origin` (the file name) prefixes messages; `temperatures` are the error
/// model's sensor temperatures (degC) for the whole program (empty: 20 degC).
pub fn correct_program(
    corrector: &Corrector,
    text: &str,
    origin: &str,
    options: &NcOptions,
    temperatures: &[f64],
) -> Result<NcResult, CompensateError> {
    let machine = corrector.machine;
    let input = |m: String| CompensateError::Input(format!("{origin}: {m}"));
    let blocks = parse::parse_program(text).map_err(input)?;
    let moves = interpret(machine, &blocks, &options.setup).map_err(input)?;
    let n = machine.axis_count();
    let mut cx = Context {
        corrector,
        machine,
        origin,
        limits: options.limits,
        ws: CorrectionWorkspace::new(machine),
        warm: WarmStart::default(),
        q: vec![0.0; n],
        directions: vec![None; n],
        previous_directions: vec![None; n],
        temperatures: temperatures.to_vec(),
        result: NcResult {
            text: String::new(),
            moves: moves.len(),
            corrected_points: 0,
            changed_lines: 0,
            inserted_lines: 0,
            max_correction_um: 0.0,
            max_correction_urad: 0.0,
            max_residual_um: 0.0,
            max_uncorrectable_urad: 0.0,
        },
        line: 0,
    };
    let mut written = options.setup.start.clone();
    let mut out_lines: Vec<String> = blocks.iter().map(|b| b.text.clone()).collect();
    let mut inserted: Vec<Vec<String>> = vec![Vec::new(); blocks.len()];
    for m in &moves {
        let block = &blocks[m.block];
        cx.line = block.line;
        let arc = arc_geometry(m);
        let pieces = cx.pieces(m, arc.as_ref(), options)?;
        // the shift of the start is what the controller holds there: the written end of the move
        // before (arc centres move by the mean shift of their ends)
        let mut c_prev: Vec<f64> = written.iter().zip(&m.start).map(|(w, s)| w - s).collect();
        for (i, (t, c)) in pieces.into_iter().enumerate() {
            let mut p = vec![0.0; machine.axis_count()];
            point_at(m, arc.as_ref(), t, &mut p);
            let target: Vec<f64> = p.iter().zip(&c).map(|(a, b)| a + b).collect();
            let centre = match (m.kind, arc.as_ref()) {
                (MoveKind::Arc { plane, centre, .. }, Some(_)) => Some([
                    centre[0] + 0.5 * (c_prev[plane.first] + c[plane.first]),
                    centre[1] + 0.5 * (c_prev[plane.second] + c[plane.second]),
                ]),
                _ => None,
            };
            if i == 0 {
                let new = rewrite_block(machine, options, block, m, &target, centre, &mut written);
                if new != block.text {
                    cx.result.changed_lines += 1;
                }
                out_lines[m.block] = new;
                c_prev = c;
            } else if let Some(line) = piece_line(machine, options, m, &target, centre, &mut written) {
                inserted[m.block].push(line);
                cx.result.inserted_lines += 1;
                c_prev = c;
            }
            // a piece that moves no axis at the written resolution is left out (no bare `G1`);
            // the next piece starts where the controller is, with the correction there
        }
        directions_at(m, arc.as_ref(), 1.0, &cx.previous_directions.clone(), &mut cx.previous_directions);
    }
    let mut text_out = String::with_capacity(text.len() + 64 * cx.result.inserted_lines);
    for (line, extra) in out_lines.iter().zip(&inserted) {
        text_out.push_str(line);
        text_out.push('\n');
        for e in extra {
            text_out.push_str(e);
            text_out.push('\n');
        }
    }
    cx.result.text = text_out;
    Ok(cx.result)
}

/// Parameters `0 = t_0 < ... < t_k = 1` between which no axis reverses: for an arc, the points
/// where its angle crosses a multiple of 90 degrees (a plane axis turns around there).
fn reversals(arc: Option<&ArcGeometry>) -> Vec<f64> {
    let mut out = vec![0.0];
    if let Some(g) = arc {
        let quarter = std::f64::consts::FRAC_PI_2;
        let (a0, a1) = (g.start_angle, g.start_angle + g.sweep);
        let (lo, hi) = (a0.min(a1), a0.max(a1));
        let mut k = (lo / quarter).floor() + 1.0;
        while k * quarter < hi - 1e-12 {
            let t = (k * quarter - a0) / g.sweep;
            if t > 1e-9 && t < 1.0 - 1e-9 {
                out.push(t);
            }
            k += 1.0;
        }
        out.sort_by(|a, b| a.total_cmp(b));
    }
    out.push(1.0);
    out
}

/// Number text with `decimals` digits, trailing zeros removed (`12.5`, `-3`, `0.0012`).
fn number(value: f64, decimals: usize) -> String {
    let mut s = format!("{value:.decimals$}");
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" {
        s = "0".into();
    }
    s
}

fn decimals_of(options: &NcOptions, inch: bool) -> usize {
    if inch {
        options.decimals_inch
    } else {
        options.decimals
    }
}

/// The value to write for `axis` so that the controller ends at `target` (machine units), given
/// what it holds now (`written`, machine units) and the word of the original block, if any; `None`
/// when the original text (or the absence of a word) already gives the target to the written
/// resolution. Updates `written`.
fn axis_value(
    machine: &Machine,
    options: &NcOptions,
    m: &Move,
    axis: usize,
    target: f64,
    original: Option<f64>,
    written: &mut [f64],
) -> Option<String> {
    let decimals = decimals_of(options, m.inch);
    let half = 0.5 * 10f64.powi(-(decimals as i32));
    let to_prog = |v: f64| to_program_units(machine, axis, v, m.inch);
    let to_mach = |v: f64| to_machine_units(machine, axis, v, m.inch);
    let desired = if m.incremental { to_prog(target - written[axis]) } else { to_prog(target - m.offset[axis]) };
    let current = match original {
        Some(v) => v,
        None if m.incremental => 0.0,
        None => to_prog(written[axis] - m.offset[axis]),
    };
    let (value, text) = if (desired - current).abs() < half {
        (current, None)
    } else {
        let t = number(desired, decimals);
        (t.parse::<f64>().unwrap_or(desired), Some(t))
    };
    written[axis] = if m.incremental { written[axis] + to_mach(value) } else { to_mach(value) + m.offset[axis] };
    text
}

/// Centre words `(letter, value)` of an arc piece whose corrected centre is `centre` (machine
/// units), relative to the controller's start `start` (machine units).
fn centre_values(machine: &Machine, options: &NcOptions, m: &Move, centre: [f64; 2], start: &[f64]) -> [(char, f64, String); 2] {
    let MoveKind::Arc { plane, .. } = m.kind else { unreachable!("centre of a line") };
    let decimals = decimals_of(options, m.inch);
    let axes = [plane.first, plane.second];
    std::array::from_fn(|d| {
        let v = to_program_units(machine, axes[d], centre[d] - start[axes[d]], m.inch);
        (plane.centre_letters[d], v, number(v, decimals))
    })
}

/// The block with its numbers replaced and missing words added; everything else as written.
fn rewrite_block(
    machine: &Machine,
    options: &NcOptions,
    block: &Block,
    m: &Move,
    target: &[f64],
    centre: Option<[f64; 2]>,
    written: &mut [f64],
) -> String {
    let start = written.to_vec();
    let mut edits: Vec<(std::ops::Range<usize>, String)> = Vec::new();
    let mut appended: Vec<String> = Vec::new();
    for (axis, a) in machine.axes().iter().enumerate() {
        let word = block.words_of(a.letter).next();
        if let Some(text) = axis_value(machine, options, m, axis, target[axis], word.map(|w| w.value), written) {
            match word {
                Some(w) => edits.push((w.number.clone(), text)),
                None => appended.push(format!("{}{text}", a.letter)),
            }
        }
    }
    if let (Some(c), MoveKind::Arc { r_format, .. }) = (centre, m.kind) {
        let half = 0.5 * 10f64.powi(-(decimals_of(options, m.inch) as i32));
        let values = centre_values(machine, options, m, c, &start);
        let endpoints_changed = !edits.is_empty() || !appended.is_empty();
        if r_format {
            if endpoints_changed {
                let r = block.words_of('R').next().expect("R-format arc");
                edits.push((r.number.start - 1..r.number.end, format!("{}{} {}{}", values[0].0, values[0].2, values[1].0, values[1].2)));
            }
        } else {
            for (letter, v, text) in values {
                let word = block.words_of(letter).next();
                if (v - word.map_or(0.0, |w| w.value)).abs() >= half {
                    match word {
                        Some(w) => edits.push((w.number.clone(), text)),
                        None => appended.push(format!("{letter}{text}")),
                    }
                }
            }
        }
    }
    let mut text = block.text.clone();
    if !appended.is_empty() {
        let at = block.insertion_point();
        text.insert_str(at, &format!(" {}", appended.join(" ")));
    }
    edits.sort_by_key(|(r, _)| std::cmp::Reverse(r.start));
    for (range, new) in edits {
        text.replace_range(range, &new);
    }
    text
}

/// A new line for a piece of a split move: the motion word and the words that must change;
/// `None` (nothing written, `written` unchanged) when no axis moves at the written resolution.
fn piece_line(
    machine: &Machine,
    options: &NcOptions,
    m: &Move,
    target: &[f64],
    centre: Option<[f64; 2]>,
    written: &mut [f64],
) -> Option<String> {
    let start = written.to_vec();
    let mut words = vec![match m.kind {
        MoveKind::Rapid => "G0".to_string(),
        MoveKind::Feed => "G1".to_string(),
        MoveKind::Arc { clockwise: true, .. } => "G2".to_string(),
        MoveKind::Arc { clockwise: false, .. } => "G3".to_string(),
    }];
    let piece = Move { incremental: m.incremental, ..m.clone() };
    for (axis, a) in machine.axes().iter().enumerate() {
        if let Some(text) = axis_value(machine, options, &piece, axis, target[axis], None, written) {
            words.push(format!("{}{text}", a.letter));
        }
    }
    if words.len() == 1 {
        written.copy_from_slice(&start);
        return None;
    }
    if let Some(c) = centre {
        for (letter, _, text) in centre_values(machine, options, m, c, &start) {
            words.push(format!("{letter}{text}"));
        }
    }
    Some(words.join(" "))
}
