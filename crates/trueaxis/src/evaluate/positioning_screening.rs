//! Screening of an ISO 230-2 positioning test (laser readings of `target`, `dev`, `dir`, `run`).
//!
//! Each reading x_ij (target i, run j, one direction) is compared with the median of its target
//! and direction over the runs, r_ij = x_ij - median_j x_ij; the robust scale sigma is the MAD of
//! all r_ij (scaled to a standard deviation, with a floor of `SIGMA_FLOOR_UM`). Then:
//! - a run whose deviations are under 1/100 (or over 100 times) the other runs' (median |dev|) is
//!   a unit slip (mm or nm among um); a run whose median |r| exceeds `RUN_LIMIT` sigma does not
//!   belong with the others: another axis or test;
//! - a single reading beyond `READING_LIMIT` sigma is an outlier (a beam interruption, a mistyped
//!   value);
//! - targets of a linear axis that span 0.01 ... 5 mm while the deviations vary by more than 1000 um/m
//!   of that span are metres written as mm (no machine axis errs by 0.1 %);
//! - a temperature column (`T:<sensor>`, `T_<sensor>`) that changes by more than
//!   `DRIFT_LIMIT_DEGC` during the test is reported with what the change does over the travel
//!   (11.5 um/(m K), steel, for the material; 0.93 um/(m K) for an air refractive index left
//!   uncompensated; Edlen 1966).
//!
//! The evaluation itself stays as ISO 230-2 defines it: each finding states the result without the
//! suspect run or reading beside it ("R would be 4.1 um without run 4"), nothing is removed.

use crate::data::CsvTable;
use crate::evaluate::iso230_2::{evaluate, Direction, PositioningData, Reading};
use crate::screen::finding::{lines_text, Finding, Kind};
use crate::screen::robust::{mad_sigma, median};
use std::collections::BTreeMap;

/// The floor of the robust scale (um): below it, readings are at the resolution of the laser.
pub const SIGMA_FLOOR_UM: f64 = 0.05;
/// A run whose median |r| exceeds this many sigma is inconsistent with the others.
pub const RUN_LIMIT: f64 = 5.0;
/// A reading beyond this many sigma from the median of its target is an outlier.
pub const READING_LIMIT: f64 = 8.0;
/// A temperature change (degC) during a test that is reported.
pub const DRIFT_LIMIT_DEGC: f64 = 0.5;

/// All findings of a positioning test; `table` (the file as read) gives the temperature columns.
pub fn positioning(data: &PositioningData, table: Option<&CsvTable>) -> Vec<Finding> {
    let mut out = Vec::new();
    out.extend(targets_in_metres(data));
    out.extend(runs_and_readings(data));
    if let Some(t) = table {
        out.extend(temperature_drift(data, t));
    }
    out
}

/// Residuals from the median of each (target, direction), with sigma.
fn residuals(data: &PositioningData) -> (Vec<f64>, f64) {
    let key =
        |r: &Reading| ((r.target / crate::evaluate::iso230_2::TARGET_TOLERANCE_MM / 10.0).round() as i64, r.direction == Direction::Plus);
    let mut groups: BTreeMap<(i64, bool), Vec<f64>> = BTreeMap::new();
    for r in &data.readings {
        groups.entry(key(r)).or_default().push(r.dev);
    }
    let medians: BTreeMap<(i64, bool), f64> = groups.iter().map(|(k, v)| (*k, median(v))).collect();
    let r: Vec<f64> = data.readings.iter().map(|x| x.dev - medians[&key(x)]).collect();
    let sigma = mad_sigma(&r).max(SIGMA_FLOOR_UM);
    (r, sigma)
}

/// The readings of `data` without those `drop` selects.
fn without(data: &PositioningData, drop: impl Fn(&Reading) -> bool) -> PositioningData {
    PositioningData { readings: data.readings.iter().filter(|r| !drop(r)).cloned().collect(), ..data.clone() }
}

/// "A would be .. and R .. um without <what> (with it: A .., R ..)".
fn consequence(data: &PositioningData, reduced: &PositioningData, what: &str) -> String {
    match (evaluate(data), evaluate(reduced)) {
        (Ok(with), Ok(w)) => format!(
            "A would be {:.1} {u} and R {:.1} {u} without {what} (with it: A {:.1} {u}, R {:.1} {u})",
            w.a,
            w.r,
            with.a,
            with.r,
            u = data.unit()
        ),
        _ => format!("without {what} the test cannot be evaluated"),
    }
}

fn runs_and_readings(data: &PositioningData) -> Vec<Finding> {
    let mut out = Vec::new();
    if data.readings.len() < 6 {
        return out;
    }
    let (r, sigma) = residuals(data);
    let u = data.unit();
    let mut runs: Vec<i64> = data.readings.iter().map(|x| x.run).collect();
    runs.sort_unstable();
    runs.dedup();
    let mut bad_runs = Vec::new();
    for &run in &runs {
        let own: Vec<usize> = (0..r.len()).filter(|&i| data.readings[i].run == run).collect();
        let level = median(&own.iter().map(|&i| r[i].abs()).collect::<Vec<_>>());
        let size =
            |sel: &dyn Fn(&Reading) -> bool| median(&data.readings.iter().filter(|x| sel(x)).map(|x| x.dev.abs()).collect::<Vec<_>>());
        let (mine, others) = (size(&|x| x.run == run), size(&|x| x.run != run));
        let ratio = mine / others;
        let unit_slip = ratio.is_finite() && !(0.01..=100.0).contains(&ratio);
        if runs.len() < 3 || (level <= RUN_LIMIT * sigma && !unit_slip) {
            continue;
        }
        bad_runs.push(run);
        let (kind, what) = if unit_slip {
            (Kind::Unit, format!("its deviations are {ratio:.2e} times those of the other runs (median |dev| {mine:.3e} against {others:.3} {u}): written in another unit (mm among um?)"))
        } else {
            (Kind::Inconsistent, format!("its deviations differ from the other runs' at the same targets by {level:.1} {u} (median), {:.0} times their scatter of {sigma:.2} {u}: a run of another axis or another test?", level / sigma))
        };
        let lines: Vec<u64> = data.readings.iter().filter(|x| x.run == run).map(|x| x.line).collect();
        let reduced = without(data, |x| x.run == run);
        out.push(
            Finding::flag(kind, &data.origin, format!("run {run} (lines {})", lines_text(&lines)), what)
                .with_consequence(consequence(data, &reduced, &format!("run {run}")))
                .with_lines(lines),
        );
    }
    for (i, x) in data.readings.iter().enumerate() {
        if bad_runs.contains(&x.run) || r[i].abs() <= READING_LIMIT * sigma {
            continue;
        }
        let reduced = without(data, |y| y.line == x.line);
        out.push(
            Finding::flag(
                Kind::Outlier,
                &data.origin,
                format!("line {}, run {}, target {} {} ({})", x.line, x.run, x.target, data.position_unit(), x.direction.symbol()),
                format!(
                    "dev {:.3} {u} is {:+.1} {u} from the median of the other runs at this target, {:.0} times their robust scatter of {sigma:.2} {u} \
                     (limit {READING_LIMIT}): a beam interruption or a mistyped reading?",
                    x.dev,
                    r[i],
                    r[i].abs() / sigma
                ),
            )
            .with_consequence(consequence(data, &reduced, &format!("line {}", x.line)))
            .with_lines(vec![x.line]),
        );
    }
    out
}

fn targets_in_metres(data: &PositioningData) -> Option<Finding> {
    if data.rotary {
        return None;
    }
    let (lo, hi) = data.readings.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| (a.min(r.target), b.max(r.target)));
    let (dlo, dhi) = data.readings.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| (a.min(r.dev), b.max(r.dev)));
    let travel = hi - lo;
    if travel > 0.01 && travel < 5.0 && dhi - dlo > 1.0 * travel {
        return Some(
            Finding::flag(
                Kind::Unit,
                &data.origin,
                "column target",
                format!(
                    "the targets span {travel} mm while the deviations vary by {:.1} um, {:.0} um/m of the span: no machine axis errs by that much; \
                     the targets look like metres: give them in mm (or label the header `target [m]`)",
                    dhi - dlo,
                    (dhi - dlo) / travel * 1000.0
                ),
            )
            .refusing(),
        );
    }
    None
}

fn temperature_drift(data: &PositioningData, table: &CsvTable) -> Vec<Finding> {
    let mut out = Vec::new();
    if data.rotary {
        return out;
    }
    let (lo, hi) = data.readings.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| (a.min(r.target), b.max(r.target)));
    let travel = hi - lo;
    for h in table.headers() {
        let name = &h.name;
        let is_temperature = name.len() > 2 && (name.starts_with("T:") || name.starts_with("T_"));
        let Ok(values) = table.numbers(name) else { continue };
        if !is_temperature || values.iter().any(|v| !v.is_finite()) || values.is_empty() {
            continue;
        }
        let (tlo, thi) = values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
        let change = thi - tlo;
        if change <= DRIFT_LIMIT_DEGC {
            continue;
        }
        let air = name.to_ascii_lowercase().contains("air");
        let (per_degc, what) = if air {
            (0.93, "an air refractive index left uncompensated (0.93 um/(m K))")
        } else {
            (11.5, "the expansion of steel (11.5 um/(m K)) not corrected")
        };
        let effect = per_degc * 1e-3 * travel * change;
        out.push(
            Finding::flag(
                Kind::Drift,
                &data.origin,
                format!("column {}", h.text),
                format!("the temperature changed by {change:.1} degC during the test ({tlo:.1} to {thi:.1} degC)"),
            )
            .with_consequence(format!(
                "over the travel of {travel:.0} mm this is up to {effect:.1} um in the deviations with {what}; \
             the result holds only if the instrument compensated it (the --scale-temperature options, docs/screening.md)"
            )),
        );
    }
    out
}
