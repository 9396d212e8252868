//! The adaptive Monte Carlo method of JCGM 101 §7.9.4 for several outputs (JCGM 102 §7.8, as used
//! in seed 004 §4.1): sequences of `M` trials until, for every output, twice the standard deviations
//! of the sequence values of the estimate, the standard uncertainty and both coverage interval
//! endpoints are below the numerical tolerance `delta`.
//!
//! Reproducibility: trial `i` of sequence `h` draws from the ChaCha8 stream `(seed, h, block)`,
//! `block = i / BLOCK`; blocks run in parallel (rayon) into fixed slots and every sum runs in a
//! fixed order, so a seed gives the same result on any number of threads.

use super::intervals::{shortest_interval, symmetric_interval, SampleSummary};
use super::UncertaintyError;
use nalgebra::DMatrix;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Trials per random-number stream and per parallel task.
pub const BLOCK: usize = 500;

/// The random-number stream of one block of trials: `ChaCha8Rng::seed_from_u64(seed)` with stream
/// `sequence * 2^32 + block`. The stream `block = 2^32 - 1` of each sequence is reserved for
/// draws made once per sequence ([`TrialModel::begin_sequence`]).
pub fn trial_rng(seed: u64, sequence: u64, block: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream((sequence << 32) | (block & 0xffff_ffff));
    rng
}

const SEQUENCE_STREAM: u64 = 0xffff_ffff;

/// A model evaluated once per Monte Carlo trial: draws its inputs and writes its outputs.
pub trait TrialModel: Sync {
    /// Draws made once per sequence (e.g. the start time of the cyclic drift, seed 004 eq. 12).
    type Sequence: Sync;
    /// Buffers reused between the trials of one thread.
    type Workspace: Send;
    fn outputs(&self) -> usize;
    fn workspace(&self) -> Self::Workspace;
    fn begin_sequence(&self, rng: &mut ChaCha8Rng) -> Self::Sequence;
    /// Trial `trial` (0-based, within its sequence): fills `out` with one value per output.
    fn trial(&self, sequence: &Self::Sequence, trial: usize, rng: &mut ChaCha8Rng, ws: &mut Self::Workspace, out: &mut [f64]);
}

/// Which coverage interval the adaptive loop stabilises (both are reported).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IntervalKind {
    /// Probabilistically symmetric (JCGM 101 §7.7.1).
    #[default]
    Symmetric,
    /// Shortest (JCGM 101 §7.7.2).
    Shortest,
}

/// Settings of the adaptive procedure (JCGM 101 §7.9.4).
#[derive(Clone, Debug, PartialEq)]
pub struct McSettings {
    /// Coverage probability `p`, e.g. 0.95.
    pub coverage: f64,
    /// Numerical tolerance `delta` in the unit of the outputs (seed 004: 0.05 um or urad).
    pub tolerance: f64,
    /// Trials per sequence `M`: JCGM 101 uses `max(J, 10^4)` with `J = ceil(100 / (1 - p))`.
    pub trials_per_sequence: usize,
    /// Upper limit of the number of sequences `h`.
    pub max_sequences: usize,
    pub seed: u64,
    pub interval: IntervalKind,
}

impl McSettings {
    /// JCGM 101 defaults for coverage `p` and tolerance `delta`: `M = max(ceil(100/(1-p)), 10^4)`,
    /// at most 1000 sequences, seed 1, symmetric intervals.
    pub fn new(coverage: f64, tolerance: f64) -> McSettings {
        McSettings {
            coverage,
            tolerance,
            trials_per_sequence: minimum_trials(coverage).max(10_000),
            max_sequences: 1000,
            seed: 1,
            interval: IntervalKind::Symmetric,
        }
    }

    pub fn validate(&self) -> Result<(), UncertaintyError> {
        let bad = |m: String| Err(UncertaintyError::Input(m));
        if !(self.coverage > 0.0 && self.coverage < 1.0) {
            return bad(format!("coverage probability {} must lie strictly between 0 and 1", self.coverage));
        }
        if !(self.tolerance > 0.0 && self.tolerance.is_finite()) {
            return bad(format!("numerical tolerance {} must be a positive number", self.tolerance));
        }
        let j = minimum_trials(self.coverage);
        if self.trials_per_sequence < j {
            return bad(format!(
                "trials_per_sequence = {} is too small for coverage {}: JCGM 101 §7.9.4 needs at least 100 / (1 - p) = {j}",
                self.trials_per_sequence, self.coverage
            ));
        }
        if self.trials_per_sequence > MAX_TRIALS_PER_SEQUENCE {
            return bad(format!(
                "trials_per_sequence = {} is more than {MAX_TRIALS_PER_SEQUENCE}: every trial value is kept (8 bytes per output), \
                 use more sequences of fewer trials instead",
                self.trials_per_sequence
            ));
        }
        if self.max_sequences < 2 {
            return bad("max_sequences must be at least 2 (the adaptive test compares sequences)".into());
        }
        Ok(())
    }
}

/// Largest `M` accepted: 10^6 trials, 100 times the JCGM 101 default of 10^4.
pub const MAX_TRIALS_PER_SEQUENCE: usize = 1_000_000;
/// Largest number of trial values a run may keep (`M x max_sequences x outputs`, 8 bytes each:
/// 2 GB), checked before the first trial.
pub const MAX_KEPT_VALUES: usize = 250_000_000;

/// `J = ceil(100 / (1 - p))` (JCGM 101 §7.9.4 b).
pub fn minimum_trials(coverage: f64) -> usize {
    (100.0 / (1.0 - coverage) - 1e-9).ceil().max(2.0) as usize
}

/// Control variables after sequence `h >= 2` (JCGM 101 §7.9.4 f; seed 004 Fig. 13): the standard
/// deviations of the averages of the sequence estimates `s_y`, standard uncertainties `s_u`, and
/// lower and upper interval endpoints, per output and their maximum over outputs.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ControlVariables {
    pub sequence: usize,
    /// `[s_y, s_u, s_low, s_high]` per output.
    pub per_output: Vec<[f64; 4]>,
    /// Largest `s_y` over the outputs, then `s_u`, `s_low`, `s_high`.
    pub max: [f64; 4],
}

impl ControlVariables {
    /// True when `2 s <= delta` for all four control variables of every output (§7.9.4 j).
    pub fn stable(&self, tolerance: f64) -> bool {
        self.max.iter().all(|s| 2.0 * s <= tolerance)
    }
}

/// Result of one output over all `h M` trials (JCGM 101 §7.9.4 g).
pub type OutputResult = SampleSummary;

/// Result of a Monte Carlo run.
#[derive(Clone, Debug)]
pub struct McResult {
    pub outputs: Vec<OutputResult>,
    /// Covariance matrix of the outputs over all trials (JCGM 102 §7.6), divisor `hM - 1`.
    pub covariance: DMatrix<f64>,
    /// Number of sequences `h`.
    pub sequences: usize,
    pub trials: usize,
    /// False when `max_sequences` ran out before the tolerance was reached.
    pub converged: bool,
    /// Control variables after each sequence from the second on.
    pub history: Vec<ControlVariables>,
    /// All trial values of each output, sorted (for histograms).
    pub samples: Vec<Vec<f64>>,
}

/// The adaptive procedure of JCGM 101 §7.9.4. `progress` is called after each sequence with its
/// number and, from the second sequence on, the control variables.
pub fn run_adaptive<M: TrialModel>(
    model: &M,
    settings: &McSettings,
    progress: &mut dyn FnMut(usize, Option<&ControlVariables>),
) -> Result<McResult, UncertaintyError> {
    run(model, settings, None, progress)
}

/// Exactly `sequences` sequences of `M` trials, without the stability test (the control variables
/// are still recorded).
pub fn run_sequences<M: TrialModel>(model: &M, settings: &McSettings, sequences: usize) -> Result<McResult, UncertaintyError> {
    run(model, settings, Some(sequences), &mut |_, _| {})
}

fn run<M: TrialModel>(
    model: &M,
    settings: &McSettings,
    fixed: Option<usize>,
    progress: &mut dyn FnMut(usize, Option<&ControlVariables>),
) -> Result<McResult, UncertaintyError> {
    settings.validate()?;
    let n_out = model.outputs();
    if n_out == 0 {
        return Err(UncertaintyError::Input("the model has no outputs".into()));
    }
    let m = settings.trials_per_sequence;
    let limit = fixed.unwrap_or(settings.max_sequences);
    let kept = m.saturating_mul(limit).saturating_mul(n_out);
    if kept > MAX_KEPT_VALUES {
        return Err(UncertaintyError::Input(format!(
            "trials_per_sequence {m} x max_sequences {limit} x {n_out} outputs = {kept} trial values to keep, more than {MAX_KEPT_VALUES} \
             (2 GB): lower max_sequences or trials_per_sequence"
        )));
    }
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); n_out];
    let mut sequence_values: Vec<Vec<[f64; 4]>> = vec![Vec::new(); n_out];
    let mut history = Vec::new();
    let mut buffer = vec![0.0; m * n_out];
    let mut column = vec![0.0; m];
    let mut converged = false;
    let mut h = 0;
    while h < limit {
        run_sequence(model, settings, h as u64, &mut buffer);
        h += 1;
        for (j, values) in sequence_values.iter_mut().enumerate() {
            for (c, row) in column.iter_mut().zip(buffer.chunks_exact(n_out)) {
                *c = row[j];
            }
            if column.iter().any(|v| !v.is_finite()) {
                return Err(UncertaintyError::Computation(format!("output {} is not finite in sequence {h}", j + 1)));
            }
            columns[j].extend_from_slice(&column);
            values.push(sequence_statistics(&mut column, settings));
        }
        if h < 2 {
            progress(h, None);
            continue;
        }
        let control = control_variables(h, &sequence_values);
        progress(h, Some(&control));
        let stable = control.stable(settings.tolerance);
        history.push(control);
        if fixed.is_none() && stable {
            converged = true;
            break;
        }
    }
    let covariance = covariance(&columns);
    let mut outputs = Vec::with_capacity(n_out);
    for values in columns.iter_mut() {
        outputs.push(SampleSummary::of(values, settings.coverage));
    }
    Ok(McResult { outputs, covariance, sequences: h, trials: h * m, converged: converged || fixed.is_some(), history, samples: columns })
}

/// One sequence of `M` trials into `buffer` (trial-major, `M x outputs`).
fn run_sequence<M: TrialModel>(model: &M, settings: &McSettings, sequence: u64, buffer: &mut [f64]) {
    let n_out = model.outputs();
    let state = model.begin_sequence(&mut trial_rng(settings.seed, sequence, SEQUENCE_STREAM));
    buffer.par_chunks_mut(BLOCK * n_out).enumerate().for_each_init(
        || model.workspace(),
        |ws, (block, chunk)| {
            let mut rng = trial_rng(settings.seed, sequence, block as u64);
            for (i, out) in chunk.chunks_exact_mut(n_out).enumerate() {
                out.fill(0.0);
                model.trial(&state, block * BLOCK + i, &mut rng, ws, out);
            }
        },
    );
}

/// Estimate, standard uncertainty and the two endpoints of one sequence (§7.9.4 d); sorts `values`.
fn sequence_statistics(values: &mut [f64], settings: &McSettings) -> [f64; 4] {
    values.sort_unstable_by(f64::total_cmp);
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let u = (values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0)).sqrt();
    let interval = match settings.interval {
        IntervalKind::Symmetric => symmetric_interval(values, settings.coverage),
        IntervalKind::Shortest => shortest_interval(values, settings.coverage),
    };
    [mean, u, interval.low, interval.high]
}

/// `s_x^2 = 1 / (h (h - 1)) sum_r (x^(r) - mean x)^2` for each of the four quantities (§7.9.4 f).
fn control_variables(h: usize, sequence_values: &[Vec<[f64; 4]>]) -> ControlVariables {
    let hf = h as f64;
    let per_output: Vec<[f64; 4]> = sequence_values
        .iter()
        .map(|values| {
            let mut s = [0.0; 4];
            for (k, sk) in s.iter_mut().enumerate() {
                let mean = values.iter().map(|v| v[k]).sum::<f64>() / hf;
                let ss = values.iter().map(|v| (v[k] - mean) * (v[k] - mean)).sum::<f64>();
                *sk = (ss / (hf * (hf - 1.0))).sqrt();
            }
            s
        })
        .collect();
    let mut max = [0.0f64; 4];
    for s in &per_output {
        for k in 0..4 {
            max[k] = max[k].max(s[k]);
        }
    }
    ControlVariables { sequence: h, per_output, max }
}

/// Sample covariance of the outputs (columns of trial values in trial order).
fn covariance(columns: &[Vec<f64>]) -> DMatrix<f64> {
    let n_out = columns.len();
    let n = columns[0].len() as f64;
    let means: Vec<f64> = columns.iter().map(|c| c.iter().sum::<f64>() / n).collect();
    let mut cov = DMatrix::zeros(n_out, n_out);
    for i in 0..n_out {
        for j in 0..=i {
            let s: f64 = columns[i].iter().zip(&columns[j]).map(|(a, b)| (a - means[i]) * (b - means[j])).sum();
            cov[(i, j)] = s / (n - 1.0);
            cov[(j, i)] = cov[(i, j)];
        }
    }
    cov
}
