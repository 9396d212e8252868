//! The rotary-axis ballbar test of Jiang 2014 (the 8 PIGEs of two rotary axes from four steps), the
//! sensitivity of its methods and simulated bar readings (of its steps and of ISO 230-4 circles),
//! through the library's entry points that `trueaxis ballbar identify`, `trueaxis ballbar
//! sensitivity` and `trueaxis ballbar simulate` use.

use crate::convert::{point3, typed};
use crate::exceptions::{input, input_msg, of, warn};
use crate::machine::{Errors, Machine};
use pyo3::prelude::*;
use std::path::PathBuf;
use trueaxis::error_model::ErrorModel;
use trueaxis::evaluate::circular_test::centre_pose;
use trueaxis::identify::pige_report::{bar_lengths, identify_pige_files, method_of, sensitivity_report, PigeRequest};
use trueaxis::instruments::ballbar::{method_step, BarLengths, JiangStep, Method, Plane, RotaryPair, Rotation};
use trueaxis::instruments::ballbar_simulation::{circle_runs, noise_stream, readings_csv, SimulationSettings};

/// The method and the bars of a test, checked as the command line checks them.
fn method_and_bars(
    method: &str,
    outer_offset: Option<f64>,
    outer_positions: Option<[f64; 2]>,
    inner_positions: Option<[f64; 2]>,
    normal_length: f64,
    extended_length: f64,
) -> PyResult<(Method, BarLengths)> {
    let bars = bar_lengths(normal_length, extended_length).map_err(of)?;
    let method = method_of(method, outer_offset, outer_positions, inner_positions).map_err(of)?;
    Ok((method, bars))
}

/// The 8 PIGEs (position and orientation errors of the axis lines) of the machine's two rotary
/// axes from the four steps of Jiang 2014: the document of `trueaxis ballbar identify --json`.
///
/// a1, a2 (outer axis) and c1, c2 (inner axis): files with the swept axis position (column of its
/// letter or `angle`, deg), `dL` (um) and an optional integer `run`. method: `extended-bar`
/// (ch. 5, default), `two-pivot` (ch. 4, needs `outer_offset` in mm) or `four-setup` (ch. 6, needs
/// `outer_positions` and `inner_positions`, (p1, p2) in mm). Bar lengths in mm; pivot offsets
/// (radial, tangential) in mm from a centring test (start-angle correction); noise: the expected
/// bar noise in um (a compensation residual above 3 times it is warned about). PIGEs in um and
/// urad, with the standard uncertainty of a single run and, over several runs, mean and standard
/// deviation. Warnings are issued as `TrueaxisWarning` (and listed in the dict).
#[pyfunction]
#[pyo3(signature = (machine, a1, a2, c1, c2, *, method = "extended-bar", outer_offset = None, outer_positions = None, inner_positions = None, normal_length = 100.0, extended_length = 150.0, pivot_offset_a = None, pivot_offset_c = None, noise = 1.0))]
#[allow(clippy::too_many_arguments)]
pub fn ballbar_identify(
    py: Python<'_>,
    machine: &Machine,
    a1: PathBuf,
    a2: PathBuf,
    c1: PathBuf,
    c2: PathBuf,
    method: &str,
    outer_offset: Option<f64>,
    outer_positions: Option<[f64; 2]>,
    inner_positions: Option<[f64; 2]>,
    normal_length: f64,
    extended_length: f64,
    pivot_offset_a: Option<[f64; 2]>,
    pivot_offset_c: Option<[f64; 2]>,
    noise: f64,
) -> PyResult<Py<PyAny>> {
    let (method, bars) = method_and_bars(method, outer_offset, outer_positions, inner_positions, normal_length, extended_length)?;
    let request = PigeRequest {
        files: [a1, a2, c1, c2],
        method,
        bars,
        pivot_offset_outer: pivot_offset_a,
        pivot_offset_inner: pivot_offset_c,
        noise_um: noise,
    };
    let m = machine.inner.as_ref();
    let report = py.detach(|| identify_pige_files(m, &request)).map_err(of)?;
    warn(py, &report.warnings)?;
    typed(py, "BallbarIdentification", &report.to_json())
}

/// How a rotary-axis ballbar method reacts to its setup and to bar noise, before it is run: the
/// document of `trueaxis ballbar sensitivity --json`. Per PIGE: its change per um of each setup
/// error of each step (either ball off its place along X, Y, Z; the bar off its calibration), in
/// um/um or urad/um; its standard uncertainty per um of bar noise; and the combined standard
/// uncertainty (um, urad) for `setup_u` (each ball's placement), `bar_u` (each bar's calibration)
/// and `noise` (bar readings), all standard uncertainties in um. Method and bars as in
/// `ballbar_identify`.
#[pyfunction]
#[pyo3(signature = (machine, *, method = "extended-bar", outer_offset = None, outer_positions = None, inner_positions = None, normal_length = 100.0, extended_length = 150.0, setup_u = 1.0, bar_u = 1.0, noise = 1.0))]
#[allow(clippy::too_many_arguments)]
pub fn ballbar_sensitivity(
    py: Python<'_>,
    machine: &Machine,
    method: &str,
    outer_offset: Option<f64>,
    outer_positions: Option<[f64; 2]>,
    inner_positions: Option<[f64; 2]>,
    normal_length: f64,
    extended_length: f64,
    setup_u: f64,
    bar_u: f64,
    noise: f64,
) -> PyResult<Py<PyAny>> {
    let (method, bars) = method_and_bars(method, outer_offset, outer_positions, inner_positions, normal_length, extended_length)?;
    let m = machine.inner.as_ref();
    let report = py.detach(|| sensitivity_report(m, method, bars, setup_u, bar_u, noise)).map_err(of)?;
    typed(py, "BallbarSensitivity", &report.to_json())
}

/// Simulated bar readings on the exact kinematic chain: the CSV text of `trueaxis ballbar simulate`
/// (the axis columns in mm and deg, `angle` in deg, `dir`, `dL` in um). test: `a1`, `a2`, `c1`, `c2`
/// (a step of the rotary-axis method on the machine's two rotary axes; method and bars as in
/// `ballbar_identify`) or `circle` (ISO 230-4: in `plane` xy, yz or zx, `radius` mm about `centre`
/// (x, y, z) mm, from `start` deg, `dir` ccw, cw or both). errors: the machine's error values (None:
/// an error-free machine). step: the angle step in deg; noise: Gaussian noise added to every reading
/// (um, standard deviation), drawn from `seed` as the command line draws it.
#[pyfunction]
#[pyo3(signature = (machine, test, *, errors = None, method = "extended-bar", outer_offset = None, outer_positions = None, inner_positions = None, normal_length = 100.0, extended_length = 150.0, plane = "xy", radius = 100.0, centre = None, dir = "both", step = 1.0, start = 0.0, noise = 0.0, seed = 1))]
#[allow(clippy::too_many_arguments)]
pub fn ballbar_simulate(
    py: Python<'_>,
    machine: &Machine,
    test: &str,
    errors: Option<&Errors>,
    method: &str,
    outer_offset: Option<f64>,
    outer_positions: Option<[f64; 2]>,
    inner_positions: Option<[f64; 2]>,
    normal_length: f64,
    extended_length: f64,
    plane: &str,
    radius: f64,
    centre: Option<&Bound<'_, PyAny>>,
    dir: &str,
    step: f64,
    start: f64,
    noise: f64,
    seed: u64,
) -> PyResult<String> {
    let m = machine.inner.as_ref();
    let settings = SimulationSettings { step_deg: step, noise_um: noise, seed, radius_mm: radius, start_deg: start };
    settings.check().map_err(of)?;
    let kind = simulated_step(test)?;
    let runs = match kind {
        None => {
            let plane = Plane::parse(plane).ok_or_else(|| input_msg(format!("plane: `{plane}` is not a plane (xy, yz, zx)")))?;
            let centre = centre.map(|c| point3(c, "centre")).transpose()?;
            circle_runs(m, plane, &centre_pose(m, centre), &settings, &rotations(dir)?).map_err(input)?
        }
        Some(s) => {
            let pair = RotaryPair::of_machine(m).map_err(input)?;
            let (method, bars) = method_and_bars(method, outer_offset, outer_positions, inner_positions, normal_length, extended_length)?;
            vec![(Rotation::Ccw, method_step(m, pair, method, s, bars, step).map_err(input)?)]
        }
    };
    let zero = ErrorModel::zero(m);
    let errors = errors.map_or(&zero, |e| e.inner.as_ref());
    py.detach(|| readings_csv(m, errors, &runs, &settings, noise_stream(kind))).map_err(of)
}

/// The step of `test` (`None`: the circle).
fn simulated_step(test: &str) -> PyResult<Option<JiangStep>> {
    if test.eq_ignore_ascii_case("circle") {
        return Ok(None);
    }
    JiangStep::parse(test).map(Some).ok_or_else(|| input_msg(format!("test: `{test}` is not one of a1, a2, c1, c2, circle")))
}

/// The runs of `dir`: ccw, cw or both (CCW first).
fn rotations(dir: &str) -> PyResult<Vec<Rotation>> {
    match dir.to_ascii_lowercase().as_str() {
        "ccw" => Ok(vec![Rotation::Ccw]),
        "cw" => Ok(vec![Rotation::Cw]),
        "both" => Ok(vec![Rotation::Ccw, Rotation::Cw]),
        _ => Err(input_msg(format!("dir: `{dir}` is not ccw, cw or both"))),
    }
}
