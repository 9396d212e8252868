//! Compensation tables for controllers and the correction of NC programs, on the exact chain.

use crate::convert::typed;
use crate::exceptions::{self, input, input_msg};
use crate::machine::{Errors, Machine};
use pyo3::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use trueaxis::compensate::export::Limits;
use trueaxis::compensate::nc::{correct_program, Controller, FileId, Header, NcOptions};
use trueaxis::compensate::{compensation, nc_json, sensor_temperatures, CompensationRequest, Corrector, ExportFormat, FormatOptions};
use trueaxis::data::write_atomically;

/// Correction limits (um, urad): the machine file's `[limits]` (or the defaults), replaced by
/// `limit_um` / `limit_urad` when given (each positive), as the command line.
fn limits(machine: &trueaxis::machine::Machine, max_um: Option<f64>, max_urad: Option<f64>) -> PyResult<Limits> {
    for (name, v, rotary) in [("limit_um", max_um, false), ("limit_urad", max_urad, true)] {
        if let Some(v) = v {
            trueaxis::machine::check_limit_value(name, v, rotary).map_err(exceptions::of)?;
        }
    }
    Limits::with_overrides(machine, max_um, max_urad).map_err(exceptions::of)
}

/// Sensor temperatures (degC) in the model's order from a dict `{"T:name": degC}` (`None`: not
/// given), as `--temperature T:name=degC` options.
fn given_temperatures(errors: &Errors, given: Option<HashMap<String, f64>>) -> PyResult<Vec<Option<f64>>> {
    let mut pairs: Vec<(String, f64)> = given.unwrap_or_default().into_iter().collect();
    pairs.sort_by(|a, b| a.0.cmp(&b.0));
    sensor_temperatures(&errors.inner, &pairs).map_err(exceptions::of)
}

/// Sensor inputs in the model's order, each input's reference (20 degC, 0 rpm, ...) when not given.
fn temperatures(errors: &Errors, given: Option<HashMap<String, f64>>) -> PyResult<Vec<f64>> {
    Ok(given_temperatures(errors, given)?.into_iter().zip(errors.inner.input_references()).map(|(t, r)| t.unwrap_or(*r)).collect())
}

/// A pose (mm, deg) from `{"X": 0.0, "Z": -200.0}`, unspecified axes 0.
fn axis_values(machine: &Machine, values: &HashMap<String, f64>, what: &str) -> PyResult<Vec<f64>> {
    let m = &machine.inner;
    let mut pose = vec![0.0; m.axis_count()];
    for (name, value) in values {
        let axis = name
            .chars()
            .next()
            .filter(|_| name.chars().count() == 1)
            .and_then(|l| m.axis_index(l.to_ascii_uppercase()))
            .ok_or_else(|| input_msg(format!("{what}: machine `{}` has no axis {name} (axes: {})", m.name, m.axis_letters())))?;
        if !value.is_finite() {
            return Err(input_msg(format!("{what}: {name} = {value} is not a finite number")));
        }
        pose[axis] = *value;
    }
    Ok(pose)
}

/// Writes compensation tables for a controller into the directory `out` (created if missing; it
/// must not hold files this call does not write; every file written atomically, all or none) and
/// returns the summary of `trueaxis compensate --json`.
///
/// format: `linuxcnc`, `linuxcnc-hal`, `isg`, `heidenhain`, `siemens`, `fanuc`, `lattice`, `csv`
/// or `json`. Corrections cancel the predicted error of the tool point relative to the workpiece
/// (exact chain); `points` per table, `grid` nodes along X, Y, Z; `reference`: the reference pose
/// of the tables, e.g. `{"X": 0, "Z": -200}` (mm, deg; default: home clamped into the travel); a
/// correction beyond `limit_um` (linear axes, um) or `limit_urad` (rotary axes, urad), by default
/// the machine file's `[limits]` (else 1000 um, 10000 urad), refuses the export (InputError). `temperatures`: `{"T:name": degC}` (20 degC for a sensor not given).
/// `poses`: a pose CSV whose poses are also corrected, each in its state (`dir:<axis>` and
/// `T:<sensor>` columns, else `temperatures`), into `corrections.csv` (d<axis> in um or urad, the
/// error before and the residual after in um, the orientation not corrected in urad). The summary
/// says what the format leaves out and the error it leaves over the travel (`format_residual`,
/// um), and summarises the corrected poses (`poses`), as `trueaxis compensate --json`. Files that
/// would leave more error than they remove are refused (InputError) unless `force`.
#[pyfunction]
#[pyo3(signature = (machine, errors, format, out, *, points = 41, grid = [9, 9, 9], reference = None, limit_um = None, limit_urad = None, comp_type = 1, max_lattice_points = None, max_table_points = None, max_cec_tables = None, hal_component = "trueaxis_comp".to_string(), temperatures = None, poses = None, force = false))]
#[allow(clippy::too_many_arguments)]
pub fn compensate(
    py: Python<'_>,
    machine: &Machine,
    errors: &Errors,
    format: &str,
    out: PathBuf,
    points: usize,
    grid: [usize; 3],
    reference: Option<HashMap<String, f64>>,
    limit_um: Option<f64>,
    limit_urad: Option<f64>,
    comp_type: u8,
    max_lattice_points: Option<usize>,
    max_table_points: Option<usize>,
    max_cec_tables: Option<usize>,
    hal_component: String,
    temperatures: Option<HashMap<String, f64>>,
    poses: Option<PathBuf>,
    force: bool,
) -> PyResult<Py<PyAny>> {
    let temperatures = given_temperatures(errors, temperatures)?;
    let reference = reference.map(|r| axis_values(machine, &r, "reference")).transpose()?;
    let limits = limits(&machine.inner, limit_um, limit_urad)?;
    let options = FormatOptions { comp_type, max_lattice_points, max_table_points, max_cec_tables, hal_component };
    let format = ExportFormat::parse(format, &options).map_err(exceptions::of)?;
    let request = CompensationRequest { format, points, grid, reference, limits, temperatures, poses, force };
    let corrector = Corrector::new(&machine.inner, &errors.inner);
    let mut job = py.detach(|| compensation(&corrector, &request)).map_err(exceptions::of)?;
    job.write(&corrector, &out).map_err(exceptions::of)?;
    typed(py, "Compensation", &job.to_json(&machine.inner, &out.display().to_string(), points))
}

/// Corrects an RS274/NGC program file (as `trueaxis nc`): every programmed point moves by the
/// correction that cancels the predicted error there, long moves are split where the correction
/// departs from a straight blend by more than `tolerance_um`. Writes the program to `out` when
/// given; returns the summary of `trueaxis nc --json` (with the program text when `out` is None).
/// `dialect`: `linuxcnc`, `fanuc`, `haas`, `mach3`, `mach4`, `grbl`, `fadal` or `siemens` (default:
/// detected); `decimals`: digits written (default: 5 for mm and 6 for inch in LinuxCNC-family
/// programs, 3 / 4 in Fanuc-family programs). The program starts with a
/// header naming the machine and error files with their SHA-256; a program with that header is
/// refused unless `force`.
#[pyfunction]
#[pyo3(signature = (machine, errors, program, *, out = None, tolerance_um = 1.0, decimals = None, dialect = None, limit_um = None, limit_urad = None, temperatures = None, force = false))]
#[allow(clippy::too_many_arguments)]
pub fn correct_nc(
    py: Python<'_>,
    machine: &Machine,
    errors: &Errors,
    program: PathBuf,
    out: Option<PathBuf>,
    tolerance_um: f64,
    decimals: Option<usize>,
    dialect: Option<&str>,
    limit_um: Option<f64>,
    limit_urad: Option<f64>,
    temperatures: Option<HashMap<String, f64>>,
    force: bool,
) -> PyResult<Py<PyAny>> {
    let temperatures = self::temperatures(errors, temperatures)?;
    let text = std::fs::read(&program).map_err(|e| input_msg(format!("{}: cannot read: {e}", program.display())))?;
    if !(tolerance_um.is_finite() && tolerance_um > 0.0) {
        return Err(input_msg("tolerance_um must be a positive number"));
    }
    if decimals.is_some_and(|d| d > 9) {
        return Err(input_msg("decimals must be at most 9"));
    }
    let mut options = NcOptions::new(&machine.inner);
    options.limits = limits(&machine.inner, limit_um, limit_urad)?;
    options.tolerance_mm = tolerance_um * 1e-3;
    options.rotary_tolerance_deg = (tolerance_um * 1e-6).to_degrees();
    options.decimals = decimals;
    options.dialect = match dialect {
        None => None,
        Some(d) => Some(Controller::parse(d).ok_or_else(|| input_msg(format!("dialect `{d}` is not one of {}", Controller::names())))?),
    };
    options.header = Some(Header {
        machine: FileId::of(&machine.origin, machine.source.as_bytes()),
        errors: FileId::of(&errors.origin, errors.source.as_bytes()),
    });
    options.force = force;
    let corrector = Corrector::new(&machine.inner, &errors.inner);
    let origin = program.display().to_string();
    let result = py.detach(|| correct_program(&corrector, &text, &origin, &options, &temperatures)).map_err(exceptions::of)?;
    if let Some(path) = &out {
        write_atomically(path, &result.program).map_err(input)?;
    }
    typed(py, "NcCorrection", &nc_json(&result, out.as_ref().map(|p| p.display().to_string()).as_deref()))
}
