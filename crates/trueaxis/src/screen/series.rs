//! Checks of one series of readings in the order they were taken:
//! - stuck: runs of identical values where the noise makes repeats improbable. With noise sigma
//!   (from first differences) and resolution q, two successive readings agree with probability
//!   p ~ q / (2 sqrt(pi) sigma); a run of L equal readings among n arises by chance about
//!   n p^(L-1) times. Runs are flagged where that expectation is below 1e-4 (and L >= 4);
//! - outliers from the neighbours: each value against the median of the `NEIGHBOURS` values on
//!   each side (itself left out); flagged beyond `k` robust sigmas of those differences;
//! - steps: the jump between a line through the 3 samples before and one through the 3 after,
//!   both taken to the middle of the interval; flagged beyond `k` robust sigmas of all such jumps
//!   and above a floor where the two lines run parallel (a heat source switched on or off turns
//!   the curve, a re-seated sensor shifts it);
//! - gaps: a sampling interval more than `GAP_FACTOR` times the median interval;
//! - duplicate rows: rows equal in every column to an earlier one.

use super::robust::{difference_sigma, mad_sigma, median, resolution};
use std::collections::HashMap;

/// Neighbours on each side that an outlier is compared with.
pub const NEIGHBOURS: usize = 4;
/// A sampling interval this many times the median interval is a gap.
pub const GAP_FACTOR: f64 = 5.0;
/// The chance expectation below which a run of identical readings is called stuck.
pub const STUCK_EXPECTATION: f64 = 1e-4;

/// Runs of identical successive values `[first, last]` (indices) that noise makes improbable.
pub fn stuck_runs(values: &[f64]) -> Vec<[usize; 2]> {
    let sigma = difference_sigma(values);
    let q = resolution(values);
    if sigma.is_nan() || sigma <= 0.0 || !q.is_finite() {
        return Vec::new();
    }
    let p = (q / (2.0 * std::f64::consts::PI.sqrt() * sigma)).min(0.99);
    let n = values.len() as f64;
    // smallest L with n p^(L-1) < STUCK_EXPECTATION
    let needed = 1.0 + ((STUCK_EXPECTATION / n).ln() / p.ln()).ceil();
    let min_len = (needed.max(4.0) as usize).min(values.len().max(4));
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..=values.len() {
        if i == values.len() || values[i] != values[start] {
            if i - start >= min_len {
                out.push([start, i - 1]);
            }
            start = i;
        }
    }
    out
}

/// Indices of values beyond `k` robust sigmas (and beyond `floor`) from the median of their
/// neighbours, with the size of each difference.
pub fn neighbour_outliers(values: &[f64], k: f64, floor: f64) -> Vec<(usize, f64)> {
    let n = values.len();
    if n < 2 * NEIGHBOURS + 1 {
        return Vec::new();
    }
    let d: Vec<f64> = (0..n)
        .map(|i| {
            let lo = i.saturating_sub(NEIGHBOURS);
            let hi = (i + NEIGHBOURS + 1).min(n);
            let around: Vec<f64> = (lo..hi).filter(|&j| j != i).map(|j| values[j]).collect();
            values[i] - median(&around)
        })
        .collect();
    let sigma = mad_sigma(&d);
    d.iter().enumerate().filter(|(_, v)| v.abs() > (k * sigma).max(floor)).map(|(i, v)| (i, *v)).collect()
}

/// Steps `(index of the last sample before, size)` of a series sampled at times `t`: the jump
/// between lines through 3 samples on each side, beyond `k` robust sigmas of all jumps and `floor`,
/// where the two lines run parallel (their slopes differ by less than half the jump over the 3
/// samples): a shift of the level, as a re-seated sensor makes, and not a change of the heating,
/// as a heat source switched on or off makes (a sensor near it jumps and turns).
pub fn steps(t: &[f64], x: &[f64], k: f64, floor: f64) -> Vec<(usize, f64)> {
    let n = x.len().min(t.len());
    if n < 8 {
        return Vec::new();
    }
    // value at `at` and slope of the line through the samples of `range`
    let line = |range: std::ops::Range<usize>, at: f64| {
        let m = range.len() as f64;
        let (tm, xm) = (range.clone().map(|i| t[i]).sum::<f64>() / m, range.clone().map(|i| x[i]).sum::<f64>() / m);
        let (sxy, sxx) = range.fold((0.0, 0.0), |(a, b), i| (a + (t[i] - tm) * (x[i] - xm), b + (t[i] - tm).powi(2)));
        let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
        (xm + slope * (at - tm), slope)
    };
    // (index, jump, change of slope times the span of 3 samples)
    let jumps: Vec<(usize, f64, f64)> = (2..n - 3)
        .map(|j| {
            let mid = 0.5 * (t[j] + t[j + 1]);
            let ((after, s_after), (before, s_before)) = (line(j + 1..j + 4, mid), line(j - 2..j + 1, mid));
            (j, after - before, (s_after - s_before) * (t[j + 3] - t[j]))
        })
        .collect();
    let sigma = mad_sigma(&jumps.iter().map(|j| j.1).collect::<Vec<_>>());
    let limit = (k * sigma).max(floor);
    // one step bends the lines of its neighbours too: keep the largest jump within 3 samples
    let largest = |i: usize| jumps[i.saturating_sub(3)..(i + 4).min(jumps.len())].iter().all(|o| o.1.abs() <= jumps[i].1.abs());
    (0..jumps.len())
        .filter(|&i| jumps[i].1.abs() > limit && largest(i) && jumps[i].2.abs() < 0.5 * jumps[i].1.abs())
        .map(|i| (jumps[i].0, jumps[i].1))
        .collect()
}

/// Gaps `(index of the last sample before, length in s)`: intervals over `GAP_FACTOR` times the
/// median interval.
pub fn gaps(t: &[f64]) -> Vec<(usize, f64)> {
    let dt: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let typical = median(&dt);
    if typical.is_nan() || typical <= 0.0 {
        return Vec::new();
    }
    dt.iter().enumerate().filter(|(_, d)| **d > GAP_FACTOR * typical).map(|(i, d)| (i, *d)).collect()
}

/// Pairs `(earlier, later)` of row indices whose values are equal in every column.
pub fn duplicate_rows(rows: &[Vec<f64>]) -> Vec<(usize, usize)> {
    let mut seen: HashMap<Vec<u64>, usize> = HashMap::new();
    let mut out = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        let key: Vec<u64> = row.iter().map(|v| if *v == 0.0 { 0 } else { v.to_bits() }).collect();
        match seen.get(&key) {
            Some(&first) => out.push((first, i)),
            None => {
                seen.insert(key, i);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(n: usize, seed: u64) -> Vec<f64> {
        // a small linear congruential generator: uniform sums, roughly normal, sigma ~ 1
        let mut s = seed;
        (0..n)
            .map(|_| {
                (0..12)
                    .map(|_| {
                        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                        (s >> 11) as f64 / (1u64 << 53) as f64
                    })
                    .sum::<f64>()
                    - 6.0
            })
            .map(|v| (v * 1000.0).round() / 1000.0)
            .collect()
    }

    #[test]
    fn stuck_and_outliers() {
        let mut v = noise(300, 1);
        assert!(stuck_runs(&v).is_empty());
        for i in 100..120 {
            v[i] = v[99];
        }
        assert_eq!(stuck_runs(&v), vec![[99, 119]]);
        let mut w = noise(300, 2);
        w[50] += 20.0;
        let o = neighbour_outliers(&w, 6.0, 0.0);
        assert_eq!(o.len(), 1);
        assert_eq!(o[0].0, 50);
    }

    #[test]
    fn steps_and_gaps() {
        let mut t: Vec<f64> = (0..100).map(|i| 60.0 * i as f64).collect();
        let mut x: Vec<f64> = noise(100, 3).iter().map(|v| 0.01 * v + 20.0).collect();
        assert!(steps(&t, &x, 8.0, 0.2).is_empty());
        for v in x.iter_mut().skip(60) {
            *v += 2.0;
        }
        let s = steps(&t, &x, 8.0, 0.2);
        assert_eq!(s.len(), 1);
        assert_eq!(s[0].0, 59);
        assert!((s[0].1 - 2.0).abs() < 0.05);
        for v in t.iter_mut().skip(30) {
            *v += 7200.0;
        }
        assert_eq!(gaps(&t), vec![(29, 7260.0)]);
    }
}
