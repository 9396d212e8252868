//! Plausibility checks of units and coverage: values whose size says they are in another unit
//! than the column claims (mm where um are expected, radians where degrees are expected), targets
//! that are not repeated in every run, a ballbar radius that disagrees with the readings, sample
//! angles that do not cover the arc a test claims. A check returns a [`Finding`] that refuses the
//! file where the result would be meaningless (bad input) and warns where
//! it is only suspicious; each message names the file, the column and the likely fix.
//!
//! The limits are physical: deviations of a machine tool from a laser, a ballbar or a probe are
//! between about 0.1 um and a few hundred um (ISO 230-2 and ISO 230-4 tests of machines from
//! micro-milling to large gantries); a ballbar reads within +-1 mm of its length (Renishaw QC20-W:
//! +-1 mm range); a laser interferometer's range is at most 80 m (Renishaw XL-80).

use super::units::Unit;

/// What to do about a finding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    /// Suspicious: the command goes on and prints the message on stderr.
    Warn,
    /// Meaningless: the command refuses the input (bad input).
    Refuse,
}

/// The outcome of a check that found something.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    pub severity: Severity,
    /// One line naming the file, the column and the likely fix.
    pub message: String,
}

impl Finding {
    fn refuse(message: String) -> Option<Finding> {
        Some(Finding { severity: Severity::Refuse, message })
    }
    fn warn(message: String) -> Option<Finding> {
        Some(Finding { severity: Severity::Warn, message })
    }
}

/// Sorts the findings of plausibility checks: the first refusal is the error (its message); the
/// warnings, after `warnings` (those of reading the file), are returned, to be shown once the
/// command has succeeded (a refused command shows its one line only).
pub fn split_findings(findings: Vec<Finding>, warnings: &[String]) -> crate::error::Result<Vec<String>> {
    let mut out = warnings.to_vec();
    let mut refusal = None;
    for f in findings {
        match f.severity {
            Severity::Warn => out.push(f.message),
            Severity::Refuse => {
                refusal.get_or_insert(f.message);
            }
        }
    }
    match refusal {
        Some(m) => Err(crate::Error::input(m)),
        None => Ok(out),
    }
}

/// Where the checked values come from, for messages.
#[derive(Clone, Copy, Debug)]
pub struct Place<'a> {
    pub file: &'a str,
    /// The column as written in the file (or a description for vendor files: `DEVIATIONS::`).
    pub column: &'a str,
}

impl Place<'_> {
    fn at(&self) -> String {
        format!("{}: column `{}`", self.file, self.column)
    }
}

/// Below this largest |deviation| (um) the values are 1000 times too small: mm written as um.
pub const DEVIATION_REFUSE_SMALL_UM: f64 = 0.02;
/// Below this largest |deviation| (um) the values are suspiciously small.
pub const DEVIATION_WARN_SMALL_UM: f64 = 0.1;
/// Above this largest |deviation| (um) the values are suspiciously large.
pub const DEVIATION_WARN_LARGE_UM: f64 = 500.0;
/// Above this largest |deviation| (um) the values are 1000 times too large: um written as mm.
pub const DEVIATION_REFUSE_LARGE_UM: f64 = 5000.0;

fn largest_abs(values: &[f64]) -> f64 {
    values.iter().filter(|v| v.is_finite()).fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Deviations (actual minus target, radial deviations, readings of a laser, ballbar or probe),
/// already in um (`unit` is the unit the column was read in: the header's, or `None` for a column
/// without one, read as um; `fix` names how to say the unit in this file, e.g. "label the header
/// `dev [mm]`"). All zeros (an error-free simulation) pass.
pub fn deviation_scale(values_um: &[f64], unit: Option<Unit>, place: Place, fix_small: &str, fix_large: &str) -> Option<Finding> {
    let m = largest_abs(values_um);
    let written = |u: Option<Unit>| u.map_or("as um: the header names no unit".to_string(), |u| format!("in {}", u.symbol));
    if m == 0.0 {
        return None;
    }
    if m < DEVIATION_REFUSE_SMALL_UM {
        return Finding::refuse(format!(
            "{}: the largest deviation is {m:.3e} um ({}): machine-tool deviations are microns, so these values are \
             1000 times too small, most likely mm; {fix_small}",
            place.at(),
            written(unit)
        ));
    }
    if m > DEVIATION_REFUSE_LARGE_UM {
        return Finding::refuse(format!(
            "{}: the largest deviation is {:.1} mm ({}): beyond any machine tool's error, most likely um read as mm or nm as um; \
             {fix_large}",
            place.at(),
            m / 1000.0,
            written(unit)
        ));
    }
    if m < DEVIATION_WARN_SMALL_UM {
        return Finding::warn(format!(
            "{}: the largest deviation is only {m:.4} um ({}); if the values are mm, {fix_small}",
            place.at(),
            written(unit)
        ));
    }
    if m > DEVIATION_WARN_LARGE_UM {
        return Finding::warn(format!(
            "{}: the largest deviation is {:.3} mm ({}); if the values are um, {fix_large}",
            place.at(),
            m / 1000.0,
            written(unit)
        ));
    }
    None
}

/// Angles read as degrees that look like radians: at least 8 samples, all within one turn in
/// radians (|a| <= 2 pi) and spanning at least pi/2 there (a sweep of 90 deg written in radians).
/// Refused when the test needs the angles (a ballbar circle, a rotary sweep): as degrees such a
/// sweep covers at most 6.3 deg.
pub fn angles_in_radians(values_deg: &[f64], place: Place, fix: &str) -> Option<Finding> {
    if values_deg.len() < 8 || values_deg.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let (lo, hi) = values_deg.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    let two_pi = std::f64::consts::TAU + 1e-3;
    if lo >= -two_pi && hi <= two_pi && hi - lo >= std::f64::consts::FRAC_PI_2 {
        return Finding::refuse(format!(
            "{}: the angles run from {lo:.4} to {hi:.4}: as degrees a sweep of {:.2} deg, as radians {:.1} deg; they look like radians: {fix}",
            place.at(),
            hi - lo,
            (hi - lo).to_degrees()
        ));
    }
    None
}

/// One reading of a positioning test for [`targets_per_run`]: target (mm or deg), direction
/// (`+1` / `-1`), run number and line.
#[derive(Clone, Copy, Debug)]
pub struct TargetReading {
    pub target: f64,
    pub direction: i8,
    pub run: i64,
    pub line: u64,
}

/// Targets of a positioning test (ISO 230-2 repeats every target in every run):
/// - two target values closer than 1e-3 of the travel but not equal (within `tolerance`): one
///   target written with different digits in different runs, or actual positions written as
///   targets: refused (each would count as its own target with one run);
/// - a target missing from some runs: warned;
/// - targets spanning more than 100 m (beyond a laser interferometer's range): refused (um read as mm).
pub fn targets_per_run(readings: &[TargetReading], tolerance: f64, unit: &str, place: Place) -> Option<Finding> {
    if readings.is_empty() || readings.iter().any(|r| !r.target.is_finite()) {
        return None;
    }
    let mut targets: Vec<(f64, u64)> = readings.iter().map(|r| (r.target, r.line)).collect();
    targets.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let travel = targets[targets.len() - 1].0 - targets[0].0;
    if unit == "mm" && travel > 100_000.0 {
        return Finding::refuse(format!(
            "{}: the targets span {:.1} m, beyond the range of a laser interferometer; they look like um: label the header `target [um]`",
            place.at(),
            travel / 1000.0
        ));
    }
    let mut distinct: Vec<(f64, u64)> = Vec::new();
    for t in &targets {
        match distinct.last() {
            Some(d) if t.0 - d.0 <= tolerance => {}
            _ => distinct.push(*t),
        }
    }
    let near = 1e-3 * travel;
    if let Some(w) = distinct.windows(2).find(|w| w[1].0 - w[0].0 < near) {
        return Finding::refuse(format!(
            "{}: targets {} {unit} (line {}) and {} {unit} (line {}) differ by only {:.3e} {unit}: one target written with different digits, \
             or actual positions written as targets; give each target position one value (the nominal position) in every run",
            place.at(),
            w[0].0,
            w[0].1,
            w[1].0,
            w[1].1,
            w[1].0 - w[0].0
        ));
    }
    // runs: (run, direction) pairs in order of appearance
    let mut runs: Vec<(i64, i8)> = Vec::new();
    for r in readings {
        if !runs.contains(&(r.run, r.direction)) {
            runs.push((r.run, r.direction));
        }
    }
    let mut missing: Vec<String> = Vec::new();
    for d in &distinct {
        let absent: Vec<String> = runs
            .iter()
            .filter(|(run, dir)| !readings.iter().any(|r| r.run == *run && r.direction == *dir && (r.target - d.0).abs() <= tolerance))
            .map(|(run, dir)| format!("{run} ({})", if *dir > 0 { '+' } else { '-' }))
            .collect();
        if !absent.is_empty() {
            missing.push(format!("{} {unit} from run {}", d.0, absent.join(", ")));
        }
    }
    if !missing.is_empty() {
        let more = if missing.len() > 3 { format!(" and {} more", missing.len() - 3) } else { String::new() };
        missing.truncate(3);
        return Finding::warn(format!(
            "{}: targets missing from some runs: {}{more}; ISO 230-2 approaches every target in every run (a run cut short, or a \
             mistyped target?)",
            place.at(),
            missing.join("; ")
        ));
    }
    None
}

/// Ballbar readings (um, after unit conversion) against the test's radius (mm): readings whose
/// size is that of a length, not of a deviation, are absolute bar lengths; those of another radius
/// mean the radius (or the file) is wrong: refused; readings beyond a ballbar's +-1 mm range are
/// refused too.
pub fn ballbar_readings(readings_um: &[f64], radius_mm: f64, place: Place) -> Option<Finding> {
    let finite: Vec<f64> = readings_um.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() || !(radius_mm.is_finite() && radius_mm > 0.0) {
        return None;
    }
    let mean = finite.iter().sum::<f64>() / finite.len() as f64;
    if mean.abs() > 10_000.0 {
        return Finding::refuse(format!(
            "{}: the readings are lengths of about {:.4} mm, not deviations, and the radius is {radius_mm} mm; give the radius of the bar \
             that made them, or the deviations from it (`dL` in um)",
            place.at(),
            mean / 1000.0
        ));
    }
    let m = largest_abs(&finite);
    if m > 1000.0 {
        return Finding::refuse(format!(
            "{}: a reading of {:.1} um is beyond the +-1 mm range of a ballbar: the values are not bar deviations in um (in mm? label the \
             header `dL [mm]`), or the radius {radius_mm} mm is not the bar's",
            place.at(),
            m
        ));
    }
    None
}

/// Bar lengths (mm) read from a length column against the test's radius (mm): a mean more than
/// 1 mm from the radius is another bar's, refused.
pub fn bar_lengths(lengths_mm: &[f64], radius_mm: f64, place: Place) -> Option<Finding> {
    let finite: Vec<f64> = lengths_mm.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() || !(radius_mm.is_finite() && radius_mm > 0.0) {
        return None;
    }
    let mean = finite.iter().sum::<f64>() / finite.len() as f64;
    if (mean - radius_mm).abs() > 1.0 {
        return Finding::refuse(format!(
            "{}: the bar lengths are about {mean:.4} mm but the radius is {radius_mm} mm: give the radius of the bar that made them",
            place.at()
        ));
    }
    None
}

/// The radius of a circle given by axis positions (mean distance from the programmed centre, mm)
/// against the test's radius: more than 1 % apart is refused (a wrong --radius or --centre).
pub fn circle_radius(measured_mm: f64, radius_mm: f64, place: Place) -> Option<Finding> {
    if measured_mm.is_finite() && radius_mm > 0.0 && (measured_mm - radius_mm).abs() > 0.01 * radius_mm {
        return Finding::refuse(format!(
            "{}: the positions lie on a circle of radius {measured_mm:.3} mm about the centre, but the radius of the test is {radius_mm} mm; \
             give the bar's length as the radius and the programmed centre",
            place.at()
        ));
    }
    None
}

/// Sample angles (deg, in the order taken) against the arc the test claims (deg): the swept span
/// (unwrapped) plus 1.5 steps short of the claim is warned; covering less than half of it is
/// refused (a truncated file, or a feed, sample rate or radius in the header that disagrees with
/// the readings).
pub fn arc_coverage(angles_deg: &[f64], claimed_arc_deg: f64, place: Place) -> Option<Finding> {
    if angles_deg.len() < 2 || !(claimed_arc_deg.is_finite() && claimed_arc_deg > 0.0) || angles_deg.iter().any(|a| !a.is_finite()) {
        return None;
    }
    // unwrap steps larger than half a turn
    let mut covered = 0.0f64;
    let (mut lo, mut hi, mut acc) = (0.0f64, 0.0f64, 0.0f64);
    let mut step = f64::INFINITY;
    for w in angles_deg.windows(2) {
        let mut d = w[1] - w[0];
        d -= 360.0 * (d / 360.0).round();
        if d != 0.0 {
            step = step.min(d.abs());
        }
        acc += d;
        lo = lo.min(acc);
        hi = hi.max(acc);
        covered = hi - lo;
    }
    let step = if step.is_finite() { step } else { 0.0 };
    if covered + 1.5 * step >= claimed_arc_deg {
        return None;
    }
    let message = format!(
        "{}: the sample angles cover {covered:.1} deg but the test claims an arc of {claimed_arc_deg} deg: a truncated file, or a feed rate, \
         sample rate or radius in the header that disagrees with the readings",
        place.at()
    );
    if covered < 0.5 * claimed_arc_deg {
        Finding::refuse(message)
    } else {
        Finding::warn(message)
    }
}

/// A value of an error parameter in mm (translations) or rad (rotations), as vendor formats of
/// error parameters write them: above 5 mm or 0.05 rad (2.9 deg) it is no machine error and is
/// refused (um or urad written as mm or rad); above 0.5 mm or 5 mrad it is warned.
pub fn error_parameter_scale(largest_abs: f64, rotation: bool, name: &str) -> Option<Finding> {
    let (warn, refuse, unit, smaller) = if rotation { (5e-3, 0.05, "rad", "urad") } else { (0.5, 5.0, "mm", "um") };
    if largest_abs > refuse {
        return Finding::refuse(format!(
            "{name}: a value of {largest_abs} {unit} is beyond any machine error; the file holds {smaller}, not {unit} as the format \
             prescribes (export the \"Vendor\" variant in mm and rad)"
        ));
    }
    if largest_abs > warn {
        return Finding::warn(format!(
            "{name}: a value of {largest_abs} {unit} is unusually large for a machine error (values are in {unit})"
        ));
    }
    None
}

/// A temperature (degC) of the material or the air recorded with a test: outside -30 ... 80 degC
/// it is refused for a correction to 20 degC (kelvin or Fahrenheit written as degC); outside
/// 10 ... 35 degC it is warned.
pub fn temperature_degc(t: f64, what: &str, place: Place) -> Option<Finding> {
    if !t.is_finite() || !(-30.0..=80.0).contains(&t) {
        return Finding::refuse(format!(
            "{}: the {what} {t} degC is no workshop temperature (kelvin or Fahrenheit?); give it in degC",
            place.at()
        ));
    }
    if !(10.0..=35.0).contains(&t) {
        return Finding::warn(format!("{}: the {what} {t} degC is unusual for a calibration; check its unit", place.at()));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const AT: Place = Place { file: "f.csv", column: "dev" };

    #[test]
    fn deviation_scales() {
        assert_eq!(deviation_scale(&[0.0012, -0.0035], None, AT, "A", "B").unwrap().severity, Severity::Refuse);
        assert_eq!(deviation_scale(&[1.2, -3.5], None, AT, "A", "B"), None);
        assert_eq!(deviation_scale(&[0.0, 0.0], None, AT, "A", "B"), None);
        assert_eq!(deviation_scale(&[1200.0], None, AT, "A", "B").unwrap().severity, Severity::Warn);
        assert_eq!(deviation_scale(&[12_000.0], Some(Unit::MM), AT, "A", "B").unwrap().severity, Severity::Refuse);
    }

    #[test]
    fn radians_and_arcs() {
        let rad: Vec<f64> = (0..72).map(|k| (k as f64 * 5.0).to_radians()).collect();
        assert_eq!(angles_in_radians(&rad, AT, "fix").unwrap().severity, Severity::Refuse);
        let deg: Vec<f64> = (0..72).map(|k| k as f64 * 5.0).collect();
        assert_eq!(angles_in_radians(&deg, AT, "fix"), None);
        assert_eq!(arc_coverage(&deg, 360.0, AT), None);
        assert_eq!(arc_coverage(&deg[..36], 360.0, AT).unwrap().severity, Severity::Refuse);
        assert_eq!(arc_coverage(&deg[..60], 360.0, AT).unwrap().severity, Severity::Warn);
    }
}
