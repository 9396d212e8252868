//! The error budget for machine design (Zhu 2008 appendices B and C), `trueaxis.BudgetProblem`,
//! `trueaxis.budget_configurations` and `trueaxis.budget_miniaturisation`, through the library's
//! entry points that `trueaxis budget analyse`, `allocate`, `configurations` and `miniaturisation`
//! use (`trueaxis::budget::problem`, `documents`, `configuration_study`, `miniaturisation_study`): tolerances in um (linear
//! errors) and urad (angular and squareness errors), volumetric errors in um, part sizes, points
//! and travel in mm, rotary positions and tilts in deg.

use crate::convert::{typed, with_array2};
use crate::exceptions::{self, input, input_msg};
use crate::identify::Reduced;
use crate::machine::{parse_frame, Machine};
use crate::progress::Progress;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use std::collections::HashMap;
use std::path::PathBuf;
use trueaxis::budget::allocate::{AllocationOptions, Stack, Target};
use trueaxis::budget::configuration_study::ConfigurationStudy;
use trueaxis::budget::global::GeneticOptions;
use trueaxis::budget::miniaturisation::{ARCSEC_URAD, SIZES};
use trueaxis::budget::miniaturisation_study::{MiniaturisationOptions, MiniaturisationStudy};
use trueaxis::budget::problem::{budget_spec, pose_sets, rotary_positions, BudgetProblem as Problem, PoseSource};
use trueaxis::budget::ranking::StudyOptions;
use trueaxis::budget::spec::KindValues;
use trueaxis::data::write_atomically;

/// A part size: one number (a cube) or three (x, y, z), in mm.
fn part_size(obj: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    let size = match obj.extract::<f64>() {
        Ok(edge) => [edge; 3],
        Err(_) => obj.extract::<[f64; 3]>().map_err(|_| input_msg("parts: each part is L or (L, M, N) in mm"))?,
    };
    if size.iter().all(|v| v.is_finite() && *v > 0.0) {
        Ok(size)
    } else {
        Err(input_msg(format!("parts: {size:?} is not a part size: positive lengths in mm")))
    }
}

/// An error-budget problem (Zhu 2008 appendix B) as the options of `trueaxis budget analyse` and
/// `allocate` state it: the machine, the tolerances (a budget file, or one per kind of error), the
/// points, the frame and the pose sets. Its methods are the two commands.
#[pyclass(module = "trueaxis", frozen)]
pub struct BudgetProblem {
    inner: Problem,
    machine: Machine,
    /// The keyword arguments it was made with (pickling).
    kwargs: Py<PyDict>,
}

/// The target of an allocation from `target_um` or `target_xyz` (um).
fn target(target_um: Option<f64>, target_xyz: Option<[f64; 3]>) -> PyResult<Target> {
    match (target_um, target_xyz) {
        (Some(v), None) if v.is_finite() && v > 0.0 => Ok(Target::Total(v)),
        (Some(v), None) => Err(input_msg(format!("--target-um {v}: the target must be a positive number of um"))),
        (None, Some(v)) if v.iter().all(|x| x.is_finite() && *x > 0.0) => Ok(Target::PerDirection(v)),
        (None, Some(v)) => Err(input_msg(format!("--target-xyz: {v:?} is not three positive targets x,y,z in um"))),
        _ => Err(input_msg("give one of target_um (the 3D error, um) and target_xyz (x, y, z in um)")),
    }
}

#[pymethods]
impl BudgetProblem {
    /// Tolerances: `budget` (a budget file, TOML) or `linear_um`, `angular_urad`, `squareness_urad`
    /// for every component. Poses: `poses` (a pose CSV, or an array (poses, axes), mm and deg), `parts` (sizes in mm, each L or
    /// (L, M, N): the tool point on a grid of `part_nodes` points per edge over the part, centred on
    /// the workpiece point) or `grid` (points per linear axis over the travel; the default, with
    /// 5); `rotary` the rotary axes' positions for parts and grids, e.g. `{"A": 30}` (deg, default
    /// 0). `tool_point`, `work_point` (mm), `frame` (`workpiece` or `machine`).
    #[new]
    #[pyo3(signature = (machine, *, budget = None, linear_um = 5.0, angular_urad = 10.0, squareness_urad = 10.0, poses = None, parts = None, grid = None, part_nodes = 5, rotary = None, tool_point = None, work_point = None, frame = "workpiece"))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        machine: &Machine,
        budget: Option<PathBuf>,
        linear_um: f64,
        angular_urad: f64,
        squareness_urad: f64,
        poses: Option<&Bound<'_, PyAny>>,
        parts: Option<Vec<Bound<'_, PyAny>>>,
        grid: Option<usize>,
        part_nodes: usize,
        rotary: Option<HashMap<char, f64>>,
        tool_point: Option<&Bound<'_, PyAny>>,
        work_point: Option<&Bound<'_, PyAny>>,
        frame: &str,
    ) -> PyResult<BudgetProblem> {
        let kwargs = PyDict::new(py);
        kwargs.set_item("budget", &budget)?;
        kwargs.set_item("linear_um", linear_um)?;
        kwargs.set_item("angular_urad", angular_urad)?;
        kwargs.set_item("squareness_urad", squareness_urad)?;
        kwargs.set_item("poses", poses)?;
        kwargs.set_item("parts", &parts)?;
        kwargs.set_item("grid", grid)?;
        kwargs.set_item("part_nodes", part_nodes)?;
        kwargs.set_item("rotary", &rotary)?;
        kwargs.set_item("tool_point", tool_point)?;
        kwargs.set_item("work_point", work_point)?;
        kwargs.set_item("frame", frame)?;
        let m = machine.inner.as_ref().clone();
        let spec = budget_spec(&m, budget.as_deref(), KindValues([linear_um, angular_urad, squareness_urad])).map_err(exceptions::of)?;
        let setup = machine.setup(tool_point, work_point)?;
        let given: Vec<(char, f64)> = rotary.iter().flatten().map(|(c, v)| (c.to_ascii_uppercase(), *v)).collect();
        let rotary = rotary_positions(&m, &given).map_err(exceptions::of)?;
        let sizes: Vec<[f64; 3]> = parts.iter().flatten().map(part_size).collect::<PyResult<_>>()?;
        let (path, given) = match poses {
            Some(p) if p.is_instance_of::<PyString>() || p.hasattr("__fspath__")? => (Some(p.extract::<PathBuf>()?), None),
            Some(p) => (None, Some(with_array2(p, "poses", |values, _| Ok(values.to_vec()))?)),
            None => (None, None),
        };
        let source = match (&path, &given, sizes.is_empty(), grid) {
            (Some(path), None, true, None) => PoseSource::File(path),
            (None, Some(user), true, None) => PoseSource::Given { label: "poses", user },
            (None, None, false, None) => PoseSource::Parts { sizes: &sizes, nodes: part_nodes },
            (None, None, true, grid) => PoseSource::Grid(grid.unwrap_or(5)),
            _ => return Err(input_msg("poses, parts and grid: give one of them (default: a grid of 5 points per axis)")),
        };
        let sets = pose_sets(&m, &setup, &source, &rotary).map_err(exceptions::of)?;
        let inner = Problem { machine: m, spec, setup, frame: parse_frame(frame)?, sets };
        Ok(BudgetProblem { inner, machine: machine.clone(), kwargs: kwargs.unbind() })
    }

    /// Labels of the pose sets (the part sizes, the pose file, or `work volume`).
    #[getter]
    fn sets(&self) -> Vec<String> {
        self.inner.sets.iter().map(|s| s.label.clone()).collect()
    }

    /// The poses of each set (mm, deg): a list of arrays (poses, axes).
    #[getter]
    fn poses<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyArray2<f64>>>> {
        let n = self.inner.machine.axis_count();
        self.inner.sets.iter().map(|s| PyArray1::from_slice(py, &s.user).reshape([s.user.len() / n, n])).collect()
    }

    /// Names of the components (ISO 230), the order of every table.
    #[getter]
    fn components(&self) -> Vec<String> {
        self.inner.spec.components.iter().map(|c| c.id.to_string()).collect()
    }

    /// The forward analysis: the document of `trueaxis budget analyse --json` (per pose set:
    /// root-sum-square and worst-case stack-up per direction and in 3D in um, singular values and
    /// part sensitivities in mm, the share of every axis, kind and component in %, angular errors
    /// with their lever arm in mm). `out` writes the per-pose stack-up CSV, `sensitivity` the
    /// sensitivity matrix CSV (um per um or per urad), as the command's options do. The GIL is
    /// released.
    #[pyo3(signature = (*, out = None, sensitivity = None))]
    fn analyse(&self, py: Python<'_>, out: Option<PathBuf>, sensitivity: Option<PathBuf>) -> PyResult<Py<PyAny>> {
        let problem = &self.inner;
        let analyses = py.detach(|| problem.analyse()).map_err(exceptions::of)?;
        if let Some(path) = &out {
            write_atomically(path, problem.poses_csv(&analyses).as_bytes()).map_err(input)?;
        }
        if let Some(path) = &sensitivity {
            write_atomically(path, problem.sensitivity_csv(&analyses).as_bytes()).map_err(input)?;
        }
        typed(py, "BudgetAnalysis", &problem.analysis_json(&analyses))
    }

    /// The cost-optimal tolerances for a target volumetric error (Zhu 2008 eqs. B.5-B.8) on the
    /// problem's one pose set: the document of `trueaxis budget allocate --json` (tolerances in um
    /// and urad, homogenised in um/m and urad, the cost, the binding constraints with their
    /// multipliers and the cost change per um of target, the KKT residual and duality gap).
    /// `target_um` (the 3D error at every pose, um) or `target_xyz` (x, y, z in um); `stack` `rss`
    /// (tolerances as standard deviations) or `worst-case`; `seed` and `generations` of the genetic
    /// global stage; `out` writes the allocated budget file (TOML) for `BudgetProblem(budget=...)`.
    /// The GIL is released.
    #[pyo3(signature = (*, target_um = None, target_xyz = None, stack = "rss", seed = 1, generations = 500, out = None))]
    #[allow(clippy::too_many_arguments)]
    fn allocate(
        &self,
        py: Python<'_>,
        target_um: Option<f64>,
        target_xyz: Option<[f64; 3]>,
        stack: &str,
        seed: u64,
        generations: usize,
        out: Option<PathBuf>,
    ) -> PyResult<Py<PyAny>> {
        let stack = match stack {
            "rss" => Stack::Rss,
            "worst-case" | "worst_case" => Stack::WorstCase,
            other => return Err(input_msg(format!("stack `{other}`: expected rss or worst-case"))),
        };
        let target = target(target_um, target_xyz)?;
        let options = AllocationOptions { stack, target, genetic: GeneticOptions { generations, seed, ..GeneticOptions::default() } };
        let problem = &self.inner;
        let (a, s) = py.detach(|| problem.allocate(&options)).map_err(exceptions::of)?;
        if let Some(path) = &out {
            write_atomically(path, problem.allocation_toml(&a, &options, s.poses()).as_bytes()).map_err(input)?;
        }
        typed(py, "BudgetAllocation", &problem.allocation_json(&a, &options, s.poses()))
    }

    /// The root-sum-square 3D error (um) at each pose of `poses` (an array (poses, axes), mm and
    /// deg) with every rotary axis where the problem's first pose set has it: the values of the
    /// map `trueaxis budget analyse --plots` draws over the mid-planes of the travel. The GIL is
    /// released.
    fn rss_at<'py>(&self, py: Python<'py>, poses: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = self.inner.machine.axis_count();
        let user = with_array2(poses, "poses", |values, shape| {
            if shape[1] != n {
                return Err(input_msg(format!("poses: {} columns, the machine has {n} axes", shape[1])));
            }
            Ok(values.to_vec())
        })?;
        let problem = &self.inner;
        let values = py.detach(|| problem.rss_at(&user)).map_err(exceptions::of)?;
        Ok(PyArray1::from_vec(py, values))
    }

    /// Rebuilds a problem from its machine and keyword arguments (pickling; files read again).
    #[staticmethod]
    fn _from_kwargs(py: Python<'_>, machine: &Bound<'_, PyAny>, kwargs: Bound<'_, PyDict>) -> PyResult<Py<PyAny>> {
        Ok(py.get_type::<BudgetProblem>().call((machine,), Some(&kwargs))?.unbind())
    }

    fn __reduce__(slf: &Bound<'_, Self>) -> PyResult<Reduced<(Machine, Py<PyDict>)>> {
        let p = slf.get();
        Ok((slf.get_type().getattr("_from_kwargs")?.unbind(), (p.machine.clone(), p.kwargs.clone_ref(slf.py()))))
    }

    fn __repr__(&self) -> String {
        format!("BudgetProblem({}, {} components, sets {:?})", self.inner.machine.name, self.inner.spec.components.len(), self.sets())
    }
}

/// The five-axis configuration study (Zhu 2008 appendix C): the document of `trueaxis budget
/// configurations --json` (the counts of the enumeration, the travel in mm a part needs and the
/// space utility per category, and the budget of each of the 288 five-degree-of-freedom
/// configurations with the same tolerances, ranked by the RMS of the root-sum-square 3D error in
/// um).
///
/// `part`: L or (L, M, N) in mm; `tool_length` in mm; tolerances in um and urad; `nodes` per edge
/// of the part; `tilt_deg` the tool's tilt in the tilted poses (deg). `progress(done, total)`, if
/// given, is called after each configuration's budget (about 2 s in all); an exception it raises
/// is raised once the study ends. The GIL is released.
#[pyfunction]
#[pyo3(signature = (*, part = None, tool_length = 100.0, linear_um = 5.0, angular_urad = 10.0, squareness_urad = 10.0, nodes = 3, tilt_deg = 30.0, progress = None))]
#[allow(clippy::too_many_arguments)]
pub fn budget_configurations(
    py: Python<'_>,
    part: Option<&Bound<'_, PyAny>>,
    tool_length: f64,
    linear_um: f64,
    angular_urad: f64,
    squareness_urad: f64,
    nodes: usize,
    tilt_deg: f64,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let part = part.map(part_size).transpose()?.unwrap_or([100.0; 3]);
    let options = StudyOptions { part, tool_length, tolerances: KindValues([linear_um, angular_urad, squareness_urad]), nodes, tilt_deg };
    let progress = Progress::new(progress)?;
    let study = py.detach(|| ConfigurationStudy::run(&options, &|done, total| progress.report(done, total)));
    progress.finish()?;
    typed(py, "BudgetConfigurations", &study.map_err(exceptions::of)?.to_json())
}

/// The miniaturisation case (Zhu 2008 appendix B.2): the document of `trueaxis budget
/// miniaturisation --json`: a three-axis machine scaled to cubic parts of `sizes` mm with equal
/// errors (`linear_um` um, `angular_urad` urad, default 1 arcsec), per size the part sensitivities
/// and robustness indices (mm), the shares by axis and kind (%) and the cost-optimal allocation
/// for a root-sum-square target of `relative_accuracy` times the part size per direction (um),
/// its genetic stage seeded by `seed`. The GIL is released.
#[pyfunction]
#[pyo3(signature = (*, sizes = None, linear_um = 1.0, angular_urad = ARCSEC_URAD, relative_accuracy = 1e-4, seed = 1))]
pub fn budget_miniaturisation(
    py: Python<'_>,
    sizes: Option<Vec<f64>>,
    linear_um: f64,
    angular_urad: f64,
    relative_accuracy: f64,
    seed: u64,
) -> PyResult<Py<PyAny>> {
    let options =
        MiniaturisationOptions { sizes: sizes.unwrap_or_else(|| SIZES.to_vec()), linear_um, angular_urad, relative_accuracy, seed };
    let study = py.detach(|| MiniaturisationStudy::run(&options)).map_err(exceptions::of)?;
    typed(py, "BudgetMiniaturisation", &study.to_json())
}
