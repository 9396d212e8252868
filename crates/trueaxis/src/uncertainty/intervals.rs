//! Coverage intervals and summary statistics of a Monte Carlo sample (JCGM 101 §7.5-§7.7).

use super::sort::{order_statistic, sort_values, sorted_tail, End};
use rayon::prelude::*;

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

/// [`symmetric_interval`] of values in any order, by selection instead of a sort (two order
/// statistics, each from the values beyond a sampled threshold; linear time): the same two values.
/// `values` is left as it is (the `&mut` of an earlier form that reordered them is kept).
pub fn symmetric_interval_of_unsorted(values: &mut [f64], p: f64) -> CoverageInterval {
    symmetric_interval_of(values, p)
}

/// [`symmetric_interval_of_unsorted`] of shared values.
pub(super) fn symmetric_interval_of(values: &[f64], p: f64) -> CoverageInterval {
    let m = values.len();
    let q = coverage_count(m, p);
    let r = (m - q).div_ceil(2).clamp(1, m - q);
    CoverageInterval { low: order_statistic(values, r - 1), high: order_statistic(values, r + q - 1) }
}

/// Shortest `p` coverage interval of `sorted` values (JCGM 101 §7.7.2): `[y_(r*), y_(r*+q)]`
/// with `r*` minimising `y_(r+q) - y_(r)` over `r = 1 .. M - q` (the first such `r` on ties).
pub fn shortest_interval(sorted: &[f64], p: f64) -> CoverageInterval {
    let m = sorted.len();
    let q = coverage_count(m, p);
    shortest_of_tails(&sorted[..m - q], &sorted[q..])
}

/// The shortest interval from the `M - q` lowest sorted values and the `M - q` highest: the
/// candidate intervals are `[low[r], high[r]]`.
fn shortest_of_tails(low: &[f64], high: &[f64]) -> CoverageInterval {
    let mut best = 0;
    for r in 1..low.len() {
        if high[r] - low[r] < high[best] - low[best] {
            best = r;
        }
    }
    CoverageInterval { low: low[best], high: high[best] }
}

/// [`shortest_interval`] of values in any order, sorting only the two tails it reads: the
/// `M - q` smallest values (the candidate lower endpoints) and the `M - q` largest (the upper
/// ones), each taken by selection and then sorted; for `p = 0.95` a twentieth of the values each.
/// The same interval as after a full sort; `values` is left as it is. At least 2 values.
pub fn shortest_interval_of_unsorted(values: &[f64], p: f64) -> CoverageInterval {
    coverage_intervals_of_unsorted(values, p).1
}

/// Both coverage intervals of values in any order, `(symmetric, shortest)`: the two sorted tails
/// of [`shortest_interval_of_unsorted`] hold the order statistics of the symmetric interval too.
/// When the tails overlap (`p <= 1/2`) the values are sorted. Bit for bit the intervals of the
/// sorted values.
pub fn coverage_intervals_of_unsorted(values: &[f64], p: f64) -> (CoverageInterval, CoverageInterval) {
    let m = values.len();
    let q = coverage_count(m, p);
    let tail = m - q;
    if 2 * tail >= m {
        let mut sorted = values.to_vec();
        sort_values(&mut sorted);
        return (symmetric_interval(&sorted, p), shortest_interval(&sorted, p));
    }
    let (low, high) = (sorted_tail(values, tail, End::Low), sorted_tail(values, tail, End::High));
    // sorted[r - 1] and sorted[r + q - 1] with r <= M - q: low[r - 1] and high[r - 1]
    let r = tail.div_ceil(2).clamp(1, tail);
    (CoverageInterval { low: low[r - 1], high: high[r - 1] }, shortest_of_tails(&low, &high))
}

/// `kernel` applied to the columns four at a time (the last group padded with its first column,
/// whose extra results are dropped): a kernel over a fixed-size group keeps its side-by-side sums
/// in registers. The results in the order of the columns.
pub(super) fn in_fours<T>(columns: &[&[f64]], kernel: impl Fn([&[f64]; 4]) -> [T; 4]) -> Vec<T> {
    let mut out = Vec::with_capacity(columns.len());
    for group in columns.chunks(4) {
        let four = std::array::from_fn(|k| group.get(k).copied().unwrap_or(group[0]));
        out.extend(kernel(four).into_iter().take(group.len()));
    }
    out
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
        let [moments] = moments([&*values]);
        Self::with(moments, symmetric_interval(values, p), shortest_interval(values, p))
    }

    /// Summaries of several outputs from their values in the order given (each at least 2
    /// values), without sorting them: the sums in that order, four outputs side by side (their
    /// additions overlap instead of each waiting for the previous one), the intervals by
    /// [`coverage_intervals_of_unsorted`]; groups of outputs in parallel. The intervals
    /// equal those of [`SampleSummary::of`] exactly; the moments differ from it only by the
    /// rounding of the summation order.
    pub fn of_unsorted(columns: &[Vec<f64>], p: f64) -> Vec<SampleSummary> {
        let groups: Vec<Vec<SampleSummary>> = columns
            .par_chunks(8)
            .map(|group| {
                let slices: Vec<&[f64]> = group.iter().map(|c| c.as_slice()).collect();
                let moments = if slices.iter().all(|c| c.len() == slices[0].len()) {
                    in_fours(&slices, moments)
                } else {
                    slices.iter().map(|&c| moments([c])[0]).collect()
                };
                group
                    .iter()
                    .zip(moments)
                    .map(|(values, m)| {
                        let (symmetric, shortest) = coverage_intervals_of_unsorted(values, p);
                        Self::with(m, symmetric, shortest)
                    })
                    .collect()
            })
            .collect();
        groups.into_iter().flatten().collect()
    }

    fn with(moments: Moments, symmetric: CoverageInterval, shortest: CoverageInterval) -> SampleSummary {
        let Moments { mean, std_uncertainty, skewness, excess_kurtosis } = moments;
        SampleSummary { mean, std_uncertainty, symmetric, shortest, skewness, excess_kurtosis }
    }
}

/// Mean, standard deviation (divisor `M - 1`), skewness and excess kurtosis of a sample.
#[derive(Clone, Copy, Debug)]
pub(super) struct Moments {
    pub mean: f64,
    pub std_uncertainty: f64,
    pub skewness: f64,
    pub excess_kurtosis: f64,
}

/// The [`Moments`] of `K` samples of one length, their sums side by side; each sum adds its
/// values in the order given, as one sample alone would (the index loops keep the `K` sums side
/// by side).
#[allow(clippy::needless_range_loop)]
pub(super) fn moments<const K: usize>(samples: [&[f64]; K]) -> [Moments; K] {
    let len = samples[0].len();
    let n = len as f64;
    let mut sum = [-0.0f64; K];
    for i in 0..len {
        for k in 0..K {
            sum[k] += samples[k][i];
        }
    }
    let mean = sum.map(|s| s / n);
    let (mut m2, mut m3, mut m4) = ([0.0f64; K], [0.0f64; K], [0.0f64; K]);
    for i in 0..len {
        for k in 0..K {
            let d = samples[k][i] - mean[k];
            let d2 = d * d;
            m2[k] += d2;
            m3[k] += d2 * d;
            m4[k] += d2 * d2;
        }
    }
    std::array::from_fn(|k| {
        let variance = m2[k] / (n - 1.0);
        let (m2n, m3n, m4n) = (m2[k] / n, m3[k] / n, m4[k] / n);
        let (skewness, excess_kurtosis) = if m2n > 0.0 { (m3n / m2n.powf(1.5), m4n / (m2n * m2n) - 3.0) } else { (0.0, 0.0) };
        Moments { mean: mean[k], std_uncertainty: variance.sqrt(), skewness, excess_kurtosis }
    })
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

    /// Test samples: Gaussian-like, rounded to few distinct values (ties), with signed zeros, or
    /// skewed (a cube), from a fixed seed.
    fn sample(m: usize, case: usize, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<f64> {
        use rand::Rng;
        (0..m)
            .map(|_| {
                let g: f64 = (0..4).map(|_| rng.gen::<f64>()).sum::<f64>() - 2.0;
                match case {
                    0 => g,
                    1 => (g * 3.0).round(),
                    2 => (g * 8.0).round() * 0.0 * g.signum(),
                    _ => g * g * g,
                }
            })
            .collect()
    }

    #[test]
    fn selection_and_tail_sorts_give_the_intervals_of_the_full_sort_exactly() {
        use rand::SeedableRng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(23);
        let mut checked = 0;
        for m in [2usize, 3, 4, 5, 7, 10, 19, 20, 21, 99, 100, 101, 255, 256, 1000, 1001, 4999, 10_000, 30_000] {
            for case in 0..4 {
                let values = sample(m, case, &mut rng);
                let mut sorted = values.clone();
                sorted.sort_unstable_by(f64::total_cmp);
                for p in [0.3, 0.5, 0.6, 0.9, 0.95, 0.99, 0.999] {
                    let (want_sym, want_short) = (symmetric_interval(&sorted, p), shortest_interval(&sorted, p));
                    let bits = |c: CoverageInterval| (c.low.to_bits(), c.high.to_bits());
                    let got = symmetric_interval_of_unsorted(&mut values.clone(), p);
                    assert_eq!(bits(got), bits(want_sym), "symmetric: m {m}, case {case}, p {p}");
                    let got = shortest_interval_of_unsorted(&values, p);
                    assert_eq!(bits(got), bits(want_short), "shortest: m {m}, case {case}, p {p}");
                    let (sym, short) = coverage_intervals_of_unsorted(&values, p);
                    assert_eq!((bits(sym), bits(short)), (bits(want_sym), bits(want_short)), "both: m {m}, case {case}, p {p}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 19 * 4 * 7);
    }

    #[test]
    fn summaries_without_sorting_equal_the_sorted_ones() {
        // intervals exactly; the moments summed in another order to 1e-13 of the scale
        use rand::SeedableRng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for outputs in [1usize, 2, 3, 5, 8, 14] {
            let columns: Vec<Vec<f64>> = (0..outputs).map(|j| sample(3001 + 1000 * (j % 2), j % 4, &mut rng)).collect();
            for p in [0.5, 0.95] {
                let together = SampleSummary::of_unsorted(&columns, p);
                for (j, column) in columns.iter().enumerate() {
                    let sorted = SampleSummary::of(&mut column.clone(), p);
                    let (a, b) = (together[j], sorted);
                    assert_eq!((a.symmetric, a.shortest), (b.symmetric, b.shortest), "output {j} of {outputs}, p {p}");
                    let scale = b.std_uncertainty.max(1e-300);
                    assert!((a.mean - b.mean).abs() <= 1e-13 * scale, "mean {} vs {}", a.mean, b.mean);
                    assert!((a.std_uncertainty - b.std_uncertainty).abs() <= 1e-13 * scale);
                    assert!((a.skewness - b.skewness).abs() <= 1e-11 && (a.excess_kurtosis - b.excess_kurtosis).abs() <= 1e-11);
                    // and the plain formulas in the order given, bit for bit
                    let len = column.len() as f64;
                    let mean = column.iter().sum::<f64>() / len;
                    let var = column.iter().map(|v| (v - mean) * (v - mean)).fold(0.0, |s, d| s + d) / (len - 1.0);
                    assert_eq!(a.mean.to_bits(), mean.to_bits());
                    assert_eq!(a.std_uncertainty.to_bits(), var.sqrt().to_bits());
                }
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
