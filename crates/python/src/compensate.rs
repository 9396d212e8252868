//! Compensation tables for controllers and the correction of NC programs, on the exact chain.

use crate::convert::to_py;
use crate::errors::{computation, input, input_msg};
use crate::machine::{Errors, Machine};
use pyo3::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use trueaxis::compensate::export::{largest_corrections, ExportInput, Limits};
use trueaxis::compensate::nc::{correct_program, Dialect, NcOptions};
use trueaxis::compensate::{
    axis_tables, compensation_json, nc_json, residual_of_format, volumetric_grid, CompensateError, Corrector, ExportFormat, FormatOptions,
    TableSpec,
};
use trueaxis::data::write_atomically;

fn failure(e: CompensateError) -> PyErr {
    if e.is_input() {
        input(e)
    } else {
        computation(e)
    }
}

/// Correction limits (um, urad): the machine file's `[limits]` (or the defaults), replaced by
/// `limit_um` / `limit_urad` when given (each positive), as the command line.
fn limits(machine: &trueaxis::machine::Machine, max_um: Option<f64>, max_urad: Option<f64>) -> PyResult<Limits> {
    for (name, v) in [("limit_um", max_um), ("limit_urad", max_urad)] {
        if v.is_some_and(|v| !(v.is_finite() && v > 0.0)) {
            return Err(input_msg(format!("{name} must be a positive number")));
        }
    }
    Limits::with_overrides(machine, max_um, max_urad).map_err(failure)
}

/// Sensor temperatures (degC) in the model's order from a dict `{"T:name": degC}`; 20 degC
/// for a sensor not given.
fn temperatures(errors: &Errors, given: Option<HashMap<String, f64>>) -> PyResult<Vec<f64>> {
    let sensors = errors.inner.sensors();
    let given = given.unwrap_or_default();
    if let Some(name) = given.keys().find(|k| !sensors.contains(k)) {
        return Err(input_msg(format!("temperature: the error model has no sensor `{name}` (sensors: {})", sensors.join(", "))));
    }
    Ok(sensors.iter().map(|s| given.get(s).copied().unwrap_or(20.0)).collect())
}

/// Writes compensation tables for a controller into the directory `out` (created if missing;
/// every file written atomically) and returns the summary of `trueaxis compensate --json`.
///
/// format: `linuxcnc`, `linuxcnc-hal`, `isg`, `heidenhain`, `siemens`, `fanuc`, `lattice`, `csv`
/// or `json`. Corrections cancel the predicted error of the tool point relative to the workpiece
/// (exact chain); `points` per table, `grid` nodes along X, Y, Z; a correction beyond `limit_um`
/// (linear axes, um) or `limit_urad` (rotary axes, urad), by default the machine file's `[limits]`
/// (else 1000 um, 10000 urad), refuses the export (InputError).
/// `temperatures`: `{"T:name": degC}`. The summary says what the format leaves out and the error it
/// leaves over the travel (`format_residual`, um), as `trueaxis compensate --json`.
#[pyfunction]
#[pyo3(signature = (machine, errors, format, out, *, points = 41, grid = [9, 9, 9], limit_um = None, limit_urad = None, comp_type = 1, max_lattice_points = None, max_table_points = None, max_cec_tables = None, hal_component = "trueaxis_comp".to_string(), temperatures = None))]
#[allow(clippy::too_many_arguments)]
pub fn compensate(
    py: Python<'_>,
    machine: &Machine,
    errors: &Errors,
    format: &str,
    out: PathBuf,
    points: usize,
    grid: [usize; 3],
    limit_um: Option<f64>,
    limit_urad: Option<f64>,
    comp_type: u8,
    max_lattice_points: Option<usize>,
    max_table_points: Option<usize>,
    max_cec_tables: Option<usize>,
    hal_component: String,
    temperatures: Option<HashMap<String, f64>>,
) -> PyResult<Py<PyAny>> {
    let options = FormatOptions { comp_type, max_lattice_points, max_table_points, max_cec_tables, hal_component };
    let format = ExportFormat::parse(format, &options).map_err(input_msg)?;
    let m = &machine.inner;
    let limits = limits(m, limit_um, limit_urad)?;
    let temperatures = self::temperatures(errors, temperatures)?;
    let spec = TableSpec { points, reference: None, temperatures: temperatures.clone() };
    let corrector = Corrector::new(m, &errors.inner);
    let has_xyz = ['X', 'Y', 'Z'].iter().all(|&l| m.axis_index(l).is_some());
    let (tables, grid, files, left_out, residual) = py.detach(|| -> PyResult<_> {
        let tables = axis_tables(&corrector, &spec).map_err(failure)?;
        let grid = if format.wants_grid(has_xyz) { Some(volumetric_grid(&corrector, grid, &spec).map_err(failure)?) } else { None };
        let export_input = ExportInput { machine: m, errors: &errors.inner, tables: &tables, grid: grid.as_ref(), limits };
        let (files, exported) = format.export(&export_input).map_err(failure)?;
        let residual = match &exported {
            Some(e) => Some(residual_of_format(&corrector, &temperatures, e.applied.as_ref()).map_err(failure)?),
            None => None,
        };
        let left_out = exported.map_or_else(Vec::new, |e| e.left_out);
        Ok((tables, grid, files, left_out, residual))
    })?;
    let written = ExportInput { machine: m, errors: &errors.inner, tables: &tables, grid: grid.as_ref(), limits };
    let extent = largest_corrections(&written, format.coverage());
    std::fs::create_dir_all(&out).map_err(|e| input_msg(format!("{}: cannot create the output directory: {e}", out.display())))?;
    for f in &files {
        write_atomically(&out.join(&f.name), f.contents.as_bytes()).map_err(input)?;
    }
    let names: Vec<&str> = files.iter().map(|f| f.name.as_str()).collect();
    let doc =
        compensation_json(m, &out.display().to_string(), &names, tables.tables.len(), points, &extent, &left_out, residual.as_ref(), None);
    to_py(py, &doc)
}

/// Corrects an RS274/NGC program file (as `trueaxis nc`): every programmed point moves by the
/// correction that cancels the predicted error there, long moves are split where the correction
/// departs from a straight blend by more than `tolerance_um`. Writes the program to `out` when
/// given; returns the summary of `trueaxis nc --json` (with the program text when `out` is None).
/// `dialect`: `linuxcnc` or `fanuc` (default: detected); `decimals`: digits written (default: 5 for
/// mm and 6 for inch in LinuxCNC programs, 3 / 4 in Fanuc programs).
#[pyfunction]
#[pyo3(signature = (machine, errors, program, *, out = None, tolerance_um = 1.0, decimals = None, dialect = None, limit_um = None, limit_urad = None, temperatures = None))]
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
) -> PyResult<Py<PyAny>> {
    let temperatures = self::temperatures(errors, temperatures)?;
    let text = std::fs::read_to_string(&program).map_err(|e| input_msg(format!("{}: cannot read: {e}", program.display())))?;
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
        Some(d) => Some(Dialect::parse(d).ok_or_else(|| input_msg(format!("dialect `{d}` is not linuxcnc or fanuc")))?),
    };
    let corrector = Corrector::new(&machine.inner, &errors.inner);
    let origin = program.display().to_string();
    let result = py.detach(|| correct_program(&corrector, &text, &origin, &options, &temperatures)).map_err(failure)?;
    if let Some(path) = &out {
        write_atomically(path, result.text.as_bytes()).map_err(input)?;
    }
    to_py(py, &nc_json(&result, out.as_ref().map(|p| p.display().to_string()).as_deref()))
}
