//! Points along a programmed move (straight line in axis space, or a
//! circular / helical arc in its plane with the other axes interpolated linearly), and the choice of
//! split points where the correction varies along the move more than a tolerance.

use crate::trace::{Move, MoveKind};
use std::f64::consts::TAU;

/// Start angle, sweep (signed, rad; counterclockwise positive in the plane's first/second axes),
/// start and end radii of an arc move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcGeometry {
    pub start_angle: f64,
    pub sweep: f64,
    pub start_radius: f64,
    pub end_radius: f64,
}

/// The geometry of an arc move (`None` for lines). Start = end in the plane is a full circle.
pub fn arc_geometry(m: &Move) -> Option<ArcGeometry> {
    let MoveKind::Arc { clockwise, plane, centre, .. } = m.kind else { return None };
    let rel = |p: &[f64]| (p[plane.first] - centre[0], p[plane.second] - centre[1]);
    let (sx, sy) = rel(&m.start);
    let (ex, ey) = rel(&m.end);
    let (a0, a1) = (sy.atan2(sx), ey.atan2(ex));
    let closed = (m.start[plane.first] - m.end[plane.first]).abs() < 1e-9 && (m.start[plane.second] - m.end[plane.second]).abs() < 1e-9;
    let ccw = if closed { TAU } else { (a1 - a0).rem_euclid(TAU) };
    let sweep = if clockwise { -(if closed { TAU } else { (a0 - a1).rem_euclid(TAU) }) } else { ccw };
    Some(ArcGeometry { start_angle: a0, sweep, start_radius: sx.hypot(sy), end_radius: ex.hypot(ey) })
}

/// Machine position at parameter `t` in [0, 1] along the move (mm, deg), into `out`.
pub fn point_at(m: &Move, arc: Option<&ArcGeometry>, t: f64, out: &mut [f64]) {
    for (k, o) in out.iter_mut().enumerate() {
        *o = m.start[k] + t * (m.end[k] - m.start[k]);
    }
    if let (Some(g), MoveKind::Arc { plane, centre, .. }) = (arc, m.kind) {
        if t >= 1.0 {
            let n = out.len();
            out.copy_from_slice(&m.end[..n]);
            return;
        }
        let angle = g.start_angle + t * g.sweep;
        let r = g.start_radius + t * (g.end_radius - g.start_radius);
        out[plane.first] = centre[0] + r * angle.cos();
        out[plane.second] = centre[1] + r * angle.sin();
    }
}

/// Shortest piece, as a fraction of the move, that is still split.
pub const MIN_PIECE: f64 = 1e-6;

/// The pieces of a move: the parameter of each piece's end and the correction there (mm or deg per
/// axis).
pub type Pieces = Vec<(f64, Vec<f64>)>;

/// How far correction `b` is from `a`, in tolerances: the length of the vector of the linear axes'
/// differences, or the largest rotary one (`tolerance(axis)`: the axis's tolerance and whether it
/// is linear).
pub fn departure(a: &[f64], b: &[f64], tolerance: &dyn Fn(usize) -> (f64, bool)) -> f64 {
    let (mut linear, mut worst) = (0.0, 0.0f64);
    for k in 0..a.len() {
        let (tol, is_linear) = tolerance(k);
        let d = (b[k] - a[k]) / tol;
        if is_linear {
            linear += d * d;
        } else {
            worst = worst.max(d.abs());
        }
    }
    worst.max(linear.sqrt())
}

/// Parameters `0 < t_1 < ... < t_k = 1` of the pieces such that, on every piece, the correction
/// `correction(t)` (one value per axis, mm or deg) departs from the straight blend of its values at
/// the piece ends by at most the tolerance, checked at the quarter points of each piece
/// (`tolerance(axis)` gives an axis's tolerance and whether it is linear: the departures of the
/// linear axes count together, as the length of their vector, so that the tool point stays within
/// the tolerance of the path; a rotary axis counts alone)
/// (recursive bisection); each with the correction at its end. A piece shorter than
/// [`MIN_PIECE`] of the move is accepted as it is: the correction jumps there (a discontinuous
/// error model; the pose correction itself is continuous, also through 5-axis singularities), and
/// the jump becomes a short piece of its own instead of endless splitting. `Ok(None)` when more than
/// `max_pieces` would be needed; an error of `correction` is passed on.
pub fn split_points<E>(
    correction: &mut dyn FnMut(f64) -> Result<Vec<f64>, E>,
    tolerance: &dyn Fn(usize) -> (f64, bool),
    max_pieces: usize,
) -> Result<Option<Pieces>, E> {
    Ok(split_from(correction, tolerance, max_pieces)?.map(|(_, p)| p))
}

/// [`split_points`] with the correction at the start of the move as well.
pub fn split_from<E>(
    correction: &mut dyn FnMut(f64) -> Result<Vec<f64>, E>,
    tolerance: &dyn Fn(usize) -> (f64, bool),
    max_pieces: usize,
) -> Result<Option<(Vec<f64>, Pieces)>, E> {
    let c0 = correction(0.0)?;
    let c1 = correction(1.0)?;
    let mut pieces = Vec::new();
    let mut stack = vec![(0.0, 1.0, c0.clone(), c1)];
    // depth-first, right half pushed first so pieces come out in order
    while let Some((a, b, ca, cb)) = stack.pop() {
        let mut worst: f64 = 0.0;
        let mut mid = None;
        for f in [0.25, 0.5, 0.75] {
            let t = a + f * (b - a);
            let c = correction(t)?;
            let blend: Vec<f64> = ca.iter().zip(&cb).map(|(a, b)| a + f * (b - a)).collect();
            worst = worst.max(departure(&blend, &c, tolerance));
            if f == 0.5 {
                mid = Some(c);
            }
        }
        if worst <= 1.0 || b - a < MIN_PIECE {
            pieces.push((b, cb));
        } else {
            if pieces.len() + stack.len() + 2 > max_pieces {
                return Ok(None);
            }
            let cm = mid.expect("mid point sampled");
            let t = 0.5 * (a + b);
            stack.push((t, b, cm.clone(), cb));
            stack.push((a, t, ca, cm));
        }
    }
    Ok(Some((c0, pieces)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bisection_meets_the_tolerance_of_a_quadratic() {
        // c(t) = t^2 (mm): the deviation from the chord over a piece of length h is h^2 / 4 at its
        // middle, so a tolerance of 1e-3 needs h <= 0.0632: 16 pieces of 1/16
        let mut f = |t: f64| Ok::<_, ()>(vec![t * t]);
        let split = split_points(&mut f, &|_| (1e-3, true), 1000).unwrap().unwrap();
        let pieces: Vec<f64> = split.iter().map(|p| p.0).collect();
        assert_eq!(pieces.len(), 16);
        assert!((pieces[0] - 1.0 / 16.0).abs() < 1e-15);
        assert_eq!(*pieces.last().unwrap(), 1.0);
        // the correction at every piece end is the function there
        assert!(split.iter().all(|(t, c)| c[0] == t * t));
        let mut g = |t: f64| Ok::<_, ()>(vec![t * t]);
        assert_eq!(split_points(&mut g, &|_| (1e-9, true), 50), Ok(None));
        let mut line = |t: f64| Ok::<_, ()>(vec![3.0 * t - 1.0]);
        assert_eq!(split_points(&mut line, &|_| (1e-12, true), 10), Ok(Some(vec![(1.0, vec![2.0])])));
        let mut failing = |t: f64| if t > 0.6 { Err("beyond") } else { Ok(vec![t]) };
        assert_eq!(split_points(&mut failing, &|_| (1e-3, true), 10), Err("beyond"));
    }

    #[test]
    fn a_jump_of_the_correction_is_isolated_in_a_short_piece() {
        // a step of 1 mm at t = 0.3: bisection narrows it down to a piece shorter than MIN_PIECE
        let mut step = |t: f64| Ok::<_, ()>(vec![if t < 0.3 { 0.0 } else { 1.0 }]);
        let pieces: Vec<f64> = split_points(&mut step, &|_| (1e-3, true), 1000).unwrap().unwrap().iter().map(|p| p.0).collect();
        assert!(pieces.len() < 2 * 22, "{} pieces", pieces.len());
        let jump = pieces.windows(2).find(|w| w[0] < 0.3 && w[1] >= 0.3).expect("a piece holds the step");
        assert!(jump[1] - jump[0] < MIN_PIECE);
        assert_eq!(*pieces.last().unwrap(), 1.0);
    }
}
