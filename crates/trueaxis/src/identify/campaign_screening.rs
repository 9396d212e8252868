//! Screening of an identification campaign (3D-ball, length and probing measurements).
//!
//! Before the fit, per measurement and reading channel (records in the order taken, which for a
//! trajectory is the order of the poses):
//! - the noise of the channel from first differences (`robust::difference_sigma`) against the
//!   noise the campaign states (`sigma_um`): a channel whose ratio is under 1/50 of the median ratio
//!   of the other channels of the campaign, or over 50 times it, is in another unit (mm among um)
//!   and is refused: no result from it is meaningful;
//! - runs of identical readings where the noise makes them improbable (`series::stuck_runs`);
//! - records equal in every pose and reading to an earlier one (a file appended to itself, a logger
//!   writing twice): counted as independent they shrink every uncertainty by up to sqrt 2.
//!
//! After the fit, each row i of the weighted problem (design row g_i, weight w_i = 1/sigma_i^2):
//! the leverage h_i = w_i g_i^T (X^T W X)^-1 g_i, the residual studentized with the robust scale s
//! of the weighted residuals (MAD, so that the outliers do not hide behind the s0 they inflate),
//! t_i = sqrt(w_i) r_i / (s sqrt(1 - h_i)), and Cook's distance D_i = t_i^2 h_i / (p (1 - h_i))
//! (Cook 1977). A row with |t_i| > `STUDENTIZED_LIMIT` or D_i > `COOK_LIMIT` is flagged.

use crate::identify::{Campaign, DesignMatrix, Identification};
use crate::screen::finding::{lines_text, Finding, Kind};
use crate::screen::robust::{difference_sigma, mad_sigma, median};
use crate::screen::series::{duplicate_rows, stuck_runs};
use std::collections::BTreeSet;

/// A studentized residual beyond this is an outlier (false alarm of a clean 2,400-row campaign
/// under 1 %: 2 P(|z| > 5.5) x 2400 = 1e-4).
pub const STUDENTIZED_LIMIT: f64 = 5.5;
/// Cook's distance beyond this flags a reading that alone moves the solution by about the width of
/// its confidence region (Cook 1977).
pub const COOK_LIMIT: f64 = 0.5;
/// A channel's noise ratio this far (either way) from the others' is a unit slip.
pub const NOISE_RATIO_LIMIT: f64 = 50.0;

/// The data file of a measurement, as named in messages.
fn file_of(m: &crate::identify::Measurement) -> String {
    m.data.display().to_string()
}

/// Findings before the fit: unit slips of one channel, stuck sensors, duplicate records.
pub fn before_fit(campaign: &Campaign) -> Vec<Finding> {
    let mut out = Vec::new();
    // (measurement, channel, noise / stated sigma)
    let mut ratios: Vec<(usize, usize, f64)> = Vec::new();
    for (k, m) in campaign.measurements.iter().enumerate() {
        let Some(readings) = &m.readings else { continue };
        let names = m.instrument.channels();
        let nc = names.len();
        let file = file_of(m);
        for (c, name) in names.iter().enumerate() {
            let series: Vec<f64> = readings.iter().skip(c).step_by(nc).copied().collect();
            let sigma = m.sigma_um.get(c).or(m.sigma_um.first()).copied().unwrap_or(1.0);
            let noise = difference_sigma(&series);
            if noise.is_finite() && sigma > 0.0 && series.len() >= 10 {
                ratios.push((k, c, noise / sigma));
            }
            for [a, b] in stuck_runs(&series) {
                let lines: Vec<u64> = m.lines[a..=b].to_vec();
                out.push(
                    Finding::flag(
                        Kind::Stuck,
                        &file,
                        format!("column {name}, lines {}", lines_text(&lines)),
                        format!("{} successive readings are all {} um where the noise is {noise:.2} um", b - a + 1, series[a]),
                    )
                    .with_consequence("identify counts them as independent readings; --exclude-outliers leaves them out")
                    .with_lines(lines),
                );
            }
        }
        let poses_per = m.poses.len() / m.records().max(1);
        let rows: Vec<Vec<f64>> = (0..m.records())
            .map(|r| m.poses[r * poses_per..(r + 1) * poses_per].iter().chain(&readings[r * nc..(r + 1) * nc]).copied().collect())
            .collect();
        let dups = duplicate_rows(&rows);
        if !dups.is_empty() {
            let lines: Vec<u64> = dups.iter().map(|&(_, later)| m.lines[later]).collect();
            let (n, total) = (dups.len(), m.records());
            out.push(
                Finding::flag(
                    Kind::Duplicate,
                    &file,
                    format!("lines {}", lines_text(&lines)),
                    format!(
                        "{n} of {total} records repeat an earlier one in every pose and reading (first: line {} repeats line {})",
                        m.lines[dups[0].1], m.lines[dups[0].0]
                    ),
                )
                .with_consequence(format!(
                    "counted as independent they shrink every uncertainty by up to {:.2} times; --exclude-outliers leaves the repeats out",
                    (total as f64 / (total - n) as f64).sqrt()
                ))
                .with_lines(lines),
            );
        }
    }
    for &(k, c, ratio) in &ratios {
        let others: Vec<f64> = ratios.iter().filter(|o| (o.0, o.1) != (k, c)).map(|o| o.2).collect();
        let typical = median(&others);
        if others.is_empty() || typical.is_nan() || typical <= 0.0 {
            continue;
        }
        let factor = ratio / typical;
        if (1.0 / NOISE_RATIO_LIMIT..=NOISE_RATIO_LIMIT).contains(&factor) {
            continue;
        }
        let m = &campaign.measurements[k];
        let name = m.instrument.channels()[c];
        let guess = if factor < 1.0 { "mm among um?" } else { "nm among um?" };
        out.push(
            Finding::flag(
                Kind::Unit,
                &file_of(m),
                format!("column {name}"),
                format!(
                    "its noise from reading to reading is {:.2e} times the stated sigma, where the other channels' is {typical:.2}: \
                     the column is {:.0} times {} than the others, most likely in another unit ({guess}); give it in um",
                    ratio,
                    if factor < 1.0 { 1.0 / factor } else { factor },
                    if factor < 1.0 { "smaller" } else { "larger" }
                ),
            )
            .refusing(),
        );
    }
    out
}

/// One row of the weighted problem after the fit.
#[derive(Clone, Copy, Debug)]
pub struct RowDiagnostic {
    /// Leverage h_i.
    pub leverage: f64,
    /// Studentized residual t_i (robust scale).
    pub studentized: f64,
    /// Cook's distance D_i.
    pub cook: f64,
}

/// Leverage, studentized residual and Cook's distance of every row of `design` for `result`.
pub fn row_diagnostics(design: &DesignMatrix, result: &Identification) -> Vec<RowDiagnostic> {
    let weighted: Vec<f64> = result.residuals.iter().zip(&design.weights).map(|(r, w)| r * w.sqrt()).collect();
    let s = mad_sigma(&weighted).max(1e-12);
    let p = result.identifiability.rank.max(1) as f64;
    let s0sq = (result.sigma0 * result.sigma0).max(1e-300);
    (0..design.rows())
        .map(|i| {
            let g: Vec<f64> = design.matrix.row(i).iter().copied().collect();
            let h = (design.weights[i] * result.prediction_variance(&g) / s0sq).clamp(0.0, 0.999_999);
            let t = weighted[i] / (s * (1.0 - h).sqrt());
            RowDiagnostic { leverage: h, studentized: t, cook: t * t * h / (p * (1.0 - h)) }
        })
        .collect()
}

/// Outliers after the fit, one finding per measurement listing its suspect readings.
pub fn after_fit(campaign: &Campaign, design: &DesignMatrix, result: &Identification) -> Vec<Finding> {
    let diagnostics = row_diagnostics(design, result);
    let mut out = Vec::new();
    for (k, m) in campaign.measurements.iter().enumerate() {
        let names = m.instrument.channels();
        let rows: Vec<usize> = (0..design.rows())
            .filter(|&i| design.records[i].0 == k)
            .filter(|&i| diagnostics[i].studentized.abs() > STUDENTIZED_LIMIT || diagnostics[i].cook > COOK_LIMIT)
            .collect();
        if rows.is_empty() {
            continue;
        }
        let lines: BTreeSet<u64> = rows.iter().map(|&i| m.lines[design.records[i].1]).collect();
        let lines: Vec<u64> = lines.into_iter().collect();
        let worst = rows
            .iter()
            .copied()
            .max_by(|&a, &b| diagnostics[a].studentized.abs().total_cmp(&diagnostics[b].studentized.abs()))
            .unwrap_or(rows[0]);
        // rows of a measurement are record by record, channel by channel
        let first = design.records.iter().position(|r| r.0 == k).unwrap_or(0);
        let channel = names[(worst - first) % names.len()];
        let d = diagnostics[worst];
        out.push(
            Finding::flag(
                Kind::Outlier,
                &file_of(m),
                format!("lines {}", lines_text(&lines)),
                format!(
                    "{} readings beyond the limits (studentized residual {STUDENTIZED_LIMIT}, Cook's distance {COOK_LIMIT}); the worst, \
                     line {} column {channel}, residual {:+.2} um, studentized {:+.1}, Cook's distance {:.3}",
                    rows.len(),
                    m.lines[design.records[worst].1],
                    result.residuals[worst],
                    d.studentized,
                    d.cook
                ),
            )
            .with_lines(lines),
        );
    }
    out
}

/// The campaign without the records on the lines of `findings` (outliers, stuck readings and
/// repeated records of each measurement's file): for `--exclude-outliers`.
pub fn excluding(campaign: &Campaign, findings: &[Finding]) -> Campaign {
    let mut out = campaign.clone();
    for m in &mut out.measurements {
        let file = file_of(m);
        let drop: BTreeSet<u64> = findings
            .iter()
            .filter(|f| f.file == file && matches!(f.kind, Kind::Outlier | Kind::Stuck | Kind::Duplicate))
            .flat_map(|f| f.lines.iter().copied())
            .collect();
        if drop.is_empty() {
            continue;
        }
        let (records, nc) = (m.records(), m.instrument.channels().len());
        let poses_per = m.poses.len() / records.max(1);
        let keep: Vec<usize> = (0..records).filter(|&r| !drop.contains(&m.lines[r])).collect();
        m.poses = keep.iter().flat_map(|&r| m.poses[r * poses_per..(r + 1) * poses_per].to_vec()).collect();
        m.readings = m.readings.as_ref().map(|v| keep.iter().flat_map(|&r| v[r * nc..(r + 1) * nc].to_vec()).collect());
        m.lines = keep.iter().map(|&r| m.lines[r]).collect();
    }
    out
}

/// An identification with its screening: the findings before and after the fit and, where
/// readings are suspect, the fit without them.
#[derive(Clone, Debug)]
pub struct ScreenedIdentification {
    /// The result reported: of every reading (flag only), or without the suspect ones (`exclude`).
    pub result: Identification,
    /// The campaign `result` was fitted to (the suspect records removed when `exclude`).
    pub campaign: Campaign,
    pub findings: Vec<Finding>,
    /// The other fit: without the suspect readings (flag only) or of every reading (`exclude`);
    /// `None` when nothing was suspect.
    pub other: Option<Identification>,
    /// Records left out of `result` (0 unless `exclude`).
    pub excluded_records: usize,
    /// The robust fit's weights when `result` is robust (`campaign_robust::identify_robust`);
    /// `other` is then the least-squares fit.
    pub robust: Option<super::robust_campaign::RobustFit>,
}

/// The findings before the fit (a refusing one is an input error), the least-squares fit of every
/// reading, and the findings after it (outliers).
pub fn screen_and_fit(
    campaign: &Campaign,
    machine: &crate::machine::Machine,
    nominal: &crate::error_model::ErrorModel,
    options: &crate::identify::IndirectOptions,
) -> Result<(Vec<Finding>, Identification), crate::identify::IdentifyError> {
    use crate::identify::{identify, IdentifyError};
    let mut findings = before_fit(campaign);
    if let Some(f) = findings.iter().find(|f| f.refuse) {
        return Err(IdentifyError::Input(f.line()));
    }
    let all = identify(campaign, machine, nominal, options)?;
    if campaign.measurements.iter().all(|m| m.readings.is_some()) {
        let design = campaign.design_matrix(machine, nominal)?;
        if design.rows() == all.residuals.len() {
            findings.extend(after_fit(campaign, &design, &all));
        }
    }
    Ok((findings, all))
}

/// Screens `campaign`, identifies, screens the residuals and, where records are suspect (outliers,
/// stuck readings, repeats), identifies again without them. A refusing finding is an input error.
/// With `exclude` the result is that of the remaining records; either way both fits are kept and
/// each outlier finding states the largest change of a parameter in units of its uncertainty.
pub fn identify_screened(
    campaign: &Campaign,
    machine: &crate::machine::Machine,
    nominal: &crate::error_model::ErrorModel,
    options: &crate::identify::IndirectOptions,
    exclude: bool,
) -> Result<ScreenedIdentification, crate::identify::IdentifyError> {
    use crate::identify::identify;
    let (mut findings, all) = screen_and_fit(campaign, machine, nominal, options)?;
    let reduced = excluding(campaign, &findings);
    let excluded_records: usize = campaign.measurements.iter().zip(&reduced.measurements).map(|(a, b)| a.records() - b.records()).sum();
    if excluded_records == 0 {
        return Ok(ScreenedIdentification {
            result: all,
            campaign: campaign.clone(),
            findings,
            other: None,
            excluded_records: 0,
            robust: None,
        });
    }
    let without = identify(&reduced, machine, nominal, options)?;
    let change = largest_change(&all, &without);
    for f in findings.iter_mut().filter(|f| matches!(f.kind, Kind::Outlier | Kind::Stuck | Kind::Duplicate)) {
        f.consequence = if f.consequence.is_empty() { change.clone() } else { format!("{}; {change}", f.consequence) };
    }
    Ok(if exclude {
        ScreenedIdentification { result: without, campaign: reduced, findings, other: Some(all), excluded_records, robust: None }
    } else {
        ScreenedIdentification {
            result: all,
            campaign: campaign.clone(),
            findings,
            other: Some(without),
            excluded_records: 0,
            robust: None,
        }
    })
}

/// "without the suspect records (N): TZ changes by x um, k times its uncertainty".
fn largest_change(all: &Identification, without: &Identification) -> String {
    let worst = (0..all.names.len())
        .filter_map(|j| {
            let u = without.std_uncertainty.get(j).copied().flatten().or(all.std_uncertainty[j])?;
            let d = without.values[j] - all.values[j];
            (u > 0.0).then_some((j, d, d.abs() / u))
        })
        .max_by(|a, b| a.2.total_cmp(&b.2));
    match worst {
        Some((j, d, k)) => format!(
            "without the suspect records {} changes by {d:+.3} {} ({k:.1} times its uncertainty), the largest change of any parameter",
            all.names[j], all.units[j]
        ),
        None => "without the suspect records no parameter changes measurably".into(),
    }
}

impl ScreenedIdentification {
    /// Adds what screening found to the document of `identify --json`: `data_quality` (the
    /// findings), `excluded_records`, and the values of the other fit, `with_all_readings` (after
    /// `--exclude-outliers` left records out) or `without_suspect_readings` (flag only).
    pub fn add_to_json(&self, doc: &mut serde_json::Value) {
        doc["data_quality"] = crate::screen::findings_json(&self.findings);
        doc["excluded_records"] = self.excluded_records.into();
        if let Some(robust) = &self.robust {
            doc["robust"] = robust.json();
        }
        if let Some(other) = &self.other {
            let key = match (&self.robust, self.excluded_records) {
                (Some(_), _) => "least_squares",
                (None, 0) => "without_suspect_readings",
                (None, _) => "with_all_readings",
            };
            doc[key] = other.names.iter().zip(&other.values).map(|(n, v)| (n.clone(), serde_json::json!(v))).collect();
        }
    }
}
