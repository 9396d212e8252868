//! Python objects to and from the library's file formats: a dictionary becomes the TOML text that
//! the file readers parse (so a dictionary is checked exactly like a file), a JSON document becomes
//! plain Python objects (dict, list, float, int, str, bool, None).

use crate::exceptions::input_msg;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A JSON document as Python objects (through `json.loads`, so the values equal those of the
/// command line's `--json` output read by Python).
pub fn to_py(py: Python<'_>, value: &serde_json::Value) -> PyResult<Py<PyAny>> {
    Ok(py.import("json")?.call_method1("loads", (value.to_string(),))?.unbind())
}

/// A typed result (the class `class` of `trueaxis.results`) holding the JSON document `value`: its
/// fields as attributes with numpy arrays, `to_dict()` the document (docs/python.md).
pub fn typed(py: Python<'_>, class: &str, value: &serde_json::Value) -> PyResult<Py<PyAny>> {
    let doc = to_py(py, value)?;
    Ok(py.import("trueaxis.results")?.getattr(class)?.call1((doc,))?.unbind())
}

/// TOML text of a Python mapping (nested dicts, lists, tuples, numpy arrays, numbers, strings,
/// booleans); `what` names it in messages.
pub fn toml_text(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<String> {
    match to_toml(obj, what)? {
        toml::Value::Table(t) => toml::to_string(&t).map_err(|e| input_msg(format!("{what}: {e}"))),
        _ => Err(input_msg(format!("{what}: expected a dict"))),
    }
}

fn to_toml(obj: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(obj.extract()?));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract()?));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| input_msg(format!("{at}: keys must be strings")))?;
            if v.is_none() {
                continue;
            }
            let value = to_toml(&v, &format!("{at}.{key}"))?;
            table.insert(key, value);
        }
        return Ok(toml::Value::Table(table));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let items = obj.try_iter()?.enumerate().map(|(i, v)| to_toml(&v?, &format!("{at}[{i}]"))).collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    if obj.hasattr("tolist")? {
        return to_toml(&obj.call_method0("tolist")?, at);
    }
    Err(input_msg(format!("{at}: a {} cannot be written to a trueaxis file", obj.get_type().name()?)))
}

/// A 2-D float64 array from any array-like (numpy array of any dtype or memory layout, nested
/// lists), copied row-major: `(values, [rows, columns])`. `what` names the argument in messages.
pub fn array2(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<(Vec<f64>, [usize; 2])> {
    with_array2(obj, what, |values, shape| Ok((values.to_vec(), shape)))
}

/// Calls `f` with the row-major float64 values of a 2-D array-like and its shape, without a copy
/// when `obj` is already an aligned C-contiguous float64 array; any other dtype (float32, int64,
/// ...), layout or nested lists are converted to one first by `numpy.require` (arrays unpickled by
/// Dask may be unaligned, which `numpy.require` also fixes). `what` names the argument in messages.
pub fn with_array2<R>(obj: &Bound<'_, PyAny>, what: &str, f: impl FnOnce(&[f64], [usize; 2]) -> PyResult<R>) -> PyResult<R> {
    use numpy::{PyArrayMethods, PyUntypedArrayMethods};
    let np = obj.py().import("numpy")?;
    let required = np
        .call_method1("require", (obj, "float64", vec!["C", "A"]))
        .map_err(|e| input_msg(format!("{what}: not an array of numbers: {e}")))?;
    let array = required.cast::<numpy::PyArray2<f64>>().map_err(|_| {
        let ndim: usize = required.getattr("ndim").and_then(|n| n.extract()).unwrap_or(0);
        input_msg(format!("{what}: expected a 2-dimensional array, got {ndim} dimensions"))
    })?;
    let shape = array.shape();
    let readonly = array.readonly();
    let values = readonly.as_slice().map_err(|e| input_msg(format!("{what}: {e}")))?;
    f(values, [shape[0], shape[1]])
}

/// A point of 3 coordinates (mm) from any sequence of 3 numbers; `what` names it in messages.
pub fn point3(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<trueaxis::geometry::Vec3> {
    let values: Vec<f64> =
        obj.extract().map_err(|_| input_msg(format!("{what}: expected 3 numbers x, y, z in mm, got a {}", type_name(obj))))?;
    match values[..] {
        [x, y, z] if values.iter().all(|v| v.is_finite()) => Ok(trueaxis::geometry::Vec3::new(x, y, z)),
        [_, _, _] => Err(input_msg(format!("{what}: x, y, z must be finite numbers (mm)"))),
        _ => Err(input_msg(format!("{what}: expected 3 numbers x, y, z in mm, got {}", values.len()))),
    }
}

fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "value".into())
}

/// A `pandas.DataFrame` of named columns (pandas is optional: without it an ImportError that says
/// how to install it); `what` names the method in the message.
pub fn dataframe<'py>(py: Python<'py>, columns: Vec<(&str, Bound<'py, PyAny>)>, what: &str) -> PyResult<Bound<'py, PyAny>> {
    let pandas = py.import("pandas").map_err(|_| {
        pyo3::exceptions::PyImportError::new_err(format!("{what} needs pandas, which is not installed: pip install pandas"))
    })?;
    let data = PyDict::new(py);
    for (name, values) in columns {
        data.set_item(name, values)?;
    }
    pandas.call_method1("DataFrame", (data,))
}
