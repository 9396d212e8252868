//! Ballbar text exports: a `Key: value` header with the test's radius (the bar length), feed rate,
//! direction, sample rate, arc and start angle, then a table of readings: an angle (deg) or a
//! sample number, and the radial deviation (or the bar length itself).
//!
//! No public description of a ballbar program's text export was found (Renishaw's Ballbar 20
//! stores tests in its own files; its text exports are not documented publicly). What is assumed,
//! and read forgivingly (docs/user-guide.md, "Instrument files"):
//! - header keys in any case and with units in the key or the value: `Radius: 100 mm` or
//!   `Radius (mm): 100` (also `Ballbar length`, `Bar length`), `Feed rate: 1000 mm/min` (`Feed`,
//!   `Feedrate`; mm/min, m/min, mm/s), `Direction: CCW` (`CW`, `CCW`, `both`, `clockwise`,
//!   `anticlockwise`, `G2`, `G3`), `Sample rate: 250 Hz`, `Arc: 360` (deg; `Data arc`, `Capture
//!   arc`), `Start angle: 0` (deg), `Plane: XY` (`G17` `G18` `G19`);
//! - readings with an angle column (`angle`, `theta`; deg unless the header says otherwise), or a
//!   sample column (`sample`, `index`, `point`) or none: the angle of sample k (from 0) is then
//!   `start + s * (F / 60) / R * k / f` (rad), F the feed rate (mm/min), R the radius (mm), f the
//!   sample rate (Hz), s = +1 counter-clockwise and -1 clockwise;
//! - the deviation column (`dL`, `deviation`, `dr`, ...; um unless the header says otherwise), or a
//!   length column (`radius`, `length`), from which the deviation `length - R` is taken.

use super::header::normalised;
use super::metadata::Metadata;
use super::units::{number_with_unit, Dimension, Unit};

/// Sense of a circular test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sense {
    Ccw,
    Cw,
    Both,
}

/// The test parameters in the header of a ballbar export (mm, mm/min, Hz, deg).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BallbarHeader {
    pub radius_mm: Option<f64>,
    pub feed_mm_per_min: Option<f64>,
    pub sense: Option<Sense>,
    pub sample_rate_hz: Option<f64>,
    pub arc_deg: Option<f64>,
    /// Overshoot arc before and after the capture arc (deg): a raw capture that still holds the
    /// feed moves and the overshoots (`instruments::ballbar_raw`).
    pub overshoot_deg: Option<f64>,
    pub start_deg: Option<f64>,
    /// `xy`, `yz` or `zx`.
    pub plane: Option<&'static str>,
}

enum Key {
    Radius,
    Feed,
    Sense,
    Rate,
    Arc,
    Overshoot,
    Start,
    Plane,
}

fn key_of(key: &str) -> Option<Key> {
    let k = normalised(key);
    let k = k.split(['(', '[']).next().unwrap_or("");
    Some(match k {
        "radius" | "ballbarlength" | "barlength" | "nominalradius" | "testradius" | "ballbarradius" | "length" => Key::Radius,
        "feed" | "feedrate" | "speed" | "vorschub" => Key::Feed,
        "direction" | "dir" | "rotation" | "sense" | "richtung" => Key::Sense,
        "samplerate" | "samplingrate" | "datarate" | "samplefrequency" | "rate" => Key::Rate,
        "arc" | "dataarc" | "capturearc" | "testarc" | "datacapturearc" | "arcangle" | "sweep" => Key::Arc,
        "overshoot" | "overshootangle" | "overtravel" | "overrun" => Key::Overshoot,
        "startangle" | "start" | "startposition" => Key::Start,
        "plane" | "testplane" | "ebene" => Key::Plane,
        _ => return None,
    })
}

/// True for the header keys of a ballbar test (radius, feed rate, direction, sample rate, arc,
/// overshoot, start angle, plane).
pub fn is_test_key(key: &str) -> bool {
    key_of(key).is_some()
}

/// A number with an optional unit in the value or the key (`Radius (mm): 100`), converted to
/// `want`; the dimension must match.
fn quantity(key: &str, value: &str, want: Unit) -> crate::error::Result<f64> {
    let (v, unit) = number_with_unit(value).ok_or_else(|| crate::Error::input(format!("`{key}: {value}` is not a number with a unit")))?;
    let key_unit = key.rfind(['(', '[']).and_then(|i| Unit::parse(key[i + 1..].trim_end_matches([')', ']'])));
    let unit = unit.or(key_unit).unwrap_or(want);
    if unit.dimension != want.dimension {
        return Err(crate::Error::input(format!("`{key}: {value}`: {} is not {}", unit.symbol, want.dimension.name())));
    }
    let v = unit.convert(v, want);
    if !v.is_finite() {
        return Err(crate::Error::input(format!("`{key}: {value}` is not a finite number")));
    }
    Ok(v)
}

/// The sense written in a header: `CCW`, `CW`, `both`, `clockwise`, `anticlockwise`,
/// `counterclockwise`, `G2` (clockwise), `G3`.
pub fn sense_of(text: &str) -> Option<Sense> {
    match normalised(text).as_str() {
        "ccw" | "anticlockwise" | "counterclockwise" | "g3" | "+" | "positive" => Some(Sense::Ccw),
        "cw" | "clockwise" | "g2" | "-" | "negative" => Some(Sense::Cw),
        "both" | "ccw/cw" | "cw/ccw" | "ccw+cw" | "cw+ccw" | "bidirectional" => Some(Sense::Both),
        _ => None,
    }
}

impl BallbarHeader {
    /// Reads the test parameters from the `Key: value` pairs of a file's header (kept in
    /// [`Metadata::other`]). A value that cannot be read is an error naming the key.
    pub fn from_metadata(m: &Metadata) -> crate::error::Result<BallbarHeader> {
        let mut h = BallbarHeader::default();
        for (key, value) in &m.other {
            let Some(k) = key_of(key) else { continue };
            match k {
                Key::Radius => h.radius_mm = Some(quantity(key, value, Unit::MM)?),
                Key::Feed => h.feed_mm_per_min = Some(quantity(key, value, Unit::MM_PER_MIN)?),
                Key::Rate => h.sample_rate_hz = Some(quantity(key, value, Unit::HZ)?),
                Key::Arc => h.arc_deg = Some(quantity(key, value, Unit::DEG)?),
                Key::Overshoot => h.overshoot_deg = Some(quantity(key, value, Unit::DEG)?),
                Key::Start => h.start_deg = Some(quantity(key, value, Unit::DEG)?),
                Key::Sense => {
                    h.sense = Some(sense_of(value).ok_or_else(|| crate::Error::input(format!("`{key}: {value}` is not CCW, CW or both")))?);
                }
                Key::Plane => {
                    h.plane = Some(match normalised(value).as_str() {
                        "xy" | "g17" | "yx" => "xy",
                        "yz" | "g19" | "zy" => "yz",
                        "zx" | "xz" | "g18" => "zx",
                        _ => return Err(crate::Error::input(format!("`{key}: {value}` is not a plane (XY, YZ, ZX)"))),
                    })
                }
            }
        }
        if let Some(r) = h.radius_mm.filter(|r| !(r.is_finite() && *r > 0.0)) {
            return Err(crate::Error::input(format!("the radius {r} mm must be positive")));
        }
        Ok(h)
    }

    /// True when nothing was recorded.
    pub fn is_empty(&self) -> bool {
        *self == BallbarHeader::default()
    }

    /// The angles (deg) of `n` samples taken at a fixed rate along the circle (see the module
    /// documentation), counter-clockwise (`ccw`) or clockwise. Needs the radius, feed rate and
    /// sample rate; an error names what is missing.
    pub fn sample_angles(&self, n: usize, ccw: bool) -> crate::error::Result<Vec<f64>> {
        let (Some(r), Some(feed), Some(rate)) = (self.radius_mm, self.feed_mm_per_min, self.sample_rate_hz) else {
            let missing: Vec<&str> = [
                (self.radius_mm.is_none(), "Radius"),
                (self.feed_mm_per_min.is_none(), "Feed rate"),
                (self.sample_rate_hz.is_none(), "Sample rate"),
            ]
            .iter()
            .filter(|x| x.0)
            .map(|x| x.1)
            .collect();
            return Err(crate::Error::input(format!(
                "the readings have no angle column; their angles follow from the header's radius, feed rate and sample rate, but it lacks {}",
                missing.join(", ")
            )));
        };
        if !(feed > 0.0 && rate > 0.0 && r > 0.0) {
            return Err(crate::Error::input("the radius, feed rate and sample rate must be positive"));
        }
        let step_deg = (feed / 60.0 / r / rate).to_degrees();
        let s = if ccw { 1.0 } else { -1.0 };
        let start = self.start_deg.unwrap_or(0.0);
        Ok((0..n).map(|k| start + s * step_deg * k as f64).collect())
    }
}

/// True when the dimension of a header unit is a length (a bar-length column).
pub fn is_length(unit: Option<Unit>) -> bool {
    unit.is_none_or(|u| u.dimension == Dimension::Length)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_values_with_units() {
        let m = Metadata::from_pairs([
            ("Radius (mm)", "100"),
            ("Feed rate", "1 m/min"),
            ("Direction", "anticlockwise"),
            ("Sample rate", "250 Hz"),
            ("Arc", "360"),
            ("Plane", "G17"),
        ]);
        let h = BallbarHeader::from_metadata(&m).unwrap();
        assert_eq!(h.radius_mm, Some(100.0));
        assert_eq!(h.feed_mm_per_min, Some(1000.0));
        assert_eq!(h.sense, Some(Sense::Ccw));
        assert_eq!(h.sample_rate_hz, Some(250.0));
        assert_eq!(h.arc_deg, Some(360.0));
        assert_eq!(h.plane, Some("xy"));
        // 1000 mm/min on R 100: 1/6 rad/s; at 250 Hz 2/3 mrad per sample
        let a = h.sample_angles(3, true).unwrap();
        assert!((a[2] - 2.0 * (1000.0f64 / 60.0 / 100.0 / 250.0).to_degrees()).abs() < 1e-12);
        let e = BallbarHeader::from_metadata(&Metadata::from_pairs([("Feed rate", "1 kHz")])).unwrap_err().to_string();
        assert!(e.contains("not a feed rate"), "{e}");
    }
}
