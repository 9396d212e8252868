//! `trueaxis.Machine` and `trueaxis.Errors`: a machine description and its error model, from
//! files, TOML text or dictionaries; the volumetric error of many poses at once.

use crate::convert::{array2, point3, toml_text, typed, with_array2};
use crate::exceptions::{computation, input, input_msg};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;
use trueaxis::error_model::{Direction, ErrorModel};
use trueaxis::geometry::Vec3;
use trueaxis::model::{Frame, Predictor, Setup};
use trueaxis::poses::{predictions_json, read_poses};

fn read_text(path: &std::path::Path, what: &str) -> PyResult<String> {
    std::fs::read_to_string(path).map_err(|e| input_msg(format!("{}: cannot read {what}: {e}", path.display())))
}

/// A machine description (structure, axes, tool point); immutable.
///
/// Positions are in mm (linear axes) and deg (rotary axes), in the order of `axes`.
#[pyclass(module = "trueaxis", frozen)]
#[derive(Clone)]
pub struct Machine {
    pub inner: Arc<trueaxis::machine::Machine>,
    /// The TOML text it was read from (pickling; the header of a corrected NC program).
    pub(crate) source: String,
    pub(crate) origin: String,
}

impl Machine {
    fn parse(text: String, origin: &str) -> PyResult<Machine> {
        let inner = trueaxis::machine::Machine::from_toml_str(&text, origin).map_err(input)?;
        Ok(Machine { inner: Arc::new(inner), source: text, origin: origin.to_string() })
    }

    /// `(N, axes)` positions (mm, deg) as a flat row-major vector and N, checked against the travel.
    pub fn poses_of(&self, poses: &Bound<'_, PyAny>) -> PyResult<(Vec<f64>, usize)> {
        with_array2(poses, "poses", |user, shape| Ok((user.to_vec(), self.check_poses(user, shape)?)))
    }

    /// The number of poses of a `(N, axes)` array of positions (mm, deg), each checked against the
    /// travel of its axes.
    pub fn check_poses(&self, user: &[f64], shape: [usize; 2]) -> PyResult<usize> {
        let n_axes = self.inner.axis_count();
        if shape[1] != n_axes {
            return Err(input_msg(format!(
                "poses: expected an array of shape (N, {n_axes}) with the axes {} in mm and deg, got ({}, {})",
                self.inner.axis_letters(),
                shape[0],
                shape[1]
            )));
        }
        // the test of `Axis::in_range` (travel widened by 1e-9) over all poses without branches;
        // an axis without travel accepts every finite position; NaN fails every comparison
        let bounds: Vec<[f64; 2]> =
            self.inner.axes().iter().map(|a| a.range.map_or([-f64::MAX, f64::MAX], |[lo, hi]| [lo - 1e-9, hi + 1e-9])).collect();
        let inside = |pose: &[f64]| pose.iter().zip(&bounds).fold(true, |ok, (&v, &[lo, hi])| ok & (v >= lo) & (v <= hi));
        if !user.chunks_exact(n_axes.max(1)).fold(true, |ok, pose| ok & inside(pose)) {
            for (i, pose) in user.chunks(n_axes.max(1)).enumerate() {
                self.inner.check_range(pose).map_err(|e| crate::exceptions::of(e.context(format!("poses: row {i}"))))?;
            }
        }
        Ok(shape[0])
    }

    /// `(count, axes)` directions of motion from -1, 0, +1 (`None` at rest), checked.
    fn directions_of(&self, directions: &Bound<'_, PyAny>, count: usize) -> PyResult<Vec<Option<Direction>>> {
        let n_axes = self.inner.axis_count();
        let (values, shape) = array2(directions, "directions")?;
        if shape != [count, n_axes] {
            return Err(input_msg(format!(
                "directions: expected an array of shape ({count}, {n_axes}) of -1, 0, +1 for the axes {}, got ({}, {})",
                self.inner.axis_letters(),
                shape[0],
                shape[1]
            )));
        }
        let letters: Vec<char> = self.inner.axis_letters().chars().collect();
        values
            .iter()
            .enumerate()
            .map(|(k, &v)| {
                if v == 1.0 {
                    Ok(Some(Direction::Positive))
                } else if v == -1.0 {
                    Ok(Some(Direction::Negative))
                } else if v == 0.0 {
                    Ok(None)
                } else {
                    Err(input_msg(format!(
                        "directions: row {}, axis {}: {v} is not -1, 0 or +1 (the direction of motion; 0 at rest)",
                        k / n_axes.max(1),
                        letters[k % n_axes.max(1)]
                    )))
                }
            })
            .collect()
    }

    /// `(count, sensors)` temperatures (degC) in the order of `model.sensors()`, flat; empty for
    /// a model without temperature terms.
    fn temperatures_of(&self, model: &ErrorModel, temperatures: Option<&Bound<'_, PyAny>>, count: usize) -> PyResult<Vec<f64>> {
        let sensors = model.sensors();
        match temperatures.map(|t| array2(t, "temperatures")).transpose()? {
            Some((t, shape)) if shape == [count, sensors.len()] => Ok(t),
            Some((_, shape)) => Err(input_msg(format!(
                "temperatures: expected an array of shape ({count}, {}) for the sensors {:?} (degC), got {:?}",
                sensors.len(),
                sensors,
                shape
            ))),
            None if sensors.is_empty() => Ok(Vec::new()),
            None => Err(input_msg(format!("temperatures: the error model needs the sensors {sensors:?} (degC)"))),
        }
    }

    /// The setup of a prediction: tool and work points (mm, machine frame at home), each a
    /// sequence of 3 numbers, by default the machine's tool point and the origin.
    pub fn setup(&self, tool_point: Option<&Bound<'_, PyAny>>, work_point: Option<&Bound<'_, PyAny>>) -> PyResult<Setup> {
        Ok(Setup {
            tool_point: tool_point.map(|p| point3(p, "tool_point")).transpose()?.unwrap_or(self.inner.tool_point),
            work_point: work_point.map(|p| point3(p, "work_point")).transpose()?.unwrap_or_else(Vec3::zeros),
        })
    }
}

/// `workpiece` or `machine`.
pub fn parse_frame(frame: &str) -> PyResult<Frame> {
    match frame {
        "workpiece" => Ok(Frame::Workpiece),
        "machine" => Ok(Frame::Machine),
        other => Err(input_msg(format!("frame `{other}`: expected `workpiece` or `machine`"))),
    }
}

#[pymethods]
impl Machine {
    /// Reads a machine TOML file.
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Machine> {
        let inner = trueaxis::machine::Machine::load(&path).map_err(input)?;
        let source = read_text(&path, "machine file")?;
        Ok(Machine { inner: Arc::new(inner), source, origin: path.display().to_string() })
    }

    /// A machine from the text of a machine TOML file; `origin` names it in messages.
    #[staticmethod]
    #[pyo3(signature = (text, origin = "<machine>"))]
    fn from_toml(text: String, origin: &str) -> PyResult<Machine> {
        Machine::parse(text, origin)
    }

    /// A machine from a dict with the keys of a machine TOML file (`name`, `structure`, `axes`, `tool`).
    #[staticmethod]
    fn from_dict(d: &Bound<'_, PyAny>) -> PyResult<Machine> {
        Machine::parse(toml_text(d, "machine")?, "<machine dict>")
    }

    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// Axis letters in the order of the pose columns, e.g. `"XYZAC"`.
    #[getter]
    fn axes(&self) -> String {
        self.inner.axis_letters()
    }

    /// Unit of each axis position (`mm` or `deg`).
    #[getter]
    fn units(&self) -> Vec<&'static str> {
        self.inner.axes().iter().map(|a| a.position_unit()).collect()
    }

    /// Tool point at home in the machine frame (mm).
    #[getter]
    fn tool_point(&self) -> (f64, f64, f64) {
        let p = self.inner.tool_point;
        (p[0], p[1], p[2])
    }

    /// The TOML text of the description.
    #[getter]
    fn toml(&self) -> String {
        self.source.clone()
    }

    /// Reads a pose CSV (one column per axis, named by letter): `(N, axes)` positions in mm and deg.
    fn read_poses<'py>(&self, py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let table = read_poses(&path, &self.inner).map_err(input)?;
        let n = self.inner.axis_count().max(1);
        PyArray1::from_vec(py, table.user).reshape([table.lines.len(), n])
    }

    /// Volumetric error at each pose by the exact kinematic chain, vectorised (the GIL is released).
    ///
    /// poses: float64 array (N, axes) in mm and deg. Returns (N, 6) in the columns
    /// `PREDICTION_COLUMNS`: dx dy dz in um and drx dry drz in urad, of the tool point relative to
    /// the workpiece point, actual minus nominal, in the workpiece frame (or `frame="machine"`);
    /// with `with_dl=True` (N, 7), the last column the length change dL in um
    /// (`PREDICTION_COLUMNS_WITH_DL`). `temperatures`: (N, sensors) in degC, in the order of
    /// `errors.sensors`, when the error model has temperature terms. Tool and work points in mm,
    /// in the machine frame at home (defaults: the machine's tool point, the origin).
    /// `directions`: (N, axes) of -1, 0, +1 (any integer or float dtype, e.g. int8), the direction
    /// of motion of each axis at each pose (0: at rest), for bidirectional errors (`EXX+`/`EXX-`)
    /// — the `dir:<axis>` columns of a pose file; without `directions` every axis is at rest, so a
    /// bidirectional error is the mean of its two directions (as for a pose file without them).
    /// Any array-like of numbers (float32, int64, lists) is converted to float64; a C-contiguous
    /// float64 array is read in place. The batch kernel writes the returned array in place; `out`, a
    /// C-contiguous float64 array of shape (N, 6) or (N, 7), is written instead of a new array and
    /// returned (as NumPy's `out=`), so that a loop over batches allocates nothing.
    #[pyo3(signature = (errors, poses, *, tool_point = None, work_point = None, frame = "workpiece", temperatures = None, directions = None, with_dl = false, out = None))]
    #[allow(clippy::too_many_arguments)]
    fn predict<'py>(
        &self,
        py: Python<'py>,
        errors: &Errors,
        poses: &Bound<'py, PyAny>,
        tool_point: Option<&Bound<'py, PyAny>>,
        work_point: Option<&Bound<'py, PyAny>>,
        frame: &str,
        temperatures: Option<&Bound<'py, PyAny>>,
        directions: Option<&Bound<'py, PyAny>>,
        with_dl: bool,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let directions_given = directions;
        let setup = self.setup(tool_point, work_point)?;
        let frame = parse_frame(frame)?;
        let columns = if with_dl { 7 } else { 6 };
        with_array2(poses, "poses", |user, shape| {
            let count = self.check_poses(user, shape)?;
            let directions = directions_given.map(|d| self.directions_of(d, count)).transpose()?;
            let temperatures = self.temperatures_of(&errors.inner, temperatures, count)?;
            let out = match out {
                Some(o) => {
                    let o = o.cast::<PyArray2<f64>>().map_err(|_| input_msg("out: expected a float64 numpy array"))?.clone();
                    if o.shape() != [count, columns] || !o.is_c_contiguous() {
                        return Err(input_msg(format!(
                            "out: expected a C-contiguous float64 array of shape ({count}, {columns}), got shape {:?}",
                            o.shape()
                        )));
                    }
                    o
                }
                // SAFETY: every element is written below (one row per pose) before Python sees it
                None => unsafe { PyArray2::<f64>::new(py, [count, columns], false) },
            };
            {
                let mut written = out.try_readwrite().map_err(|e| input_msg(format!("out: {e}")))?;
                let values = written.as_slice_mut().expect("a new array is contiguous");
                let mut predictor = Predictor::new(&self.inner, &errors.inner);
                predictor.setup = setup;
                predictor.frame = frame;
                py.detach(|| predictor.predict_user_into(user, directions.as_deref(), &temperatures, columns, values));
                // all finite (a fold without branches), else the first pose that is not
                if !values.iter().fold(true, |ok, v| ok & v.is_finite()) {
                    let i = values.iter().position(|v| !v.is_finite()).unwrap_or(0);
                    return Err(computation(trueaxis::data::DataError::NotFinite {
                        message: format!("the prediction of pose {} is not a finite number", i / columns + 1),
                    }));
                }
            }
            Ok(out)
        })
    }

    /// The document of `trueaxis predict --json` for a pose CSV file: per pose the axis positions
    /// and dx dy dz dL (um), drx dry drz (urad), rounded to 1e-4 as the command line prints them.
    #[pyo3(signature = (errors, poses, *, tool_point = None, work_point = None, frame = "workpiece"))]
    fn predict_file<'py>(
        &self,
        py: Python<'py>,
        errors: &Errors,
        poses: PathBuf,
        tool_point: Option<&Bound<'py, PyAny>>,
        work_point: Option<&Bound<'py, PyAny>>,
        frame: &str,
    ) -> PyResult<Py<PyAny>> {
        let table = read_poses(&poses, &self.inner).map_err(input)?;
        let frame_value = parse_frame(frame)?;
        let temperatures = table.temperatures_of(errors.inner.sensors()).map_err(|m| input_msg(format!("{}: {m}", poses.display())))?;
        let mut predictor = Predictor::new(&self.inner, &errors.inner);
        predictor.setup = self.setup(tool_point, work_point)?;
        predictor.frame = frame_value;
        let internal = table.internal(&self.inner);
        let predictions = py.detach(|| predictor.predict_states(&internal, table.directions.as_deref(), &temperatures));
        let doc = predictions_json(&self.inner, &table.user, &predictions, frame).map_err(computation)?;
        typed(py, "Prediction", &doc)
    }

    fn __reduce__(slf: &Bound<'_, Self>) -> PyResult<(Py<PyAny>, (String, String))> {
        let m = slf.get();
        Ok((slf.get_type().getattr("from_toml")?.unbind(), (m.source.clone(), m.origin.clone())))
    }

    fn __repr__(&self) -> String {
        format!("Machine(name={:?}, structure axes {:?}, from {})", self.inner.name, self.inner.axis_letters(), self.origin)
    }
}

/// The error model of a machine (constants, tables, polynomials, bases, temperature terms), in
/// the units of the error-values file: um and urad.
#[pyclass(module = "trueaxis", frozen)]
#[derive(Clone)]
pub struct Errors {
    pub inner: Arc<ErrorModel>,
    pub machine: Machine,
    pub(crate) source: String,
    pub(crate) origin: String,
}

impl Errors {
    fn parse(text: String, origin: &str, machine: &Machine) -> PyResult<Errors> {
        let inner = ErrorModel::from_toml_str(&text, origin, &machine.inner).map_err(input)?;
        Ok(Errors { inner: Arc::new(inner), machine: machine.clone(), source: text, origin: origin.to_string() })
    }

    pub fn from_text(text: String, origin: &str, machine: &Machine) -> PyResult<Errors> {
        Errors::parse(text, origin, machine)
    }
}

#[pymethods]
impl Errors {
    /// Reads an error-values TOML file for `machine`.
    #[staticmethod]
    fn from_file(path: PathBuf, machine: &Machine) -> PyResult<Errors> {
        let inner = ErrorModel::load(&path, &machine.inner).map_err(input)?;
        let source = read_text(&path, "error-values file")?;
        Ok(Errors { inner: Arc::new(inner), machine: machine.clone(), source, origin: path.display().to_string() })
    }

    /// An error model from the text of an error-values file.
    #[staticmethod]
    #[pyo3(signature = (text, machine, origin = "<errors>"))]
    fn from_toml(text: String, machine: &Machine, origin: &str) -> PyResult<Errors> {
        Errors::parse(text, origin, machine)
    }

    /// An error model from a dict with the tables of an error-values file, e.g.
    /// `{"constant": {"EX0C": 10.0}, "table": {"EXX": {"position": [...], "value": [...]}}}` (um, urad).
    #[staticmethod]
    fn from_dict(d: &Bound<'_, PyAny>, machine: &Machine) -> PyResult<Errors> {
        Errors::parse(toml_text(d, "errors")?, "<errors dict>", machine)
    }

    /// All errors zero.
    #[staticmethod]
    fn zero(machine: &Machine) -> Errors {
        Errors {
            inner: Arc::new(ErrorModel::zero(&machine.inner)),
            machine: machine.clone(),
            source: String::new(),
            origin: "<zero>".into(),
        }
    }

    /// Temperature sensors the model needs (`T:<sensor>` columns), in order.
    #[getter]
    fn sensors(&self) -> Vec<String> {
        self.inner.sensors().to_vec()
    }

    /// The TOML text of the model.
    #[getter]
    fn toml(&self) -> String {
        self.source.clone()
    }

    fn __reduce__(slf: &Bound<'_, Self>) -> PyResult<(Py<PyAny>, (String, Machine, String))> {
        let e = slf.get();
        Ok((slf.get_type().getattr("from_toml")?.unbind(), (e.source.clone(), e.machine.clone(), e.origin.clone())))
    }

    fn __repr__(&self) -> String {
        format!("Errors(machine={:?}, from {})", self.machine.inner.name, self.origin)
    }
}
