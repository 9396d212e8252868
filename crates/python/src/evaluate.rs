//! Standard evaluations from their files: ISO 230-2 positioning tests and ISO 230-4 circular tests,
//! through the library's entry points that `trueaxis iso230-2` and `trueaxis ballbar iso230-4` use.

use crate::convert::{point3, typed};
use crate::exceptions::{input_msg, of, warn};
use crate::machine::Machine;
use pyo3::prelude::*;
use std::path::PathBuf;
use trueaxis::evaluate::circular_test::{cartesian_machine, circular_test_file, CircularTestOptions};
use trueaxis::evaluate::positioning_test::evaluate_file;
use trueaxis::instruments::ballbar::Plane;
use trueaxis::instruments::{TemperatureOptions, TemperatureSource};

/// A temperature given as degC (a number) or as the name of a data column (e.g. `"T:scale"`).
fn temperature_source(value: Option<&Bound<'_, PyAny>>, what: &str) -> PyResult<Option<TemperatureSource>> {
    let Some(v) = value else { return Ok(None) };
    if let Ok(t) = v.extract::<f64>() {
        return Ok(Some(TemperatureSource::Uniform(t)));
    }
    match v.extract::<String>() {
        Ok(text) => Ok(Some(TemperatureSource::parse(&text))),
        Err(_) => Err(input_msg(format!("{what}: expected a temperature in degC or the name of a column (e.g. \"T:scale\")"))),
    }
}

/// The temperature and expansion coefficient of one body go together.
fn pair(temperature: &Option<TemperatureSource>, expansion: Option<f64>, names: (&str, &str)) -> PyResult<()> {
    if temperature.is_some() != expansion.is_some() {
        return Err(input_msg(format!("{} and {} must be given together (degC or a column, and um/m/K)", names.0, names.1)));
    }
    Ok(())
}

/// The correction of positioning readings to 20 degC as `iso230_2` and `fit` take it: the scale's
/// and the artefact's temperature (degC or a column) each with its expansion (um/m/K), the datum
/// (mm), and whether to ignore the file's recorded environment.
pub(crate) fn temperature_options(
    scale_temperature: Option<&Bound<'_, PyAny>>,
    scale_expansion: Option<f64>,
    artefact_temperature: Option<&Bound<'_, PyAny>>,
    artefact_expansion: Option<f64>,
    temperature_datum: f64,
    no_file_temperature: bool,
) -> PyResult<TemperatureOptions> {
    let options = TemperatureOptions {
        scale_temperature: temperature_source(scale_temperature, "scale_temperature")?,
        scale_expansion,
        artefact_temperature: temperature_source(artefact_temperature, "artefact_temperature")?,
        artefact_expansion,
        datum_mm: temperature_datum,
        no_file_temperature,
    };
    pair(&options.scale_temperature, scale_expansion, ("scale_temperature", "scale_expansion"))?;
    pair(&options.artefact_temperature, artefact_expansion, ("artefact_temperature", "artefact_expansion"))?;
    Ok(options)
}

/// ISO 230-2:2014 accuracy and repeatability of positioning from a table of bidirectional runs
/// (columns target in mm, dev in um, dir `+`/`-`, run; or one column per run and direction) or a
/// Renishaw `.rtl` file: the document of `trueaxis iso230-2 --json` (A, R, E, M, B and their
/// unidirectional values in um, urad for a rotary axis, coverage factor 2; the file's `metadata`;
/// the `temperature_correction` applied).
///
/// The deviations are corrected to 20 degC with `scale_temperature` (degC, or a column with one
/// temperature per reading) and `scale_expansion` (um/m/K) of the machine scale, and/or
/// `artefact_temperature` and `artefact_expansion` of a reference artefact, about
/// `temperature_datum` (mm); without them, with the material temperature and expansion
/// coefficient the file records, unless `no_file_temperature`. Plausibility warnings and notes
/// are issued as `TrueaxisWarning`.
#[pyfunction]
#[pyo3(signature = (path, *, scale_temperature = None, scale_expansion = None, artefact_temperature = None, artefact_expansion = None, temperature_datum = 0.0, no_file_temperature = false))]
#[allow(clippy::too_many_arguments)]
pub fn iso230_2(
    py: Python<'_>,
    path: PathBuf,
    scale_temperature: Option<&Bound<'_, PyAny>>,
    scale_expansion: Option<f64>,
    artefact_temperature: Option<&Bound<'_, PyAny>>,
    artefact_expansion: Option<f64>,
    temperature_datum: f64,
    no_file_temperature: bool,
) -> PyResult<Py<PyAny>> {
    let options = temperature_options(
        scale_temperature,
        scale_expansion,
        artefact_temperature,
        artefact_expansion,
        temperature_datum,
        no_file_temperature,
    )?;
    let test = py.detach(|| evaluate_file(&path, &options)).map_err(of)?;
    warn(py, &test.warnings)?;
    warn(py, &test.notes)?;
    typed(py, "PositioningTest", &test.to_json())
}

/// ISO 230-4 circular test with a ballbar: the document of `trueaxis ballbar iso230-4 --json`
/// (per run the least-squares centre and radius change, circular deviation G and radial deviation
/// F in um; hysteresis H in um; diagnostics fitted on the machine's kinematic model with their
/// standard uncertainties; the file's metadata).
///
/// path: a table (`angle` in deg or the plane's two axis columns in mm, `dL` in um, optional `dir`
/// ccw/cw) or a ballbar text export. machine: the machine the diagnostics are fitted on (default: a
/// Cartesian machine whose three slides carry the tool). plane: `xy`, `yz` or `zx` (default: the
/// file's, else xy); radius: the bar length in mm (default: the file's); centre: the programmed
/// centre x, y, z in mm; feed in mm/min (servo mismatch in ms), pitch of the ball screws in mm
/// (cyclic errors), spike_width the decay angle of reversal spikes in deg.
#[pyfunction]
#[pyo3(signature = (path, *, machine = None, plane = None, radius = None, centre = None, feed = None, pitch = None, spike_width = 3.0))]
#[allow(clippy::too_many_arguments)]
pub fn iso230_4(
    py: Python<'_>,
    path: PathBuf,
    machine: Option<&Machine>,
    plane: Option<&str>,
    radius: Option<f64>,
    centre: Option<&Bound<'_, PyAny>>,
    feed: Option<f64>,
    pitch: Option<f64>,
    spike_width: f64,
) -> PyResult<Py<PyAny>> {
    let plane = plane.map(|p| Plane::parse(p).ok_or_else(|| input_msg(format!("plane: `{p}` is not a plane (xy, yz, zx)")))).transpose()?;
    let options = CircularTestOptions {
        plane,
        radius_mm: radius,
        centre_mm: centre.map(|c| point3(c, "centre")).transpose()?,
        feed_mm_per_min: feed,
        pitch_mm: pitch,
        spike_width_deg: spike_width,
    };
    let cartesian;
    let m = match machine {
        Some(m) => m.inner.as_ref(),
        None => {
            cartesian = cartesian_machine();
            &cartesian
        }
    };
    let test = py.detach(|| circular_test_file(&path, m, &options)).map_err(of)?;
    warn(py, &test.file.warnings)?;
    typed(py, "CircularTest", &test.to_json())
}
