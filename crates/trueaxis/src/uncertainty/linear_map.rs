//! The linear identification `p = P y`, `P = (X^T W X)^-1 X^T W` (Andolfatto et al. 2011 eq. 5 with weights),
//! computed once, and the uncertainty sources compiled into linear maps to the parameters:
//! - Gaussian sources independent per observation (sensor noise, frame transformation, statistical
//!   drift) are Gaussian in the parameters with covariance `P Sigma P^T`: one multivariate normal of
//!   dimension n_par, whatever the number of observations;
//! - the cyclic drift is a trigonometric polynomial of the start time `tau`, so its effect is
//!   `sum_k g_k cos(k w tau) + h_k sin(k w tau)` with `g_k, h_k` precomputed;
//! - other distributions are drawn per observation and mapped by the columns of `P`.
//!
//! [`Evaluation::PerObservation`] draws every observation error and applies `P`;
//! [`Evaluation::BruteForce`] re-solves the least squares in each trial (QR, `identify::fit_linear`).
//! With the same seed the last two give the same trials; the reduced form gives the same
//! distribution (the cyclic part trial by trial).

use super::chain_drift::{measurement_time, reduce_to_period, statistical_drift_uncertainty, PeriodicDrift, StartPhase};
use super::distributions::{Distribution, MultivariateNormal};
use super::monte_carlo::{trials_one_by_one, TrialModel};
use super::sources::{Source, SourceKind};
use super::DesignMatrix;
use crate::error::Error;
use crate::identify::{fit_linear, IdentifyError};
use nalgebra::{DMatrix, DVector};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution as _, StandardNormal};

/// How a Monte Carlo trial is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Evaluation {
    /// Per-source linear maps (the fast path).
    #[default]
    Reduced,
    /// Every observation error drawn, then `p = p0 + P e`.
    PerObservation,
    /// Every observation error drawn, then the weighted least squares solved again.
    BruteForce,
}

/// The identification of a [`DesignMatrix`], with its pseudo-inverse.
#[derive(Clone, Debug)]
pub struct IdentificationMap {
    pub design: DesignMatrix,
    /// `P`, n_par x n_obs (parameter unit per um).
    pub pseudo_inverse: DMatrix<f64>,
    /// `p0 = P y` from the measured values (parameter units).
    pub estimate: Vec<f64>,
    /// Singular values of `W^1/2 X` with unit-length columns, largest first.
    pub singular_values: Vec<f64>,
    pub condition_number: f64,
}

fn identify_error(e: IdentifyError) -> Error {
    match e {
        IdentifyError::RankDeficient { .. } => Error::computation(e.to_string()),
        other => Error::input(other.to_string()),
    }
}

impl IdentificationMap {
    /// Checks the rank (a rank-deficient design names the inseparable parameters, a failed
    /// computation) and computes `P` by the SVD of the column-scaled `W^1/2 X`:
    /// `P = D^-1 V S^-1 U^T W^1/2`.
    pub fn new(design: DesignMatrix) -> Result<IdentificationMap, Error> {
        fit_linear(&design.x, &design.measured, Some(&design.weight), &design.parameters).map_err(identify_error)?;
        let (n, p) = design.x.shape();
        let sqrt_w: Vec<f64> = design.weight.iter().map(|w| w.sqrt()).collect();
        let mut a = design.x.clone();
        for (i, w) in sqrt_w.iter().enumerate() {
            a.row_mut(i).scale_mut(*w);
        }
        let scale: Vec<f64> = (0..p).map(|j| a.column(j).norm()).collect();
        for (j, s) in scale.iter().enumerate() {
            a.column_mut(j).unscale_mut(*s);
        }
        let svd = a.svd(true, true);
        let (Some(u), Some(v_t)) = (svd.u.as_ref(), svd.v_t.as_ref()) else {
            return Err(Error::computation("singular value decomposition failed"));
        };
        let mut order: Vec<usize> = (0..p).collect();
        order.sort_by(|&i, &j| svd.singular_values[j].total_cmp(&svd.singular_values[i]));
        let singular_values: Vec<f64> = order.iter().map(|&i| svd.singular_values[i]).collect();
        // P = D^-1 V S^-1 U^T W^1/2
        let mut vs = v_t.transpose();
        for j in 0..p {
            vs.column_mut(j).unscale_mut(svd.singular_values[j]);
        }
        let mut pinv = vs * u.transpose();
        for (j, s) in scale.iter().enumerate() {
            pinv.row_mut(j).unscale_mut(*s);
        }
        for (i, w) in sqrt_w.iter().enumerate() {
            pinv.column_mut(i).scale_mut(*w);
        }
        debug_assert_eq!(pinv.shape(), (p, n));
        let estimate = (&pinv * DVector::from_column_slice(&design.measured)).as_slice().to_vec();
        let condition_number = singular_values[0] / singular_values[p - 1];
        Ok(IdentificationMap { design, pseudo_inverse: pinv, estimate, singular_values, condition_number })
    }

    pub fn parameter_count(&self) -> usize {
        self.design.parameter_count()
    }

    /// `out += P e` for observation errors `e` (um).
    pub fn add_mapped(&self, e: &[f64], out: &mut [f64]) {
        for (i, ei) in e.iter().enumerate() {
            if *ei != 0.0 {
                for (o, pij) in out.iter_mut().zip(self.pseudo_inverse.column(i).iter()) {
                    *o += pij * ei;
                }
            }
        }
    }

    /// Parameters from observations `y` (um) by re-solving the weighted least squares (QR):
    /// the brute-force reference.
    pub fn solve_least_squares(&self, y: &[f64]) -> Result<Vec<f64>, Error> {
        let d = &self.design;
        fit_linear(&d.x, y, Some(&d.weight), &d.parameters).map(|f| f.coefficients).map_err(identify_error)
    }

    /// GUM covariance of the parameters due to `source` (JCGM 100 §5.2, Soons 1993 eq. A.4):
    /// `P Sigma P^T` for sources independent per observation; for the cyclic drift, with `tau`
    /// uniform over the period, `sum_k (g_k g_k^T + h_k h_k^T) / 2`.
    pub fn gum_covariance(&self, source: &Source) -> Result<DMatrix<f64>, Error> {
        let compiled = CompiledSource::new(self, source)?;
        Ok(match &compiled {
            CompiledSource::PerObservation { rows, .. } => {
                let mut b = self.pseudo_inverse.clone();
                for (i, d) in rows.iter().enumerate() {
                    b.column_mut(i).scale_mut(d.as_ref().map_or(0.0, |d| d.standard_uncertainty()));
                }
                &b * b.transpose()
            }
            CompiledSource::Cyclic(c) => {
                let n = self.parameter_count();
                let mut cov = DMatrix::zeros(n, n);
                for (g, h) in &c.harmonics {
                    cov += (g * g.transpose() + h * h.transpose()) * 0.5;
                }
                cov
            }
            CompiledSource::Correlated { groups, normal } => {
                // sum over points of B_g V B_g^T, B_g the columns of P of the point's rows
                let v = normal.covariance();
                let n = self.parameter_count();
                let mut cov = DMatrix::zeros(n, n);
                for group in groups {
                    let b = DMatrix::from_fn(n, group.len(), |i, k| group[k].map_or(0.0, |row| self.pseudo_inverse[(i, row)]));
                    cov += &b * &v * b.transpose();
                }
                cov
            }
        })
    }

    /// Expectation of the parameters with `sources` (GUM, first order): `p0 + P E{e}`.
    pub fn gum_estimate(&self, sources: &[&Source]) -> Result<Vec<f64>, Error> {
        let mut out = self.estimate.clone();
        for source in sources {
            if let CompiledSource::PerObservation { rows, .. } = CompiledSource::new(self, source)? {
                let means: Vec<f64> = rows.iter().map(|d| d.as_ref().map_or(0.0, |d| d.mean())).collect();
                self.add_mapped(&means, &mut out);
            }
        }
        Ok(out)
    }

    /// The Monte Carlo model of the identification with `sources` acting together.
    pub fn model(&self, sources: &[&Source], evaluation: Evaluation) -> Result<LinearModel<'_>, Error> {
        LinearModel::new(self, sources, evaluation)
    }
}

/// A source in terms of the observations.
#[derive(Clone, Debug)]
enum CompiledSource {
    /// An independent draw per observation (`None`: the source does not act on it).
    PerObservation {
        rows: Vec<Option<Distribution>>,
        all_normal: bool,
    },
    Cyclic(CyclicMap),
    /// Joint Gaussian draws over groups of observations (the rows of one point, in the order of
    /// the source's channels; `None` where the point lacks a channel).
    Correlated {
        groups: Vec<Vec<Option<usize>>>,
        normal: MultivariateNormal,
    },
}

/// The cyclic drift of one source: per observation its drift function (index) and time.
#[derive(Clone, Debug)]
struct CyclicMap {
    functions: Vec<PeriodicDrift>,
    rows: Vec<Option<usize>>,
    period: f64,
    run_duration: f64,
    start_phase: StartPhase,
    /// `(g_k, h_k)` for k = 1..K: the parameters move by `g_k cos(k w tau) + h_k sin(k w tau)`.
    harmonics: Vec<(DVector<f64>, DVector<f64>)>,
}

impl CyclicMap {
    /// `tau = t0 + (n - 1) t_m` reduced to one period (Andolfatto et al. 2011 eq. 12 without the point time).
    fn tau(&self, t0: f64, trial: usize) -> f64 {
        reduce_to_period(measurement_time(t0, trial, self.run_duration, 0.0), self.period)
    }
}

impl CompiledSource {
    fn new(map: &IdentificationMap, source: &Source) -> Result<CompiledSource, Error> {
        let design = &map.design;
        let channel_of = |name: &str| {
            design
                .channel_index(name)
                .ok_or_else(|| Error::input(format!("source `{}`: channel `{name}` is not in the design", source.name)))
        };
        let per_channel = |list: Vec<(usize, Distribution)>| {
            let rows: Vec<Option<Distribution>> =
                design.channel.iter().map(|c| list.iter().find(|(k, _)| k == c).map(|(_, d)| d.clone())).collect();
            let all_normal = rows.iter().flatten().all(Distribution::is_normal);
            CompiledSource::PerObservation { rows, all_normal }
        };
        match &source.kind {
            SourceKind::Noise { channels } => {
                let list = channels.iter().map(|(c, d)| Ok((channel_of(c)?, d.clone()))).collect::<Result<Vec<_>, Error>>()?;
                Ok(per_channel(list))
            }
            SourceKind::StatisticalDrift { channels } => {
                let list = channels
                    .iter()
                    .map(|(c, e)| Ok((channel_of(c)?, Distribution::Normal { mean: 0.0, u: statistical_drift_uncertainty(*e) })))
                    .collect::<Result<Vec<_>, Error>>()?;
                Ok(per_channel(list))
            }
            SourceKind::Correlated { channels, covariance } => {
                let index = channels.iter().map(|c| channel_of(c)).collect::<Result<Vec<_>, _>>()?;
                // rows of the source's channels grouped by measurement time, in order of appearance
                let mut groups: Vec<(f64, Vec<Option<usize>>)> = Vec::new();
                for (row, (&c, &t)) in design.channel.iter().zip(&design.time).enumerate() {
                    let Some(k) = index.iter().position(|&i| i == c) else { continue };
                    let slot = match groups.iter().position(|(time, _)| *time == t) {
                        Some(g) => g,
                        None => {
                            groups.push((t, vec![None; channels.len()]));
                            groups.len() - 1
                        }
                    };
                    if groups[slot].1[k].replace(row).is_some() {
                        return Err(Error::input(format!(
                            "source `{}`: channel `{}` has two observations at t = {t} s; a correlated source draws one value per channel and point \
                             (give each point its own time)",
                            source.name, channels[k]
                        )));
                    }
                }
                let normal = MultivariateNormal::new(DVector::zeros(channels.len()), covariance)
                    .map_err(|e| Error::input(format!("source `{}`: {e}", source.name)))?;
                Ok(CompiledSource::Correlated { groups: groups.into_iter().map(|g| g.1).collect(), normal })
            }
            SourceKind::CyclicDrift(cyclic) => {
                let period = cyclic.period();
                if cyclic.channels.iter().any(|(_, d)| (d.period() - period).abs() > 1e-12 * period) {
                    return Err(Error::input(format!("source `{}`: all channels need the same period", source.name)));
                }
                let mut functions = Vec::new();
                let mut index = vec![None; design.channels.len()];
                for (c, d) in &cyclic.channels {
                    index[channel_of(c)?] = Some(functions.len());
                    functions.push(d.clone());
                }
                let rows: Vec<Option<usize>> = design.channel.iter().map(|&c| index[c]).collect();
                let run_duration = cyclic.run_duration.unwrap_or_else(|| design.time.iter().copied().fold(0.0, f64::max));
                if run_duration <= 0.0 {
                    return Err(Error::input(format!(
                        "source `{}`: the run duration t_m is zero: give run_duration_s or measurement times t > 0",
                        source.name
                    )));
                }
                let harmonics = cyclic_harmonics(map, &functions, &rows);
                Ok(CompiledSource::Cyclic(CyclicMap { functions, rows, period, run_duration, start_phase: cyclic.start_phase, harmonics }))
            }
        }
    }
}

/// `g_k = -P u_k`, `h_k = -P v_k` with `u_k[i] = a_k cos(k w t_i) + b_k sin(k w t_i)` and
/// `v_k[i] = b_k cos(k w t_i) - a_k sin(k w t_i)` (the drift is subtracted from the measurement):
/// then `-D(tau + t_i) = -sum_k cos(k w tau) u_k[i] + sin(k w tau) v_k[i]`.
fn cyclic_harmonics(map: &IdentificationMap, functions: &[PeriodicDrift], rows: &[Option<usize>]) -> Vec<(DVector<f64>, DVector<f64>)> {
    let k_max = functions.iter().map(PeriodicDrift::harmonic_count).max().unwrap_or(0);
    let n = rows.len();
    (1..=k_max)
        .map(|k| {
            let (mut u, mut v) = (DVector::zeros(n), DVector::zeros(n));
            for (i, f) in rows.iter().enumerate() {
                let Some(f) = f.map(|f| &functions[f]) else { continue };
                if k > f.harmonic_count() {
                    continue;
                }
                let (a, b) = f.coefficients(k);
                let angle = k as f64 * f.omega() * map.design.time[i];
                u[i] = a * angle.cos() + b * angle.sin();
                v[i] = b * angle.cos() - a * angle.sin();
            }
            (-(&map.pseudo_inverse * u), -(&map.pseudo_inverse * v))
        })
        .collect()
}

/// The Monte Carlo model: one trial draws the sources and gives the identified parameters.
pub struct LinearModel<'a> {
    map: &'a IdentificationMap,
    evaluation: Evaluation,
    sources: Vec<CompiledSource>,
    /// Reduced form: the Gaussian per-observation sources together, and their mean effect.
    gaussian: Option<MultivariateNormal>,
    constant: Vec<f64>,
    /// Reduced form whose only per-trial draws are the Gaussian and the start times: a block of
    /// trials at once ([`LinearModel::reduced_block`]).
    by_blocks: bool,
}

/// Per-thread buffers.
pub struct LinearWorkspace {
    errors: Vec<f64>,
    observations: Vec<f64>,
    /// A block's standard normal variates, component-major.
    normals: Vec<f64>,
    /// A block's start times per cyclic source drawn per trial, source-major.
    starts: Vec<f64>,
    /// A block's cosine and sine of one harmonic.
    cos: Vec<f64>,
    sin: Vec<f64>,
}

impl<'a> LinearModel<'a> {
    fn new(map: &'a IdentificationMap, sources: &[&Source], evaluation: Evaluation) -> Result<LinearModel<'a>, Error> {
        let compiled = sources.iter().map(|s| CompiledSource::new(map, s)).collect::<Result<Vec<_>, _>>()?;
        let n = map.parameter_count();
        let mut constant = map.estimate.clone();
        let mut gaussian = None;
        if evaluation == Evaluation::Reduced {
            let normal: Vec<&Source> = sources
                .iter()
                .zip(&compiled)
                .filter(|(_, c)| matches!(c, CompiledSource::PerObservation { all_normal: true, .. } | CompiledSource::Correlated { .. }))
                .map(|(s, _)| *s)
                .collect();
            constant = map.gum_estimate(&normal)?;
            if !normal.is_empty() {
                let mut cov = DMatrix::zeros(n, n);
                for s in &normal {
                    cov += map.gum_covariance(s)?;
                }
                gaussian = Some(MultivariateNormal::new(DVector::zeros(n), &cov)?);
            }
        }
        let by_blocks = evaluation == Evaluation::Reduced
            && !compiled.iter().any(|c| matches!(c, CompiledSource::PerObservation { all_normal: false, .. }));
        Ok(LinearModel { map, evaluation, sources: compiled, gaussian, constant, by_blocks })
    }

    /// Draws the error of every observation (um) into `e`: noise added, drift subtracted.
    fn draw_observation_errors(&self, t0: &[f64], trial: usize, rng: &mut ChaCha8Rng, e: &mut [f64]) {
        e.fill(0.0);
        let mut cyclic = 0;
        for source in &self.sources {
            match source {
                CompiledSource::PerObservation { rows, .. } => {
                    for (ei, d) in e.iter_mut().zip(rows) {
                        if let Some(d) = d {
                            *ei += d.sample(rng);
                        }
                    }
                }
                CompiledSource::Correlated { groups, normal } => {
                    let mut draw = vec![0.0; normal.dimension()];
                    for group in groups {
                        draw.fill(0.0);
                        normal.add_centred_sample(rng, &mut draw);
                        for (row, v) in group.iter().zip(&draw) {
                            if let Some(row) = row {
                                e[*row] += v;
                            }
                        }
                    }
                }
                CompiledSource::Cyclic(c) => {
                    let tau = c.tau(start_time(c, t0[cyclic], rng), trial);
                    cyclic += 1;
                    for (i, f) in c.rows.iter().enumerate() {
                        if let Some(f) = f {
                            e[i] -= c.functions[*f].value(tau + self.map.design.time[i]);
                        }
                    }
                }
            }
        }
    }

    fn reduced_trial(&self, t0: &[f64], trial: usize, rng: &mut ChaCha8Rng, out: &mut [f64]) {
        out.copy_from_slice(&self.constant);
        if let Some(g) = &self.gaussian {
            g.add_centred_sample(rng, out);
        }
        let mut cyclic = 0;
        for source in &self.sources {
            match source {
                CompiledSource::PerObservation { all_normal: true, .. } | CompiledSource::Correlated { .. } => {}
                CompiledSource::PerObservation { rows, .. } => {
                    for (i, d) in rows.iter().enumerate() {
                        if let Some(d) = d {
                            let e = d.sample(rng);
                            for (o, p) in out.iter_mut().zip(self.map.pseudo_inverse.column(i).iter()) {
                                *o += p * e;
                            }
                        }
                    }
                }
                CompiledSource::Cyclic(c) => {
                    let tau = c.tau(start_time(c, t0[cyclic], rng), trial);
                    cyclic += 1;
                    let w = 2.0 * std::f64::consts::PI / c.period;
                    for (k, (g, h)) in c.harmonics.iter().enumerate() {
                        let angle = (k + 1) as f64 * w * tau;
                        let (s, co) = angle.sin_cos();
                        for ((o, gk), hk) in out.iter_mut().zip(g.iter()).zip(h.iter()) {
                            *o += gk * co + hk * s;
                        }
                    }
                }
            }
        }
    }
}

impl LinearModel<'_> {
    /// [`LinearModel::reduced_trial`] for the `n = out.len() / n_par` trials from `first` on, the
    /// values output-major (`out[r n + i]`): the draws in the order of the trials (each trial's
    /// normals, then its start times), then every value through the same operations in the same
    /// order as one trial alone, vectorised over the trials. Only for models whose per-trial draws
    /// are those (`by_blocks`).
    fn reduced_block(&self, t0: &[f64], first: usize, rng: &mut ChaCha8Rng, ws: &mut LinearWorkspace, out: &mut [f64]) {
        let n_par = self.constant.len();
        let n = out.len() / n_par;
        let cyclic: Vec<&CyclicMap> = self
            .sources
            .iter()
            .filter_map(|s| match s {
                CompiledSource::Cyclic(c) => Some(c),
                CompiledSource::PerObservation { .. } | CompiledSource::Correlated { .. } => None,
            })
            .collect();
        let dimension = self.gaussian.as_ref().map_or(0, MultivariateNormal::dimension);
        ws.normals.resize(dimension * n, 0.0);
        ws.starts.resize(cyclic.len() * n, 0.0);
        for i in 0..n {
            for j in 0..dimension {
                ws.normals[j * n + i] = StandardNormal.sample(rng);
            }
            for (k, c) in cyclic.iter().enumerate() {
                ws.starts[k * n + i] = start_time(c, t0[k], rng);
            }
        }
        for (o, c) in out.chunks_exact_mut(n).zip(&self.constant) {
            o.fill(*c);
        }
        if let Some(g) = &self.gaussian {
            g.add_centred_block(&ws.normals, out);
        }
        ws.cos.resize(n, 0.0);
        ws.sin.resize(n, 0.0);
        for (k, c) in cyclic.iter().enumerate() {
            let w = 2.0 * std::f64::consts::PI / c.period;
            for (harmonic, (g, h)) in c.harmonics.iter().enumerate() {
                for i in 0..n {
                    let tau = c.tau(ws.starts[k * n + i], first + i);
                    let angle = (harmonic + 1) as f64 * w * tau;
                    (ws.sin[i], ws.cos[i]) = angle.sin_cos();
                }
                for ((o, gk), hk) in out.chunks_exact_mut(n).zip(g.iter()).zip(h.iter()) {
                    for ((o, co), s) in o.iter_mut().zip(&ws.cos).zip(&ws.sin) {
                        *o += gk * co + hk * s;
                    }
                }
            }
        }
    }
}

/// The start time `t0`: the sequence's (Andolfatto et al. 2011 eq. 12), or a new one for this trial.
fn start_time(c: &CyclicMap, sequence_t0: f64, rng: &mut ChaCha8Rng) -> f64 {
    match c.start_phase {
        StartPhase::Sequence => sequence_t0,
        StartPhase::Trial => c.period * rng.gen::<f64>(),
    }
}

impl TrialModel for LinearModel<'_> {
    /// Start time `t0` (s) of each cyclic source, uniform over its period.
    type Sequence = Vec<f64>;
    type Workspace = LinearWorkspace;

    fn outputs(&self) -> usize {
        self.map.parameter_count()
    }

    fn workspace(&self) -> LinearWorkspace {
        let n = self.map.design.observations();
        LinearWorkspace {
            errors: vec![0.0; n],
            observations: vec![0.0; n],
            normals: Vec::new(),
            starts: Vec::new(),
            cos: Vec::new(),
            sin: Vec::new(),
        }
    }

    fn begin_sequence(&self, rng: &mut ChaCha8Rng) -> Vec<f64> {
        self.sources
            .iter()
            .filter_map(|s| match s {
                CompiledSource::Cyclic(c) => Some(c.period * rng.gen::<f64>()),
                CompiledSource::PerObservation { .. } | CompiledSource::Correlated { .. } => None,
            })
            .collect()
    }

    fn trial_block(&self, t0: &Vec<f64>, first: usize, rng: &mut ChaCha8Rng, ws: &mut LinearWorkspace, out: &mut [f64]) {
        if self.by_blocks {
            self.reduced_block(t0, first, rng, ws, out);
        } else {
            trials_one_by_one(self, t0, first, rng, ws, out);
        }
    }

    fn trial(&self, t0: &Vec<f64>, trial: usize, rng: &mut ChaCha8Rng, ws: &mut LinearWorkspace, out: &mut [f64]) {
        match self.evaluation {
            Evaluation::Reduced => self.reduced_trial(t0, trial, rng, out),
            Evaluation::PerObservation => {
                self.draw_observation_errors(t0, trial, rng, &mut ws.errors);
                out.copy_from_slice(&self.map.estimate);
                self.map.add_mapped(&ws.errors, out);
            }
            Evaluation::BruteForce => {
                self.draw_observation_errors(t0, trial, rng, &mut ws.errors);
                for ((y, m), e) in ws.observations.iter_mut().zip(&self.map.design.measured).zip(&ws.errors) {
                    *y = m + e;
                }
                match self.map.solve_least_squares(&ws.observations) {
                    Ok(p) => out.copy_from_slice(&p),
                    Err(_) => out.fill(f64::NAN),
                }
            }
        }
    }
}
