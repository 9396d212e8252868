//! A parametric error function fitted to one error measured along its axis (laser, level,
//! straightedge), `trueaxis.fit`, through the library's direct fit that `trueaxis fit` runs
//! (`trueaxis::identify::direct_job`; Soons 1993 §3.2): positions in mm (deg for rotary axes),
//! values in um (urad for angular errors), points in mm in the machine frame at home,
//! temperatures in degC, expansion coefficients in um/m/K.

use crate::convert::{point3, typed};
use crate::evaluate::temperature_options;
use crate::exceptions::{input, of, warn};
use crate::machine::{Errors, Machine};
use pyo3::prelude::*;
use std::collections::BTreeMap;
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::identify::{run_direct_job, DirectFitJob, Given};

/// `{"Y": 0, "Z": -200}` as the command's `--at Y=0,Z=-200`.
fn at_text(at: Option<BTreeMap<String, f64>>) -> Option<String> {
    at.map(|at| at.iter().map(|(axis, v)| format!("{axis}={v}")).collect::<Vec<_>>().join(","))
}

/// Fits the motion error `parameter` (EXX, EBX, EYZ, ...) measured in `data` (a table read
/// forgivingly, or a Renishaw .rtl file): the document of `trueaxis fit --json` (the functions
/// kept by stepwise selection with their coefficients and standard uncertainties, the residual
/// statistics in um or urad, the 95 % prediction band, the strongest periodic residual, data
/// quality; `plus` and `minus` with `direction="both"`; the file's `metadata` and the
/// `temperature_correction` applied).
///
/// The keyword arguments are the command's options: `machine` (relates the readings to the
/// parameter through the exact chain with `instrument` laser-linear | laser-straightness |
/// laser-angular | level, `optics_offset` (A, B) in mm, `beam_on` tool | workpiece,
/// `level_reference`, the known `errors_in` whose Abbe terms are removed, `tool_point`,
/// `work_point` in mm, `at` the other axes' positions, e.g. `{"Z": -200}`); the columns
/// `position` and `value`; the basis (`domain` (min, max), `family` piecewise | bspline |
/// legendre | none, `degree`, `knots` or `knot_spacing`, `continuity`, `constant`, `constraint`
/// none | straightness | revolution, `periodic` terms `"WAVELENGTH[:DEGREE[:KNOT;KNOT...]]"`,
/// `refine_wavelength`); `stepwise` (the confidence of the selection); `direction` `+` | `-` |
/// `both`; `drift`; the correction to 20 degC as `iso230_2` takes it. `errors_out` writes or
/// updates an error-values file (needs `machine`) as `--errors-out` does. Warnings and notes are
/// issued as `TrueaxisWarning`. The GIL is released.
#[pyfunction]
#[pyo3(signature = (data, parameter, *, machine = None, instrument = None, optics_offset = None, beam_on = None, level_reference = "base", errors_in = None, tool_point = None, work_point = None, at = None, position = None, value = "dev", domain = None, family = "piecewise", degree = 2, knots = None, knot_spacing = None, continuity = 1, constant = true, constraint = "none", periodic = None, refine_wavelength = None, stepwise = None, direction = None, drift = false, scale_temperature = None, scale_expansion = None, artefact_temperature = None, artefact_expansion = None, temperature_datum = 0.0, no_file_temperature = false, errors_out = None))]
#[allow(clippy::too_many_arguments)]
pub fn fit(
    py: Python<'_>,
    data: PathBuf,
    parameter: String,
    machine: Option<&Machine>,
    instrument: Option<String>,
    optics_offset: Option<[f64; 2]>,
    beam_on: Option<String>,
    level_reference: &str,
    errors_in: Option<&Errors>,
    tool_point: Option<&Bound<'_, PyAny>>,
    work_point: Option<&Bound<'_, PyAny>>,
    at: Option<BTreeMap<String, f64>>,
    position: Option<String>,
    value: &str,
    domain: Option<[f64; 2]>,
    family: &str,
    degree: usize,
    knots: Option<Vec<f64>>,
    knot_spacing: Option<f64>,
    continuity: usize,
    constant: bool,
    constraint: &str,
    periodic: Option<Vec<String>>,
    refine_wavelength: Option<f64>,
    stepwise: Option<f64>,
    direction: Option<String>,
    drift: bool,
    scale_temperature: Option<&Bound<'_, PyAny>>,
    scale_expansion: Option<f64>,
    artefact_temperature: Option<&Bound<'_, PyAny>>,
    artefact_expansion: Option<f64>,
    temperature_datum: f64,
    no_file_temperature: bool,
    errors_out: Option<PathBuf>,
) -> PyResult<Py<PyAny>> {
    let temperature = temperature_options(
        scale_temperature,
        scale_expansion,
        artefact_temperature,
        artefact_expansion,
        temperature_datum,
        no_file_temperature,
    )?;
    let job = DirectFitJob {
        machine: machine.map(|m| Given::Value(m.inner.as_ref().clone())),
        instrument,
        optics_offset,
        beam_on,
        level_reference: level_reference.into(),
        temperature,
        errors_in: errors_in.map(|e| Given::Value(e.inner.as_ref().clone())),
        errors_out: errors_out.clone(),
        tool_point: tool_point.map(|p| point3(p, "tool_point")).transpose()?,
        work_point: work_point.map(|p| point3(p, "work_point")).transpose()?,
        at: at_text(at),
        position,
        value: value.into(),
        domain,
        family: family.into(),
        degree,
        knots: knots.unwrap_or_default(),
        knot_spacing,
        continuity,
        constant,
        constraint: constraint.into(),
        periodic: periodic.unwrap_or_default(),
        refine_wavelength,
        stepwise,
        direction,
        drift,
        ..DirectFitJob::new(data, parameter)
    };
    let run = py.detach(|| run_direct_job(&job)).map_err(of)?;
    if let Some(path) = &errors_out {
        let text = run.error_values_text(path).map_err(of)?;
        write_atomically(path, text.as_bytes()).map_err(input)?;
    }
    warn(py, &run.warnings)?;
    warn(py, &run.applied.notes)?;
    typed(py, "DirectFit", &run.to_json())
}
