//! The check of a corrected program against the original through an independent reader: the
//! canonical moves of the corrected program (read by rs274, or by any reader that gives machine
//! positions) are pushed through the erroneous machine (exact chain with the error model, in the
//! state of each move: directions of motion, temperatures, the tool point of the tool offset in
//! force), and must land on the nominal positions of the original program's moves: every original
//! move end within `end_um`, every point along the corrected path (the pieces of a split move, the
//! middle of every move, three points of every arc) within `path_um` of the original path.

use super::rs274::{Canon, Kind};
use trueaxis::error_model::{Direction, ErrorModel, MachineState};
use trueaxis::geometry::Vec3;
use trueaxis::machine::{AxisKind, Machine};
use trueaxis::model::{nominal_chain, volumetric_error, Frame, Setup};

/// The erroneous machine.
pub struct Oracle<'a> {
    pub machine: &'a Machine,
    pub errors: &'a ErrorModel,
    pub temperatures: Vec<f64>,
}

/// What a comparison found.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Report {
    /// Original moves matched, corrected moves that were pieces of split moves.
    pub moves: usize,
    pub pieces: usize,
    /// Largest distance of a corrected end from its original end, and of a corrected path point
    /// from the original path (um).
    pub worst_end_um: f64,
    pub worst_path_um: f64,
    /// Original moves of kept canned cycles (checked with their slack), and the largest distance
    /// of an R point from its target along the cycle axis (um).
    pub holes: usize,
    pub worst_along_um: f64,
}

/// What a kept canned cycle leaves at one of its original moves (um, beyond the end tolerance):
/// the written hole position carries the correction at the bottom, so its other points stand off
/// theirs by what the corrector reports per hole.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Slack {
    /// Allowed distance of the end from its target beyond `end_um`; with `along_exact` only across
    /// the cycle axis (`axis`: 0 X, 1 Y, 2 Z), the end along it within `end_um` (the R point).
    pub end_um: f64,
    pub along_exact: bool,
    pub axis: usize,
    /// Allowed distance of the path's points beyond `path_um`.
    pub path_um: f64,
}

/// An arc of a path: machine axes of its plane (first, second), centre, signed sweep (rad), start
/// angle, start and end radii.
type ArcPath = ([usize; 2], [f64; 2], f64, f64, f64, f64);

/// A move as a path in machine positions.
#[derive(Clone, Debug)]
struct Path {
    start: Vec<f64>,
    end: Vec<f64>,
    /// Machine axes of the plane (first, second), centre, signed sweep (rad), start angle, radii.
    arc: Option<ArcPath>,
    tool: [f64; 3],
}

impl Path {
    fn point(&self, t: f64) -> Vec<f64> {
        let mut p: Vec<f64> = self.start.iter().zip(&self.end).map(|(s, e)| s + t * (e - s)).collect();
        if let Some(([a, b], c, sweep, a0, r0, r1)) = self.arc {
            let angle = a0 + t * sweep;
            let r = r0 + t * (r1 - r0);
            p[a] = c[0] + r * angle.cos();
            p[b] = c[1] + r * angle.sin();
        }
        p
    }

    /// Direction of each axis at `t` (the sign of its velocity), or `None` when it does not move.
    fn directions(&self, t: f64) -> Vec<Option<Direction>> {
        let h = 1e-6;
        let (p0, p1) = (self.point((t - h).max(0.0)), self.point((t + h).min(1.0)));
        p0.iter().zip(&p1).map(|(a, b)| super::direction_of(b - a)).collect()
    }
}

impl Oracle<'_> {
    /// Machine positions of a canonical move; an error when it moves an axis the machine lacks.
    fn axes(&self, end: &[f64; 6]) -> Result<Vec<f64>, String> {
        let letters = ['X', 'Y', 'Z', 'A', 'B', 'C'];
        let mut q = vec![0.0; self.machine.axis_count()];
        for (k, l) in letters.iter().enumerate() {
            match self.machine.axis_index(*l) {
                Some(i) => q[i] = end[k],
                None if end[k].abs() > 1e-9 => return Err(format!("a move of axis {l}, which the machine does not have")),
                None => {}
            }
        }
        Ok(q)
    }

    /// Where the nominal machine and the erroneous machine (no direction of motion: a model
    /// without backlash) put the tool point of a canonical move's end (workpiece frame, mm).
    pub fn landing(&self, m: &Canon) -> Result<(Vec3, Vec3), String> {
        let q = self.axes(&m.end)?;
        Ok((self.nominal(&q, m.tool), self.actual(&q, m.tool, &vec![None; q.len()])))
    }

    fn paths(&self, moves: &[Canon], start: &[f64]) -> Result<Vec<Path>, String> {
        let mut prev = start.to_vec();
        let mut out = Vec::with_capacity(moves.len());
        for m in moves {
            let end = self.axes(&m.end)?;
            let arc = match m.kind {
                Kind::Arc { axes, centre, turns } => {
                    let (a, b) = (
                        self.machine.axis_index(['X', 'Y', 'Z'][axes[0]]).unwrap(),
                        self.machine.axis_index(['X', 'Y', 'Z'][axes[1]]).unwrap(),
                    );
                    let a0 = (prev[b] - centre[1]).atan2(prev[a] - centre[0]);
                    let a1 = (end[b] - centre[1]).atan2(end[a] - centre[0]);
                    let tau = std::f64::consts::TAU;
                    let closed = (prev[a] - end[a]).abs() < 1e-9 && (prev[b] - end[b]).abs() < 1e-9;
                    let base = if closed {
                        tau
                    } else if turns > 0 {
                        (a1 - a0).rem_euclid(tau)
                    } else {
                        (a0 - a1).rem_euclid(tau)
                    };
                    let extra = (turns.abs() - 1).max(0) as f64 * tau;
                    let sweep = (base + extra) * f64::from(turns.signum());
                    let (r0, r1) = ((prev[a] - centre[0]).hypot(prev[b] - centre[1]), (end[a] - centre[0]).hypot(end[b] - centre[1]));
                    Some(([a, b], centre, sweep, a0, r0, r1))
                }
                _ => None,
            };
            out.push(Path { start: prev.clone(), end: end.clone(), arc, tool: m.tool });
            prev = end;
        }
        Ok(out)
    }

    fn setup(&self, tool: [f64; 3]) -> Setup {
        let mut s = Setup::of_machine(self.machine);
        s.tool_point -= Vec3::new(tool[0], tool[1], tool[2]);
        s
    }

    /// The nominal tool point relative to the workpiece (workpiece frame, mm).
    fn nominal(&self, q: &[f64], tool: [f64; 3]) -> Vec3 {
        let mut internal = vec![0.0; q.len()];
        self.machine.pose_to_internal(q, &mut internal);
        let setup = self.setup(tool);
        let t = nominal_chain(self.machine, self.machine.tool_chain(), &internal, None);
        let w = nominal_chain(self.machine, self.machine.work_chain(), &internal, None);
        w.inverse().transform_point(&t.transform_point(&setup.tool_point)) - setup.work_point
    }

    /// Where the erroneous machine puts the tool point (workpiece frame, mm).
    fn actual(&self, q: &[f64], tool: [f64; 3], directions: &[Option<Direction>]) -> Vec3 {
        let mut internal = vec![0.0; q.len()];
        self.machine.pose_to_internal(q, &mut internal);
        let mut values = vec![0.0; self.machine.parameter_count()];
        let state = MachineState { directions: Some(directions), temperatures: &self.temperatures };
        self.errors.values_at_state(self.machine, &internal, &state, &mut values);
        let e = volumetric_error(self.machine, &internal, &values, &self.setup(tool), Frame::Workpiece);
        self.nominal(q, tool) + e.position
    }

    /// The parameter of the point of `path` nearest to `x` and the distance (mm) to it.
    fn nearest(&self, x: &Vec3, path: &Path) -> (f64, f64) {
        let d = |t: f64| (self.nominal(&path.point(t), path.tool) - x).norm();
        let samples = 32;
        let best = (0..=samples).map(|i| i as f64 / samples as f64).min_by(|a, b| d(*a).total_cmp(&d(*b))).unwrap();
        let (mut lo, mut hi) = ((best - 1.0 / samples as f64).max(0.0), (best + 1.0 / samples as f64).min(1.0));
        for _ in 0..40 {
            let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if d(m1) < d(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        let t = 0.5 * (lo + hi);
        (t, d(t))
    }

    /// Compares the corrected moves with the original ones (both from `start`, machine positions).
    /// The state of the erroneous machine is the one of the programmed motion: the directions of
    /// the original move a corrected point belongs to (an axis that does not move keeps the
    /// direction it last moved in), not the micrometre motions of the corrections.
    ///
    /// `uncorrected`: original moves the corrector leaves as they are by design (the returns of
    /// `G28`/`G30` to their stored positions): the corrected program must reach the same machine
    /// position on the axes that return (1e-6 mm). Likewise an axis that ends at the end of its
    /// travel stays there (a correction beyond the travel is not written); the other axes of such
    /// moves must be within 0.05 mm.
    pub fn compare(
        &self,
        original: &[Canon],
        corrected: &[Canon],
        start: &[f64],
        end_um: f64,
        path_um: f64,
        uncorrected: &[usize],
    ) -> Result<Report, String> {
        self.compare_with(original, corrected, start, end_um, path_um, uncorrected, &[])
    }

    /// [`Self::compare`] with the slack of kept canned cycles (`slack[i]` for original move `i`;
    /// a shorter list: none beyond it).
    #[allow(clippy::too_many_arguments)]
    pub fn compare_with(
        &self,
        original: &[Canon],
        corrected: &[Canon],
        start: &[f64],
        end_um: f64,
        path_um: f64,
        uncorrected: &[usize],
        slack: &[Slack],
    ) -> Result<Report, String> {
        let o = self.paths(original, start)?;
        let c = self.paths(corrected, start)?;
        let n = self.machine.axis_count();
        let merge = |base: &[Option<Direction>], now: Vec<Option<Direction>>| -> Vec<Option<Direction>> {
            base.iter().zip(now).map(|(b, d)| d.or(*b)).collect()
        };
        // directions before each original move and at its end
        let mut before = Vec::with_capacity(o.len());
        let mut dirs: Vec<Option<Direction>> = vec![None; n];
        for p in &o {
            before.push(dirs.clone());
            dirs = merge(&dirs, p.directions(1.0));
        }
        let mut report = Report::default();
        let mut k = 0usize;
        for (i, op) in o.iter().enumerate() {
            let target = self.nominal(&op.end, op.tool);
            let end_dirs = merge(&before[i], op.directions(1.0));
            // a move that goes nowhere from the start (`G28 G91 Z0.` first): where the machine stood
            let at_start = o[..=i].iter().all(|p| p.end.iter().zip(start).all(|(a, b)| (a - b).abs() < 1e-12));
            let home_move = uncorrected.contains(&i) || at_start;
            let at_limit = |a: usize| {
                self.machine.axes()[a].range.is_some_and(|[lo, hi]| (op.end[a] - lo).abs() < 1e-9 || (op.end[a] - hi).abs() < 1e-9)
            };
            let exempt = home_move || (0..n).any(at_limit);
            let landing = |j: usize| {
                if exempt {
                    let same = (0..n).all(|a| {
                        let exact = at_limit(a) || home_move && (op.end[a] - op.start[a]).abs() > 1e-9;
                        (c[j].end[a] - op.end[a]).abs() < if exact { 1e-6 } else { 0.05 }
                    });
                    if same {
                        target
                    } else {
                        target + Vec3::new(1.0, 0.0, 0.0)
                    }
                } else {
                    self.actual(&c[j].end, c[j].tool, &end_dirs)
                }
            };
            let zero_length = i > 0 && op.arc.is_none() && (self.nominal(&o[i - 1].end, o[i - 1].tool) - target).norm() < 1e-9;
            let sl = slack.get(i).copied().unwrap_or_default();
            let lands = |j: usize| {
                let v = (landing(j) - target) * 1e3;
                if sl.along_exact {
                    let along = v[sl.axis];
                    along.abs() <= end_um && (v.norm_squared() - along * along).max(0.0).sqrt() <= end_um + sl.end_um
                } else {
                    v.norm() <= end_um + sl.end_um
                }
            };
            // a zero-length original move may have no corrected copy (written only when it moves)
            let found = if k < c.len() && lands(k) {
                Some(k)
            } else if zero_length && k > 0 && lands(k - 1) {
                Some(k - 1)
            } else {
                (k..c.len()).find(|&j| lands(j))
            };
            let Some(j) = found else {
                let near =
                    (k.saturating_sub(1)..c.len().min(k + 5)).map(|j| (landing(j) - target).norm() * 1e3).fold(f64::INFINITY, f64::min);
                return Err(format!(
                    "original move {} ({:?} to {:?}) is not reached: the nearest corrected move of the next five lands {near:.4} um away",
                    i + 1,
                    original[i].kind,
                    op.end
                ));
            };
            let v = (landing(j) - target) * 1e3;
            if sl.end_um == 0.0 {
                report.worst_end_um = report.worst_end_um.max(v.norm());
            }
            if sl.along_exact {
                report.worst_along_um = report.worst_along_um.max(v[sl.axis].abs());
            }
            report.holes += usize::from(sl != Slack::default());
            // the corrected path from k to j follows the original move
            for (jj, cp) in c.iter().enumerate().take(j + 1).skip(k.min(j + 1)) {
                // a rapid: only its end matters; the first move starts where the machine stood,
                // which no program can correct
                let rapid = corrected[jj].kind == Kind::Traverse;
                // the step of the correction where an axis reverses (backlash): a few micrometres
                // of straight move at one point of the original path, inside the error model's
                // own discontinuity
                let length = (self.nominal(&cp.end, cp.tool) - self.nominal(&cp.start, cp.tool)).norm();
                let original_length: f64 = (0..16)
                    .map(|s| {
                        (self.nominal(&op.point((s + 1) as f64 / 16.0), op.tool) - self.nominal(&op.point(s as f64 / 16.0), op.tool)).norm()
                    })
                    .sum();
                let step = !matches!(corrected[jj].kind, Kind::Arc { .. }) && length < 0.02 && length < 0.01 * original_length;
                let mut ts: Vec<f64> = if rapid || jj == 0 || step {
                    vec![]
                } else if cp.arc.is_some() {
                    vec![0.25, 0.5, 0.75]
                } else {
                    vec![0.5]
                };
                if jj < j {
                    ts.push(1.0);
                    report.pieces += 1;
                }
                for t in ts {
                    let q = cp.point(t);
                    let (t_original, _) = self.nearest(&self.nominal(&q, cp.tool), op);
                    // at a piece's end, the directions it arrives with (an axis may reverse there)
                    let t_dir = if t == 1.0 { (t_original - 1e-4).max(0.0) } else { t_original };
                    let mut d = merge(&before[i], op.directions(t_dir));
                    if step {
                        // at a reversal the step itself moves the axis the new way
                        d = merge(&d, cp.directions(1.0));
                    }
                    let x = self.actual(&q, cp.tool, &d);
                    let dist = self.nearest(&x, op).1 * 1e3;
                    report.worst_path_um = report.worst_path_um.max(dist);
                    if dist > path_um + sl.path_um {
                        return Err(format!(
                            "corrected move {} ({:?} to {:?}, a piece of original move {} to {:?}) leaves the original path by {dist:.4} um at t = {t}",
                            jj + 1,
                            corrected[jj].kind,
                            cp.end,
                            i + 1,
                            op.end
                        ));
                    }
                }
            }
            report.moves += 1;
            k = k.max(j + 1);
        }
        if k < c.len() {
            let last = &c[k - 1].end;
            if let Some(j) = (k..c.len()).find(|&j| c[j].end.iter().zip(last).any(|(a, b)| (a - b).abs() * 1e3 > end_um)) {
                return Err(format!("corrected move {} has no original move", j + 1));
            }
        }
        Ok(report)
    }
}

/// Whether `machine` has only linear axes.
pub fn linear_only(machine: &Machine) -> bool {
    machine.axes().iter().all(|a| a.kind == AxisKind::Linear)
}
