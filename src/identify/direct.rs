//! The direct-measurement workflow behind `trueaxis fit`: read one measured error along its axis
//! from a CSV, optionally keep one direction and remove per-cycle drift, fit a parametric function
//! with stepwise selection, refine periodic wavelengths, and report (seed 000 §3.2).

use super::drift::{remove_cycle_drift, CycleDrift};
use super::fit::{dominant_period, fit_error_function, refine_wavelength, FitOptions, FittedFunction};
use super::IdentifyError;
use crate::data::CsvTable;
use crate::errors::ErrorModel;
use crate::machine::{Machine, ParameterId};
use crate::model::{jacobian, Frame, JacobianWorkspace, Setup, JACOBIAN_ROWS};
use crate::report::{fit_plot_svg, FitPlot, ReportError};
use serde_json::json;

/// What to fit and how.
#[derive(Clone, Debug)]
pub struct DirectFitRequest {
    pub parameter: ParameterId,
    /// Column of positions (mm or deg), e.g. `target` or the axis letter.
    pub position_column: String,
    /// Column of measured values (um or urad), e.g. `dev`.
    pub value_column: String,
    /// Keep only rows whose `dir` column is `+` or `-` (a bidirectional model is two fits).
    pub direction: Option<char>,
    /// Remove per-cycle linear drift using the `run` and `t` (s) columns (seed 000 §3.2.2).
    pub remove_drift: bool,
    /// Refine every periodic wavelength within this relative bracket before the final fit.
    pub refine_wavelength: Option<f64>,
    pub options: FitOptions,
    /// The measurement equation through the kinematic model; without it the readings are taken as
    /// the parameter values themselves.
    pub model: Option<DirectModel>,
}

/// The measurement equation of a direct instrument (laser linear / straightness / angular optics,
/// level) through the kinematic model (seed 000 §3.2.2, sequential estimation): the reading is the
/// component of the volumetric error (machine frame) that corresponds to the parameter (`EXX` ->
/// `dx`, `EBX` -> `dry`, ...) between the instrument's tool-side and workpiece-side points, with the
/// other axes at fixed positions. Each reading `m` gives the parameter value
/// `(m - sum_{k != p} J_k E_k) / J_p`: known errors `E_k` (e.g. the angular errors fitted first)
/// have their Abbe contributions removed, and `J_p` (e.g. -1 for a slide that carries the
/// workpiece) fixes the sign.
#[derive(Clone, Debug)]
pub struct DirectModel {
    pub machine: Machine,
    /// Errors already known (zero where unknown).
    pub known: ErrorModel,
    /// Positions of all axes (user units, canonical order); the measured axis's entry is replaced
    /// by each observation's position.
    pub fixed_pose: Vec<f64>,
    pub setup: Setup,
}

impl DirectModel {
    /// Converts readings (um or urad) at axis positions (mm or deg) into values of `parameter`.
    pub fn parameter_values(&self, parameter: &ParameterId, positions: &[f64], readings: &[f64]) -> Result<Vec<f64>, IdentifyError> {
        let m = &self.machine;
        let p = m.parameter_index(parameter).map_err(IdentifyError::Input)?;
        let axis = parameter
            .axis()
            .and_then(|a| m.axis_index(a))
            .ok_or_else(|| IdentifyError::Input(format!("{parameter} is not a motion error of an axis")))?;
        let row = parameter.component().index();
        let n = m.parameter_count();
        let to_user = 1.0 / parameter.component().to_internal();
        let mut jac = vec![0.0; JACOBIAN_ROWS * n];
        let mut ws = JacobianWorkspace::default();
        let mut known = vec![0.0; n];
        let mut q = vec![0.0; m.axis_count()];
        let mut user = self.fixed_pose.clone();
        positions
            .iter()
            .zip(readings)
            .map(|(x, reading)| {
                user[axis] = *x;
                m.check_range(&user).map_err(IdentifyError::Input)?;
                m.pose_to_internal(&user, &mut q);
                jacobian(m, &q, &self.setup, Frame::Machine, &mut ws, &mut jac);
                self.known.values_at(m, &q, &mut known);
                let r = &jac[row * n..(row + 1) * n];
                if r[p].abs() < 0.5 {
                    return Err(IdentifyError::Input(format!(
                        "at {x}: the reading does not see {parameter} (sensitivity {:.3}); check the instrument points and the parameter",
                        r[p]
                    )));
                }
                let abbe: f64 = r.iter().zip(&known).enumerate().filter(|(k, _)| *k != p).map(|(_, (j, e))| j * e).sum::<f64>() * to_user;
                Ok((reading - abbe) / r[p])
            })
            .collect()
    }
}

/// The result of a direct fit.
#[derive(Clone, Debug)]
pub struct DirectFitReport {
    pub parameter: ParameterId,
    pub fitted: FittedFunction,
    /// Positions and values used (after direction selection and drift removal).
    pub positions: Vec<f64>,
    pub values: Vec<f64>,
    /// Drift removed per cycle.
    pub drift: Vec<CycleDrift>,
    /// The periodic wavelengths finally used.
    pub wavelengths: Vec<f64>,
    /// Strongest sinusoid left in the residuals: period (mm or deg) and amplitude.
    pub residual_period: Option<(f64, f64)>,
}

/// Runs the workflow on a table.
pub fn run_direct_fit(table: &CsvTable, request: &DirectFitRequest) -> Result<DirectFitReport, IdentifyError> {
    let mut positions = table.numbers(&request.position_column)?;
    let mut values = table.numbers(&request.value_column)?;
    // drift removal works on whole back-and-forth cycles, before one direction is selected
    let dirs = if table.has_column("dir") { Some(table.texts("dir")?) } else { None };
    let sign: Option<Vec<f64>> = match &dirs {
        Some(d) => Some(
            d.iter()
                .enumerate()
                .map(|(i, t)| match t.as_str() {
                    "+" => Ok(1.0),
                    "-" => Ok(-1.0),
                    _ => Err(table.row_error(i, &format!("column dir: `{t}` is neither + nor -"))),
                })
                .collect::<Result<_, _>>()?,
        ),
        None => None,
    };
    let mut drift = Vec::new();
    if request.remove_drift {
        let cycles: Vec<i64> = table.numbers("run")?.iter().map(|r| r.round() as i64).collect();
        let (clean, found) = remove_cycle_drift(&cycles, &table.numbers("t")?, &values, sign.as_deref())?;
        values = clean;
        drift = found;
    }
    let mut keep: Vec<usize> = (0..table.len()).collect();
    if let Some(d) = request.direction {
        let sign =
            sign.as_ref().ok_or_else(|| IdentifyError::Input("a direction was asked for but the data have no `dir` column".into()))?;
        let want = if d == '+' { 1.0 } else { -1.0 };
        keep.retain(|&i| sign[i] == want);
        if keep.is_empty() {
            return Err(IdentifyError::Input(format!("no rows with dir = {d}")));
        }
    }
    positions = keep.iter().map(|&i| positions[i]).collect();
    values = keep.iter().map(|&i| values[i]).collect();
    if let Some(model) = &request.model {
        values = model.parameter_values(&request.parameter, &positions, &values)?;
    }
    let mut options = request.options.clone();
    if let Some(rel) = request.refine_wavelength {
        for k in 0..options.spec.periodic.len() {
            options.spec = refine_wavelength(&positions, &values, &options.spec, k, rel)?;
        }
    }
    let fitted = fit_error_function(&positions, &values, &options)?;
    let (lo, hi) = options.spec.domain.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
    let spacing = (hi - lo) / positions.len().max(2) as f64;
    let residual_period = dominant_period(&positions, &fitted.fit.residuals, (2.0 * spacing).max(1e-9), hi - lo);
    let wavelengths = options.spec.periodic.iter().map(|p| p.wavelength).collect();
    Ok(DirectFitReport { parameter: request.parameter, fitted, positions, values, drift, wavelengths, residual_period })
}

impl DirectFitReport {
    /// The JSON document of `trueaxis fit --json` (values in the parameter's unit, um or urad).
    pub fn to_json(&self) -> serde_json::Value {
        let f = &self.fitted;
        let unit = self.parameter.unit();
        let terms: Vec<serde_json::Value> = f
            .names
            .iter()
            .zip(&f.coefficients)
            .zip(&f.std_uncertainties)
            .map(|((n, c), u)| json!({"function": n, "coefficient": c, "std_uncertainty": u}))
            .collect();
        json!({
            "parameter": self.parameter.to_string(),
            "unit": unit,
            "observations": self.positions.len(),
            "terms": terms,
            "removed": f.removed,
            "residual_std": f.fit.sigma,
            "residual_rms": f.rms,
            "max_abs_residual": f.max_abs_residual,
            "max_cooks_distance": {"observation": f.max_cooks_distance.0 + 1, "value": f.max_cooks_distance.1},
            "max_prediction_half_width_95": f.max_prediction_half_width,
            "wavelengths": self.wavelengths,
            "drift": self.drift.iter().map(|d| json!({"run": d.cycle, "rate_per_s": d.rate, "offset": d.offset})).collect::<Vec<_>>(),
            "residual_period": self.residual_period.map(|(p, a)| json!({"period": p, "amplitude": a})),
        })
    }

    /// The plot of the data, the fit and its 95 % prediction band.
    pub fn plot_svg(&self, position_unit: &str) -> Result<String, ReportError> {
        let (lo, hi) = self.positions.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
        let nodes = 400;
        let curve: Vec<(f64, f64, f64)> = (0..=nodes)
            .map(|k| {
                let x = lo + (hi - lo) * k as f64 / nodes as f64;
                let (v, h) = self.fitted.predict(x, 0.95);
                (x, v, h)
            })
            .collect();
        let points: Vec<(f64, f64)> = self.positions.iter().copied().zip(self.values.iter().copied()).collect();
        let title = format!("{} fitted by {} functions", self.parameter, self.fitted.names.len());
        let x_label = format!("position ({position_unit})");
        let y_label = format!("{} ({})", self.parameter, self.parameter.unit());
        fit_plot_svg(&FitPlot {
            title: &title,
            x_label: &x_label,
            y_label: &y_label,
            points: &points,
            curve: &curve,
            band_label: "95 % prediction interval",
        })
    }
}
