//! Screening of a thermal campaign (rows of time `t` in s, `run`, temperatures `T:<sensor>` in
//! degC, errors in um).
//!
//! - Temperature by the sensor's role, read from its name: ambient (`amb`, `air`, `room`, `env`)
//!   5 ... 40 degC, spindle (`spindle`, `motor`, `bearing`) 5 ... 90 degC, structure (any other)
//!   5 ... 60 degC; outside is flagged. An ambient or structure column whose every value lies above
//!   45 and, read as degF, inside its role's range, is degF: refused (a model fitted to it writes a
//!   constant of hundreds of um that real degC readings would apply).
//! - Per run: gaps in `t` (`series::gaps`); steps of each temperature beyond `STEP_LIMIT` robust
//!   sigmas and `STEP_FLOOR_DEGC` between gaps (`series::steps`: a re-seated sensor); stuck
//!   sensors (`series::stuck_runs`); rows repeated in every column.
//!
//! A series split at its gaps ([`split_at_gaps`]) is fitted segment by segment: the state-space
//! model starts again from the first sample after each gap.

use crate::screen::finding::{lines_text, Finding, Kind};
use crate::screen::series::{duplicate_rows, gaps, steps, stuck_runs};
use crate::thermal::thermal_campaign::Campaign;

/// A temperature step beyond this many robust sigmas of all jumps (and the floor) is flagged.
pub const STEP_LIMIT: f64 = 10.0;
/// The smallest temperature step flagged (degC).
pub const STEP_FLOOR_DEGC: f64 = 0.5;

/// The role of a temperature sensor and its plausible range (degC).
fn role(sensor: &str) -> (&'static str, [f64; 2]) {
    let s = sensor.to_ascii_lowercase();
    if ["amb", "air", "room", "env"].iter().any(|k| s.contains(k)) {
        ("ambient", [5.0, 40.0])
    } else if ["spindle", "motor", "bearing"].iter().any(|k| s.contains(k)) {
        ("spindle", [5.0, 90.0])
    } else {
        ("structure", [5.0, 60.0])
    }
}

/// The rows of each run, in file order, cut at the gaps of `t`: `(run, rows)` per segment.
fn segments(c: &Campaign, t: &[f64]) -> Vec<(String, Vec<usize>)> {
    let mut out = Vec::new();
    for run in c.run_names() {
        let rows: Vec<usize> = (0..c.len()).filter(|&i| c.runs[i] == run).collect();
        let times: Vec<f64> = rows.iter().map(|&i| t[i]).collect();
        let mut start = 0;
        for (g, _) in gaps(&times) {
            out.push((run.clone(), rows[start..=g].to_vec()));
            start = g + 1;
        }
        out.push((run, rows[start..].to_vec()));
    }
    out
}

/// All findings of a thermal campaign.
pub fn campaign(c: &Campaign) -> Vec<Finding> {
    let mut out = Vec::new();
    let file = &c.origin;
    let lines = |rows: &[usize]| rows.iter().map(|&i| c.lines.get(i).copied().unwrap_or(i as u64 + 1)).collect::<Vec<u64>>();
    for s in c.sensors() {
        let Ok(v) = c.column(&s) else { continue };
        let (lo, hi) = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
        let (what, [rlo, rhi]) = role(&s[2..]);
        let as_c = |f: f64| (f - 32.0) * 5.0 / 9.0;
        if what != "spindle" && lo > 45.0 && as_c(lo) >= rlo && as_c(hi) <= rhi {
            out.push(
                Finding::flag(
                    Kind::Temperature,
                    file,
                    format!("column {s}"),
                    format!(
                        "the {what} temperatures run from {lo} to {hi} degC, as degF {:.1} to {:.1} degC: they look like degF; give them in degC \
                         (or label the header `{s} [degF]`)",
                        as_c(lo),
                        as_c(hi)
                    ),
                )
                .with_consequence("a model fitted to them writes a constant of hundreds of um that real degC readings would apply")
                .refusing(),
            );
        } else if lo < rlo || hi > rhi {
            out.push(Finding::flag(
                Kind::Temperature,
                file,
                format!("column {s}"),
                format!("the temperatures run from {lo} to {hi} degC, outside {rlo} ... {rhi} degC for a sensor on the {what}; check its unit and place"),
            ));
        }
    }
    let Ok(t) = c.column("t") else { return out };
    for run in c.run_names() {
        let rows: Vec<usize> = (0..c.len()).filter(|&i| c.runs[i] == run).collect();
        let times: Vec<f64> = rows.iter().map(|&i| t[i]).collect();
        for (g, length) in gaps(&times) {
            let (a, b) = (rows[g], rows[g + 1]);
            out.push(
                Finding::flag(
                    Kind::Gap,
                    file,
                    format!("{}lines {} and {}", run_label(&run), lines(&[a])[0], lines(&[b])[0]),
                    format!("no samples for {:.0} min between t = {} s and {} s", length / 60.0, t[a], t[b]),
                )
                .with_consequence("a state-space model integrates the temperatures across it as if they were constant; --split-gaps starts it again after the gap")
                .with_lines(vec![lines(&[a])[0], lines(&[b])[0]]),
            );
        }
    }
    for (run, rows) in segments(c, t) {
        let times: Vec<f64> = rows.iter().map(|&i| t[i]).collect();
        for s in c.sensors() {
            let Ok(v) = c.column(&s) else { continue };
            let x: Vec<f64> = rows.iter().map(|&i| v[i]).collect();
            for (j, d) in steps(&times, &x, STEP_LIMIT, STEP_FLOOR_DEGC) {
                let (a, b) = (rows[j], rows[j + 1]);
                out.push(
                    Finding::flag(
                        Kind::Step,
                        file,
                        format!("column {s}, {}lines {}-{}", run_label(&run), lines(&[a])[0], lines(&[b])[0]),
                        format!("the temperature jumps by {d:+.2} degC between t = {} s and {} s, which its course before and after does not explain: a re-seated or re-plugged sensor?", t[a], t[b]),
                    )
                    .with_consequence("a model fitted across it takes the jump for heat; fit the rows on one side only, or correct the sensor's offset")
                    .with_lines(lines(&rows[j + 1..])),
                );
            }
            for [a, b] in stuck_runs(&x) {
                let l = lines(&rows[a..=b]);
                out.push(
                    Finding::flag(
                        Kind::Stuck,
                        file,
                        format!("column {s}, {}lines {}", run_label(&run), lines_text(&l)),
                        format!("{} successive readings are all {} degC where the sensor's noise makes that improbable", b - a + 1, x[a]),
                    )
                    .with_lines(l),
                );
            }
        }
    }
    let rows: Vec<Vec<f64>> = (0..c.len()).map(|i| c.names.iter().filter_map(|n| c.column(n).ok().map(|v| v[i])).collect()).collect();
    let dups = duplicate_rows(&rows);
    if !dups.is_empty() {
        let l = lines(&dups.iter().map(|d| d.1).collect::<Vec<_>>());
        out.push(
            Finding::flag(
                Kind::Duplicate,
                file,
                format!("lines {}", lines_text(&l)),
                format!("{} rows repeat an earlier row in every column", dups.len()),
            )
            .with_consequence("counted as independent they make the fit look more certain than it is")
            .with_lines(l),
        );
    }
    out
}

fn run_label(run: &str) -> String {
    if run.is_empty() {
        String::new()
    } else {
        format!("run {run}, ")
    }
}

/// The suffix of the run name of a segment after a gap: `warmup [after gap 1]`.
pub const AFTER_GAP: &str = " [after gap ";

/// The campaign with each run cut at its gaps: the rows after the k-th gap of run R belong to the
/// run `R [after gap k]` (selected with R by `--train-runs R`), so that a state-space model starts
/// again there.
pub fn split_at_gaps(c: &Campaign) -> Campaign {
    let Ok(t) = c.column("t") else { return c.clone() };
    let mut out = c.clone();
    let mut previous = String::new();
    let mut k = 0;
    for (run, rows) in segments(c, t) {
        k = if run == previous { k + 1 } else { 0 };
        if k > 0 {
            for &i in &rows {
                out.runs[i] = format!("{run}{AFTER_GAP}{k}]");
            }
        }
        previous = run;
    }
    out
}

/// Reads a thermal campaign and screens it: with `skip_missing` the rows with a blank cell are
/// left out and listed (else a blank cell is an input error naming its line); a refusing finding
/// is an input error; with `split_gaps` each run is cut at its gaps ([`split_at_gaps`]).
pub fn read_screened(
    path: &std::path::Path,
    skip_missing: bool,
    split_gaps: bool,
) -> Result<(Campaign, Vec<Finding>), crate::error::Error> {
    let (c, dropped) = if skip_missing { Campaign::read_skipping_missing(path)? } else { (Campaign::read(path)?, Vec::new()) };
    let mut findings = Vec::new();
    if !dropped.is_empty() {
        findings.push(
            Finding::flag(
                Kind::Missing,
                &c.origin,
                format!("lines {}", lines_text(&dropped)),
                format!("{} row(s) with a blank cell (a logger dropout) left out (--skip-missing)", dropped.len()),
            )
            .with_lines(dropped),
        );
    }
    findings.extend(campaign(&c));
    if let Some(f) = findings.iter().find(|f| f.refuse) {
        return Err(crate::error::Error::input(f.line()));
    }
    let c = if split_gaps { split_at_gaps(&c) } else { c };
    Ok((c, findings))
}
