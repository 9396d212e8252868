//! LinuxCNC's NURBS in the XY plane (LinuxCNC 2.9 manual, "G5.2 G5.3 NURBS Block"), converted into
//! straight feed moves (mm or inch, the program's units):
//!
//! - `G5.2 X Y P L` starts collecting control points: the current position is the first (weight 1,
//!   or `P` when the first block has no X Y), each block with X and Y adds one of weight `P` > 0;
//!   `L` sets the order k (3, a quadratic, unless L > 3, as rs274 reads it); the position stays at
//!   the start until the curve runs, so incremental X Y (G91) count from the start;
//! - `G5.3` runs the curve: the non-uniform rational B-spline of order k through the n + 1 control
//!   points P_i with weights w_i on the clamped uniform knot vector t_i = 0 (i < k), i - k + 1
//!   (k <= i <= n), n - k + 2 (i > n) (LinuxCNC's `knot_vector_creator`, Piegl and Tiller 1997,
//!   eq. 4.2), C(u) = sum N_i,k(u) w_i P_i / sum N_i,k(u) w_i, u in [0, n - k + 2]; it ends at the
//!   last control point, and the motion mode is none after it.
//!
//! The curve is split into rational Bézier segments by knot insertion (Boehm 1980: every interior
//! knot raised to multiplicity k - 1) and each segment is halved (de Casteljau in homogeneous
//! coordinates) until its control polygon is within [`CHORD_MM`] of the chord from its first to
//! its last point. With positive weights a rational Bézier segment lies in the convex hull of its
//! control points (Piegl and Tiller 1997, property P4.9), so every chord is within [`CHORD_MM`]
//! of the curve: a bound, not an estimate. LinuxCNC itself runs the curve as biarcs through 4 (n + 1)
//! of its points, which leave it by its own (unstated) amount: the corrected program follows the
//! curve as defined.

use crate::execute::Words;
use crate::interpret::Exec;
use crate::modal::{Motion, PlaneSelect, MM_PER_INCH};
use crate::splines::CHORD_MM;
use crate::trace::Role;

/// At most this many chords per curve.
const MAX_CHORDS: usize = 1_000_000;

/// Halvings of one Bézier segment at most (a segment 2^-40 of its length is flat).
const MAX_DEPTH: u32 = 40;

/// A NURBS being collected between `G5.2` and `G5.3`.
#[derive(Clone, Debug, PartialEq)]
pub struct Pending {
    /// Control points X, Y (program units) and weight.
    pub points: Vec<[f64; 3]>,
    /// The order k (degree k - 1).
    pub order: usize,
    /// The line of the `G5.2` (1-based), for messages.
    pub line: usize,
}

/// `G5.2`: adds the block's control point (and, first, the current position).
pub(crate) fn control_point(exec: &mut Exec, w: &mut Words) -> Result<(), String> {
    if exec.state.plane != PlaneSelect::Xy {
        return Err("G5.2 (NURBS) needs the XY plane (G17)".into());
    }
    let (x, y, p, l) = (w.has(b'X'), w.has(b'Y'), w.take(b'P'), w.take(b'L'));
    if x != y {
        return Err("a NURBS control point (G5.2) needs both X and Y".into());
    }
    let start = exec.state.position;
    if exec.nurbs.is_none() {
        let weight = if !x { p.unwrap_or(1.0) } else { 1.0 };
        if weight <= 0.0 {
            return Err(format!("NURBS weight P{weight} must be positive"));
        }
        exec.nurbs = Some(Pending { points: vec![[start[0], start[1], weight]], order: 3, line: exec.line_number });
    } else if !x && p.is_some() {
        return Err("P without X and Y is the weight of the first control point only (G5.2)".into());
    }
    if let Some(l) = l {
        if l.fract() != 0.0 || !(1.0..=64.0).contains(&l) {
            return Err(format!("NURBS order L{l} must be a whole number up to 64"));
        }
        if l > 3.0 {
            exec.nurbs.as_mut().expect("set above").order = l as usize;
        }
    }
    if x {
        let weight = p.ok_or("every NURBS control point needs its weight P (G5.2)")?;
        if !(weight > 0.0 && weight.is_finite()) {
            return Err(format!("NURBS weight P{weight} must be positive"));
        }
        let end = exec.end_point(w, false)?;
        if (2..end.len()).any(|k| end[k] != start[k]) {
            return Err("a NURBS (G5.2) moves X and Y only".into());
        }
        exec.nurbs.as_mut().expect("set above").points.push([end[0], end[1], weight]);
    }
    exec.state.motion = Motion::Spline(52);
    Ok(())
}

/// `G5.3`: runs the collected curve as chords.
pub(crate) fn finish(exec: &mut Exec, w: &Words) -> Result<(), String> {
    let Some(nurbs) = exec.nurbs.take() else {
        return Err("G5.3 without a G5.2 NURBS before it".into());
    };
    if w.axes().1 {
        return Err("G5.3 takes no axis words (the control points are on the G5.2 lines)".into());
    }
    if nurbs.points.len() < nurbs.order {
        return Err(format!(
            "the NURBS of line {} has {} control points, fewer than its order L = {}",
            nurbs.line,
            nurbs.points.len(),
            nurbs.order
        ));
    }
    let tolerance = CHORD_MM / if exec.state.frame.inch { MM_PER_INCH } else { 1.0 };
    let vertices = chords(&nurbs.points, nurbs.order, tolerance)?;
    if vertices.iter().flatten().any(|v| !v.is_finite()) {
        return Err(format!("the NURBS of line {} cannot be evaluated: its numbers are too large", nurbs.line));
    }
    let start = exec.state.position;
    for v in vertices {
        let mut p = start;
        p[0] = v[0];
        p[1] = v[1];
        exec.straight(false, p, Role::Generated, false, 0)?;
    }
    exec.state.motion = Motion::None;
    Ok(())
}

/// The chord vertices after the first control point of the NURBS of `points` (X, Y, weight) and
/// `order`, each chord within `tolerance` of the curve; the last is the last control point.
pub(crate) fn chords(points: &[[f64; 3]], order: usize, tolerance: f64) -> Result<Vec<[f64; 2]>, String> {
    let mut out = Vec::new();
    for segment in bezier_segments(points, order) {
        halve(&segment, tolerance, 0, &mut out)?;
    }
    if let (Some(last), Some(p)) = (out.last_mut(), points.last()) {
        *last = [p[0], p[1]];
    }
    Ok(out)
}

/// The clamped uniform knot vector of `n + 1` control points and order `k`.
pub fn knots(n: usize, k: usize) -> Vec<f64> {
    (0..=n + k)
        .map(|i| {
            if i < k {
                0.0
            } else if i <= n {
                (i - k + 1) as f64
            } else {
                (n + 2 - k) as f64
            }
        })
        .collect()
}

/// The rational Bézier segments (homogeneous control points w x, w y, w; degree k - 1) of the
/// NURBS, one per knot span, by inserting every interior knot until it has multiplicity k - 1.
fn bezier_segments(points: &[[f64; 3]], order: usize) -> Vec<Vec<[f64; 3]>> {
    let degree = order - 1;
    let mut q: Vec<[f64; 3]> = points.iter().map(|p| [p[0] * p[2], p[1] * p[2], p[2]]).collect();
    let mut t = knots(points.len() - 1, order);
    let spans = points.len() + 1 - order;
    for knot in 1..spans {
        for _ in 1..degree {
            insert(&mut q, &mut t, degree, knot as f64);
        }
    }
    (0..spans).map(|s| q[s * degree..=s * degree + degree].to_vec()).collect()
}

/// Inserts knot `u` once (Boehm 1980): the control points of the span it falls in are blended.
fn insert(q: &mut Vec<[f64; 3]>, t: &mut Vec<f64>, degree: usize, u: f64) {
    let span = (degree..t.len() - degree - 1).rev().find(|&s| t[s] <= u).expect("u inside the knots");
    let mut new = Vec::with_capacity(q.len() + 1);
    new.extend_from_slice(&q[..=span - degree]);
    for i in span - degree + 1..=span {
        let a = (u - t[i]) / (t[i + degree] - t[i]);
        new.push(std::array::from_fn(|c| (1.0 - a) * q[i - 1][c] + a * q[i][c]));
    }
    new.extend_from_slice(&q[span..]);
    *q = new;
    t.insert(span + 1, u);
}

/// Adds the chord ends of one rational Bézier segment to `out`, halving it until flat.
fn halve(h: &[[f64; 3]], tolerance: f64, depth: u32, out: &mut Vec<[f64; 2]>) -> Result<(), String> {
    let p: Vec<[f64; 2]> = h.iter().map(|q| [q[0] / q[2], q[1] / q[2]]).collect();
    let (a, b) = (p[0], p[p.len() - 1]);
    if depth >= MAX_DEPTH || p.iter().all(|&c| distance_to_segment(c, a, b) <= tolerance) {
        if out.len() >= MAX_CHORDS {
            return Err(format!("the NURBS needs more than {MAX_CHORDS} chords within {tolerance} of the curve"));
        }
        out.push(b);
        return Ok(());
    }
    let (left, right) = split(h);
    halve(&left, tolerance, depth + 1, out)?;
    halve(&right, tolerance, depth + 1, out)
}

/// The halves of a Bézier segment at t = 1/2 (de Casteljau, homogeneous coordinates).
fn split(h: &[[f64; 3]]) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let mut level = h.to_vec();
    let (mut left, mut right) = (vec![level[0]], vec![level[level.len() - 1]]);
    while level.len() > 1 {
        level = level.windows(2).map(|w| std::array::from_fn(|c| 0.5 * (w[0][c] + w[1][c]))).collect();
        left.push(level[0]);
        right.push(level[level.len() - 1]);
    }
    right.reverse();
    (left, right)
}

/// The distance of `c` from the segment `a`-`b`.
fn distance_to_segment(c: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let length2 = dx * dx + dy * dy;
    let s = if length2 > 0.0 { (((c[0] - a[0]) * dx + (c[1] - a[1]) * dy) / length2).clamp(0.0, 1.0) } else { 0.0 };
    (c[0] - a[0] - s * dx).hypot(c[1] - a[1] - s * dy)
}
