//! Thermal error models fitted to a campaign and evaluated on one, the modes of a thermal model and
//! the placement of its temperature sensors, through the library's entry points that `trueaxis
//! thermal fit`, `predict`, `modes` and `place` use.

use crate::convert::typed;
use crate::exceptions::{self, input, input_msg};
use crate::machine::Machine;
use crate::progress::Progress;
use pyo3::prelude::*;
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::screen::irls::Weighting;
use trueaxis::thermal::campaign_fit::{fit_campaign, CampaignFit, FitRequest, ModelForm};
use trueaxis::thermal::campaign_predict::{predict_campaign, read_model_file};
use trueaxis::thermal::model_file::load_model;
use trueaxis::thermal::modes_report::ModesReport;
use trueaxis::thermal::placement_job::{place_sensors, placement_modes, PlaceMethod, PlacementRequest};
use trueaxis::thermal::thermal_campaign::Campaign;
use trueaxis::thermal::{LanczosProgress, SpectrumMethod, DEFAULT_SHARE};

/// Fits a thermal error model to a campaign CSV (columns `t` in s, `run`, `T:<sensor>` in degC,
/// the error in um): the document of `trueaxis thermal fit --json` (`model`, `kept`, residual
/// statistics in um of `training` and of each `validation` run or part).
///
/// model: `regression` (PITE/PDTE, Zhu 2008 eqs. 3.12-3.15, with intercepts unless
/// `no_intercept`; `position` names an axis column whose powers up to `degree` enter it) or
/// `state-space` (the drift as `rates` first-order lags of the sensors' rises, Soons 1993 §3.4.4).
/// train_runs: the runs to train on (the others validate); validate: `"time-split:F"` trains on
/// the first fraction F of each training run and verifies on the rest. sensors: the sensor
/// columns (default all); select: `"correlation:N"` or `"stepwise"`. geometric_degree: the
/// geometric/thermal split (the degree of the geometric polynomial in the position, `degree` that
/// of the position multiplying the temperatures); by_direction / ranges (breakpoints in mm or deg):
/// the G-T model (NISTIR 5236), one model per direction of motion (column `dir`) and position
/// range. With `time_constants=N`: the
/// eq. 3.17 fit of N shared time constants (min) to the temperature records instead, over the
/// first `until` s of each run. out: write the model file (TOML) for `thermal_predict`;
/// terms_out with parameter (e.g. `"EZZ"`): the model as error terms (T - 20 degC) for
/// `Errors.from_file`, checked against `machine` when given. As the command's options
/// (docs/screening.md): skip_missing leaves out the rows with a blank cell (a logger dropout) and
/// lists them under `data_quality`; split_gaps cuts each run at its gaps in `t`; robust
/// (`"huber"` or `"tukey"`) fits the regression by M-estimation, its weights, coefficient
/// uncertainties and downweighted samples under `robust`.
#[pyfunction]
#[pyo3(signature = (data, error = None, *, model = "regression", rates = 2, validate = None, time_constants = None, until = None, sensors = None, select = None, position = None, degree = 0, no_intercept = false, geometric_degree = None, by_direction = false, ranges = None, train_runs = None, out = None, parameter = None, terms_out = None, machine = None, skip_missing = false, split_gaps = false, robust = None))]
#[allow(clippy::too_many_arguments)]
pub fn thermal_fit(
    py: Python<'_>,
    data: PathBuf,
    error: Option<String>,
    model: &str,
    rates: usize,
    validate: Option<String>,
    time_constants: Option<usize>,
    until: Option<f64>,
    sensors: Option<Vec<String>>,
    select: Option<String>,
    position: Option<String>,
    degree: usize,
    no_intercept: bool,
    geometric_degree: Option<usize>,
    by_direction: bool,
    ranges: Option<Vec<f64>>,
    train_runs: Option<Vec<String>>,
    out: Option<PathBuf>,
    parameter: Option<String>,
    terms_out: Option<PathBuf>,
    machine: Option<&Machine>,
    skip_missing: bool,
    split_gaps: bool,
    robust: Option<&str>,
) -> PyResult<Py<PyAny>> {
    let robust = match robust {
        None => None,
        Some(name) => Some(Weighting::parse(name).ok_or_else(|| input_msg(format!("robust `{name}`: expected huber or tukey")))?),
    };
    let model = match model {
        "regression" => ModelForm::Regression,
        "state-space" | "state_space" => ModelForm::StateSpace,
        other => return Err(input_msg(format!("model `{other}`: expected regression or state-space"))),
    };
    if terms_out.is_some() && parameter.is_none() {
        return Err(input_msg("terms_out needs parameter: the ISO parameter the error is (e.g. EZZ, TZ)"));
    }
    let request = FitRequest {
        error,
        model,
        rates,
        validate,
        time_constants,
        until,
        sensors,
        select,
        position,
        degree,
        no_intercept,
        geometric_degree,
        by_direction,
        ranges,
        train_runs,
        robust,
        terms: terms_out.is_some(),
    };
    let (campaign, findings) =
        trueaxis::thermal::thermal_screening::read_screened(&data, skip_missing, split_gaps).map_err(exceptions::of)?;
    let name = data.display().to_string();
    let fitted = py.detach(|| fit_campaign(&campaign, &name, &request)).map_err(exceptions::of)?;
    if let CampaignFit::Model(m) = &fitted {
        if let Some(path) = &out {
            write_atomically(path, m.model.to_toml().as_bytes()).map_err(input)?;
        }
        if let (Some(path), Some(parameter)) = (&terms_out, &parameter) {
            if let Some(text) = m.terms_text(parameter, machine.map(|m| m.inner.as_ref())).map_err(exceptions::of)? {
                write_atomically(path, text.as_bytes()).map_err(input)?;
            }
        }
    }
    let mut doc = fitted.to_json();
    doc["data_quality"] = trueaxis::screen::findings_json(&findings);
    typed(py, "ThermalFit", &doc)
}

/// Evaluates a fitted thermal error model (the TOML file `thermal_fit(..., out=...)` or `trueaxis
/// thermal fit --out` writes) on a campaign CSV: the document of `trueaxis thermal predict --json`
/// (per row the run, `t` in s, the prediction in um and, with the error column present, the
/// measured value and the residual; residual statistics per run in um).
#[pyfunction]
pub fn thermal_predict(py: Python<'_>, model: PathBuf, data: PathBuf) -> PyResult<Py<PyAny>> {
    let model = read_model_file(&model).map_err(exceptions::of)?;
    let campaign = Campaign::read(&data).map_err(exceptions::of)?;
    let prediction = py.detach(|| predict_campaign(&model, &campaign)).map_err(exceptions::of)?;
    typed(py, "ThermalPrediction", &prediction.to_json())
}

/// The thermal modes of a model file (`examples/thermal/*.toml`, docs/thermal.md): the document of
/// `trueaxis thermal modes --json` (per mode the time constant in min and s, its weight under the
/// model's step load, its share, whether it is dominant; the dominant modes carry `share` of the
/// weight). `method`: `auto`, `dense`, `lanczos` or `lobpcg`. `progress(done, total)`, if given, is
/// called as the modes converge (`total` = the modes asked, at most one per node).
#[pyfunction]
#[pyo3(signature = (model, *, count = 10, share = DEFAULT_SHARE, method = "auto", progress = None))]
pub fn thermal_modes(
    py: Python<'_>,
    model: PathBuf,
    count: usize,
    share: f64,
    method: &str,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let method = match method {
        "auto" => SpectrumMethod::Auto,
        "dense" => SpectrumMethod::Dense,
        "lanczos" => SpectrumMethod::Lanczos,
        "lobpcg" => SpectrumMethod::Lobpcg,
        other => return Err(input_msg(format!("method `{other}`: expected auto, dense, lanczos or lobpcg"))),
    };
    let model = load_model(&model).map_err(exceptions::of)?;
    let total = count.min(model.system.node_count());
    let progress = Progress::new(progress)?;
    let report = py.detach(|| {
        ModesReport::new(&model, count, method, share, &mut |p| match p {
            LanczosProgress::Iterating { converged, .. } | LanczosProgress::Refining { converged, .. } => {
                progress.report(converged.min(total), total)
            }
            _ => {}
        })
    });
    progress.report(total, total);
    progress.finish()?;
    typed(py, "ThermalModes", &report.map_err(exceptions::of)?.to_json())
}

/// Temperature-sensor placement for the dominant modes of a model file (Zhu 2008 §3.4): the
/// document of `trueaxis thermal place --json` (the sensors with their node, position in m and the
/// dominant modes each serves, numbered from 1; the rank and condition number of the sensor-mode
/// matrix Phi_s, null when infinite). `count` modes are computed, the dominant ones carry `share`
/// of the weight; `method` modal | efi | exhaustive | gauss; `sensors` their number (default one
/// per dominant mode); `reuse` the modal rule's reuse fraction. `score=True` scores every method by
/// the error of the elongation model it leads to (um, `scores`), with the bar's `expansion`
/// coefficient in um/m/K. The GIL is released.
#[pyfunction]
#[pyo3(signature = (model, *, count = 20, share = DEFAULT_SHARE, method = "modal", sensors = None, reuse = 0.8, score = false, expansion = 10.8))]
#[allow(clippy::too_many_arguments)]
pub fn thermal_place(
    py: Python<'_>,
    model: PathBuf,
    count: usize,
    share: f64,
    method: &str,
    sensors: Option<usize>,
    reuse: f64,
    score: bool,
    expansion: f64,
) -> PyResult<Py<PyAny>> {
    let request = PlacementRequest {
        count,
        share,
        method: PlaceMethod::parse(method).map_err(exceptions::of)?,
        sensors,
        reuse,
        score: score.then_some(expansion),
    };
    request.check().map_err(exceptions::of)?;
    let model = load_model(&model).map_err(exceptions::of)?;
    let placement = py.detach(|| {
        let basis = placement_modes(&model, count, &mut |_| {})?;
        place_sensors(&model, basis, &request)
    });
    typed(py, "ThermalPlacement", &placement.map_err(exceptions::of)?.to_json(&model))
}
