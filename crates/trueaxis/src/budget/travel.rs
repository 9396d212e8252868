//! The travel a configuration needs for a part (Zhu 2008 Table C.2): the largest `|x|`, `|y|`, `|z|`
//! of the linear axes over every point of a part `[0, l] x [0, m] x [0, n]` (a corner on the pivot
//! of the rotary axes) and every position of the two rotary axes, from the inverse of the ideal
//! form-shaping function with a tool of length `p`.
//!
//! For the three categories the linear positions are linear in `cos` and `sin` of the rotary axis
//! nearer the tool (`R2^T R1^T P - p e_z`, `R1^T P - p R2 e_z`, `P - p R1 R2 e_z`), so their largest
//! magnitude over that axis is `|C| + sqrt(A^2 + B^2)` from three evaluations; over the other axis a
//! grid of 1 deg is refined by golden-section search; over the part, the eight corners (a linear
//! function is largest at a corner of a box).
//!
//! Against Table C.2 this reproduces every entry except four of the split category, where the
//! appendix prints `sqrt(p^2 + ...)` for a travel whose exact value is `p + sqrt(...)`: AXYZB Z,
//! BXYZA Z, CXYZA Y, CXYZB X (e.g. AXYZB: `z = -sin(a) m + cos(a) n - cos(b) p` reaches
//! `sqrt(m^2 + n^2) + p` with `b = 180 deg`). The tests check all 36 entries.

use super::configurations::{ideal_pose, Pattern};
use crate::error::Error;
use crate::geometry::Vec3;
use nalgebra::Matrix3;
use std::f64::consts::PI;

/// The linear positions (mm, X Y Z) that put the tool point at `point` (workpiece frame) with the
/// rotary axes at `angles` (rad, in sequence order); `None` if the linear axes do not span space.
pub fn linear_positions(sequence: &[char; 5], angles: [f64; 2], point: &Vec3, tool_length: f64) -> Option<Vec3> {
    let at = |lin: [f64; 3]| -> Vec3 {
        let mut q = [0.0; 5];
        let mut r = 0;
        for (i, c) in sequence.iter().enumerate() {
            match "XYZ".find(*c) {
                Some(k) => q[i] = lin[k],
                None => {
                    q[i] = angles[r];
                    r += 1;
                }
            }
        }
        ideal_pose(sequence, &q, tool_length).0
    };
    let c = at([0.0; 3]);
    let m = Matrix3::from_columns(&[at([1.0, 0.0, 0.0]) - c, at([0.0, 1.0, 0.0]) - c, at([0.0, 0.0, 1.0]) - c]);
    m.try_inverse().map(|inv| inv * (point - c))
}

/// Largest `|coordinate k|` over the part corners and every position of the rotary axis nearer the
/// tool, with the other rotary axis at `first` (rad).
fn inner(sequence: &[char; 5], first: f64, corners: &[Vec3], p: f64, k: usize) -> f64 {
    let mut best: f64 = 0.0;
    for corner in corners {
        let value = |second: f64| linear_positions(sequence, [first, second], corner, p).map_or(0.0, |v| v[k]);
        let (f0, f90, f180) = (value(0.0), value(0.5 * PI), value(PI));
        let c = 0.5 * (f0 + f180);
        let a = 0.5 * (f0 - f180);
        let b = f90 - c;
        best = best.max(c.abs() + a.hypot(b));
    }
    best
}

/// The travel (mm) of X, Y and Z a configuration of one of the three categories needs for a part of
/// `l x m x n` mm with a tool of length `p` mm.
pub fn required_travel(sequence: &[char; 5], part: [f64; 3], tool_length: f64) -> Result<[f64; 3], Error> {
    if Pattern::of(sequence) == Pattern::Mixed {
        return Err(Error::input(format!("{}: travel is computed for the three categories only", sequence.iter().collect::<String>())));
    }
    let corners: Vec<Vec3> =
        (0..8).map(|i| Vec3::new(part[0] * (i & 1) as f64, part[1] * (i >> 1 & 1) as f64, part[2] * (i >> 2 & 1) as f64)).collect();
    let mut travel = [0.0; 3];
    for (k, t) in travel.iter_mut().enumerate() {
        let g = |first: f64| inner(sequence, first, &corners, tool_length, k);
        let steps = 360;
        let h = 2.0 * PI / steps as f64;
        let values: Vec<f64> = (0..steps).map(|i| g(i as f64 * h)).collect();
        let mut best = values.iter().copied().fold(0.0, f64::max);
        // refine the four largest local maxima of the grid by golden-section search
        let mut peaks: Vec<usize> =
            (0..steps).filter(|&i| values[i] >= values[(i + steps - 1) % steps] && values[i] >= values[(i + 1) % steps]).collect();
        peaks.sort_by(|a, b| values[*b].total_cmp(&values[*a]));
        for &i in peaks.iter().take(4) {
            let (mut lo, mut hi) = ((i as f64 - 1.0) * h, (i as f64 + 1.0) * h);
            let ratio = 0.5 * (5f64.sqrt() - 1.0);
            let (mut x1, mut x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
            let (mut g1, mut g2) = (g(x1), g(x2));
            for _ in 0..60 {
                if g1 < g2 {
                    lo = x1;
                    x1 = x2;
                    g1 = g2;
                    x2 = lo + ratio * (hi - lo);
                    g2 = g(x2);
                } else {
                    hi = x2;
                    x2 = x1;
                    g2 = g1;
                    x1 = hi - ratio * (hi - lo);
                    g1 = g(x1);
                }
            }
            best = best.max(g1.max(g2));
        }
        *t = best;
    }
    Ok(travel)
}

/// Space utility: the part's volume over the product of the travels (Zhu 2008 Fig. C.1).
pub fn space_utility(part: [f64; 3], travel: [f64; 3]) -> f64 {
    part.iter().product::<f64>() / travel.iter().product::<f64>()
}
