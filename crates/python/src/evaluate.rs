//! ISO 230-2 evaluation of positioning accuracy and repeatability.

use crate::convert::to_py;
use crate::errors::{computation, input};
use pyo3::prelude::*;
use std::path::PathBuf;
use trueaxis::evaluate::iso230_2::{evaluate, read_runs};
use trueaxis::evaluate::EvaluateError;

fn failure(e: EvaluateError) -> PyErr {
    if e.is_input() {
        input(e)
    } else {
        computation(e)
    }
}

/// ISO 230-2:2014 accuracy and repeatability of positioning from a CSV of bidirectional runs
/// (columns target in mm, dev in um, dir `+`/`-`, run): the document of `trueaxis iso230-2
/// --json` (A, R, E, M, B and their unidirectional values in um, coverage factor 2).
#[pyfunction]
pub fn iso230_2(py: Python<'_>, path: PathBuf) -> PyResult<Py<PyAny>> {
    let data = read_runs(&path).map_err(failure)?;
    let result = evaluate(&data).map_err(failure)?;
    to_py(py, &result.to_json())
}
