//! The rotary-axis ballbar test of Jiang 2014 (the 8 PIGEs of two rotary axes from four steps) and the
//! sensitivity of its methods, through the library's entry points that `trueaxis ballbar identify`
//! and `trueaxis ballbar sensitivity` use.

use crate::convert::typed;
use crate::exceptions::{of, warn};
use crate::machine::Machine;
use pyo3::prelude::*;
use std::path::PathBuf;
use trueaxis::identify::pige_report::{bar_lengths, identify_pige_files, method_of, sensitivity_report, PigeRequest};
use trueaxis::instruments::ballbar::{BarLengths, Method};

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
