//! Robust level and scale: the median and the median absolute deviation (MAD) scaled by 1.4826,
//! which estimates the standard deviation of normal data and is unmoved by up to half of the data
//! being wrong (Rousseeuw and Croux 1993); the noise of a smooth series from the MAD of its first
//! differences divided by sqrt 2; Huber weights for iteratively reweighted least squares
//! (Huber 1981, tuning constant 1.345 for 95 % efficiency at normal data).

/// Scales the MAD to a normal standard deviation: 1 / Phi^-1(3/4).
pub const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// The Huber tuning constant (95 % efficiency at normal data).
pub const HUBER_K: f64 = 1.345;

/// The median of the finite values (NaN when there are none).
pub fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// The MAD about the median, scaled to a normal standard deviation.
pub fn mad_sigma(values: &[f64]) -> f64 {
    let m = median(values);
    let deviations: Vec<f64> = values.iter().map(|x| (x - m).abs()).collect();
    MAD_TO_SIGMA * median(&deviations)
}

/// The noise of a series whose signal changes slowly from sample to sample: the MAD of the first
/// differences over sqrt 2 (each difference holds two independent noise terms).
pub fn difference_sigma(values: &[f64]) -> f64 {
    let d: Vec<f64> = values.windows(2).map(|w| w[1] - w[0]).collect();
    mad_sigma(&d) / std::f64::consts::SQRT_2
}

/// The Huber weight of a residual `r` in units of its standard deviation: 1 inside `HUBER_K`,
/// `HUBER_K / |r|` outside.
pub fn huber_weight(r: f64) -> f64 {
    if r.abs() <= HUBER_K {
        1.0
    } else {
        HUBER_K / r.abs()
    }
}

/// The smallest step between distinct values: the resolution the values were written with.
pub fn resolution(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_mad() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        // one gross value does not move the scale
        let s = mad_sigma(&[1.0, 2.0, 3.0, 4.0, 1000.0]);
        assert!((s - MAD_TO_SIGMA).abs() < 1e-12);
    }
}
