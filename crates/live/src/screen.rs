//! Screening of live readings before they reach the model: a value that is not a number, outside
//! the physical range of its sensor, or a jump beyond the rate limit is refused with its reason
//! (docs/live.md). Ranges default to the physical range of the quantity that the campaign reader
//! applies (`trueaxis::io::ranges`: temperatures -100 to 300 degC); rates to
//! [`crate::mapping::DEFAULT_RATE_LIMIT`] per second plus [`crate::mapping::DEFAULT_NOISE`].
//!
//! Units: degC, s.

use crate::mapping::{Mapping, DEFAULT_NOISE, DEFAULT_RATE_LIMIT, RATE_WINDOW_S};
use trueaxis::io::ranges;

/// The limits of one input.
#[derive(Clone, Debug, PartialEq)]
pub struct InputLimits {
    pub name: String,
    /// Physical range [lo, hi] in the input's unit after conversion (degC for temperatures).
    pub range: [f64; 2],
    /// Largest rate of change (per s); `None`: not checked (inputs other than temperatures).
    pub rate_limit: Option<f64>,
    /// A change this small is never a jump.
    pub noise: f64,
}

impl InputLimits {
    /// The limits of input `name` from the mapping, or the defaults of its quantity.
    pub fn of(name: &str, mapping: &Mapping) -> InputLimits {
        let entry = mapping.input_of(name);
        let temperature = name.starts_with("T:");
        // other inputs (a spindle speed S:<name>, rpm) are only checked to be finite by default
        let default = if temperature { [ranges::TEMPERATURE_DEGC.min, ranges::TEMPERATURE_DEGC.max] } else { [f64::MIN, f64::MAX] };
        InputLimits {
            name: name.into(),
            range: entry.and_then(|e| e.range).unwrap_or(default),
            rate_limit: entry.and_then(|e| e.rate_limit).or(temperature.then_some(DEFAULT_RATE_LIMIT)),
            noise: entry.and_then(|e| e.noise).unwrap_or(DEFAULT_NOISE),
        }
    }

    /// Why `value` at time `t_s` is refused, given the last accepted reading `(t, value)`; `None`
    /// when it is accepted.
    pub fn refusal(&self, value: f64, t_s: f64, last: Option<(f64, f64)>) -> Option<String> {
        let [lo, hi] = self.range;
        if !value.is_finite() {
            return Some(format!("{}: the reading is not a number", self.name));
        }
        if value < lo || value > hi {
            return Some(format!("{}: {value} is outside the physical range [{lo}, {hi}]", self.name));
        }
        if let (Some(rate), Some((t0, v0))) = (self.rate_limit, last) {
            let dt = (t_s - t0).clamp(0.0, RATE_WINDOW_S);
            let allowed = rate * dt + self.noise;
            if (value - v0).abs() > allowed {
                return Some(format!(
                    "{}: a jump of {:+.3} in {:.1} s from the last accepted {v0} (rate limit {rate} per s + {} allows {allowed:.3})",
                    self.name,
                    value - v0,
                    t_s - t0,
                    self.noise
                ));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_and_rate_refusals_name_the_sensor() {
        let l = InputLimits { name: "T:p1".into(), range: [0.0, 60.0], rate_limit: Some(0.05), noise: 0.5 };
        assert!(l.refusal(20.0, 0.0, None).is_none());
        assert!(l.refusal(61.0, 0.0, None).unwrap().contains("outside the physical range"));
        assert!(l.refusal(f64::NAN, 0.0, None).unwrap().contains("not a number"));
        // 120 s after 20 degC: 0.05 * 120 + 0.5 = 6.5 degC allowed
        assert!(l.refusal(26.4, 120.0, Some((0.0, 20.0))).is_none());
        assert!(l.refusal(26.6, 120.0, Some((0.0, 20.0))).unwrap().contains("jump of +6.600"));
        // the window caps the allowance at 0.05 * 600 + 0.5 = 30.5 degC, whatever the gap
        assert!(l.refusal(50.0, 86_400.0, Some((0.0, 20.0))).is_none());
        assert!(l.refusal(51.0, 86_400.0, Some((0.0, 20.0))).is_some());
    }
}
