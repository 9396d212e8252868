//! `trueaxis.Sources`, `trueaxis.UncertaintyPlan` and `trueaxis.BudgetRun`: the GUM and adaptive
//! Monte Carlo uncertainty of an identification (JCGM 101/102, Andolfatto et al. 2011 Table 5), in one process
//! (`UncertaintyPlan.run`) or cut into chunks for a distributed engine: any process computes
//! `UncertaintyPlan.run_chunk(stage, chunk)`, the driver feeds the chunk values of each sequence
//! in order to a `BudgetRun`, which stops each stage at the sequence one process stops at, with
//! the same numbers (every chunk draws only from its own counter-based random streams).

use crate::convert::{array2, toml_text, typed};
use crate::exceptions::{input_msg, of};
use crate::identify::{Campaign, Reduced};
use crate::machine::{parse_frame, Machine};
use crate::progress::Progress;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;
use trueaxis::identify::{solve, Identification, IndirectOptions};
use trueaxis::uncertainty::{
    budget_json, from_identification, pose_uncertainties, run_chunk, AdaptiveRun, BudgetPlan, Chunk, DesignMatrix, Evaluation,
    IdentificationMap, McResult, McSettings, Source,
};

/// Uncertainty sources and Monte Carlo settings (a sources TOML file, docs/uncertainty.md).
#[pyclass(module = "trueaxis", frozen)]
#[derive(Clone)]
pub struct Sources {
    inner: trueaxis::uncertainty::Sources,
    source: String,
    origin: String,
}

impl Sources {
    fn parse(text: String, origin: &str) -> PyResult<Sources> {
        let inner = trueaxis::uncertainty::Sources::from_toml_str(&text, origin).map_err(of)?;
        Ok(Sources { inner, source: text, origin: origin.into() })
    }
}

#[pymethods]
impl Sources {
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Sources> {
        let origin = path.display().to_string();
        trueaxis::uncertainty::Sources::load(&path).map_err(of)?;
        let text = std::fs::read_to_string(&path).map_err(|e| input_msg(format!("{origin}: cannot read: {e}")))?;
        Sources::parse(text, &origin)
    }

    #[staticmethod]
    #[pyo3(signature = (text, origin = "<sources>"))]
    fn from_toml(text: String, origin: &str) -> PyResult<Sources> {
        Sources::parse(text, origin)
    }

    /// From a dict with the keys of a sources file (`seed`, `tolerance`, `[[source]]` as a list
    /// under `source`, ...).
    #[staticmethod]
    fn from_dict(d: &Bound<'_, PyAny>) -> PyResult<Sources> {
        Sources::parse(toml_text(d, "sources")?, "<sources dict>")
    }

    /// Names of the sources.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.inner.sources.iter().map(|s| s.name.clone()).collect()
    }

    /// The seed of the random numbers.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.settings.seed
    }

    fn __reduce__(slf: &Bound<'_, Self>) -> PyResult<(Py<PyAny>, (String, String))> {
        let s = slf.get();
        Ok((slf.get_type().getattr("from_toml")?.unbind(), (s.source.clone(), s.origin.clone())))
    }
}

/// The picklable state of a plan: design CSV, design origin, sources, seed override, budget.
type PlanState = (String, String, Sources, Option<u64>, bool);

/// What only the driver needs: the campaign behind the design, for pose uncertainties.
struct CampaignContext {
    machine: Machine,
    campaign: Campaign,
    identification: Identification,
}

/// An uncertainty budget ready to run: the identification map of a design, the sources and the
/// Monte Carlo settings. Stages: each source alone (with several sources and `budget=True`), then
/// all sources together. Picklable (the design and the sources travel as text), so a distributed
/// engine can send it to its workers once.
#[pyclass(module = "trueaxis", frozen)]
pub struct UncertaintyPlan {
    map: IdentificationMap,
    sources: Vec<Source>,
    settings: McSettings,
    alone: bool,
    design_origin: String,
    sources_state: Sources,
    seed_override: Option<u64>,
    context: Option<Arc<CampaignContext>>,
}

impl UncertaintyPlan {
    fn build(
        design: DesignMatrix,
        design_origin: String,
        sources: &Sources,
        seed: Option<u64>,
        budget: bool,
        context: Option<Arc<CampaignContext>>,
    ) -> PyResult<UncertaintyPlan> {
        let mut settings = sources.inner.settings.clone();
        if let Some(seed) = seed {
            settings.seed = seed;
        }
        sources.inner.check_channels(&design).map_err(|e| of(trueaxis::Error::input(format!("{}: {e}", sources.origin))))?;
        let map = IdentificationMap::new(design).map_err(of)?;
        let plan = UncertaintyPlan {
            map,
            sources: sources.inner.sources.clone(),
            settings,
            alone: budget,
            design_origin,
            sources_state: sources.clone(),
            seed_override: seed,
            context,
        };
        plan.plan()?;
        Ok(plan)
    }

    fn plan(&self) -> PyResult<BudgetPlan<'_>> {
        BudgetPlan::new(&self.map, &self.sources, &self.settings, Evaluation::Reduced, self.alone).map_err(of)
    }

    fn check_stage(&self, stage: usize) -> PyResult<()> {
        let stages = self.plan()?.stages();
        if stage >= stages {
            return Err(input_msg(format!("stage {stage}: the plan has stages 0..{stages}")));
        }
        Ok(())
    }

    /// The document of `trueaxis uncertainty --json` from the stage results.
    #[allow(clippy::too_many_arguments)]
    fn document(
        &self,
        py: Python<'_>,
        runs: Vec<McResult>,
        poses: Option<&Bound<'_, PyAny>>,
        tool_point: Option<&Bound<'_, PyAny>>,
        work_point: Option<&Bound<'_, PyAny>>,
        frame: &str,
    ) -> PyResult<Py<PyAny>> {
        let budget = self.plan()?.assemble(runs).map_err(of)?;
        let poses = match (poses, &self.context) {
            (None, _) => Vec::new(),
            (Some(_), None) => {
                return Err(input_msg(
                    "poses need a plan from a campaign (UncertaintyPlan.from_campaign): the parameters' effect on dx dy dz",
                ))
            }
            (Some(p), Some(ctx)) => {
                let m = &ctx.machine;
                let (user, _) = m.poses_of(p)?;
                let setup = m.setup(tool_point, work_point)?;
                pose_uncertainties(
                    &m.inner,
                    &ctx.campaign.inner,
                    &ctx.identification,
                    &budget,
                    &user,
                    &setup,
                    parse_frame(frame)?,
                    self.settings.coverage,
                )
                .map_err(of)?
            }
        };
        typed(py, "UncertaintyBudget", &budget_json(&self.design_origin, &self.map, &budget, &self.settings, &poses))
    }
}

fn chunk_of(t: (usize, usize, usize)) -> Chunk {
    Chunk { sequence: t.0, first_block: t.1, blocks: t.2 }
}

#[pymethods]
impl UncertaintyPlan {
    /// From a design-matrix CSV (channel, t, [y], [weight], one column per parameter).
    #[staticmethod]
    #[pyo3(signature = (path, sources, *, seed = None, budget = true))]
    fn from_design(path: PathBuf, sources: &Sources, seed: Option<u64>, budget: bool) -> PyResult<UncertaintyPlan> {
        let design = DesignMatrix::read_csv(&path).map_err(of)?;
        UncertaintyPlan::build(design, path.display().to_string(), sources, seed, budget, None)
    }

    /// From a campaign's identification (as `trueaxis uncertainty --machine --campaign`): record k
    /// measured at k * point_time s.
    #[staticmethod]
    #[pyo3(signature = (machine, campaign, sources, *, point_time = 0.75, seed = None, budget = true))]
    fn from_campaign(
        machine: &Machine,
        campaign: &Campaign,
        sources: &Sources,
        point_time: f64,
        seed: Option<u64>,
        budget: bool,
    ) -> PyResult<UncertaintyPlan> {
        let nominal = campaign.nominal()?;
        let design = campaign.inner.design_matrix(&machine.inner, &nominal).map_err(of)?;
        let start = campaign.inner.nominal_values(&nominal).map_err(of)?;
        let identification = solve(&design, &start, &IndirectOptions::default()).map_err(of)?;
        let design = from_identification(&design, point_time).map_err(of)?;
        let context = CampaignContext { machine: machine.clone(), campaign: campaign.clone(), identification };
        UncertaintyPlan::build(design, campaign.inner.origin.clone(), sources, seed, budget, Some(Arc::new(context)))
    }

    /// Rebuilds a plan from its picklable state (no campaign: pose uncertainties need the original).
    #[staticmethod]
    fn _from_state(
        design_csv: String,
        design_origin: String,
        sources: PyRef<'_, Sources>,
        seed: Option<u64>,
        budget: bool,
    ) -> PyResult<UncertaintyPlan> {
        let design = DesignMatrix::from_csv_reader(design_csv.as_bytes(), &design_origin).map_err(of)?;
        UncertaintyPlan::build(design, design_origin, &sources, seed, budget, None)
    }

    fn __reduce__(slf: &Bound<'_, Self>) -> PyResult<Reduced<PlanState>> {
        let p = slf.get();
        Ok((
            slf.get_type().getattr("_from_state")?.unbind(),
            (p.map.design.to_csv(), p.design_origin.clone(), p.sources_state.clone(), p.seed_override, p.alone),
        ))
    }

    /// Number of Monte Carlo runs: each source alone (budget), then all together (the last).
    #[getter]
    fn stages(&self) -> PyResult<usize> {
        Ok(self.plan()?.stages())
    }

    /// The source run alone at stage `k`; None for the run with all sources.
    fn stage_name(&self, stage: usize) -> PyResult<Option<String>> {
        self.check_stage(stage)?;
        Ok(self.plan()?.stage(stage).map(String::from))
    }

    /// Names of the parameters (the columns of the trial values).
    #[getter]
    fn parameters(&self) -> Vec<String> {
        self.map.design.parameters.clone()
    }

    #[getter]
    fn seed(&self) -> u64 {
        self.settings.seed
    }

    /// Trials per sequence M.
    #[getter]
    fn trials_per_sequence(&self) -> usize {
        self.settings.trials_per_sequence
    }

    #[getter]
    fn max_sequences(&self) -> usize {
        self.settings.max_sequences
    }

    /// Sequence `sequence` (0-based) cut into chunks of at most `blocks_per_chunk` blocks of
    /// `trueaxis.BLOCK` trials (default: the whole sequence): a list of
    /// `(sequence, first_block, blocks)`, the same for every stage.
    #[pyo3(signature = (sequence, blocks_per_chunk = None))]
    fn chunks(&self, sequence: usize, blocks_per_chunk: Option<usize>) -> Vec<(usize, usize, usize)> {
        let per = blocks_per_chunk.unwrap_or_else(|| trueaxis::uncertainty::blocks_per_sequence(&self.settings));
        Chunk::of_sequence(&self.settings, sequence, per).into_iter().map(|c| (c.sequence, c.first_block, c.blocks)).collect()
    }

    /// The trial values of one chunk of stage `stage`: an array (trials, parameters) in the
    /// parameter units. Deterministic: the same on any process for the same plan. The GIL is
    /// released.
    fn run_chunk<'py>(&self, py: Python<'py>, stage: usize, chunk: (usize, usize, usize)) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.check_stage(stage)?;
        let chunk = chunk_of(chunk);
        if chunk.first_block + chunk.blocks > trueaxis::uncertainty::blocks_per_sequence(&self.settings) || chunk.blocks == 0 {
            return Err(input_msg(format!(
                "chunk {:?}: not a range of blocks of one sequence",
                (chunk.sequence, chunk.first_block, chunk.blocks)
            )));
        }
        let plan = self.plan()?;
        let model = plan.model(stage).map_err(of)?;
        let values = py.detach(|| run_chunk(&model, &self.settings, &chunk));
        let n = self.map.parameter_count();
        let rows = values.len() / n;
        PyArray1::from_vec(py, values).reshape([rows, n])
    }

    /// An empty run of every stage, to be fed the chunk values of each sequence in order.
    fn start(slf: &Bound<'_, Self>) -> PyResult<BudgetRun> {
        let p = slf.get();
        let stages = p.plan()?.stages();
        let runs =
            (0..stages).map(|_| AdaptiveRun::new(p.map.parameter_count(), &p.settings, None)).collect::<Result<Vec<_>, _>>().map_err(of)?;
        Ok(BudgetRun { plan: slf.clone().unbind(), runs: runs.into_iter().map(Some).collect() })
    }

    /// The whole budget in this process (threads), the document of `trueaxis uncertainty --json`;
    /// `poses` (N, axes) in mm and deg gives the uncertainty of the predicted dx dy dz there (a
    /// plan from a campaign). The GIL is released during the Monte Carlo. `progress(done, total)`,
    /// if given, is called after each sequence of trials: `done` sequences of at most `total`
    /// (every stage's most; the adaptive run stops earlier once its results are stable); an
    /// exception it raises is raised once the current stage ends.
    #[pyo3(signature = (*, poses = None, tool_point = None, work_point = None, frame = "workpiece", progress = None))]
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        py: Python<'_>,
        poses: Option<&Bound<'_, PyAny>>,
        tool_point: Option<&Bound<'_, PyAny>>,
        work_point: Option<&Bound<'_, PyAny>>,
        frame: &str,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let plan = self.plan()?;
        let progress = Progress::new(progress)?;
        let most = self.settings.max_sequences;
        let total = plan.stages() * most;
        let runs = py.detach(|| {
            let mut runs = Vec::with_capacity(plan.stages());
            for k in 0..plan.stages() {
                if progress.failed() {
                    break;
                }
                let mut report = |h: usize, _: Option<&_>| progress.report(k * most + h, total);
                runs.push(trueaxis::uncertainty::run_adaptive(&plan.model(k)?, &self.settings, &mut report)?);
            }
            Ok::<_, trueaxis::Error>(runs)
        });
        progress.finish()?;
        let runs = runs.map_err(of)?;
        self.document(py, runs, poses, tool_point, work_point, frame)
    }
}

/// The state of a budget being computed from chunks: one adaptive Monte Carlo run per stage.
#[pyclass(module = "trueaxis")]
pub struct BudgetRun {
    plan: Py<UncertaintyPlan>,
    runs: Vec<Option<AdaptiveRun>>,
}

impl BudgetRun {
    fn run_mut(&mut self, stage: usize) -> PyResult<&mut AdaptiveRun> {
        let count = self.runs.len();
        self.runs
            .get_mut(stage)
            .and_then(Option::as_mut)
            .ok_or_else(|| input_msg(format!("stage {stage}: the run has stages 0..{count} and has not been finished")))
    }
}

#[pymethods]
impl BudgetRun {
    /// The sequence (0-based) stage `stage` needs next; None when that stage is complete.
    fn next_sequence(&mut self, stage: usize) -> PyResult<Option<usize>> {
        Ok(self.run_mut(stage)?.next_sequence())
    }

    /// True when every stage is complete.
    #[getter]
    fn done(&self) -> bool {
        self.runs.iter().all(|r| r.as_ref().is_some_and(|r| r.next_sequence().is_none()))
    }

    /// Takes the next sequence of stage `stage` as a list of `(chunk, values)` covering it in
    /// order (values from `UncertaintyPlan.run_chunk`); returns True when the stage is complete.
    fn push(&mut self, stage: usize, chunks: Vec<((usize, usize, usize), Bound<'_, PyAny>)>) -> PyResult<bool> {
        let run = self.run_mut(stage)?;
        let mut pieces: Vec<(Chunk, Vec<f64>)> = Vec::with_capacity(chunks.len());
        for (c, v) in &chunks {
            let (values, shape) = array2(v, "chunk values")?;
            if shape[1] != run.outputs() {
                return Err(input_msg(format!("chunk {c:?}: values of shape {shape:?}, expected (trials, {})", run.outputs())));
            }
            pieces.push((chunk_of(*c), values));
        }
        run.push_chunks(&pieces).map_err(of)?;
        Ok(run.next_sequence().is_none())
    }

    /// The document of `trueaxis uncertainty --json` once every stage is complete (see
    /// `UncertaintyPlan.run` for `poses`).
    #[pyo3(signature = (*, poses = None, tool_point = None, work_point = None, frame = "workpiece"))]
    fn finish(
        &mut self,
        py: Python<'_>,
        poses: Option<&Bound<'_, PyAny>>,
        tool_point: Option<&Bound<'_, PyAny>>,
        work_point: Option<&Bound<'_, PyAny>>,
        frame: &str,
    ) -> PyResult<Py<PyAny>> {
        if !self.done() {
            return Err(input_msg("the budget is not complete: every stage needs its sequences until next_sequence() is None"));
        }
        let runs: Vec<McResult> = self.runs.iter_mut().map(|r| r.take().expect("checked by done").finish()).collect();
        self.plan.get().document(py, runs, poses, tool_point, work_point, frame)
    }
}
