//! ISO 230-4 circular tests with a ballbar: least-squares centre, circular deviation `G`, radial
//! deviation `F`, circular hysteresis `H`, and the diagnostics of [`super::ballbar_diagnostics`].
//!
//! Definitions (ISO 230-4:2005 clause 3, for a ballbar whose pivot is the nominal centre):
//! - radial deviation `F`: the reading `dL`, actual minus nominal radius about the nominal centre;
//!   `F_max`, `F_min` its extremes (outward positive);
//! - circular deviation `G`: the smallest radial separation of two circles concentric with the
//!   least-squares circle (LSC) that enclose the path: `max r_i - min r_i` about the LSC centre;
//! - circular hysteresis `H`: the largest radial difference between the CW and CCW paths at the
//!   same angle.
//!
//! The LSC is the algebraic circle fit of Jiang 2014 §4.2 on the points `(R + dL_i) (cos t, sin t)`,
//! equal to the geometric LSC to first order in `dL / R`.

use super::ballbar_diagnostics::{diagnose, CircularRun, DiagnosticOptions, Diagnostics, RESOLUTION_UM};
use super::EvaluateError;
use crate::data::{CsvTable, DataError};
use crate::identify::pige::kasa_fit;
use crate::instruments::ballbar::{
    angle_column, ballbar_header, bar_readings, check_arc, check_bar_deviations, circle_test, CircleSpec, Plane, Rotation,
};
use crate::instruments::ballbar_raw::sampled_rows;
use crate::io::ballbar::BallbarHeader;
use crate::io::plausibility::Place;
use crate::io::units::Dimension;
use crate::machine::Machine;
use serde_json::{json, Value};

/// The ISO 230-4 values of one run (um unless stated).
#[derive(Clone, Debug, PartialEq)]
pub struct CircularValues {
    pub rotation: Rotation,
    pub samples: usize,
    /// Swept angle of the data (deg).
    pub arc_deg: f64,
    /// LSC centre relative to the pivot, in the plane's two axes.
    pub centre_um: [f64; 2],
    /// LSC radius minus the nominal radius.
    pub radius_change_um: f64,
    pub g_um: f64,
    pub f_max_um: f64,
    pub f_min_um: f64,
}

/// Evaluation of a circular test: per run, the hysteresis between runs, the diagnostics.
#[derive(Clone, Debug, PartialEq)]
pub struct Iso2304Result {
    pub plane: Plane,
    pub radius_mm: f64,
    pub runs: Vec<CircularValues>,
    /// Circular hysteresis `H` (um) when a CW and a CCW run cover common angles.
    pub hysteresis_um: Option<f64>,
    pub diagnostics: Diagnostics,
}

fn invalid(origin: &str, message: String) -> EvaluateError {
    EvaluateError::Invalid { origin: origin.to_string(), message }
}

/// ISO 230-4 values of one run with readings `dl` (mm) at angles (rad), nominal radius (mm).
pub fn circular_values(rotation: Rotation, angles: &[f64], dl: &[f64], radius: f64) -> Result<CircularValues, EvaluateError> {
    let points: Vec<[f64; 2]> = angles.iter().zip(dl).map(|(t, d)| [(radius + d) * t.cos(), (radius + d) * t.sin()]).collect();
    let fit = kasa_fit(&points).map_err(|e| EvaluateError::NotFinite(format!("least-squares circle: {e}")))?;
    let r: Vec<f64> = points.iter().map(|p| (p[0] - fit.centre[0]).hypot(p[1] - fit.centre[1])).collect();
    let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let unwrapped = unwrap(angles);
    Ok(CircularValues {
        rotation,
        samples: angles.len(),
        arc_deg: (max(&unwrapped) - min(&unwrapped)).to_degrees(),
        centre_um: [fit.centre[0] * 1e3, fit.centre[1] * 1e3],
        radius_change_um: (fit.radius - radius) * 1e3,
        g_um: (max(&r) - min(&r)) * 1e3,
        f_max_um: max(dl) * 1e3,
        f_min_um: min(dl) * 1e3,
    })
}

/// Angles made continuous (no jumps of more than pi between neighbours).
fn unwrap(angles: &[f64]) -> Vec<f64> {
    let tau = std::f64::consts::TAU;
    let mut out: Vec<f64> = Vec::with_capacity(angles.len());
    for &a in angles {
        let v = match out.last() {
            Some(&prev) => a + tau * ((prev - a) / tau).round(),
            None => a,
        };
        out.push(v);
    }
    out
}

/// Reading of `run` interpolated at angle `t` (periodic, linear), if `t` lies within its data.
fn interpolate(angles: &[f64], dl: &[f64], t: f64) -> Option<f64> {
    let tau = std::f64::consts::TAU;
    let mut pairs: Vec<(f64, f64)> = angles.iter().map(|a| a.rem_euclid(tau)).zip(dl.iter().copied()).collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let t = t.rem_euclid(tau);
    let full = unwrap(angles).iter().fold(0.0f64, |m, a| m.max((a - unwrap(angles)[0]).abs())) > tau - 0.1;
    let step_limit = 0.2; // rad: do not bridge gaps wider than ~11 deg
    let n = pairs.len();
    for i in 0..n {
        let (a0, d0) = pairs[i];
        let (mut a1, d1) = pairs[(i + 1) % n];
        if i + 1 == n {
            if !full {
                break;
            }
            a1 += tau;
        }
        let tt = if t < a0 { t + tau } else { t };
        if tt >= a0 && tt <= a1 && a1 - a0 <= step_limit {
            let w = if a1 > a0 { (tt - a0) / (a1 - a0) } else { 0.0 };
            return Some(d0 + w * (d1 - d0));
        }
    }
    None
}

/// Circular hysteresis `H` (um): the largest |dL_ccw(t) - dL_cw(t)| over the CCW angles covered by
/// the CW run.
pub fn hysteresis(ccw: &CircularRun, cw: &CircularRun) -> Option<f64> {
    ccw.test
        .angles
        .iter()
        .zip(&ccw.dl)
        .filter_map(|(&t, &d)| interpolate(&cw.test.angles, &cw.dl, t).map(|e| (d - e).abs() * 1e3))
        .reduce(f64::max)
}

/// Evaluates the runs of a circular test (ISO values per run, hysteresis, diagnostics).
pub fn evaluate(machine: &Machine, runs: &[CircularRun], options: &DiagnosticOptions) -> Result<Iso2304Result, EvaluateError> {
    if runs.is_empty() {
        return Err(EvaluateError::Invalid { origin: "circular test".into(), message: "no runs".into() });
    }
    let values = runs.iter().map(|r| circular_values(r.rotation, &r.test.angles, &r.dl, options.radius)).collect::<Result<Vec<_>, _>>()?;
    let ccw = runs.iter().find(|r| r.rotation == Rotation::Ccw);
    let cw = runs.iter().find(|r| r.rotation == Rotation::Cw);
    let hysteresis_um = match (ccw, cw) {
        (Some(a), Some(b)) => hysteresis(a, b),
        _ => None,
    };
    let diagnostics = diagnose(machine, runs, options).map_err(|e| EvaluateError::NotFinite(format!("diagnostics fit: {e}")))?;
    Ok(Iso2304Result { plane: options.plane, radius_mm: options.radius, runs: values, hysteresis_um, diagnostics })
}

/// The runs of a circular-test file, with what the file says about the test.
#[derive(Clone, Debug)]
pub struct CircularFile {
    pub runs: Vec<CircularRun>,
    pub metadata: crate::io::Metadata,
    /// The test parameters of a ballbar export's header.
    pub header: BallbarHeader,
    /// Findings of the plausibility checks that only warn, each naming the file and column.
    pub warnings: Vec<String>,
}

/// Reads a circular-test file for `machine`, forgivingly (`data::CsvTable`; a ballbar export with a
/// `Key: value` header, `io::ballbar`): a column `angle` (deg, in the plane: from the first axis
/// toward the second), the two axis columns of the plane (mm, e.g. `X,Y`), or sample numbers with
/// the radius, feed rate and sample rate in the header; `dL` (um, the bar reading: actual minus
/// nominal length; or bar lengths); optional `dir` (`ccw` or `cw`) to hold both runs in one file;
/// without it the file is one run whose sense follows the angles (or the header's direction).
/// `centre` holds every axis position of the programmed centre (mm, deg). Errors name the file, line
/// and column; a header radius or plane that disagrees with `radius` / `plane` is refused.
pub fn read_circular(
    path: impl AsRef<std::path::Path>,
    machine: &Machine,
    plane: Plane,
    radius: f64,
    centre: &[f64],
) -> Result<CircularFile, EvaluateError> {
    let path = path.as_ref();
    let origin = path.display().to_string();
    let table = CsvTable::read(path)?;
    read_circular_table(&table, &origin, machine, plane, radius, centre)
}

/// As [`read_circular`] from a table already read.
pub fn read_circular_table(
    table: &CsvTable,
    origin: &str,
    machine: &Machine,
    plane: Plane,
    radius: f64,
    centre: &[f64],
) -> Result<CircularFile, EvaluateError> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(invalid(origin, format!("the radius must be a positive number of mm, got {radius}")));
    }
    let header = ballbar_header(table)?;
    if let Some(r) = header.radius_mm.filter(|r| (r - radius).abs() > 1e-9 * radius.max(1.0)) {
        return Err(invalid(
            origin,
            format!("the file's header gives the radius {r} mm, but the test's radius is {radius} mm; give the bar's length"),
        ));
    }
    if let Some(p) = header.plane.filter(|p| *p != plane.name()) {
        return Err(invalid(
            origin,
            format!("the file's header gives the plane {}, but the test's plane is {}", p.to_uppercase(), plane.name().to_uppercase()),
        ));
    }
    let (a, b, _) = plane.letters();
    let (ia, ib) = match (machine.axis_index(a), machine.axis_index(b)) {
        (Some(ia), Some(ib)) => (ia, ib),
        _ => {
            return Err(invalid(
                origin,
                format!("plane {} needs axes {a} and {b}; the machine has {}", plane.name(), machine.axis_letters()),
            ))
        }
    };
    let mut warnings: Vec<String> = table.warnings().to_vec();
    let dl_um = bar_readings(table, Some(radius), &mut warnings)?;
    let dirs: Option<Vec<Rotation>> = if table.has_column("dir") {
        let texts = table.texts("dir")?;
        Some(
            texts
                .iter()
                .enumerate()
                .map(|(i, t)| Rotation::parse(t).ok_or_else(|| table.row_error(i, &format!("column dir: `{t}` is not `ccw` or `cw`"))))
                .collect::<Result<_, _>>()?,
        )
    } else {
        None
    };
    // the plane's axis columns, when they move (a rotary test holds them still), must lie on the
    // circle of the test
    if let Some(f) = crate::evaluate::ballbar_screening::circle_axes(table, origin, a, b) {
        return Err(EvaluateError::Input(f.line()));
    }
    let axis_columns = table.has_column(&a.to_string()) && table.has_column(&b.to_string());
    let positions = if axis_columns {
        let xa = table.numbers_as(&a.to_string(), Dimension::Length)?;
        let xb = table.numbers_as(&b.to_string(), Dimension::Length)?;
        let span = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max) - v.iter().copied().fold(f64::INFINITY, f64::min);
        let moving = span(&xa) > 1e-9 || span(&xb) > 1e-9;
        let mean_radius = xa.iter().zip(&xb).map(|(p, q)| (q - centre[ib]).hypot(p - centre[ia])).sum::<f64>() / xa.len() as f64;
        let columns = format!("{a}, {b}");
        if let Some(f) =
            crate::io::plausibility::circle_radius(mean_radius, radius, Place { file: origin, column: &columns }).filter(|_| moving)
        {
            return Err(invalid(origin, f.message.strip_prefix(&format!("{origin}: ")).unwrap_or(&f.message).to_string()));
        }
        Some((xa, xb))
    } else {
        None
    };
    let all_rows = || (0..dl_um.len()).collect::<Vec<usize>>();
    let (rows, angles_deg): (Vec<usize>, Vec<f64>) = if table.has_column("angle") {
        (all_rows(), angle_column(table, "angle")?)
    } else if let Some((xa, xb)) = &positions {
        (all_rows(), xa.iter().zip(xb).map(|(p, q)| (q - centre[ib]).atan2(p - centre[ia]).to_degrees()).collect())
    } else if header.feed_mm_per_min.is_some() || header.sample_rate_hz.is_some() {
        let ccw: Vec<bool> = match &dirs {
            Some(d) => d.iter().map(|r| *r == Rotation::Ccw).collect(),
            None => vec![header.sense != Some(crate::io::ballbar::Sense::Cw); dl_um.len()],
        };
        let runs: Vec<i64> = ccw.iter().map(|c| i64::from(*c)).collect();
        let header = BallbarHeader { radius_mm: Some(radius), ..header.clone() };
        sampled_rows(table, &header, &runs, &ccw, &dl_um, &mut warnings)?
    } else {
        return Err(DataError::Invalid {
            origin: origin.to_string(),
            message: format!(
                "needs a column `angle` (deg) or the columns `{a}` and `{b}` (mm), or sample numbers with `Feed rate` and `Sample rate` in the header"
            ),
        }
        .into());
    };
    // a raw capture keeps the rows of its capture arcs only
    let dl_um: Vec<f64> = rows.iter().map(|&i| dl_um[i]).collect();
    check_bar_deviations(table, Some(radius), &dl_um, &mut warnings)?;
    let dl: Vec<f64> = dl_um.iter().map(|v| v * 1e-3).collect();
    let dirs: Option<Vec<Rotation>> = dirs.map(|d| rows.iter().map(|&i| d[i]).collect());
    let angles: Vec<f64> = angles_deg.iter().map(|d| d.to_radians()).collect();
    let mut runs = Vec::new();
    for rotation in [Rotation::Ccw, Rotation::Cw] {
        let rows: Vec<usize> = match &dirs {
            Some(d) => (0..dl.len()).filter(|&i| d[i] == rotation).collect(),
            None => {
                let u = unwrap(&angles);
                let sense = if u.last() >= u.first() { Rotation::Ccw } else { Rotation::Cw };
                if sense == rotation {
                    (0..dl.len()).collect()
                } else {
                    Vec::new()
                }
            }
        };
        if rows.is_empty() {
            continue;
        }
        if rows.len() < 8 {
            return Err(invalid(
                origin,
                format!("the {} run has {} samples; a circular test needs at least 8", rotation.name(), rows.len()),
            ));
        }
        let run_angles: Vec<f64> = rows.iter().map(|&i| angles[i]).collect();
        let spec = CircleSpec { plane, centre: centre.to_vec(), radius, angles: run_angles, rotation };
        let test = circle_test(machine, &spec).map_err(|e| invalid(origin, e.to_string()))?;
        runs.push(CircularRun { rotation, test, dl: rows.iter().map(|&i| dl[i]).collect() });
    }
    let run_of: Vec<i64> = match &dirs {
        Some(d) => d.iter().map(|r| i64::from(*r == Rotation::Ccw)).collect(),
        None => vec![1; dl.len()],
    };
    check_arc(table, &header, &angles_deg, &run_of, &mut warnings)?;
    Ok(CircularFile { runs, metadata: table.metadata().clone(), header, warnings })
}

fn round(v: f64, digits: i32) -> f64 {
    let f = 10f64.powi(digits);
    (v * f).round() / f
}

impl Iso2304Result {
    /// One JSON document: `{"plane", "radius_mm", "runs": [{"dir", "G_um", "F_max_um", ...}],
    /// "H_um", "diagnostics": [{"name", "parameter", "value", "unit", "std_uncertainty", "effect_um",
    /// "share_percent"}], "residual_rms_um", "omitted"}`.
    pub fn to_json(&self) -> Value {
        let runs: Vec<Value> = self
            .runs
            .iter()
            .map(|r| {
                json!({
                    "dir": r.rotation.name(), "samples": r.samples, "arc_deg": round(r.arc_deg, 3),
                    "centre_um": [round(r.centre_um[0], 4), round(r.centre_um[1], 4)],
                    "radius_change_um": round(r.radius_change_um, 4),
                    "G_um": round(r.g_um, 4), "F_max_um": round(r.f_max_um, 4), "F_min_um": round(r.f_min_um, 4)
                })
            })
            .collect();
        let diagnostics: Vec<Value> = self
            .diagnostics
            .items
            .iter()
            .map(|d| {
                json!({
                    "name": d.name, "parameter": d.parameter, "value": round(d.value, 4), "unit": d.unit,
                    "std_uncertainty": round(d.std_uncertainty, 4), "effect_um": round(d.effect_um, 4),
                    "share_percent": round(d.share_percent, 2)
                })
            })
            .collect();
        json!({
            "plane": self.plane.name(), "radius_mm": self.radius_mm, "runs": runs,
            "H_um": self.hysteresis_um.map(|h| round(h, 4)),
            "diagnostics": diagnostics,
            "residual_rms_um": round(self.diagnostics.residual_rms_um, 4),
            "samples": self.diagnostics.samples,
            "omitted": self.diagnostics.omitted,
        })
    }

    /// Lines of text: the ISO values, then the diagnostics (used in the table and beside the plot).
    pub fn summary_lines(&self) -> Vec<String> {
        let mut out = Vec::new();
        for r in &self.runs {
            out.push(format!(
                "{:>3}: G = {:.2} um, F = {:+.2} / {:+.2} um, centre ({:+.2}, {:+.2}) um",
                r.rotation.name().to_uppercase(),
                r.g_um,
                r.f_max_um,
                r.f_min_um,
                r.centre_um[0],
                r.centre_um[1]
            ));
        }
        if let Some(h) = self.hysteresis_um {
            out.push(format!("H = {h:.2} um"));
        }
        let (resolved, small): (Vec<_>, Vec<_>) =
            self.diagnostics.items.iter().filter(|d| d.effect_um > 0.0).partition(|d| d.effect_um >= RESOLUTION_UM);
        for d in resolved {
            out.push(format!("{}: {:+.2} ± {:.2} {} ({:.0} %)", d.name, d.value, d.std_uncertainty, d.unit, d.share_percent));
        }
        if !small.is_empty() {
            let names: Vec<&str> = small.iter().map(|d| d.name.as_str()).collect();
            out.push(format!("effects below the {RESOLUTION_UM} um bar resolution (no share): {}", names.join(", ")));
        }
        out.push(format!("fit residual RMS {:.3} um", self.diagnostics.residual_rms_um));
        out
    }
}
