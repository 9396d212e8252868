//! Raw ballbar captures: the angles of the capture arc from a stream of bar-length samples.
//!
//! A ballbar records bar-length samples at a fixed rate, not angles. One run is a feed-in move
//! (the bar shortened or lengthened by about 1.5 mm onto the test radius), an overshoot arc in which
//! the machine reaches the programmed feed, the data-capture arc, an overshoot arc in which it
//! stops, and the feed-out move (ISO 230-4 annex; Jiang 2014 §4.2 and Table 4.1: 45 deg of overshoot
//! for a C-axis test, 2 deg for a 90 deg A-axis arc). At constant feed the samples of the capture
//! arc are evenly spread over it, so sample `i` of `N + 1` lies at `theta_i = i Theta / N`
//! (Jiang 2014 §4.2).
//!
//! The capture arc is found in the stream as follows:
//! 1. the arc is the stretch between the feed-in and the feed-out, where the deviation from the
//!    nominal length stays within `feed_threshold_um` (the feed moves change it by about 1.5 mm);
//! 2. acceleration and deceleration are symmetric, so the capture arc is centred in that stretch;
//! 3. its number of samples follows from the constant angular speed of the programmed feed:
//!    `samples per deg = f_s 60 R pi / (180 F)` (f_s in Hz, R in mm, F in mm/min); without a feed,
//!    the stretch is taken as run at constant speed over `Theta + 2 overshoot`.
//!
//! Units: deviations in um, angles in deg, radius in mm, feed in mm/min, sample rate in Hz.

use super::ballbar::sample_angles;
use crate::data::{CsvTable, DataError};
use crate::io::ballbar::BallbarHeader;

/// What the test programme was: the arc and how it was run.
#[derive(Clone, Debug, PartialEq)]
pub struct ArcProgramme {
    /// The data-capture arc `Theta` (deg, > 0).
    pub capture_arc_deg: f64,
    /// The overshoot arc before and after the capture arc (deg, >= 0).
    pub overshoot_deg: f64,
    /// Angle of the first capture sample (deg) and the sense of rotation (+1 counter-clockwise,
    /// -1 clockwise, seen from the positive normal of the test plane).
    pub start_deg: f64,
    pub direction: f64,
    /// Test radius (mm), feed (mm/min) and sample rate (Hz): with all three, the capture arc's
    /// sample count follows from the programmed speed; without, from the length of the stretch.
    pub radius_mm: Option<f64>,
    pub feed_mm_min: Option<f64>,
    pub sample_rate_hz: Option<f64>,
    /// Largest deviation (um) that still belongs to the arc; the feed moves exceed it.
    pub feed_threshold_um: f64,
}

impl ArcProgramme {
    /// A programme with the usual feed threshold of 300 um (the feed moves are about 1.5 mm).
    pub fn new(capture_arc_deg: f64, overshoot_deg: f64) -> ArcProgramme {
        ArcProgramme {
            capture_arc_deg,
            overshoot_deg,
            start_deg: 0.0,
            direction: 1.0,
            radius_mm: None,
            feed_mm_min: None,
            sample_rate_hz: None,
            feed_threshold_um: 300.0,
        }
    }

    /// Samples per degree at the programmed feed: `f_s 60 R pi / (180 F)`, when radius, feed and
    /// sample rate are all given.
    pub fn samples_per_deg(&self) -> Option<f64> {
        Some(self.sample_rate_hz? * 60.0 * self.radius_mm? * std::f64::consts::PI / (180.0 * self.feed_mm_min?))
    }
}

/// The capture arc found in a raw stream.
#[derive(Clone, Debug, PartialEq)]
pub struct CapturedArc {
    /// Angle of each capture sample (deg): `start + direction i Theta / N`.
    pub angles_deg: Vec<f64>,
    /// Bar-length deviation of each capture sample (um).
    pub dev_um: Vec<f64>,
    /// Index in the stream of the first capture sample, and of the first and last sample of the
    /// stretch between the feed moves.
    pub first_sample: usize,
    pub stretch: (usize, usize),
    /// Samples per degree used to size the capture arc, and those the stretch shows when taken at
    /// constant speed over `Theta + 2 overshoot`.
    pub samples_per_deg: f64,
    pub samples_per_deg_of_stretch: f64,
    /// Plausibility warnings (e.g. the stretch and the programmed feed disagree).
    pub warnings: Vec<String>,
}

/// Finds the capture arc in `samples` (bar-length deviations in um, in recording order) and gives
/// each capture sample its angle, `theta_i = i Theta / N` (Jiang 2014 §4.2).
pub fn capture_arc(samples: &[f64], programme: &ArcProgramme) -> crate::error::Result<CapturedArc> {
    let bad = |m: String| Err(crate::Error::input(m));
    let p = programme;
    if !(p.capture_arc_deg.is_finite() && p.capture_arc_deg > 0.0 && p.capture_arc_deg <= 720.0) {
        return bad(format!("capture arc {} deg: give an arc in (0, 720] deg", p.capture_arc_deg));
    }
    if !(p.overshoot_deg.is_finite() && (0.0..=180.0).contains(&p.overshoot_deg)) {
        return bad(format!("overshoot {} deg: give an overshoot in [0, 180] deg", p.overshoot_deg));
    }
    if !(p.direction == 1.0 || p.direction == -1.0) || !p.start_deg.is_finite() {
        return bad("the direction is +1 (counter-clockwise) or -1 (clockwise) and the start angle finite".into());
    }
    if !(p.feed_threshold_um.is_finite() && p.feed_threshold_um > 0.0) {
        return bad(format!("feed threshold {} um: give a positive value", p.feed_threshold_um));
    }
    for (name, value) in [("radius (mm)", p.radius_mm), ("feed (mm/min)", p.feed_mm_min), ("sample rate (Hz)", p.sample_rate_hz)] {
        if let Some(v) = value {
            if !(v.is_finite() && v > 0.0) {
                return bad(format!("{name} {v}: give a positive value"));
            }
        }
    }
    if let Some(i) = samples.iter().position(|v| !v.is_finite()) {
        return bad(format!("sample {} is not a number", i + 1));
    }
    let inside = |v: &f64| v.abs() <= p.feed_threshold_um;
    let (Some(first), Some(last)) = (samples.iter().position(inside), samples.iter().rposition(inside)) else {
        return bad(format!(
            "no sample within {} um of the nominal length: the whole stream looks like a feed move; are the samples in um (not mm)?",
            p.feed_threshold_um
        ));
    };
    let stretch_len = last - first + 1;
    let mut warnings = Vec::new();
    if first == 0 && last + 1 == samples.len() {
        warnings.push(format!(
            "no feed-in or feed-out move (a change of more than {} um) in the stream: it is taken as the arc alone; are the samples in um?",
            p.feed_threshold_um
        ));
    }
    let total_deg = p.capture_arc_deg + 2.0 * p.overshoot_deg;
    let of_stretch = (stretch_len - 1) as f64 / total_deg;
    let per_deg = match p.samples_per_deg() {
        Some(k) => {
            // the overshoots hold the acceleration: the stretch is a little longer than at constant
            // speed, never shorter, and not by more than the overshoots themselves
            if of_stretch < 0.98 * k {
                return bad(format!(
                    "the arc between the feed moves holds {stretch_len} samples, fewer than {:.0} that a {} deg capture arc and 2 x {} deg overshoot need at {} mm/min on {} mm at {} Hz: check the feed, the radius and the sample rate",
                    k * total_deg,
                    p.capture_arc_deg,
                    p.overshoot_deg,
                    p.feed_mm_min.unwrap_or_default(),
                    p.radius_mm.unwrap_or_default(),
                    p.sample_rate_hz.unwrap_or_default()
                ));
            }
            if of_stretch > 1.25 * k {
                warnings.push(format!(
                    "the arc between the feed moves is {:.0} % longer than the programmed feed gives: is the feed right, or does the file hold more than one run?",
                    100.0 * (of_stretch / k - 1.0)
                ));
            }
            k
        }
        None => of_stretch,
    };
    let capture_len = (p.capture_arc_deg * per_deg).round() as usize + 1;
    if capture_len < 3 || capture_len > stretch_len {
        return bad(format!("the capture arc needs {capture_len} samples and the arc between the feed moves holds {stretch_len}"));
    }
    // centred: acceleration in the first overshoot mirrors deceleration in the last
    let start = first + (stretch_len - capture_len) / 2;
    let n = (capture_len - 1) as f64;
    let angles_deg = (0..capture_len).map(|i| p.start_deg + p.direction * i as f64 * p.capture_arc_deg / n).collect();
    Ok(CapturedArc {
        angles_deg,
        dev_um: samples[start..start + capture_len].to_vec(),
        first_sample: start,
        stretch: (first, last),
        samples_per_deg: per_deg,
        samples_per_deg_of_stretch: of_stretch,
        warnings,
    })
}

/// Readings beyond this (um) in a fixed-rate file without an overshoot in its header are most
/// likely feed moves of a raw capture: warned.
pub const FEED_MOVE_SUSPECT_UM: f64 = 300.0;

/// The rows of a fixed-rate ballbar file (no angle column) that the test evaluates, and their
/// angles (deg). Rows group into runs by `groups` (consecutive rows with one key, e.g. run and
/// sense); `ccw` gives each row's sense. When the header states an overshoot, the file is a raw
/// capture: each run's capture arc is found by [`capture_arc`] (the feed moves and overshoots
/// dropped, `theta_i = i Theta / N`) and only its rows are kept; otherwise every row is kept at
/// the angle its sample number gives ([`super::ballbar::sample_angles`]).
pub fn sampled_rows(
    table: &CsvTable,
    header: &BallbarHeader,
    groups: &[i64],
    ccw: &[bool],
    dl_um: &[f64],
    warnings: &mut Vec<String>,
) -> Result<(Vec<usize>, Vec<f64>), DataError> {
    let bad = |m: String| DataError::Invalid { origin: table.origin().to_string(), message: m };
    let Some(overshoot) = header.overshoot_deg else {
        if let Some(v) = dl_um.iter().find(|v| v.abs() > FEED_MOVE_SUSPECT_UM) {
            warnings.push(format!(
                "{}: a reading of {v:.1} um: if the file holds the feed moves and overshoots of a raw capture, state `Overshoot: <deg>` \
                 (and `Arc:`) in its header so that only the capture arc is evaluated",
                table.origin()
            ));
        }
        let angles = sample_angles(table, header, groups, ccw)?;
        return Ok(((0..angles.len()).collect(), angles));
    };
    let arc =
        header.arc_deg.ok_or_else(|| bad("a raw capture (`Overshoot:` in the header) needs the capture arc too (`Arc: <deg>`)".into()))?;
    let (mut rows, mut angles) = (Vec::new(), Vec::new());
    let mut first = 0;
    while first < groups.len() {
        let end = (first..groups.len()).find(|&i| groups[i] != groups[first]).unwrap_or(groups.len());
        let programme = ArcProgramme {
            capture_arc_deg: arc,
            overshoot_deg: overshoot,
            start_deg: header.start_deg.unwrap_or(0.0),
            direction: if ccw[first] { 1.0 } else { -1.0 },
            radius_mm: header.radius_mm,
            feed_mm_min: header.feed_mm_per_min,
            sample_rate_hz: header.sample_rate_hz,
            ..ArcProgramme::new(arc, overshoot)
        };
        let captured = capture_arc(&dl_um[first..end], &programme)
            .map_err(|e| bad(format!("rows {} to {} (one run): {e}", table.lines()[first], table.lines()[end - 1])))?;
        warnings.extend(captured.warnings.iter().map(|w| format!("{}: line {}: {w}", table.origin(), table.lines()[first])));
        rows.extend((0..captured.dev_um.len()).map(|i| first + captured.first_sample + i));
        angles.extend(captured.angles_deg);
        first = end;
    }
    Ok((rows, angles))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_speed_stream_without_a_feed_is_split_by_its_length() {
        // feed-in 1500 -> 0 um in 10 samples, 2 x 10 deg overshoot + 90 deg capture at 2 samples/deg
        let mut s: Vec<f64> = (0..10).map(|i| 1500.0 - 150.0 * i as f64 - 150.0).map(|v: f64| v.max(400.0)).collect();
        let arc: Vec<f64> = (0..=220).map(|i| (i as f64 * 0.5).to_radians().sin()).collect();
        s.extend(&arc);
        s.extend((0..10).map(|i| 400.0 + 100.0 * i as f64));
        let r = capture_arc(&s, &ArcProgramme::new(90.0, 10.0)).unwrap();
        assert_eq!(r.stretch, (10, 230));
        assert_eq!(r.first_sample, 30);
        assert_eq!(r.dev_um.len(), 181);
        assert!((r.angles_deg[180] - 90.0).abs() < 1e-12);
        assert!((r.dev_um[0] - arc[20]).abs() < 1e-12);
    }

    #[test]
    fn bad_programmes_and_streams_are_refused() {
        let p = ArcProgramme::new(360.0, 45.0);
        assert!(capture_arc(&[2000.0; 50], &p).unwrap_err().to_string().contains("in um (not mm)"));
        assert!(capture_arc(&[0.0, f64::NAN], &p).unwrap_err().to_string().contains("sample 2"));
        assert!(capture_arc(&[0.0; 10], &ArcProgramme::new(0.0, 45.0)).is_err());
        let mut fast = ArcProgramme::new(360.0, 45.0);
        (fast.radius_mm, fast.feed_mm_min, fast.sample_rate_hz) = (Some(100.0), Some(1000.0), Some(250.0));
        assert!(capture_arc(&[0.0; 100], &fast).unwrap_err().to_string().contains("check the feed"));
    }
}
