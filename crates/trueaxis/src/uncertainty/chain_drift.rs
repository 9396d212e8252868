//! Drift of the measurement chain during a measurement (Andolfatto et al. 2011 §4.4): the statistical method of
//! ISO/TR 230-9 and the cyclic method (a periodic drift function of time, a random start time per
//! sequence, each point measured at `t0 + (n - 1) t_m + k t_i`).

use crate::error::Error;
use std::f64::consts::PI;

/// ISO/TR 230-9 (Andolfatto et al. 2011 eq. 11): the standard uncertainty `u_EVE = E_VE / (2 sqrt 3)` of a drift
/// of magnitude (peak to valley) `E_VE`, in the unit of `E_VE`. Table 4: 6.95 um -> 2.00 um.
pub fn statistical_drift_uncertainty(e_ve: f64) -> f64 {
    e_ve / (2.0 * 3f64.sqrt())
}

/// Measurement time of Andolfatto et al. 2011 eq. 12 in s: `t_nk = t0 + (n - 1) t_m + k t_i`, written with the
/// 0-based trial index `trial = n - 1` and the time of the point within one run `point_time = k t_i`.
pub fn measurement_time(t0: f64, trial: usize, run_duration: f64, point_time: f64) -> f64 {
    t0 + trial as f64 * run_duration + point_time
}

/// `x.rem_euclid(period)` bit for bit (`period > 0`), without the software `fmod`: for `x >= 0`
/// the remainder is `x - q period` with the integer quotient `q`, representable, so one fused
/// multiply-add gives it exactly once `q` is right; `floor(x / period)` may be one off by rounding,
/// which the range test corrects. Negative `x` (where `rem_euclid` rounds `fmod + period`) and
/// quotients beyond 2^52 take `rem_euclid`. Unit: that of `x`.
pub fn reduce_to_period(x: f64, period: f64) -> f64 {
    let mut q = (x / period).floor();
    let exact = q < 4_503_599_627_370_496.0 && period > 0.0;
    if x.is_sign_negative() || !exact {
        return x.rem_euclid(period);
    }
    let mut r = (-q).mul_add(period, x);
    if r < 0.0 {
        q -= 1.0;
        r = (-q).mul_add(period, x);
    } else if r >= period {
        q += 1.0;
        r = (-q).mul_add(period, x);
    }
    r
}

/// Where the random start time `t0` of the cyclic drift is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StartPhase {
    /// Once per Monte Carlo sequence, the trials following each other in time (Andolfatto et al. 2011 eq. 12).
    #[default]
    Sequence,
    /// Independently for every trial (each trial a measurement at a random moment of the cycle).
    Trial,
}

/// A periodic drift function of time (um), a trigonometric polynomial of period `T`:
/// `D(t) = sum_k a_k cos(2 pi k t / T) + b_k sin(2 pi k t / T)`, k = 1..K, with zero mean (a drift is a
/// variation about the state at which the machine is measured).
#[derive(Clone, Debug, PartialEq)]
pub struct PeriodicDrift {
    period: f64,
    cos: Vec<f64>,
    sin: Vec<f64>,
}

impl PeriodicDrift {
    fn checked(period: f64, cos: Vec<f64>, sin: Vec<f64>) -> Result<PeriodicDrift, Error> {
        if !(period > 0.0 && period.is_finite()) {
            return Err(Error::input(format!("drift period {period} s must be a positive number")));
        }
        if cos.iter().chain(&sin).any(|v| !v.is_finite()) {
            return Err(Error::input("drift amplitudes must be finite numbers"));
        }
        Ok(PeriodicDrift { period, cos, sin })
    }

    /// `D(t) = (peak_to_valley / 2) sin(2 pi t / T + phase)`, phase in deg.
    pub fn sine(period: f64, peak_to_valley: f64, phase_deg: f64) -> Result<PeriodicDrift, Error> {
        Self::harmonics(period, &[(0.5 * peak_to_valley, phase_deg)])
    }

    /// `D(t) = sum_k A_k sin(2 pi k t / T + phi_k)` from `(A_k, phi_k in deg)`, k = 1, 2, ...
    pub fn harmonics(period: f64, terms: &[(f64, f64)]) -> Result<PeriodicDrift, Error> {
        let cos = terms.iter().map(|(a, phi)| a * phi.to_radians().sin()).collect();
        let sin = terms.iter().map(|(a, phi)| a * phi.to_radians().cos()).collect();
        Self::checked(period, cos, sin)
    }

    /// The trigonometric interpolant of `N >= 2` samples equally spaced over one period, the first at
    /// `t = 0`, after removing their mean: it passes through every (centred) sample.
    pub fn from_samples(period: f64, samples: &[f64]) -> Result<PeriodicDrift, Error> {
        let n = samples.len();
        if n < 2 {
            return Err(Error::input("a drift cycle needs at least 2 samples"));
        }
        let nf = n as f64;
        let (mut cos, mut sin) = (Vec::new(), Vec::new());
        for k in 1..=n / 2 {
            let nyquist = 2 * k == n;
            let weight = if nyquist { 1.0 / nf } else { 2.0 / nf };
            let (mut a, mut b) = (0.0, 0.0);
            for (j, x) in samples.iter().enumerate() {
                let angle = 2.0 * PI * (k * j) as f64 / nf;
                a += x * angle.cos();
                b += x * angle.sin();
            }
            cos.push(weight * a);
            sin.push(if nyquist { 0.0 } else { weight * b });
        }
        Self::checked(period, cos, sin)
    }

    pub fn period(&self) -> f64 {
        self.period
    }

    /// Number of harmonics K.
    pub fn harmonic_count(&self) -> usize {
        self.cos.len()
    }

    /// `(a_k, b_k)` of harmonic `k` (1-based).
    pub fn coefficients(&self, k: usize) -> (f64, f64) {
        (self.cos[k - 1], self.sin[k - 1])
    }

    /// Angular frequency of the fundamental, rad/s.
    pub fn omega(&self) -> f64 {
        2.0 * PI / self.period
    }

    /// `D(t)` in um at time `t` in s.
    pub fn value(&self, t: f64) -> f64 {
        let w = self.omega() * t;
        self.cos
            .iter()
            .zip(&self.sin)
            .enumerate()
            .map(|(i, (a, b))| {
                let kw = (i + 1) as f64 * w;
                a * kw.cos() + b * kw.sin()
            })
            .sum()
    }

    /// Variance of `D` at a uniformly random time: `sum_k (a_k^2 + b_k^2) / 2`.
    pub fn variance(&self) -> f64 {
        self.cos.iter().zip(&self.sin).map(|(a, b)| 0.5 * (a * a + b * b)).sum()
    }

    /// Largest minus smallest value over one period, on a grid of 4096 points (um).
    pub fn peak_to_valley(&self) -> f64 {
        let values = (0..4096).map(|i| self.value(self.period * i as f64 / 4096.0));
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
        hi - lo
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_4_statistical_uncertainties() {
        // Andolfatto et al. 2011 Table 4: E_VE 6.95 / 3.42 / 6.63 um -> u_EVE 2.00 / 0.99 / 1.91 um as printed;
        // 6.95 / (2 sqrt 3) = 2.006 would round to 2.01 (a rounding slip in the table), hence 0.01
        for (e, u) in [(6.95, 2.00), (3.42, 0.99), (6.63, 1.91)] {
            assert!((statistical_drift_uncertainty(e) - u).abs() < 0.01);
        }
        assert!((statistical_drift_uncertainty(6.95) - 2.0063).abs() < 1e-4);
    }

    #[test]
    fn reduction_to_the_period_equals_rem_euclid_bit_for_bit() {
        // the Andolfatto et al. 2011 times t0 + n t_m (t_m = 605.25 s, T = 1000 s) and awkward periods, values
        // on and next to multiples of the period, negative times, signed zeros
        let mut checked = 0;
        for period in [1000.0, 0.1, 1.0 / 3.0, 604.999_999, 7.0e-3, 86_400.0] {
            for t0 in [0.0, -0.0, 0.123_456_789, 333.3, 999.999_999_999_9, -17.5] {
                for n in (0..20_000usize).step_by(7) {
                    let x = t0 + n as f64 * 605.25;
                    for x in [x, -x, x.next_up(), x.next_down(), period * n as f64, (period * n as f64).next_down()] {
                        assert_eq!(reduce_to_period(x, period).to_bits(), x.rem_euclid(period).to_bits(), "x {x:e}, period {period}");
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 500_000);
        assert_eq!(reduce_to_period(1e300, 3.0).to_bits(), 1e300f64.rem_euclid(3.0).to_bits());
    }

    #[test]
    fn sine_and_sample_interpolation() {
        let d = PeriodicDrift::sine(600.0, 7.5, 30.0).unwrap();
        assert!((d.value(0.0) - 3.75 * 0.5).abs() < 1e-12);
        assert!((d.value(150.0) - 3.75 * (PI / 2.0 + PI / 6.0).sin()).abs() < 1e-12);
        assert!((d.peak_to_valley() - 7.5).abs() < 1e-5);
        assert!((d.variance() - 3.75 * 3.75 / 2.0).abs() < 1e-12);
        // a sawtooth cycle of 8 samples: the interpolant passes through the centred samples
        let samples = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 3.0, 1.0];
        let mean = samples.iter().sum::<f64>() / 8.0;
        let p = PeriodicDrift::from_samples(80.0, &samples).unwrap();
        for (j, s) in samples.iter().enumerate() {
            assert!((p.value(10.0 * j as f64) - (s - mean)).abs() < 1e-12, "sample {j}");
        }
        assert!((p.value(80.0 * 3.0 + 30.0) - (3.0 - mean)).abs() < 1e-12, "periodic");
    }
}
