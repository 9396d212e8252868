//! Steady values of a sampled instrument stream: one reading per pose from a continuous recording.
//!
//! A 3D-ball test (CapBall, R-test) records its sensors continuously, 1000 samples per second in
//! Andolfatto et al. 2011 §3.4, while the machine moves from pose to pose with an exact stop and a dwell at each
//! one. The reading of a pose is the mean of the sensors over its dwell, once the move and its
//! settling are over (Andolfatto et al. 2011: "a steady value algorithm"). Here a sample is steady when the
//! window of `window` samples starting at it has a peak-to-peak range of at most `max_range_um` on
//! every channel; the windows that are steady, taken together, make the plateaus; a plateau
//! shorter than `min_samples` is a pause of the move, not a dwell. Each plateau loses `trim`
//! samples at each end (the last of the settling, the start of the next move) and gives the mean
//! and the standard deviation of the rest.
//!
//! Units: whatever the channels carry (um for 3D-ball sensors); sample counts for durations.

use std::collections::VecDeque;

/// How steady a dwell must be.
#[derive(Clone, Debug, PartialEq)]
pub struct SteadySettings {
    /// Samples of the sliding window (e.g. 0.1 s worth).
    pub window: usize,
    /// Largest peak-to-peak range within a window on any channel (um), a few standard deviations
    /// of the sensor noise.
    pub max_range_um: f64,
    /// Fewest steady samples that make a dwell.
    pub min_samples: usize,
    /// Samples dropped at each end of a plateau before averaging.
    pub trim: usize,
}

impl SteadySettings {
    /// Settings for a stream at `sample_rate_hz` with sensor noise of standard deviation
    /// `noise_um`: a 0.1 s window, a range of 8 noise standard deviations (white noise over a few
    /// hundred samples spans about 6), dwells of at least 0.3 s, 0.02 s trimmed at each end.
    pub fn for_stream(sample_rate_hz: f64, noise_um: f64) -> SteadySettings {
        let samples = |s: f64| ((s * sample_rate_hz).round() as usize).max(1);
        SteadySettings { window: samples(0.1).max(3), max_range_um: 8.0 * noise_um, min_samples: samples(0.3), trim: samples(0.02) }
    }
}

/// One dwell found in the stream.
#[derive(Clone, Debug, PartialEq)]
pub struct Plateau {
    /// First and one-past-last sample of the steady stretch (before trimming).
    pub start: usize,
    pub end: usize,
    /// Mean and standard deviation of each channel over the trimmed stretch.
    pub mean: Vec<f64>,
    pub std: Vec<f64>,
}

/// The plateaus of a stream of channels of equal length (e.g. dx, dy, dz), in recording order.
pub fn plateaus(channels: &[&[f64]], settings: &SteadySettings) -> crate::error::Result<Vec<Plateau>> {
    let bad = |m: String| Err(crate::Error::input(m));
    let Some(n) = channels.first().map(|c| c.len()) else { return bad("no channel given".into()) };
    if channels.iter().any(|c| c.len() != n) {
        return bad("the channels have different lengths".into());
    }
    for (k, c) in channels.iter().enumerate() {
        if let Some(i) = c.iter().position(|v| !v.is_finite()) {
            return bad(format!("channel {}: sample {} is not a number", k + 1, i + 1));
        }
    }
    let s = settings;
    if s.window < 2 || !(s.max_range_um.is_finite() && s.max_range_um > 0.0) || s.min_samples < s.window || 2 * s.trim >= s.min_samples {
        return bad(format!(
            "steady settings: window {} (>= 2), range {} um (> 0), shortest dwell {} samples (>= the window), trim {} (less than half the shortest dwell)",
            s.window, s.max_range_um, s.min_samples, s.trim
        ));
    }
    if n < s.window {
        return Ok(Vec::new());
    }
    // steady[i]: the window [i, i + window) is within the range on every channel
    let mut steady = vec![true; n - s.window + 1];
    for c in channels {
        for (i, range) in window_ranges(c, s.window).into_iter().enumerate() {
            steady[i] &= range <= s.max_range_um;
        }
    }
    let mut out = Vec::new();
    let mut i = 0;
    while i < steady.len() {
        if !steady[i] {
            i += 1;
            continue;
        }
        let first = i;
        while i < steady.len() && steady[i] {
            i += 1;
        }
        // windows first..i are steady: samples first .. i - 1 + window
        let (start, end) = (first, i - 1 + s.window);
        if end - start >= s.min_samples {
            let (a, b) = (start + s.trim, end - s.trim);
            let m = (b - a) as f64;
            let mean: Vec<f64> = channels.iter().map(|c| c[a..b].iter().sum::<f64>() / m).collect();
            let std = channels
                .iter()
                .zip(&mean)
                .map(|(c, mu)| (c[a..b].iter().map(|v| (v - mu).powi(2)).sum::<f64>() / (m - 1.0).max(1.0)).sqrt())
                .collect();
            out.push(Plateau { start, end, mean, std });
        }
    }
    Ok(out)
}

/// The plateaus of a stream that must hold exactly one dwell per pose: `poses` of them, else an
/// error that says how many were found and what to change.
pub fn steady_values(channels: &[&[f64]], settings: &SteadySettings, poses: usize) -> crate::error::Result<Vec<Plateau>> {
    let found = plateaus(channels, settings)?;
    if found.len() == poses {
        return Ok(found);
    }
    let lengths: Vec<usize> = found.iter().map(|p| p.end - p.start).collect();
    let (shortest, longest) = (lengths.iter().min().copied().unwrap_or(0), lengths.iter().max().copied().unwrap_or(0));
    let advice = if found.len() > poses {
        format!("the moves pause or the dwells split: raise the shortest dwell above {shortest} samples or lower the range")
    } else {
        format!(
            "some dwells are not steady within {} um over {} samples: raise the range (noise, drift) or shorten the window, or check that every pose was recorded",
            settings.max_range_um, settings.window
        )
    };
    Err(crate::Error::input(format!(
        "{} steady stretches found for {poses} poses (from {shortest} to {longest} samples long): {advice}",
        found.len()
    )))
}

/// Peak-to-peak range of every window of `w` consecutive samples (monotonic queues, O(n)).
fn window_ranges(x: &[f64], w: usize) -> Vec<f64> {
    let (mut lo, mut hi): (VecDeque<usize>, VecDeque<usize>) = (VecDeque::new(), VecDeque::new());
    let mut out = Vec::with_capacity(x.len() + 1 - w);
    for (i, &v) in x.iter().enumerate() {
        while lo.back().is_some_and(|&j| x[j] >= v) {
            lo.pop_back();
        }
        while hi.back().is_some_and(|&j| x[j] <= v) {
            hi.pop_back();
        }
        lo.push_back(i);
        hi.push_back(i);
        if i + 1 >= w {
            let first = i + 1 - w;
            while lo.front().is_some_and(|&j| j < first) {
                lo.pop_front();
            }
            while hi.front().is_some_and(|&j| j < first) {
                hi.pop_front();
            }
            out.push(x[hi[0]] - x[lo[0]]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn window_ranges_equal_the_direct_ones() {
        let x: Vec<f64> = (0..200).map(|i| ((i * 37 % 101) as f64).sin() * (i % 7) as f64).collect();
        for w in [2, 5, 17] {
            let direct: Vec<f64> = x
                .windows(w)
                .map(|s| s.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - s.iter().cloned().fold(f64::INFINITY, f64::min))
                .collect();
            assert_eq!(window_ranges(&x, w), direct);
        }
    }

    #[test]
    fn two_dwells_between_ramps() {
        // ramp 0 -> 10 (20 samples), dwell at 10 (50), ramp to -5 (20), dwell at -5 (50), ramp
        let mut x: Vec<f64> = (0..20).map(|i| i as f64 * 0.5).collect();
        x.extend([10.0; 50]);
        x.extend((0..20).map(|i| 10.0 - 0.75 * i as f64));
        x.extend([-5.0; 50]);
        x.extend((0..20).map(|i| -5.0 + i as f64));
        let s = SteadySettings { window: 5, max_range_um: 0.6, min_samples: 30, trim: 2 };
        let p = steady_values(&[&x], &s, 2).unwrap();
        assert_eq!(p[0].mean, [10.0]);
        assert_eq!(p[1].mean, [-5.0]);
        assert!(steady_values(&[&x], &s, 3).unwrap_err().to_string().contains("2 steady stretches found for 3 poses"));
    }
}
