//! The adaptive Monte Carlo method of JCGM 101 §7.9.4 for several outputs (JCGM 102 §7.8, as used
//! in Andolfatto et al. 2011 §4.1): sequences of `M` trials until, for every output, twice the standard deviations
//! of the sequence values of the estimate, the standard uncertainty and both coverage interval
//! endpoints are below the numerical tolerance `delta`.
//!
//! Reproducibility: trial `i` of sequence `h` draws from the ChaCha8 stream `(seed, h, block)`,
//! `block = i / BLOCK`; blocks run in parallel (rayon) into fixed slots and every sum runs in a
//! fixed order, so a seed gives the same result on any number of threads. The same streams make
//! the run divisible into [`Chunk`]s computed anywhere (counter-based seeding: the stream of a
//! block is a function of its number, not of the blocks drawn before it) and merged in order by
//! [`AdaptiveRun`]: a run distributed over processes or machines equals one process bit for bit.

use super::intervals::{in_fours, moments, shortest_interval_of_unsorted, symmetric_interval_of, Moments, SampleSummary};
use crate::error::Error;
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
    /// Draws made once per sequence (e.g. the start time of the cyclic drift, Andolfatto et al. 2011 eq. 12).
    type Sequence: Sync;
    /// Buffers reused between the trials of one thread.
    type Workspace: Send;
    fn outputs(&self) -> usize;
    fn workspace(&self) -> Self::Workspace;
    fn begin_sequence(&self, rng: &mut ChaCha8Rng) -> Self::Sequence;
    /// Trial `trial` (0-based, within its sequence): fills `out` with one value per output.
    fn trial(&self, sequence: &Self::Sequence, trial: usize, rng: &mut ChaCha8Rng, ws: &mut Self::Workspace, out: &mut [f64]);

    /// The trials `first .. first + n` of one block, `n = out.len() / outputs`, output-major:
    /// `out[j n + i]` is output `j` of trial `first + i`. It must give, bit for bit, what `n` calls
    /// of [`TrialModel::trial`] in trial order give from the same `rng` ([`trials_one_by_one`],
    /// the provided form); a model overrides it to compute a whole block at once.
    fn trial_block(&self, sequence: &Self::Sequence, first: usize, rng: &mut ChaCha8Rng, ws: &mut Self::Workspace, out: &mut [f64]) {
        trials_one_by_one(self, sequence, first, rng, ws, out);
    }
}

/// [`TrialModel::trial_block`] by one call of [`TrialModel::trial`] per trial (each on a zeroed
/// row), the values written output-major.
pub fn trials_one_by_one<M: TrialModel + ?Sized>(
    model: &M,
    sequence: &M::Sequence,
    first: usize,
    rng: &mut ChaCha8Rng,
    ws: &mut M::Workspace,
    out: &mut [f64],
) {
    let n_out = model.outputs();
    let n = out.len() / n_out;
    let mut row = vec![0.0; n_out];
    for i in 0..n {
        row.fill(0.0);
        model.trial(sequence, first + i, rng, ws, &mut row);
        for (j, v) in row.iter().enumerate() {
            out[j * n + i] = *v;
        }
    }
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
    /// Numerical tolerance `delta` in the unit of the outputs (Andolfatto et al. 2011: 0.05 um or urad).
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

    pub fn validate(&self) -> Result<(), Error> {
        let bad = |m: String| Err(Error::input(m));
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

/// Control variables after sequence `h >= 2` (JCGM 101 §7.9.4 f; Andolfatto et al. 2011 Fig. 13): the standard
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
    /// All trial values of each output, in trial order (sequence after sequence; for histograms;
    /// sort a copy for the empirical distribution function).
    pub samples: Vec<Vec<f64>>,
}

/// The adaptive procedure of JCGM 101 §7.9.4. `progress` is called after each sequence with its
/// number and, from the second sequence on, the control variables.
pub fn run_adaptive<M: TrialModel>(
    model: &M,
    settings: &McSettings,
    progress: &mut dyn FnMut(usize, Option<&ControlVariables>),
) -> Result<McResult, Error> {
    run(model, settings, None, progress)
}

/// Exactly `sequences` sequences of `M` trials, without the stability test (the control variables
/// are still recorded).
pub fn run_sequences<M: TrialModel>(model: &M, settings: &McSettings, sequences: usize) -> Result<McResult, Error> {
    run(model, settings, Some(sequences), &mut |_, _| {})
}

fn run<M: TrialModel>(
    model: &M,
    settings: &McSettings,
    fixed: Option<usize>,
    progress: &mut dyn FnMut(usize, Option<&ControlVariables>),
) -> Result<McResult, Error> {
    let mut state = AdaptiveRun::new(model.outputs(), settings, fixed)?;
    let mut buffer = Vec::new();
    while let Some(h) = state.next_sequence() {
        run_blocks_into(model, settings, &Chunk::whole_sequence(settings, h), &mut buffer);
        let control = state.push_blocks(&buffer)?;
        progress(h + 1, control.as_ref());
    }
    Ok(state.finish())
}

/// A piece of a Monte Carlo run that any process can compute alone: the blocks
/// `first_block .. first_block + blocks` of sequence `sequence` (0-based), [`BLOCK`] trials each
/// (the last block of a sequence may be shorter). Its random numbers come only from the streams
/// of its blocks and of its sequence ([`trial_rng`]), so a run split into chunks over processes
/// or machines gives bit for bit the trial values of one process.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Chunk {
    pub sequence: usize,
    pub first_block: usize,
    pub blocks: usize,
}

impl Chunk {
    /// All the blocks of sequence `sequence`.
    pub fn whole_sequence(settings: &McSettings, sequence: usize) -> Chunk {
        Chunk { sequence, first_block: 0, blocks: blocks_per_sequence(settings) }
    }

    /// Sequence `sequence` cut into chunks of at most `blocks_per_chunk` blocks, in trial order.
    pub fn of_sequence(settings: &McSettings, sequence: usize, blocks_per_chunk: usize) -> Vec<Chunk> {
        let total = blocks_per_sequence(settings);
        let step = blocks_per_chunk.max(1);
        (0..total).step_by(step).map(|first| Chunk { sequence, first_block: first, blocks: step.min(total - first) }).collect()
    }

    /// The trials of the chunk within its sequence (0-based, end excluded).
    pub fn trials(&self, settings: &McSettings) -> std::ops::Range<usize> {
        let m = settings.trials_per_sequence;
        (self.first_block * BLOCK).min(m)..((self.first_block + self.blocks) * BLOCK).min(m)
    }
}

/// Blocks of [`BLOCK`] trials in one sequence of `M` trials.
pub fn blocks_per_sequence(settings: &McSettings) -> usize {
    settings.trials_per_sequence.div_ceil(BLOCK)
}

/// The trial values of one chunk, trial-major (`outputs` values per trial, trials in order). The
/// blocks run in parallel (rayon); the values do not depend on the number of threads.
pub fn run_chunk<M: TrialModel>(model: &M, settings: &McSettings, chunk: &Chunk) -> Vec<f64> {
    let n_out = model.outputs();
    let mut blocks = Vec::new();
    run_blocks_into(model, settings, chunk, &mut blocks);
    let mut values = vec![0.0; blocks.len()];
    for (block, rows) in blocks.chunks(BLOCK * n_out).zip(values.chunks_mut(BLOCK * n_out)) {
        let n = block.len() / n_out;
        for (i, row) in rows.chunks_exact_mut(n_out).enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = block[j * n + i];
            }
        }
    }
    values
}

/// The trial values of one chunk block by block, each block output-major (`out[j n + i]`,
/// `n` the trials of the block): the layout [`AdaptiveRun::push_blocks`] takes. Blocks in parallel.
fn run_blocks_into<M: TrialModel>(model: &M, settings: &McSettings, chunk: &Chunk, buffer: &mut Vec<f64>) {
    let n_out = model.outputs();
    let trials = chunk.trials(settings);
    buffer.clear();
    buffer.resize(trials.len() * n_out, 0.0);
    let sequence = chunk.sequence as u64;
    let state = model.begin_sequence(&mut trial_rng(settings.seed, sequence, SEQUENCE_STREAM));
    buffer.par_chunks_mut(BLOCK * n_out).enumerate().for_each_init(
        || model.workspace(),
        |ws, (k, values)| {
            let block = chunk.first_block + k;
            let mut rng = trial_rng(settings.seed, sequence, block as u64);
            model.trial_block(&state, block * BLOCK, &mut rng, ws, values);
        },
    );
}

/// The state of an adaptive Monte Carlo run (JCGM 101 §7.9.4): it takes the trial values of the
/// sequences in order, decides after each whether the results are stable, and gives the results.
/// Computing the sequences is left to the caller (one process: [`run_adaptive`]; several
/// processes or machines: [`run_chunk`] per [`Chunk`], the chunks of a sequence taken in order by
/// [`AdaptiveRun::push_chunks`]), so a distributed run stops at the same sequence with the same
/// numbers as one process.
#[derive(Clone, Debug)]
pub struct AdaptiveRun {
    settings: McSettings,
    outputs: usize,
    limit: usize,
    fixed: bool,
    columns: Vec<Vec<f64>>,
    sequence_values: Vec<Vec<[f64; 4]>>,
    history: Vec<ControlVariables>,
    converged: bool,
    sequences: usize,
}

impl AdaptiveRun {
    /// A run of `outputs` outputs: adaptive (`fixed` = `None`, at most `settings.max_sequences`),
    /// or exactly `fixed` sequences. Checks the settings and the memory the kept values need.
    pub fn new(outputs: usize, settings: &McSettings, fixed: Option<usize>) -> Result<AdaptiveRun, Error> {
        settings.validate()?;
        if outputs == 0 {
            return Err(Error::input("the model has no outputs"));
        }
        let m = settings.trials_per_sequence;
        let limit = fixed.unwrap_or(settings.max_sequences);
        let kept = m.saturating_mul(limit).saturating_mul(outputs);
        if kept > MAX_KEPT_VALUES {
            return Err(Error::input(format!(
                "trials_per_sequence {m} x max_sequences {limit} x {outputs} outputs = {kept} trial values to keep, more than {MAX_KEPT_VALUES} \
                 (2 GB): lower max_sequences or trials_per_sequence"
            )));
        }
        Ok(AdaptiveRun {
            settings: settings.clone(),
            outputs,
            limit,
            fixed: fixed.is_some(),
            columns: vec![Vec::new(); outputs],
            sequence_values: vec![Vec::new(); outputs],
            history: Vec::new(),
            converged: false,
            sequences: 0,
        })
    }

    /// The sequence (0-based) whose values come next; `None` when the run is over (stable, or the
    /// sequence limit reached).
    pub fn next_sequence(&self) -> Option<usize> {
        (!self.converged && self.sequences < self.limit).then_some(self.sequences)
    }

    /// Sequences taken so far.
    pub fn sequences(&self) -> usize {
        self.sequences
    }

    /// Number of outputs per trial.
    pub fn outputs(&self) -> usize {
        self.outputs
    }

    /// Takes the trial values of the next sequence (`M x outputs`, trial-major); returns the
    /// control variables from the second sequence on. An error when a value is not finite, the
    /// length is not that of one sequence, or the run is over.
    pub fn push_sequence(&mut self, values: &[f64]) -> Result<Option<ControlVariables>, Error> {
        let Some(h) = self.next_sequence() else {
            return Err(Error::input("the Monte Carlo run is already complete"));
        };
        let n_out = self.outputs;
        if values.len() != self.settings.trials_per_sequence * n_out {
            return Err(Error::input(format!(
                "sequence {} has {} values; expected {} trials x {n_out} outputs",
                h + 1,
                values.len(),
                self.settings.trials_per_sequence
            )));
        }
        self.push_columns(h, |j, column| column.extend(values.chunks_exact(n_out).map(|row| row[j])))
    }

    /// [`AdaptiveRun::push_sequence`] for values laid out block by block, each block of [`BLOCK`]
    /// trials (the last maybe fewer) output-major, as [`run_blocks_into`] writes them.
    fn push_blocks(&mut self, values: &[f64]) -> Result<Option<ControlVariables>, Error> {
        let Some(h) = self.next_sequence() else {
            return Err(Error::input("the Monte Carlo run is already complete"));
        };
        let n_out = self.outputs;
        debug_assert_eq!(values.len(), self.settings.trials_per_sequence * n_out);
        self.push_columns(h, |j, column| {
            for block in values.chunks(BLOCK * n_out) {
                let n = block.len() / n_out;
                column.extend_from_slice(&block[j * n..(j + 1) * n]);
            }
        })
    }

    /// Appends sequence `h` to the columns (`extend(j, column)` appends output `j`), then its
    /// statistics and control variables.
    fn push_columns(&mut self, h: usize, extend: impl Fn(usize, &mut Vec<f64>) + Sync) -> Result<Option<ControlVariables>, Error> {
        let m = self.settings.trials_per_sequence;
        // the outputs in parallel, each into its own column; the first output (in order) that is
        // not finite is the error
        let finite: Vec<bool> = self
            .columns
            .par_iter_mut()
            .enumerate()
            .map(|(j, column)| {
                extend(j, column);
                column[h * m..].iter().all(|v| v.is_finite())
            })
            .collect();
        if let Some(j) = finite.iter().position(|f| !f) {
            // the run stays as it was before this sequence
            for column in &mut self.columns {
                column.truncate(h * m);
            }
            return Err(Error::computation(format!("output {} is not finite in sequence {}", j + 1, h + 1)));
        }
        let settings = &self.settings;
        let statistics: Vec<[f64; 4]> = self
            .columns
            .par_chunks(8)
            .flat_map_iter(|group| {
                let fresh: Vec<&[f64]> = group.iter().map(|c| &c[h * m..]).collect();
                sequence_statistics(&fresh, settings)
            })
            .collect();
        for (values, s) in self.sequence_values.iter_mut().zip(statistics) {
            values.push(s);
        }
        self.sequences = h + 1;
        if self.sequences < 2 {
            return Ok(None);
        }
        let control = control_variables(self.sequences, &self.sequence_values);
        if !self.fixed && control.stable(self.settings.tolerance) {
            self.converged = true;
        }
        self.history.push(control.clone());
        Ok(Some(control))
    }

    /// Takes the next sequence as its chunks with their values ([`run_chunk`]), which must cover
    /// that sequence from its first block, in order.
    pub fn push_chunks(&mut self, chunks: &[(Chunk, Vec<f64>)]) -> Result<Option<ControlVariables>, Error> {
        let h = self.next_sequence().unwrap_or(self.sequences);
        let mut next_block = 0;
        for (c, _) in chunks {
            if c.sequence != h || c.first_block != next_block {
                return Err(Error::input(format!(
                    "chunk of sequence {} from block {} out of order: expected sequence {} from block {next_block}",
                    c.sequence + 1,
                    c.first_block,
                    h + 1
                )));
            }
            next_block += c.blocks;
        }
        let values: Vec<f64> = chunks.iter().flat_map(|(_, v)| v.iter().copied()).collect();
        self.push_sequence(&values)
    }

    /// The results over all the trials taken (JCGM 101 §7.9.4 g).
    pub fn finish(self) -> McResult {
        let AdaptiveRun { settings, columns, history, converged, sequences, fixed, .. } = self;
        let covariance = covariance(&columns);
        // no sort: the sums in trial order, the intervals by selection and sorted tails
        let outputs = SampleSummary::of_unsorted(&columns, settings.coverage);
        McResult {
            outputs,
            covariance,
            sequences,
            trials: sequences * settings.trials_per_sequence,
            converged: converged || fixed,
            history,
            samples: columns,
        }
    }
}

/// Estimate, standard uncertainty and the two endpoints of one sequence (§7.9.4 d) for each of
/// `columns` (its values in trial order): the sums in trial order, four outputs side by side
/// (the skewness and kurtosis that come with them are not used); the
/// probabilistically symmetric interval by selection (linear time), the shortest by sorting only
/// its two tails.
fn sequence_statistics(columns: &[&[f64]], settings: &McSettings) -> Vec<[f64; 4]> {
    let moments = in_fours(columns, moments);
    columns
        .iter()
        .zip(moments)
        .map(|(values, Moments { mean, std_uncertainty: u, .. })| {
            let interval = match settings.interval {
                IntervalKind::Symmetric => symmetric_interval_of(values, settings.coverage),
                IntervalKind::Shortest => shortest_interval_of_unsorted(values, settings.coverage),
            };
            [mean, u, interval.low, interval.high]
        })
        .collect()
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

/// Sample covariance of the outputs (columns of trial values in trial order, divisor `n - 1`):
/// each mean and each product sum in trial order, all the sums of a pass side by side (one pass
/// over the trials instead of one per pair); the lower triangle in two parts of about equal work,
/// in parallel.
fn covariance(columns: &[Vec<f64>]) -> DMatrix<f64> {
    let n_out = columns.len();
    let len = columns[0].len();
    let n = len as f64;
    let columns: Vec<&[f64]> = columns.iter().map(|c| &c[..len]).collect();
    let mut sums = vec![-0.0f64; n_out];
    for i in 0..len {
        for (s, c) in sums.iter_mut().zip(&columns) {
            *s += c[i];
        }
    }
    let means: Vec<f64> = sums.iter().map(|s| s / n).collect();
    // rows 0..split and split..n_out of about equal work (each row of the first part as wide as
    // split, of the second as n_out, both padded to whole vectors)
    let work = |rows: usize, width: usize| rows * width.next_multiple_of(PRODUCT_WIDTH);
    let split = (1..=n_out).min_by_key(|&s| work(s, s).max(work(n_out - s, n_out))).unwrap_or(n_out);
    let (upper, lower) = rayon::join(|| centred_products(&columns, &means, 0..split), || centred_products(&columns, &means, split..n_out));
    let packed: Vec<f64> = upper.into_iter().chain(lower).collect();
    DMatrix::from_fn(n_out, n_out, |i, j| {
        let (i, j) = if j <= i { (i, j) } else { (j, i) };
        packed[i * (i + 1) / 2 + j] / (n - 1.0)
    })
}

/// Rows of the products are padded to whole multiples of this many values (one AVX2 register).
const PRODUCT_WIDTH: usize = 4;

/// `sum_t (x_i[t] - m_i) (x_j[t] - m_j)` for the rows `i` of `rows` and `j <= i`, packed row by
/// row; every sum in trial order. The AVX2 form when the CPU has it (the same operations in the
/// same order, so the same bits).
fn centred_products(columns: &[&[f64]], means: &[f64], rows: std::ops::Range<usize>) -> Vec<f64> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2
        return unsafe { centred_products_avx2(columns, means, rows) };
    }
    centred_products_of(columns, means, rows)
}

/// [`centred_products_of`] compiled with AVX2. The CPU must have it.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn centred_products_avx2(columns: &[&[f64]], means: &[f64], rows: std::ops::Range<usize>) -> Vec<f64> {
    centred_products_of(columns, means, rows)
}

/// The products of [`centred_products`]: tiles of trials are centred and laid out trial-major,
/// then each trial adds `d_i d_j` to whole rows `i` of the product matrix at once (every `j` up to
/// the padded width, vectorised: the sums of a row are independent, each still in trial order);
/// the rows are packed to `j <= i` at the end.
#[inline(always)]
fn centred_products_of(columns: &[&[f64]], means: &[f64], rows: std::ops::Range<usize>) -> Vec<f64> {
    const TILE: usize = 64;
    if rows.is_empty() {
        return Vec::new();
    }
    let width = rows.end.next_multiple_of(PRODUCT_WIDTH);
    let trials = columns.first().map_or(0, |c| c.len());
    // a sum starts at -0.0, the neutral element of addition (also for a sum of -0.0 products)
    let mut full = vec![-0.0f64; rows.len() * width];
    // centred values of a tile, d[t * width + j]; the padding stays zero
    let mut d = vec![0.0; TILE * width];
    for start in (0..trials).step_by(TILE) {
        let len = TILE.min(trials - start);
        for (j, (column, mean)) in columns[..rows.end].iter().zip(means).enumerate() {
            for (t, x) in column[start..start + len].iter().enumerate() {
                d[t * width + j] = x - mean;
            }
        }
        for dt in d.chunks_exact(width).take(len) {
            for (row, &di) in full.chunks_exact_mut(width).zip(&dt[rows.clone()]) {
                for (s, &dj) in row.iter_mut().zip(dt) {
                    *s += di * dj;
                }
            }
        }
    }
    let mut packed = Vec::with_capacity(rows.end * (rows.end + 1) / 2 - rows.start * (rows.start + 1) / 2);
    for (row, i) in full.chunks_exact(width).zip(rows) {
        packed.extend_from_slice(&row[..=i]);
    }
    packed
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The products as the one-pair-at-a-time definition, each sum in trial order.
    fn products_by_definition(columns: &[&[f64]], means: &[f64], rows: std::ops::Range<usize>) -> Vec<f64> {
        let mut out = Vec::new();
        for i in rows {
            for j in 0..=i {
                let mut s = -0.0f64;
                for (xi, xj) in columns[i].iter().zip(columns[j]) {
                    s += (xi - means[i]) * (xj - means[j]);
                }
                out.push(s);
            }
        }
        out
    }

    #[test]
    fn centred_products_equal_the_definition_bit_for_bit() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        // 14 outputs as Andolfatto et al. 2011, odd counts, a tile remainder, a single trial, a single output
        for (outputs, trials) in [(14, 1000), (5, 130), (1, 64), (9, 1), (16, 257)] {
            let data: Vec<Vec<f64>> =
                (0..outputs).map(|k| (0..trials).map(|_| rng.gen_range(-1.0..1.0) * 10f64.powi(k as i32 % 5 - 2)).collect()).collect();
            let columns: Vec<&[f64]> = data.iter().map(|c| c.as_slice()).collect();
            let means: Vec<f64> = data.iter().map(|c| c.iter().sum::<f64>() / trials as f64).collect();
            for rows in [0..outputs, 0..outputs / 2, outputs / 2..outputs] {
                let want = products_by_definition(&columns, &means, rows.clone());
                for got in [centred_products(&columns, &means, rows.clone()), centred_products_of(&columns, &means, rows.clone())] {
                    assert_eq!(got.len(), want.len());
                    assert!(got.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()), "{outputs} x {trials}, rows {rows:?}");
                }
            }
        }
    }
}
