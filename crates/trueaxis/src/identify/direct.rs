//! The direct-measurement workflow behind `trueaxis fit`: read one measured error along its axis
//! from a CSV, optionally keep one direction and remove per-cycle drift, fit a parametric function
//! with stepwise selection, refine periodic wavelengths, and report (Soons 1993 §3.2).

use super::cycle_drift::{remove_cycle_drift, CycleDrift};
use super::fit::{fit_error_function, refine_wavelength, residual_period, FitOptions, FittedFunction, ResidualPeriod};
use super::IdentifyError;
use crate::data::CsvTable;
use crate::error_model::{Direction, ErrorModel, MachineState};
use crate::identify::direct_screening::{fit_outliers, DirectObservations};
use crate::instruments::{motion_error_axis, DirectInstrument, TableCorrection, TableCorrectionError};
use crate::io::header::RunDirection;
use crate::io::units::Dimension;
use crate::machine::{Machine, ParameterId};
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
    /// Remove per-cycle linear drift using the `run` and `t` (s) columns (Soons 1993 §3.2.2).
    pub remove_drift: bool,
    /// Refine every periodic wavelength within this relative bracket before the final fit.
    pub refine_wavelength: Option<f64>,
    pub options: FitOptions,
    /// The measurement equation through the kinematic model; without it the readings are taken as
    /// the parameter values themselves.
    pub model: Option<DirectModel>,
    /// Corrections of positioning readings to 20 degC (machine scale, reference artefact), applied
    /// first (Soons 1993 §3.2.4).
    pub corrections: Vec<TableCorrection>,
}

/// The measurement equation of a direct instrument (laser linear / straightness / angular optics,
/// level) on the exact kinematic chain (Soons 1993 §3.2.2, sequential estimation), with the other
/// axes at fixed positions. Each reading `m` at position `x` gives the value `v` of the parameter
/// that solves `reading(known errors, parameter = v; x) = m` on the exact chain: the errors already
/// known (e.g. the angular errors fitted first) enter with their Abbe effect through the chain at
/// the optics' positions, and the sensitivity of the reading to the parameter (e.g. -1 for a
/// slide that carries the workpiece) fixes the sign.
#[derive(Clone, Debug)]
pub struct DirectModel {
    pub machine: Machine,
    /// Errors already known (zero where unknown); the fitted parameter's own entry is ignored.
    pub known: ErrorModel,
    /// Positions of all axes (user units, canonical order); the measured axis's entry is replaced
    /// by each observation's position.
    pub fixed_pose: Vec<f64>,
    pub instrument: DirectInstrument,
}

impl DirectModel {
    /// Converts readings (um or urad) at axis positions (mm or deg), approached in `direction`
    /// (`None`: unknown, the mean of a bidirectional known error is used), into values of
    /// `parameter` (um or urad). Two Newton steps on the exact chain: the reading is linear in
    /// the parameter to within its square times a lever (below 1e-9 um here).
    pub fn parameter_values(
        &self,
        parameter: &ParameterId,
        positions: &[f64],
        readings: &[f64],
        direction: Option<Direction>,
    ) -> Result<Vec<f64>, IdentifyError> {
        let m = &self.machine;
        let axis = motion_error_axis(m, parameter).map_err(|e| IdentifyError::Input(e.to_string()))?;
        let p = m.parameter_index(parameter).map_err(IdentifyError::input)?;
        let to_internal = parameter.component().to_internal();
        let mut values = vec![0.0; m.parameter_count()];
        let mut q = vec![0.0; m.axis_count()];
        let mut user = self.fixed_pose.clone();
        let mut directions = vec![None; m.axis_count()];
        directions[axis] = direction;
        positions
            .iter()
            .zip(readings)
            .map(|(x, reading)| {
                user[axis] = *x;
                m.check_range(&user).map_err(IdentifyError::input)?;
                m.pose_to_internal(&user, &mut q);
                self.known.values_at_state(m, &q, &MachineState { directions: Some(&directions), temperatures: &[] }, &mut values);
                let mut at = |v: f64| {
                    values[p] = v * to_internal;
                    self.instrument.reading_user(m, &q, &values)
                };
                let base = at(0.0);
                let sensitivity = at(1.0) - base;
                if sensitivity.abs() < 0.5 {
                    return Err(IdentifyError::Input(format!(
                        "at {x}: the instrument does not see {parameter} (sensitivity {sensitivity:.3}); check the instrument, its points and \
                         the parameter"
                    )));
                }
                let mut v = (reading - base) / sensitivity;
                for _ in 0..2 {
                    // a reading far beyond any machine error (1e300) stays at its linear value
                    let next = v + (reading - at(v)) / sensitivity;
                    if next.is_finite() {
                        v = next;
                    }
                }
                Ok(v)
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
    /// Strongest sinusoid left in the residuals, above the sampling limit.
    pub residual_period: Option<ResidualPeriod>,
    /// Readings the fit does not explain (`identify::direct_screening`); the fit is of every reading.
    pub findings: Vec<crate::screen::Finding>,
}

/// Runs the workflow on a table.
pub fn run_direct_fit(table: &CsvTable, request: &DirectFitRequest) -> Result<DirectFitReport, IdentifyError> {
    // units in the headers are honoured and checked: positions mm or deg by the parameter's axis,
    // values um or urad by its component
    let p = request.parameter;
    let rotary = p.axis().is_some_and(crate::machine::is_rotary_letter);
    let position_dimension = if rotary { Dimension::Angle } else { Dimension::Length };
    let value_dimension = if p.component().is_rotation() { Dimension::Angle } else { Dimension::Length };
    let mut positions = table.numbers_as(&request.position_column, position_dimension)?;
    let mut values = table.numbers_as(&request.value_column, value_dimension)?;
    if !request.corrections.is_empty() {
        if !matches!(p, ParameterId::Motion { axis, component } if component.letter() == axis) {
            return Err(IdentifyError::Input(format!(
                "a correction to 20 degC applies to positioning readings along the axis (EXX, EYY, EZZ), not to {p}"
            )));
        }
        values = TableCorrection::apply_all(&request.corrections, table, &positions, &values).map_err(|e| match e {
            TableCorrectionError::Data(d) => IdentifyError::Data(d),
            TableCorrectionError::Scale(s) => IdentifyError::Input(s.to_string()),
        })?;
    }
    // drift removal works on whole back-and-forth cycles, before one direction is selected
    let sign: Option<Vec<f64>> = if table.has_column("dir") {
        Some(table.directions("dir")?.iter().map(|d| if *d == RunDirection::Plus { 1.0 } else { -1.0 }).collect())
    } else {
        None
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
    if let Some(model) = &request.model {
        // every position within the axis range, the error naming the file, line and column
        let axis = motion_error_axis(&model.machine, &request.parameter).map_err(|e| IdentifyError::Input(e.to_string()))?;
        let mut pose = model.fixed_pose.clone();
        let column = table.column_text(&request.position_column).unwrap_or(&request.position_column).to_string();
        for &i in &keep {
            pose[axis] = positions[i];
            model.machine.check_range(&pose).map_err(|m| table.row_error(i, &format!("column {column}: {m}")))?;
        }
    }
    positions = keep.iter().map(|&i| positions[i]).collect();
    values = keep.iter().map(|&i| values[i]).collect();
    if let Some(model) = &request.model {
        let direction = request.direction.map(|d| if d == '+' { Direction::Positive } else { Direction::Negative });
        values = model.parameter_values(&request.parameter, &positions, &values, direction)?;
    }
    let mut options = request.options.clone();
    if let Some(rel) = request.refine_wavelength {
        for k in 0..options.spec.periodic.len() {
            options.spec = refine_wavelength(&positions, &values, &options.spec, k, rel)?;
        }
    }
    let fitted = fit_error_function(&positions, &values, &options)?;
    let residual_period = residual_period(&positions, &fitted.fit.residuals, fitted.fit.sigma);
    let wavelengths = options.spec.periodic.iter().map(|p| p.wavelength).collect();
    let unit = if p.component().is_rotation() { "urad" } else { "um" };
    let observations = DirectObservations {
        table,
        rows: &keep,
        positions: &positions,
        values: &values,
        options: &options,
        position_column: &request.position_column,
        unit,
    };
    let findings = fit_outliers(&observations, &fitted)?;
    Ok(DirectFitReport { parameter: request.parameter, fitted, positions, values, drift, wavelengths, residual_period, findings })
}

impl DirectFitReport {
    /// The first result of the fit that is not a finite number, named, or `None`. A fit whose
    /// numbers overflowed (e.g. readings near 1e300) must be refused, not printed or written.
    pub fn non_finite(&self) -> Option<String> {
        let f = &self.fitted;
        let named = [
            ("the residual standard deviation", f.fit.sigma),
            ("the residual RMS", f.rms),
            ("the largest residual", f.max_abs_residual),
            ("the largest Cook's distance", f.max_cooks_distance.1),
            ("the prediction interval", f.max_prediction_half_width),
        ];
        let groups = [("a coefficient", &f.coefficients), ("a standard uncertainty", &f.std_uncertainties)];
        named
            .iter()
            .find(|(_, v)| !v.is_finite())
            .map(|(n, _)| n.to_string())
            .or_else(|| groups.iter().find(|(_, v)| v.iter().any(|x| !x.is_finite())).map(|(n, _)| n.to_string()))
            .or_else(|| self.drift.iter().any(|d| !(d.rate.is_finite() && d.offset.is_finite())).then(|| "a drift".to_string()))
            .or_else(|| self.values.iter().any(|v| !v.is_finite()).then(|| "a converted reading".to_string()))
            .or_else(|| {
                self.residual_period
                    .as_ref()
                    .is_some_and(|r| !(r.period.is_finite() && r.amplitude.is_finite()))
                    .then(|| "the periodic residual".to_string())
            })
    }

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
            "data_quality": crate::screen::findings_json(&self.findings),
            "residual_period": self.residual_period.as_ref().map(|r| json!({
                "period": r.period,
                "amplitude": r.amplitude,
                "significant": r.significant,
                "sampling_limit": r.limit,
                "sampling_step": r.uniform_step,
                "aliases": r.aliases(2),
            })),
        })
    }
}
