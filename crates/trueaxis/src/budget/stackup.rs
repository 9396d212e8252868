//! Stack-up of component tolerances into the volumetric error (Zhu 2008 eqs. B.3-B.4):
//! root-sum-square `VE_i = sqrt(sum_j (SE_ij e_j)^2)` (independent zero-mean errors of standard
//! deviation `e_j`) and worst case `VE_i = sum_j |SE_ij| e_j` (every error at its limit with the worst
//! sign), per direction, and for the 3D error vector: its root-sum-square length
//! `sqrt(VE_x^2 + VE_y^2 + VE_z^2)` and the largest length any combination of signs can give.

use crate::geometry::Vec3;
use serde::Serialize;

/// The stack-up at one pose (um).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StackUp {
    /// Root-sum-square per direction x, y, z.
    pub rss: [f64; 3],
    /// Root-sum-square length of the 3D error, `sqrt(sum_j |SE_:j e_j|^2)`.
    pub rss_total: f64,
    /// Worst case per direction.
    pub worst: [f64; 3],
    /// The largest length of the 3D error over every combination of signs of the components.
    pub worst_total: f64,
}

/// The stack-up of tolerances `t` (um, urad) through one pose's `3 x n` sensitivity matrix `s`
/// (row-major).
pub fn stack_up(s: &[f64], t: &[f64]) -> StackUp {
    let n = t.len();
    let mut rss = [0.0; 3];
    let mut worst = [0.0; 3];
    for d in 0..3 {
        let row = &s[d * n..(d + 1) * n];
        rss[d] = row.iter().zip(t).map(|(g, e)| (g * e).powi(2)).sum::<f64>().sqrt();
        worst[d] = row.iter().zip(t).map(|(g, e)| g.abs() * e).sum();
    }
    let generators: Vec<Vec3> = (0..n).map(|j| Vec3::new(s[j], s[n + j], s[2 * n + j]) * t[j]).collect();
    StackUp { rss, rss_total: (rss[0].powi(2) + rss[1].powi(2) + rss[2].powi(2)).sqrt(), worst, worst_total: worst_case(&generators).0 }
}

/// The largest length of `sum_j s_j g_j` over signs `s_j = +-1`, and signs that reach it: the
/// farthest vertex from the origin of the zonotope spanned by the generators `g_j`.
///
/// Exact method: a vertex maximises `u . x` for a direction `u` inside its normal cone, a cell of the
/// arrangement of the planes `u . g_j = 0` on the sphere; every cell has a corner `u0` on the line
/// `g_a x g_b` of two generators. Around such a corner, the generators off the plane of `g_a, g_b` take
/// the sign of `u0 . g_j` and those in the plane run through the vertices of their 2D zonotope (sorted
/// by angle, flipped one at a time). Parallel generators are merged first. `O(m^3)` for `m` distinct
/// directions; the tests compare it with all `2^n` sign combinations.
pub fn worst_case(generators: &[Vec3]) -> (f64, Vec<f64>) {
    let n = generators.len();
    let mut signs = vec![1.0; n];
    let largest = generators.iter().map(|g| g.norm()).fold(0.0, f64::max);
    if largest == 0.0 {
        return (0.0, signs);
    }
    // merged directions: the sum of the aligned members, and (member, +-1) per direction
    let mut merged: Vec<(Vec3, Vec<(usize, f64)>)> = Vec::new();
    for (j, g) in generators.iter().enumerate() {
        if g.norm() <= 1e-14 * largest {
            continue;
        }
        match merged.iter_mut().find(|(h, _)| g.cross(h).norm() <= 1e-12 * g.norm() * h.norm()) {
            Some((h, members)) => {
                let s = if g.dot(h) >= 0.0 { 1.0 } else { -1.0 };
                *h += g * s;
                members.push((j, s));
            }
            None => merged.push((*g, vec![(j, 1.0)])),
        }
    }
    let m = merged.len();
    let mut best = (-1.0, vec![1.0; m]);
    let mut consider = |merged_signs: &[f64]| {
        let v: Vec3 = merged.iter().zip(merged_signs).map(|((h, _), s)| h * *s).sum();
        if v.norm() > best.0 {
            best = (v.norm(), merged_signs.to_vec());
        }
    };
    if m == 1 {
        consider(&[1.0]);
    }
    let mut s = vec![0.0; m];
    for a in 0..m {
        for b in a + 1..m {
            let normal = merged[a].0.cross(&merged[b].0);
            if normal.norm() == 0.0 {
                continue;
            }
            let normal = normal.normalize();
            for u in [normal, -normal] {
                let e1 = merged[a].0.normalize();
                let e2 = u.cross(&e1);
                let mut plane: Vec<(f64, usize)> = Vec::new();
                for (k, (h, _)) in merged.iter().enumerate() {
                    let along = u.dot(h);
                    if along.abs() <= 1e-12 * h.norm() {
                        // angle in [0, pi) of the generator, flipped into the upper half plane
                        let (x, y) = (h.dot(&e1), h.dot(&e2));
                        let angle = y.atan2(x).rem_euclid(std::f64::consts::PI);
                        plane.push((angle, k));
                        s[k] = -1.0;
                        // the sign that points it into the upper half plane
                        if y < 0.0 || (y == 0.0 && x < 0.0) {
                            s[k] = 1.0;
                        }
                    } else {
                        s[k] = along.signum();
                    }
                }
                plane.sort_by(|p, q| p.0.total_cmp(&q.0));
                consider(&s);
                for pass in 0..2 {
                    for &(_, k) in &plane {
                        s[k] = -s[k];
                        if pass == 0 || k != plane[plane.len() - 1].1 {
                            consider(&s);
                        }
                    }
                }
            }
        }
    }
    for ((_, members), sign) in merged.iter().zip(&best.1) {
        for &(j, aligned) in members {
            signs[j] = sign * aligned;
        }
    }
    (best.0.max(0.0), signs)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_force(g: &[Vec3]) -> f64 {
        (0..1u32 << g.len())
            .map(|mask| g.iter().enumerate().map(|(j, v)| if mask >> j & 1 == 1 { *v } else { -v }).sum::<Vec3>().norm())
            .fold(0.0, f64::max)
    }

    #[test]
    fn worst_case_equals_every_sign_combination() {
        let mut state = 7_u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for trial in 0..40 {
            let n = 1 + trial % 11;
            let mut g: Vec<Vec3> = (0..n).map(|_| Vec3::new(next(), next(), next())).collect();
            if trial % 3 == 0 {
                // ties: coordinate-aligned and parallel generators, as on real machines
                for (j, v) in g.iter_mut().enumerate() {
                    v[j % 3] = 0.0;
                }
                g.push(g[0] * -2.0);
            }
            if trial % 5 == 0 {
                for v in g.iter_mut() {
                    v.z = 0.0; // all in one plane
                }
            }
            let (value, signs) = worst_case(&g);
            let exact = brute_force(&g);
            assert!((value - exact).abs() <= 1e-12 * exact.max(1.0), "trial {trial}: {value} vs {exact}");
            let reached: Vec3 = g.iter().zip(&signs).map(|(v, s)| v * *s).sum();
            assert!((reached.norm() - value).abs() <= 1e-12 * value.max(1.0));
        }
    }
}
