//! Coverage intervals and summary statistics of a Monte Carlo sample (JCGM 101 §7.5-§7.7).

/// A coverage interval `[low, high]` in the unit of the quantity.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CoverageInterval {
    pub low: f64,
    pub high: f64,
}

impl CoverageInterval {
    pub fn width(&self) -> f64 {
        self.high - self.low
    }
}

/// Number of sorted values spanned by a `p` interval among `m` (JCGM 101 §7.7.1):
/// `q = pM` if that is an integer, otherwise the integer part of `pM + 1/2`.
pub fn coverage_count(m: usize, p: f64) -> usize {
    let pm = p * m as f64;
    let q = if (pm - pm.round()).abs() < 1e-9 { pm.round() } else { (pm + 0.5).floor() };
    (q as usize).min(m.saturating_sub(1))
}

/// Probabilistically symmetric `p` coverage interval of `sorted` values (JCGM 101 §7.7.1):
/// `[y_(r), y_(r+q)]` (1-based) with `r = (M - q) / 2` when that is an integer, otherwise the
/// integer part of `(M - q + 1) / 2`. `sorted` must be in ascending order and hold at least 2 values.
pub fn symmetric_interval(sorted: &[f64], p: f64) -> CoverageInterval {
    let m = sorted.len();
    let q = coverage_count(m, p);
    let r = (m - q).div_ceil(2).clamp(1, m - q);
    CoverageInterval { low: sorted[r - 1], high: sorted[r + q - 1] }
}

/// [`symmetric_interval`] of values in any order, by selection instead of a sort (two calls of
/// `select_nth_unstable`, linear time): the same two order statistics. `values` is reordered.
pub fn symmetric_interval_of_unsorted(values: &mut [f64], p: f64) -> CoverageInterval {
    let m = values.len();
    let q = coverage_count(m, p);
    let r = (m - q).div_ceil(2).clamp(1, m - q);
    let (below, high, _) = values.select_nth_unstable_by(r + q - 1, f64::total_cmp);
    let high = *high;
    let (_, low, _) = below.select_nth_unstable_by(r - 1, f64::total_cmp);
    CoverageInterval { low: *low, high }
}

/// Shortest `p` coverage interval of `sorted` values (JCGM 101 §7.7.2): `[y_(r*), y_(r*+q)]`
/// with `r*` minimising `y_(r+q) - y_(r)` over `r = 1 .. M - q` (the first such `r` on ties).
pub fn shortest_interval(sorted: &[f64], p: f64) -> CoverageInterval {
    let m = sorted.len();
    let q = coverage_count(m, p);
    let mut best = 0;
    for r in 1..m - q {
        if sorted[r + q] - sorted[r] < sorted[best + q] - sorted[best] {
            best = r;
        }
    }
    CoverageInterval { low: sorted[best], high: sorted[best + q] }
}

/// Sorts `values` ascending in the order of `f64::total_cmp`, as `sort_unstable_by(f64::total_cmp)`
/// does, by a least-significant-digit radix sort of their order-preserving 64-bit keys (11-bit
/// digits, a pass skipped when every key has the same digit): linear time, which for the 10^4 to
/// 10^6 trial values of a Monte Carlo output is several times faster than a comparison sort.
pub fn sort_values(values: &mut [f64]) {
    const BITS: u32 = 11;
    const BUCKETS: usize = 1 << BITS;
    if values.len() < 256 {
        values.sort_unstable_by(f64::total_cmp);
        return;
    }
    // the key of f64::total_cmp: flip every bit of a negative number, the sign bit of a positive one
    let key = |v: f64| {
        let bits = v.to_bits();
        bits ^ ((((bits as i64) >> 63) as u64) | (1 << 63))
    };
    let mut keys: Vec<u64> = values.iter().map(|&v| key(v)).collect();
    let mut other = vec![0u64; keys.len()];
    for shift in (0..64).step_by(BITS as usize) {
        let mut counts = [0usize; BUCKETS];
        for k in &keys {
            counts[((k >> shift) as usize) & (BUCKETS - 1)] += 1;
        }
        if counts.contains(&keys.len()) {
            continue;
        }
        let mut start = 0;
        for c in counts.iter_mut() {
            (*c, start) = (start, start + *c);
        }
        for &k in &keys {
            let d = ((k >> shift) as usize) & (BUCKETS - 1);
            other[counts[d]] = k;
            counts[d] += 1;
        }
        std::mem::swap(&mut keys, &mut other);
    }
    for (v, k) in values.iter_mut().zip(&keys) {
        // the inverse of `key`: a key with the top bit set came from a positive number
        let bits = if k >> 63 == 1 { k ^ (1 << 63) } else { !k };
        *v = f64::from_bits(bits);
    }
}

/// Estimate, standard uncertainty and coverage intervals of one output from its sample
/// (JCGM 101 §7.6: mean and standard deviation with `M - 1`), with the skewness and excess
/// kurtosis that tell how far the distribution is from a Gaussian (0 and 0 for a Gaussian;
/// -1.5 excess kurtosis for an arc sine law, -1.2 for a rectangular one).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SampleSummary {
    pub mean: f64,
    pub std_uncertainty: f64,
    pub symmetric: CoverageInterval,
    pub shortest: CoverageInterval,
    pub skewness: f64,
    pub excess_kurtosis: f64,
}

impl SampleSummary {
    /// Summary of `values`, which are sorted in place. Sums run in the sorted order, so the
    /// result does not depend on how the sample was produced. At least 2 values.
    pub fn of(values: &mut [f64], p: f64) -> SampleSummary {
        sort_values(values);
        let sorted: &[f64] = values;
        let n = sorted.len() as f64;
        let mean = sorted.iter().sum::<f64>() / n;
        let (mut m2, mut m3, mut m4) = (0.0, 0.0, 0.0);
        for v in sorted {
            let d = v - mean;
            let d2 = d * d;
            m2 += d2;
            m3 += d2 * d;
            m4 += d2 * d2;
        }
        let variance = m2 / (n - 1.0);
        let (m2n, m3n, m4n) = (m2 / n, m3 / n, m4 / n);
        let (skewness, excess_kurtosis) = if m2n > 0.0 { (m3n / m2n.powf(1.5), m4n / (m2n * m2n) - 3.0) } else { (0.0, 0.0) };
        SampleSummary {
            mean,
            std_uncertainty: variance.sqrt(),
            symmetric: symmetric_interval(sorted, p),
            shortest: shortest_interval(sorted, p),
            skewness,
            excess_kurtosis,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jcgm_101_indices_on_1_to_100() {
        // M = 100 values 1..100, p = 0.95: q = 95, r = (100 - 95 + 1) / 2 = 3 -> [3, 98]
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(coverage_count(100, 0.95), 95);
        assert_eq!(symmetric_interval(&v, 0.95), CoverageInterval { low: 3.0, high: 98.0 });
        // M = 1000, p = 0.95: q = 950, r = 25 -> [25, 975]
        let v: Vec<f64> = (1..=1000).map(f64::from).collect();
        assert_eq!(symmetric_interval(&v, 0.95), CoverageInterval { low: 25.0, high: 975.0 });
    }

    #[test]
    fn radix_sort_equals_the_comparison_sort_bit_for_bit() {
        // signed zeros, subnormals, infinities, equal values, magnitudes from 1e-300 to 1e300
        for n in [0usize, 1, 255, 256, 1000, 30_000] {
            let mut values: Vec<f64> = (0..n)
                .map(|i| {
                    let u = ((i as f64 * 0.618_033_988_749_895).fract() - 0.5) * 2.0;
                    match i % 11 {
                        0 => 0.0,
                        1 => -0.0,
                        2 => f64::MIN_POSITIVE * u / 4.0,
                        3 => {
                            if u > 0.0 {
                                f64::INFINITY
                            } else {
                                f64::NEG_INFINITY
                            }
                        }
                        4 => 1.5,
                        _ => u * 10f64.powi((i % 601) as i32 - 300),
                    }
                })
                .collect();
            let mut want = values.clone();
            want.sort_unstable_by(f64::total_cmp);
            sort_values(&mut values);
            assert!(values.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()), "n = {n}");
        }
    }

    #[test]
    fn selection_gives_the_interval_of_the_sorted_values() {
        // shuffled 1..=m, repeated values and negative ones, several m and p
        for m in [2usize, 3, 10, 101, 1000, 10_000] {
            for p in [0.5, 0.9, 0.95, 0.99] {
                let mut values: Vec<f64> = (0..m).map(|i| ((i * 7919) % m) as f64 * 0.5 - (i % 3) as f64 * 100.0).collect();
                let mut sorted = values.clone();
                sorted.sort_by(f64::total_cmp);
                assert_eq!(symmetric_interval_of_unsorted(&mut values, p), symmetric_interval(&sorted, p), "m {m}, p {p}");
            }
        }
    }

    #[test]
    fn shortest_interval_finds_the_dense_part() {
        // values crowd near 0 on one side: the shortest interval starts at the first value
        let mut v: Vec<f64> = (0..1000).map(|i| (i as f64 / 1000.0).powi(3)).collect();
        v.sort_by(f64::total_cmp);
        let s = shortest_interval(&v, 0.9);
        assert_eq!(s.low, 0.0);
        assert!((s.high - (900.0f64 / 1000.0).powi(3)).abs() < 1e-12);
        assert!(s.width() < symmetric_interval(&v, 0.9).width());
    }
}
