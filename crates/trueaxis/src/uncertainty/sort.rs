//! Sorting the trial values of a Monte Carlo output (JCGM 101 §7.5: the discrete representation
//! of the distribution function is the sorted sample) in the order of `f64::total_cmp`, with the
//! result of `sort_unstable_by(f64::total_cmp)` bit for bit: a sorted sequence is unique, so any
//! correct sort gives the same values.
//!
//! (A distribution sort by value, about one value per bucket and insertion sorts, was tried and
//! was 1.2x slower than the radix sort at 30 000 Gaussian values: the insertion sorts mispredict.)

/// Sorts `values` ascending in the order of `f64::total_cmp`: a comparison sort below 8192
/// values (the two tails of a shortest interval, a few sequences' worth), [`radix_sort`] above,
/// where its linear time wins (2-3x at 30 000 values).
pub fn sort_values(values: &mut [f64]) {
    if values.len() < 8192 {
        values.sort_unstable_by(f64::total_cmp);
    } else {
        radix_sort(values);
    }
}

/// Least-significant-digit radix sort of the order-preserving 64-bit keys of `f64::total_cmp`:
/// six passes of 11-bit digits, the counts of all six taken in one pass over the keys, a pass
/// skipped when every key has the same digit. Linear time for any data.
pub fn radix_sort(values: &mut [f64]) {
    const BITS: usize = 11;
    const BUCKETS: usize = 1 << BITS;
    const PASSES: usize = 64usize.div_ceil(BITS);
    // the key of f64::total_cmp: flip every bit of a negative number, the sign bit of a positive one
    let key = |v: f64| {
        let bits = v.to_bits();
        bits ^ ((((bits as i64) >> 63) as u64) | (1 << 63))
    };
    let mut keys: Vec<u64> = values.iter().map(|&v| key(v)).collect();
    let mut counts = vec![[0usize; BUCKETS]; PASSES];
    for k in &keys {
        for (pass, c) in counts.iter_mut().enumerate() {
            c[((k >> (pass * BITS)) as usize) & (BUCKETS - 1)] += 1;
        }
    }
    let mut other = vec![0u64; keys.len()];
    for (pass, c) in counts.iter_mut().enumerate() {
        if c.contains(&keys.len()) {
            continue;
        }
        let mut start = 0;
        for c in c.iter_mut() {
            (*c, start) = (start, start + *c);
        }
        let shift = pass * BITS;
        for &k in &keys {
            let d = ((k >> shift) as usize) & (BUCKETS - 1);
            other[c[d]] = k;
            c[d] += 1;
        }
        std::mem::swap(&mut keys, &mut other);
    }
    for (v, k) in values.iter_mut().zip(&keys) {
        // the inverse of `key`: a key with the top bit set came from a positive number
        let bits = if k >> 63 == 1 { k ^ (1 << 63) } else { !k };
        *v = f64::from_bits(bits);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn same_bits(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    #[test]
    fn both_sorts_equal_the_comparison_sort_bit_for_bit() {
        // signed zeros, subnormals, infinities, equal values, magnitudes from 1e-300 to 1e300
        for n in [0usize, 1, 255, 256, 1000, 30_000] {
            let values: Vec<f64> = (0..n)
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
            for sort in [sort_values, radix_sort] {
                let mut got = values.clone();
                sort(&mut got);
                assert!(same_bits(&got, &want), "n = {n}");
            }
        }
    }

    #[test]
    fn radix_sort_on_finite_samples_with_ties_and_outliers() {
        // Gaussian-like, heavily tied (few distinct values), signed zeros among them, one far
        // outlier, subnormals, sizes around the threshold of sort_values
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for n in [2usize, 256, 257, 999, 8191, 8192, 10_000, 30_001] {
            for case in 0..5 {
                let values: Vec<f64> = (0..n)
                    .map(|i| {
                        let g: f64 = (0..4).map(|_| rng.gen::<f64>()).sum::<f64>() - 2.0;
                        match case {
                            0 => g,
                            1 => (g * 4.0).round() / 4.0,
                            2 => {
                                if i % 3 == 0 {
                                    -0.0
                                } else {
                                    (g * 2.0).round() * 0.0 + g.signum() * 0.0
                                }
                            }
                            3 => {
                                if i == n / 2 {
                                    1e12
                                } else {
                                    g
                                }
                            }
                            _ => 1e-310 * g,
                        }
                    })
                    .collect();
                let mut want = values.clone();
                want.sort_unstable_by(f64::total_cmp);
                let mut got = values;
                radix_sort(&mut got);
                assert!(same_bits(&got, &want), "n = {n}, case {case}");
            }
        }
    }
}
