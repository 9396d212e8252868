//! `trueaxis.Campaign`, `trueaxis.identify` and `trueaxis.Candidates`: measurement campaigns, the
//! identification of error parameters from them, and optimal measurement designs (Soons 1993
//! §4.3) whose random starts can be spread over processes or machines.

use crate::convert::{dataframe, to_py, toml_text, typed};
use crate::exceptions::{computation_msg, identify as identify_error, input_msg};
use crate::machine::{Errors, Machine};
use crate::progress::Progress;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use trueaxis::error_model::ErrorModel;
use trueaxis::identify::campaign_screening::identify_screened;
use trueaxis::identify::{
    error_values_text, identification_json, optimal_design_json, CampaignCandidates, Criterion, ExchangeOutcome, IdentifyError,
    IndirectOptions, Solver,
};

/// What `__reduce__` returns: the constructor and its arguments (pickling).
pub type Reduced<T> = (Py<PyAny>, T);

/// A measurement campaign (docs/design.md, Files): the parameters to identify and the measurements
/// with their data files (read relative to the campaign file, or to `base_dir`).
#[pyclass(module = "trueaxis", frozen)]
#[derive(Clone)]
pub struct Campaign {
    pub inner: Arc<trueaxis::identify::Campaign>,
    pub machine: Machine,
    source: String,
    origin: String,
    dir: PathBuf,
}

impl Campaign {
    fn parse(text: String, origin: &str, dir: &Path, machine: &Machine) -> PyResult<Campaign> {
        let inner = trueaxis::identify::Campaign::from_toml_str(&text, origin, dir, &machine.inner).map_err(identify_error)?;
        Ok(Campaign { inner: Arc::new(inner), machine: machine.clone(), source: text, origin: origin.into(), dir: dir.to_path_buf() })
    }

    /// The nominal errors of the campaign (`nominal_errors`, else zero).
    pub fn nominal(&self) -> PyResult<ErrorModel> {
        self.inner.nominal_errors(&self.machine.inner).map_err(identify_error)
    }
}

#[pymethods]
impl Campaign {
    /// Reads a campaign TOML file and its data files for `machine`.
    #[staticmethod]
    fn from_file(path: PathBuf, machine: &Machine) -> PyResult<Campaign> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(&path).map_err(|e| input_msg(format!("{origin}: cannot read campaign file: {e}")))?;
        Campaign::parse(text, &origin, path.parent().unwrap_or(Path::new("")), machine)
    }

    /// A campaign from TOML text; data files are read relative to `base_dir`.
    #[staticmethod]
    #[pyo3(signature = (text, machine, base_dir = PathBuf::from("."), origin = "<campaign>"))]
    fn from_toml(text: String, machine: &Machine, base_dir: PathBuf, origin: &str) -> PyResult<Campaign> {
        Campaign::parse(text, origin, &base_dir, machine)
    }

    /// A campaign from a dict with the keys of a campaign file (`parameters`, `measurement`, ...);
    /// data files are read relative to `base_dir`.
    #[staticmethod]
    #[pyo3(signature = (d, machine, base_dir = PathBuf::from(".")))]
    fn from_dict(d: &Bound<'_, PyAny>, machine: &Machine, base_dir: PathBuf) -> PyResult<Campaign> {
        Campaign::parse(toml_text(d, "campaign")?, "<campaign dict>", &base_dir, machine)
    }

    /// Names of the unknowns, in the order of the results.
    #[getter]
    fn parameters(&self) -> Vec<String> {
        self.inner.unknowns.iter().map(|u| u.name.clone()).collect()
    }

    /// Number of records (poses, lengths, ...) of all measurements.
    #[getter]
    fn records(&self) -> usize {
        self.inner.measurements.iter().map(|m| m.records()).sum()
    }

    fn __reduce__(slf: &Bound<'_, Self>) -> PyResult<Reduced<(String, Machine, PathBuf, String)>> {
        let c = slf.get();
        Ok((slf.get_type().getattr("from_toml")?.unbind(), (c.source.clone(), c.machine.clone(), c.dir.clone(), c.origin.clone())))
    }

    fn __repr__(&self) -> String {
        format!("Campaign({}, {} unknowns, {} records)", self.origin, self.inner.unknowns.len(), self.records())
    }
}

/// The result of an identification: values, uncertainties, covariance and residuals as numpy
/// arrays (parameter units: um, urad, or um per mm^k), the identified error model, and the
/// document of `trueaxis identify --json` (`to_dict`).
#[pyclass(module = "trueaxis", frozen)]
pub struct Identification {
    result: trueaxis::identify::Identification,
    campaign: Campaign,
    nominal: ErrorModel,
    /// What screening adds to the JSON document (`data_quality`, ...).
    quality: serde_json::Value,
}

#[pymethods]
impl Identification {
    /// Names of the unknowns.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.result.names.clone()
    }

    /// Units of the unknowns.
    #[getter]
    fn units(&self) -> Vec<String> {
        self.result.units.clone()
    }

    /// Identified values (parameter units).
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.result.values)
    }

    /// Standard uncertainties (parameter units); NaN for a parameter in an unidentifiable combination.
    #[getter]
    fn std_uncertainty<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.result.std_uncertainty.iter().map(|u| u.unwrap_or(f64::NAN)))
    }

    /// Covariance of the values (parameter units squared).
    #[getter]
    fn covariance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let c = &self.result.covariance;
        let rows: Vec<f64> = (0..c.nrows()).flat_map(|i| (0..c.ncols()).map(move |j| c[(i, j)])).collect();
        PyArray1::from_vec(py, rows).reshape([c.nrows(), c.ncols()])
    }

    /// Residual of every reading (um), in the order of the campaign's measurements and records.
    #[getter]
    fn residuals<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.result.residuals)
    }

    /// A pandas DataFrame, one row per unknown: `name`, `unit`, `value`, `std_uncertainty`
    /// (parameter units; NaN where not identifiable). pandas is optional (ImportError without it).
    fn to_dataframe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let columns = vec![
            ("name", self.names().into_pyobject(py)?.into_any()),
            ("unit", self.units().into_pyobject(py)?.into_any()),
            ("value", self.values(py).into_any()),
            ("std_uncertainty", self.std_uncertainty(py).into_any()),
        ];
        dataframe(py, columns, "Identification.to_dataframe")
    }

    /// The document of `trueaxis identify --json`.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let mut doc = identification_json(&self.result, &self.campaign.inner);
        if let (Some(doc), Some(quality)) = (doc.as_object_mut(), self.quality.as_object()) {
            doc.extend(quality.clone());
        }
        to_py(py, &doc)
    }

    /// The error-values TOML that `trueaxis identify --out` writes: the campaign's nominal errors
    /// with the identified parameters replaced.
    fn errors_toml(&self) -> PyResult<String> {
        let nominal_text = match &self.campaign.inner.nominal_errors {
            Some(p) => std::fs::read_to_string(p).map_err(|e| input_msg(format!("{}: {e}", p.display())))?,
            None => String::new(),
        };
        error_values_text(&self.result, &self.campaign.inner, &self.nominal, &nominal_text).map_err(identify_error)
    }

    /// The identified error model, ready for `Machine.predict`.
    fn errors(&self) -> PyResult<Errors> {
        Errors::from_text(self.errors_toml()?, "<identified errors>", &self.campaign.machine)
    }
}

/// Identifies the campaign's unknowns by weighted least squares (as `trueaxis identify`):
/// `solver` `"qr"` or `"svd"`; a rank-deficient set raises ComputationError naming the
/// inseparable combinations unless `allow_rank_deficient`; `refine` adds Levenberg-Marquardt on
/// the exact chain. Values and uncertainties in the parameters' units (um, urad, um/mm^k),
/// residuals in um. The GIL is released during the computation.
#[pyfunction]
#[pyo3(signature = (machine, campaign, *, solver = "qr", allow_rank_deficient = false, refine = false, exclude_outliers = false))]
pub fn identify(
    py: Python<'_>,
    machine: &Machine,
    campaign: &Campaign,
    solver: &str,
    allow_rank_deficient: bool,
    refine: bool,
    exclude_outliers: bool,
) -> PyResult<Identification> {
    let solver = match solver {
        "qr" => Solver::Qr,
        "svd" => Solver::Svd,
        other => return Err(input_msg(format!("solver `{other}`: expected `qr` or `svd`"))),
    };
    let nominal = campaign.nominal()?;
    let options = IndirectOptions { solver, allow_rank_deficient, refine, ..IndirectOptions::default() };
    let screened =
        py.detach(|| identify_screened(&campaign.inner, &machine.inner, &nominal, &options, exclude_outliers)).map_err(identify_error)?;
    let result = screened.result.clone();
    if result.values.iter().chain(&result.residuals).any(|v| !v.is_finite()) {
        return Err(computation_msg("the identification produced numbers that are not finite"));
    }
    let mut quality = serde_json::json!({});
    screened.add_to_json(&mut quality);
    let campaign = Campaign { inner: Arc::new(screened.campaign), ..campaign.clone() };
    Ok(Identification { result, campaign, nominal, quality })
}

fn criterion(text: &str) -> PyResult<Criterion> {
    Criterion::parse(text).map_err(input_msg)
}

/// The records of a campaign as candidates of an optimal design (D, A, E or G) by the exchange
/// algorithm. `exchange` runs all starts in one process; `exchange_starts` runs a chunk of starts
/// (each start has its own random stream) and `best_of` merges the outcomes of any chunks: the
/// result equals `exchange` for the same seed.
#[pyclass(module = "trueaxis", frozen)]
pub struct Candidates {
    inner: CampaignCandidates,
    campaign: Campaign,
}

impl Candidates {
    /// Errors as `trueaxis design optimal` names them.
    fn failure(&self, count: usize) -> impl Fn(IdentifyError) -> PyErr + '_ {
        move |e| match e {
            IdentifyError::RankDeficient { message } => computation_msg(format!("{}: rank deficient: {message}", self.campaign.origin)),
            IdentifyError::Input(message) => input_msg(format!("count {count}: {message}")),
            other => identify_error(other),
        }
    }

    fn document(&self, py: Python<'_>, count: usize, criterion_name: &str, outcomes: &[ExchangeOutcome]) -> PyResult<Py<PyAny>> {
        let set = &self.inner.set;
        let (chosen, criteria) = set.best_of(count, outcomes).map_err(self.failure(count))?;
        let all: Vec<usize> = (0..set.len()).collect();
        let full = set.criteria(&all).map_err(self.failure(count))?;
        let doc = optimal_design_json(&self.campaign.inner, &self.inner, criterion(criterion_name)?, count, &chosen, &criteria, &full);
        typed(py, "OptimalDesign", &doc)
    }
}

#[pymethods]
impl Candidates {
    /// The candidates of a campaign (its records; a planned campaign needs no readings).
    #[new]
    fn new(campaign: &Campaign) -> PyResult<Candidates> {
        let nominal = campaign.nominal()?;
        let inner = CampaignCandidates::new(&campaign.inner, &campaign.machine.inner, &nominal).map_err(identify_error)?;
        Ok(Candidates { inner, campaign: campaign.clone() })
    }

    fn __len__(&self) -> usize {
        self.inner.set.len()
    }

    /// The checks made before any start (count and starts at least 1, enough readings, a
    /// candidate set that determines every unknown).
    fn check(&self, count: usize, starts: usize) -> PyResult<()> {
        self.inner.set.check_exchange(count, starts).map_err(self.failure(count))
    }

    /// Starts `start .. stop` of the exchange algorithm for a design of `count` records: a list of
    /// `(start, design, value)`, `design` the sorted candidate indices and `value` the criterion
    /// (None, None when the start found no regular design). The GIL is released.
    #[pyo3(signature = (count, start, stop, *, criterion = "d", seed = 1))]
    #[allow(clippy::type_complexity)]
    fn exchange_starts(
        &self,
        py: Python<'_>,
        count: usize,
        start: usize,
        stop: usize,
        criterion: &str,
        seed: u64,
    ) -> PyResult<Vec<(usize, Option<Vec<usize>>, Option<f64>)>> {
        let c = self::criterion(criterion)?;
        let outcomes = py.detach(|| self.inner.set.exchange_starts(count, c, seed, start..stop));
        Ok(outcomes.into_iter().map(|o| (o.start, o.found.as_ref().map(|f| f.0.clone()), o.found.map(|f| f.1))).collect())
    }

    /// Merges outcomes of `exchange_starts` (from any chunks, in any order) into the document of
    /// `trueaxis design optimal --json`.
    #[pyo3(signature = (count, outcomes, *, criterion = "d"))]
    #[allow(clippy::type_complexity)]
    fn best_of(
        &self,
        py: Python<'_>,
        count: usize,
        outcomes: Vec<(usize, Option<Vec<usize>>, Option<f64>)>,
        criterion: &str,
    ) -> PyResult<Py<PyAny>> {
        let outcomes: Vec<ExchangeOutcome> = outcomes.into_iter().map(|(start, d, v)| ExchangeOutcome { start, found: d.zip(v) }).collect();
        self.document(py, count, criterion, &outcomes)
    }

    /// The optimal design of `count` records from `starts` random starts in this process (the
    /// document of `trueaxis design optimal --json`). `progress(done, total)`, if given, is called
    /// after each round of starts (one per core); an exception it raises stops the run at the next
    /// round and is raised here.
    #[pyo3(signature = (count, *, criterion = "d", starts = 5, seed = 1, progress = None))]
    fn exchange(
        &self,
        py: Python<'_>,
        count: usize,
        criterion: &str,
        starts: usize,
        seed: u64,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        self.check(count, starts)?;
        let c = self::criterion(criterion)?;
        let progress = Progress::new(progress)?;
        // without a callable all starts at once; with one, a round of one start per core
        let round = if progress.wanted() { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { starts };
        let outcomes = py.detach(|| {
            let mut outcomes = Vec::with_capacity(starts);
            while outcomes.len() < starts && !progress.failed() {
                let first = outcomes.len();
                outcomes.extend(self.inner.set.exchange_starts(count, c, seed, first..(first + round).min(starts)));
                progress.report(outcomes.len(), starts);
            }
            outcomes
        });
        progress.finish()?;
        self.document(py, count, criterion, &outcomes)
    }

    fn __reduce__(slf: &Bound<'_, Self>) -> PyResult<(Py<PyAny>, (Campaign,))> {
        Ok((slf.get_type().unbind().into_any(), (slf.get().campaign.clone(),)))
    }
}
