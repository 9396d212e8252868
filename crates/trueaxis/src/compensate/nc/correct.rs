//! The corrections along the moves of a run: the pose correction of
//! [`crate::compensate::Corrector`] at the points of each move, in the state there (the direction
//! of each axis, the temperatures), with the tool point of the active tool length offset; the
//! pieces a move is split into where the correction departs from a straight blend of its values
//! at the piece ends by more than the tolerance.

use super::modal::{Frame, MM_PER_INCH};
use super::path::{arc_geometry, departure, point_at, split_from, ArcGeometry, Pieces};
use super::trace::{Move, MoveKind, Role};
use super::NcOptions;
use crate::compensate::correction::{Correction, CorrectionWorkspace, Corrector, WarmStart};
use crate::compensate::coverage::{check_covered, table_ranges, TableRange};
use crate::compensate::direction_of;
use crate::compensate::export::{check_limit, Limits};
use crate::compensate::CompensateError;
use crate::error_model::{Direction, MachineState};
use crate::geometry::Vec3;
use crate::machine::{AxisKind, Machine};

/// What the corrections reached.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Extremes {
    /// Poses corrected (end points, split checks, pieces).
    pub corrected_points: usize,
    /// Largest correction of a linear axis (um) and of a rotary axis (urad).
    pub max_correction_um: f64,
    pub max_correction_urad: f64,
    /// Largest position residual after correction, the rounding of the written numbers included,
    /// and largest uncorrectable orientation (um, urad).
    pub max_residual_um: f64,
    pub max_uncorrectable_urad: f64,
}

/// Half a unit of the last digit the corrected program is written with: mm (linear axes in mm
/// and in inch) and deg.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Rounding {
    pub linear_mm: f64,
    pub linear_inch_mm: f64,
    pub rotary_deg: f64,
}

impl Rounding {
    /// For `decimals` in mm and deg and `decimals_inch` in inch.
    pub fn of_decimals(decimals: usize, decimals_inch: usize) -> Rounding {
        let half = |d: usize| 0.5 * 10f64.powi(-(d as i32));
        Rounding { linear_mm: half(decimals), linear_inch_mm: half(decimals_inch) * super::MM_PER_INCH, rotary_deg: half(decimals) }
    }
}

/// The corrector and its state along a program.
pub(super) struct Corrections<'a, 'b> {
    base: &'a Corrector<'b>,
    corrector: Corrector<'b>,
    /// Tool offset (mm, machine X Y Z) the corrector's tool point is set for.
    tool: [f64; 3],
    machine: &'a Machine,
    limits: Limits,
    /// The ranges of the error tables: points beyond them are refused.
    covered: Vec<TableRange>,
    ws: CorrectionWorkspace,
    warm: WarmStart,
    q: Vec<f64>,
    directions: Vec<Option<Direction>>,
    previous_directions: Vec<Option<Direction>>,
    temperatures: Vec<f64>,
    /// Half a unit of the last written digit, and whether the move being corrected is programmed
    /// in inch.
    rounding: Rounding,
    inch: bool,
    /// The rotary axes' part of the rounding at the end of the last move (mm).
    rotary_rounding: Option<f64>,
    pub extremes: Extremes,
    /// The correction at the end of the last move: what the controller holds at the start of the
    /// next one (mm, deg).
    start_correction: Vec<f64>,
    /// Where the messages point.
    pub origin: String,
    pub line: usize,
}

impl<'a, 'b> Corrections<'a, 'b> {
    pub fn new(corrector: &'a Corrector<'b>, limits: Limits, temperatures: &[f64], rounding: Rounding) -> Self {
        let machine = corrector.machine;
        let n = machine.axis_count();
        Corrections {
            base: corrector,
            corrector: *corrector,
            tool: [0.0; 3],
            machine,
            limits,
            covered: table_ranges(machine, corrector.errors),
            ws: CorrectionWorkspace::new(machine),
            warm: WarmStart::default(),
            q: vec![0.0; n],
            directions: vec![None; n],
            previous_directions: vec![None; n],
            temperatures: temperatures.to_vec(),
            rounding,
            inch: false,
            rotary_rounding: None,
            extremes: Extremes::default(),
            start_correction: vec![0.0; n],
            origin: String::new(),
            line: 0,
        }
    }

    /// The tool point of the tool length offset of `frame`: the machine's tool point (the
    /// controlled point without offset) minus the offset along the machine's X Y Z.
    fn set_tool(&mut self, frame: &Frame) {
        let s = if frame.inch { MM_PER_INCH } else { 1.0 };
        let tool = [frame.tool[0] * s, frame.tool[1] * s, frame.tool[2] * s];
        if tool != self.tool {
            self.tool = tool;
            self.corrector.setup.tool_point = self.base.setup.tool_point - Vec3::new(tool[0], tool[1], tool[2]);
            self.warm.reset();
        }
    }

    /// Correction (mm, deg per axis) at parameter `t` of move `m`, with the directions of motion
    /// at parameter `t_direction` (constant over a piece between direction reversals).
    fn correction(&mut self, m: &Move, arc: Option<&ArcGeometry>, t: f64, t_direction: f64) -> Result<Vec<f64>, CompensateError> {
        let n = self.machine.axis_count();
        let mut p = vec![0.0; n];
        point_at(m, arc, t, &mut p);
        for (k, &v) in p.iter().enumerate() {
            check_covered(self.machine, &self.covered, k, v, v, &|| "the program".to_string())
                .map_err(|e| CompensateError::Coverage(format!("{}: line {}: {e}", self.origin, self.line)))?;
        }
        directions_at(m, arc, t_direction, &self.previous_directions, &mut self.directions);
        self.machine.pose_to_internal(&p, &mut self.q);
        let state = MachineState { directions: Some(&self.directions), temperatures: &self.temperatures };
        let c = self.corrector.correct_along(&self.q, &state, &mut self.ws, &mut self.warm);
        let linear_half = if self.inch { self.rounding.linear_inch_mm } else { self.rounding.linear_mm };
        // the rotary axes' part through the chain at each move's end (t = 1, computed second of
        // its points), reused along the move: the lever changes little within a move
        if t == 1.0 || self.rotary_rounding.is_none() {
            self.rotary_rounding = Some(rotary_rounding(&self.corrector, self.rounding.rotary_deg, &self.q, &c, &state, &mut self.ws));
        }
        let linear_axes = self.machine.axes().iter().filter(|a| a.kind == AxisKind::Linear).count() as f64;
        let rounding = linear_half * linear_axes.sqrt() + self.rotary_rounding.unwrap_or(0.0);
        if !c.converged || c.dq[..n].iter().any(|v| !v.is_finite()) {
            return Err(CompensateError::Computation(format!(
                "{}: line {}: the correction did not converge at {p:?}",
                self.origin, self.line
            )));
        }
        let dq = c.dq_user(self.machine);
        for (k, &d) in dq.iter().enumerate() {
            let place = || {
                let words: Vec<String> = self
                    .machine
                    .axes()
                    .iter()
                    .zip(&p)
                    .map(|(a, v)| format!("{}{}", a.letter, super::dialect::format_number(*v, 4, super::Dialect::LinuxCnc)))
                    .collect();
                format!("the machine position {}", words.join(" "))
            };
            check_limit(self.machine, &self.limits, k, d, &place)
                .map_err(|e| CompensateError::Limit(format!("{}: line {}: {e}", self.origin, self.line)))?;
        }
        let r = &mut self.extremes;
        r.corrected_points += 1;
        r.max_residual_um = r.max_residual_um.max((c.residual_position.norm() + rounding) * 1e3);
        r.max_uncorrectable_urad = r.max_uncorrectable_urad.max(c.uncorrectable_orientation.norm() * 1e6);
        for (k, axis) in self.machine.axes().iter().enumerate() {
            match axis.kind {
                AxisKind::Linear => r.max_correction_um = r.max_correction_um.max(c.dq[k].abs() * 1e3),
                AxisKind::Rotary => r.max_correction_urad = r.max_correction_urad.max(c.dq[k].abs() * 1e6),
            }
        }
        Ok(dq)
    }

    /// The pieces of move `m`: per piece, the parameter of its end and the correction there.
    /// Rapid: one piece (only the end point matters). Feed: split where the correction departs
    /// from the straight blend by more than the tolerance (its directions of motion are constant).
    /// Arc: one piece when the correction along the whole arc (directions as they come) stays within
    /// the tolerance; otherwise split between the reversals (the quadrant points), each stretch
    /// with its own constant directions. A return to the `G28`/`G30` position: not corrected.
    pub fn pieces(&mut self, m: &Move, frame: &Frame, options: &NcOptions) -> Result<Pieces, CompensateError> {
        let pieces = self.pieces_of(m, frame, options)?;
        self.start_correction.clone_from(&pieces.last().expect("a piece").1);
        Ok(pieces)
    }

    fn pieces_of(&mut self, m: &Move, frame: &Frame, options: &NcOptions) -> Result<Pieces, CompensateError> {
        let n = self.machine.axis_count();
        if m.role == Role::Home {
            return Ok(vec![(1.0, vec![0.0; n])]);
        }
        self.set_tool(frame);
        self.inch = frame.inch;
        let arc = arc_geometry(m);
        let arc = arc.as_ref();
        let (machine, origin, line) = (self.machine, self.origin.clone(), self.line);
        let tolerance = |k: usize| match machine.axes()[k].kind {
            AxisKind::Linear => (options.tolerance_mm, true),
            AxisKind::Rotary => (options.rotary_tolerance_deg, false),
        };
        let too_many = || {
            CompensateError::Input(format!(
                "{origin}: line {line}: the correction varies so much along the move that it needs more than {} pieces",
                options.max_pieces
            ))
        };
        if m.kind == MoveKind::Rapid {
            let c = self.correction(m, arc, 1.0, 1.0)?;
            return Ok(vec![(1.0, c)]);
        }
        let limit = if arc.is_some() { 64 } else { options.max_pieces };
        let held = self.start_correction.clone();
        // where an axis reverses at the start of the move (backlash), the correction steps there:
        // a piece of zero length (`t` = 0) that the writer makes a short straight move
        let step = |c0: &[f64], held: &[f64]| departure(held, c0, &tolerance) > 1.0;
        let mut whole = |t: f64| self.correction(m, arc, t, t);
        match (split_from(&mut whole, &tolerance, limit)?, arc) {
            (Some((c0, mut pieces)), None) => {
                if step(&c0, &held) {
                    pieces.insert(0, (0.0, c0));
                }
                return Ok(pieces);
            }
            (None, None) => return Err(too_many()),
            // a full circle written as one block must end exactly where it starts in its plane: when
            // the correction there differs from the start's (a helix), it is split instead
            (Some((c0, mut pieces)), Some(g))
                if pieces.len() == 1 && !(g.sweep.abs() >= std::f64::consts::TAU - 1e-12 && self.plane_shift(m, &pieces[0].1) > 1e-7) =>
            {
                if step(&c0, &held) {
                    pieces.insert(0, (0.0, c0));
                }
                return Ok(pieces);
            }
            _ => {}
        }
        let mut pieces: Pieces = Vec::new();
        let mut previous = held;
        for w in reversals(arc).windows(2) {
            let (a, b) = (w[0], w[1]);
            let t_direction = 0.5 * (a + b);
            let mut f = |u: f64| self.correction(m, arc, a + u * (b - a), t_direction);
            let (c0, stretch) = split_from(&mut f, &tolerance, options.max_pieces)?.ok_or_else(too_many)?;
            if step(&c0, &previous) {
                pieces.push((a, c0));
            }
            pieces.extend(stretch.into_iter().map(|(u, c)| (a + u * (b - a), c)));
            previous.clone_from(&pieces.last().expect("a piece").1);
        }
        Ok(pieces)
    }

    /// How far the plane correction at the end of arc `m` is from the one the controller holds at
    /// its start (mm).
    fn plane_shift(&self, m: &Move, end: &[f64]) -> f64 {
        let MoveKind::Arc { plane, .. } = m.kind else { return 0.0 };
        let start = &self.start_correction;
        (end[plane.first] - start[plane.first]).hypot(end[plane.second] - start[plane.second])
    }

    /// After a move: the directions at its end are the ones the next move starts from.
    pub fn finish(&mut self, m: &Move) {
        let arc = arc_geometry(m);
        let previous = self.previous_directions.clone();
        directions_at(m, arc.as_ref(), 1.0, &previous, &mut self.previous_directions);
    }
}

/// How far the tool point can move from the corrected one when each rotary axis is written rounded
/// to its last digit (`rotary_half`, deg): the sum over the rotary axes of what the exact chain
/// says (their levers), one chain evaluation per rotary axis (mm). The linear axes' half units
/// add as a vector beside it.
fn rotary_rounding(
    corrector: &Corrector,
    rotary_half: f64,
    q: &[f64],
    c: &Correction,
    state: &MachineState,
    ws: &mut CorrectionWorkspace,
) -> f64 {
    let n = corrector.machine.axis_count();
    let mut rotary = 0.0;
    let mut shifted = [0.0; crate::compensate::MAX_AXES];
    for (k, axis) in corrector.machine.axes().iter().enumerate() {
        if axis.kind == AxisKind::Rotary {
            shifted[..n].copy_from_slice(&c.dq[..n]);
            shifted[k] += rotary_half.to_radians();
            let (moved, _) = corrector.residual_at(q, &shifted[..n], state, ws);
            rotary += (moved - c.residual_position).norm();
        }
    }
    rotary
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

/// Directions of motion at parameter `t`: the sign of the velocity of each axis; an axis that does
/// not move keeps `previous` (the direction it last moved in, which fixes its backlash side).
fn directions_at(m: &Move, arc: Option<&ArcGeometry>, t: f64, previous: &[Option<Direction>], out: &mut [Option<Direction>]) {
    for k in 0..out.len() {
        let velocity = m.end[k] - m.start[k];
        out[k] = direction_of(velocity).or(previous[k]);
    }
    if let (Some(g), MoveKind::Arc { plane, .. }) = (arc, m.kind) {
        let angle = g.start_angle + t * g.sweep;
        let r = g.start_radius + t * (g.end_radius - g.start_radius);
        let dr = g.end_radius - g.start_radius;
        // d/dt (r cos a, r sin a) with a' = sweep
        let v_first = dr * angle.cos() - r * g.sweep * angle.sin();
        let v_second = dr * angle.sin() + r * g.sweep * angle.cos();
        let tiny = 1e-12 * (r * g.sweep.abs()).max(1.0);
        for (axis, v) in [(plane.first, v_first), (plane.second, v_second)] {
            out[axis] = if v.abs() > tiny { direction_of(v) } else { previous[axis] };
        }
    }
}
