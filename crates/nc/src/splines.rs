//! LinuxCNC's splines in the XY plane (LinuxCNC 2.9 manual, "G5 Cubic spline" and "G5.1 Quadratic
//! spline"), converted into straight feed moves (mm or inch, the program's units):
//!
//! - `G5 X Y I J P Q`: the cubic Bézier curve from the start S through the control points
//!   C1 = S + (I, J) and C2 = E + (P, Q) to the end E; without I J after another G5, C1 is the
//!   start mirrored through the previous C2 (I J = -(P, Q) of the previous G5: a smooth joint);
//! - `G5.1 X Y I J`: the quadratic Bézier curve through C = S + (I, J).
//!
//! LinuxCNC runs each as one NURBS of these control points (`NURBS_FEED`), which is this Bézier
//! curve. The chords leave the curve by at most [`CHORD_MM`]: the distance of a chord of
//! parameter length h from its arc is at most h^2 max|B''| / 8, and |B''| is at most
//! 6 max(|P0 - 2 P1 + P2|, |P1 - 2 P2 + P3|) on a cubic, 2 |P0 - 2 P1 + P2| on a quadratic.

use crate::execute::Words;
use crate::interpret::Exec;
use crate::modal::{Motion, PlaneSelect, MM_PER_INCH};
use crate::trace::Role;

/// The largest distance of a chord from the curve (mm).
pub const CHORD_MM: f64 = 0.001;

/// At most this many chords per spline.
const MAX_CHORDS: usize = 1_000_000;

/// Runs `G5` (`code` 50) or `G5.1` (51) of the block as chords.
pub(crate) fn spline(exec: &mut Exec, code: u16, w: &mut Words) -> Result<(), String> {
    let name = if code == 50 { "G5" } else { "G5.1" };
    if exec.state.plane != PlaneSelect::Xy {
        return Err(format!("{name} needs the XY plane (G17)"));
    }
    let start = exec.state.position;
    let (i, j) = (w.take(b'I'), w.take(b'J'));
    let (p, q) = if code == 50 { (w.take(b'P'), w.take(b'Q')) } else { (None, None) };
    let end = exec.end_point(w, false)?;
    if (2..end.len()).any(|k| end[k] != start[k]) {
        return Err(format!("{name} moves X and Y only"));
    }
    let s = [start[0], start[1]];
    let e = [end[0], end[1]];
    let controls: Vec<[f64; 2]> = if code == 50 {
        let (Some(p), Some(q)) = (p, q) else { return Err("G5 needs both P and Q".into()) };
        let (i, j) = match (i, j, exec.state.motion, exec.spline_pq) {
            (None, None, Motion::Spline(50), Some((pp, pq))) => (-pp, -pq),
            (None, None, _, _) => return Err("G5 needs I and J unless it follows another G5".into()),
            (i, j, _, _) => (i.unwrap_or(0.0), j.unwrap_or(0.0)),
        };
        exec.spline_pq = Some((p, q));
        vec![s, [s[0] + i, s[1] + j], [e[0] + p, e[1] + q], e]
    } else {
        let (i, j) = (i.unwrap_or(0.0), j.unwrap_or(0.0));
        if i == 0.0 && j == 0.0 {
            return Err("G5.1 needs I or J (the control point's offset from the start)".into());
        }
        vec![s, [s[0] + i, s[1] + j], e]
    };
    let tolerance = CHORD_MM / if exec.state.frame.inch { MM_PER_INCH } else { 1.0 };
    let n = chords(&controls, tolerance);
    for k in 1..=n {
        let t = k as f64 / n as f64;
        let b = bezier(&controls, t);
        let mut p = start;
        p[0] = b[0];
        p[1] = b[1];
        exec.straight(false, p, Role::Generated, false, 0)?;
    }
    exec.state.motion = Motion::Spline(code);
    Ok(())
}

/// The number of chords within `tolerance` of the curve of `controls`.
pub fn chords(controls: &[[f64; 2]], tolerance: f64) -> usize {
    let second = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| (a[0] - 2.0 * b[0] + c[0]).hypot(a[1] - 2.0 * b[1] + c[1]);
    let bound = if controls.len() == 4 {
        6.0 * second(controls[0], controls[1], controls[2]).max(second(controls[1], controls[2], controls[3]))
    } else {
        2.0 * second(controls[0], controls[1], controls[2])
    };
    ((bound / (8.0 * tolerance)).sqrt().ceil() as usize).clamp(1, MAX_CHORDS)
}

/// The Bézier curve of `controls` at `t` (de Casteljau).
pub fn bezier(controls: &[[f64; 2]], t: f64) -> [f64; 2] {
    let mut p = controls.to_vec();
    while p.len() > 1 {
        p = p.windows(2).map(|w| [w[0][0] + t * (w[1][0] - w[0][0]), w[0][1] + t * (w[1][1] - w[0][1])]).collect();
    }
    p[0]
}
