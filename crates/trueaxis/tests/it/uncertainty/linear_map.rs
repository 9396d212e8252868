//! The linear identification map against brute force, and the GUM against Monte Carlo on linear
//! Gaussian models (JCGM 101 §9.1 / JCGM 102 §9): same trials, same distributions, same covariances.

use nalgebra::{DMatrix, DVector};
use rand_chacha::ChaCha8Rng;
use trueaxis::uncertainty::{
    confidence_ellipsoid, propagate, run_adaptive, run_chunk, run_sequences, trial_rng, trials_one_by_one, AdaptiveRun, Chunk, CyclicDrift,
    DesignMatrix, Distribution, Ellipsoid, Evaluation, IdentificationMap, McResult, McSettings, MultivariateNormal, PeriodicDrift, Source,
    SourceKind, StartPhase, TrialModel,
};

/// 40 poses x 3 channels, 4 parameters: a small "3D ball" design with lever arms and times
/// `t = 0.75 k` s; non-uniform weights on channel z.
fn design() -> DesignMatrix {
    let (mut rows, mut channels, mut time, mut weight) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for k in 0..40 {
        let th = 2.0 * std::f64::consts::PI * k as f64 / 40.0 * 1.3;
        let (s, c) = th.sin_cos();
        for (ch, row, w) in [
            ("x", [1.0, 0.0, 0.15 * c, 0.05 * k as f64 / 40.0], 1.0),
            ("y", [0.0, 1.0, 0.15 * s, -0.1 * c], 1.0),
            ("z", [0.3, -0.2, 0.0, 0.12 * s], 0.5),
        ] {
            rows.extend_from_slice(&row);
            channels.push(ch.to_string());
            time.push(0.75 * (k + 1) as f64);
            weight.push(w);
        }
    }
    let n = channels.len();
    let x = DMatrix::from_row_slice(n, 4, &rows);
    let truth = DVector::from_column_slice(&[2.0, -1.0, 30.0, 12.0]);
    let measured: Vec<f64> = (&x * truth).iter().enumerate().map(|(i, v)| v + 0.3 * ((i * 7 % 11) as f64 / 11.0 - 0.5)).collect();
    let names = ["a", "b", "EC0Y", "EY0C"].map(String::from).to_vec();
    DesignMatrix::new(names, &channels, time, Some(weight), Some(measured), x).unwrap()
}

fn noise(name: &str, channels: &[(&str, Distribution)]) -> Source {
    Source { name: name.into(), kind: SourceKind::Noise { channels: channels.iter().map(|(c, d)| (c.to_string(), d.clone())).collect() } }
}

fn cyclic(start_phase: StartPhase) -> Source {
    let x = PeriodicDrift::harmonics(37.0, &[(2.0, 10.0), (0.7, 80.0)]).unwrap();
    let y = PeriodicDrift::sine(37.0, 1.5, -40.0).unwrap();
    let kind = SourceKind::CyclicDrift(CyclicDrift { channels: vec![("x".into(), x), ("y".into(), y)], run_duration: None, start_phase });
    Source { name: "drift".into(), kind }
}

fn all_sources() -> Vec<Source> {
    vec![
        noise("sensors", &[("x", Distribution::Rectangular { low: -0.5, high: 0.5 }), ("y", Distribution::Normal { mean: 0.0, u: 0.3 })]),
        Source { name: "stat".into(), kind: SourceKind::StatisticalDrift { channels: vec![("z".into(), 3.0)] } },
        cyclic(StartPhase::Sequence),
    ]
}

fn settings(seed: u64) -> McSettings {
    let mut s = McSettings::new(0.95, 0.01);
    s.trials_per_sequence = 2000;
    s.seed = seed;
    s
}

fn max_abs_diff(a: &McResult, b: &McResult) -> f64 {
    a.samples.iter().flatten().zip(b.samples.iter().flatten()).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn pseudo_inverse_is_the_weighted_least_squares_solution() {
    let map = IdentificationMap::new(design()).unwrap();
    let qr = map.solve_least_squares(&map.design.measured).unwrap();
    for (a, b) in map.estimate.iter().zip(&qr) {
        assert!((a - b).abs() < 1e-10, "{a} vs {b}");
    }
    // P X = I
    let px = &map.pseudo_inverse * &map.design.x;
    assert!((px - DMatrix::<f64>::identity(4, 4)).abs().max() < 1e-12);
    // the true parameters are recovered within the small perturbation of the data
    for (a, t) in map.estimate.iter().zip([2.0, -1.0, 30.0, 12.0]) {
        assert!((a - t).abs() < 1.5, "{a} vs {t}");
    }
    assert!(map.condition_number >= 1.0 && map.condition_number < 100.0);
    assert_eq!(map.design.units, ["unit", "unit", "urad", "um"]);
}

#[test]
fn linear_map_trials_equal_brute_force_trials() {
    // every observation error drawn in the same order from the same streams; P e versus a new QR
    // least-squares solution of y + e in every trial: the same trials to rounding
    let map = IdentificationMap::new(design()).unwrap();
    let sources = all_sources();
    let refs: Vec<&Source> = sources.iter().collect();
    let fast = run_sequences(&map.model(&refs, Evaluation::PerObservation).unwrap(), &settings(5), 2).unwrap();
    let brute = run_sequences(&map.model(&refs, Evaluation::BruteForce).unwrap(), &settings(5), 2).unwrap();
    assert_eq!(fast.trials, 4000);
    assert!(max_abs_diff(&fast, &brute) < 1e-9, "{}", max_abs_diff(&fast, &brute));
    for (a, b) in fast.outputs.iter().zip(&brute.outputs) {
        assert!((a.mean - b.mean).abs() < 1e-9 && (a.std_uncertainty - b.std_uncertainty).abs() < 1e-9);
        assert!((a.symmetric.low - b.symmetric.low).abs() < 1e-9 && (a.shortest.high - b.shortest.high).abs() < 1e-9);
    }
    assert!((&fast.covariance - &brute.covariance).abs().max() < 1e-9);
}

#[test]
fn harmonic_map_of_the_cyclic_drift_equals_drawing_it_per_observation() {
    // the cyclic drift depends only on the start time: the reduced map gives the same trials
    let map = IdentificationMap::new(design()).unwrap();
    for phase in [StartPhase::Sequence, StartPhase::Trial] {
        let source = cyclic(phase);
        let reduced = run_sequences(&map.model(&[&source], Evaluation::Reduced).unwrap(), &settings(9), 2).unwrap();
        let per_obs = run_sequences(&map.model(&[&source], Evaluation::PerObservation).unwrap(), &settings(9), 2).unwrap();
        assert!(max_abs_diff(&reduced, &per_obs) < 1e-9, "{phase:?}: {}", max_abs_diff(&reduced, &per_obs));
        // and the drift moves the parameters
        assert!(reduced.outputs.iter().any(|o| o.std_uncertainty > 0.1));
    }
}

#[test]
fn reduced_and_per_observation_paths_give_the_same_distribution() {
    // the Gaussian sources become one multivariate normal in parameter space: other draws, same law
    let map = IdentificationMap::new(design()).unwrap();
    let sources = all_sources();
    let refs: Vec<&Source> = sources.iter().collect();
    let delta = 0.02;
    let mut s = McSettings::new(0.95, delta);
    s.seed = 3;
    let reduced = run_adaptive(&map.model(&refs, Evaluation::Reduced).unwrap(), &s, &mut |_, _| {}).unwrap();
    let per_obs = run_adaptive(&map.model(&refs, Evaluation::PerObservation).unwrap(), &s, &mut |_, _| {}).unwrap();
    assert!(reduced.converged && per_obs.converged);
    for (j, (a, b)) in reduced.outputs.iter().zip(&per_obs.outputs).enumerate() {
        // each result is within delta/2 (one standard deviation) of its limit: 3 delta is > 4 sigma
        for (x, y) in [
            (a.mean, b.mean),
            (a.std_uncertainty, b.std_uncertainty),
            (a.symmetric.low, b.symmetric.low),
            (a.symmetric.high, b.symmetric.high),
        ] {
            assert!((x - y).abs() < 3.0 * delta, "parameter {j}: {x} vs {y}");
        }
    }
}

#[test]
fn gum_equals_monte_carlo_on_the_gaussian_identification() {
    // only Gaussian sources: the parameters are Gaussian with covariance P Sigma P^T (GUM exact)
    let map = IdentificationMap::new(design()).unwrap();
    let sources = [
        noise("sensors", &[("x", Distribution::Normal { mean: 0.0, u: 0.28 }), ("y", Distribution::Normal { mean: 0.1, u: 0.28 })]),
        Source { name: "stat".into(), kind: SourceKind::StatisticalDrift { channels: vec![("z".into(), 6.63)] } },
    ];
    let refs: Vec<&Source> = sources.iter().collect();
    let gum_cov = map.gum_covariance(&sources[0]).unwrap() + map.gum_covariance(&sources[1]).unwrap();
    let gum_mean = map.gum_estimate(&refs).unwrap();
    let delta = 0.02;
    let mut s = McSettings::new(0.95, delta);
    s.seed = 21;
    // the per-observation path does not use the GUM covariance at all
    let mc = run_adaptive(&map.model(&refs, Evaluation::PerObservation).unwrap(), &s, &mut |_, _| {}).unwrap();
    let k = 1.959964;
    for j in 0..4 {
        let u = gum_cov[(j, j)].sqrt();
        let o = &mc.outputs[j];
        assert!((o.mean - gum_mean[j]).abs() < delta, "mean {j}");
        assert!((o.std_uncertainty - u).abs() < delta, "u {j}: {} vs {u}", o.std_uncertainty);
        assert!((o.symmetric.low - (gum_mean[j] - k * u)).abs() < 2.0 * delta, "low {j}");
        assert!((o.symmetric.high - (gum_mean[j] + k * u)).abs() < 2.0 * delta, "high {j}");
    }
    // correlations too (JCGM 102): the MC covariance within 3 % of the largest variance
    let scale = gum_cov.diagonal().max();
    assert!((&mc.covariance - &gum_cov).abs().max() < 0.03 * scale);
    // the 95 % GUM ellipsoid of the 4 parameters holds 95 % of the trials (+-0.004: > 5 sigma for 10^5 trials)
    let ellipsoid = confidence_ellipsoid(&gum_mean, &gum_cov, 0.95).unwrap();
    assert_eq!(ellipsoid.dof, 4);
    let inside = InsideEllipsoid { model: map.model(&refs, Evaluation::PerObservation).unwrap(), ellipsoid };
    let r = run_sequences(&inside, &s, 10).unwrap();
    let fraction = r.outputs[0].mean;
    assert!((fraction - 0.95).abs() < 0.004, "{fraction} of {} trials", r.trials);
}

/// 1 when the trial of `model` lies inside `ellipsoid`, else 0: its mean is the coverage fraction.
struct InsideEllipsoid<'a> {
    model: trueaxis::uncertainty::LinearModel<'a>,
    ellipsoid: Ellipsoid,
}

impl TrialModel for InsideEllipsoid<'_> {
    type Sequence = Vec<f64>;
    type Workspace = (trueaxis::uncertainty::LinearWorkspace, Vec<f64>);
    fn outputs(&self) -> usize {
        1
    }
    fn workspace(&self) -> Self::Workspace {
        (self.model.workspace(), vec![0.0; self.model.outputs()])
    }
    fn begin_sequence(&self, rng: &mut ChaCha8Rng) -> Vec<f64> {
        self.model.begin_sequence(rng)
    }
    fn trial(&self, seq: &Vec<f64>, trial: usize, rng: &mut ChaCha8Rng, ws: &mut Self::Workspace, out: &mut [f64]) {
        ws.1.fill(0.0);
        self.model.trial(seq, trial, rng, &mut ws.0, &mut ws.1);
        out[0] = if self.ellipsoid.contains(&ws.1) { 1.0 } else { 0.0 };
    }
}

#[test]
fn gum_covariance_of_the_cyclic_drift_matches_random_phase_trials() {
    // with a new start time in every trial the drift term is sum_k g_k cos + h_k sin at a uniform
    // phase: covariance sum_k (g g^T + h h^T) / 2
    let map = IdentificationMap::new(design()).unwrap();
    let source = cyclic(StartPhase::Trial);
    let gum = map.gum_covariance(&source).unwrap();
    let mut s = McSettings::new(0.95, 0.01);
    s.seed = 8;
    let r = run_sequences(&map.model(&[&source], Evaluation::Reduced).unwrap(), &s, 10).unwrap();
    let scale = gum.diagonal().max();
    assert!((&r.covariance - &gum).abs().max() < 0.02 * scale, "{}", (&r.covariance - &gum).abs().max() / scale);
    // the output is far from Gaussian: a dominant sinusoid is arc-sine-like (excess kurtosis < -0.5)
    assert!(r.outputs.iter().any(|o| o.excess_kurtosis < -0.5));
}

/// `y = A x` with x ~ N(mu, V): a 2-output linear Gaussian model through the general engine.
struct Linear {
    a: DMatrix<f64>,
    x: MultivariateNormal,
}

impl TrialModel for Linear {
    type Sequence = ();
    type Workspace = Vec<f64>;
    fn outputs(&self) -> usize {
        self.a.nrows()
    }
    fn workspace(&self) -> Vec<f64> {
        vec![0.0; self.x.dimension()]
    }
    fn begin_sequence(&self, _: &mut ChaCha8Rng) {}
    fn trial(&self, _: &(), _: usize, rng: &mut ChaCha8Rng, x: &mut Vec<f64>, out: &mut [f64]) {
        self.x.sample_into(rng, x);
        for (i, o) in out.iter_mut().enumerate() {
            *o = (0..x.len()).map(|j| self.a[(i, j)] * x[j]).sum();
        }
    }
}

#[test]
fn multivariate_normal_inputs_propagate_as_the_gum_says() {
    let v = DMatrix::from_row_slice(3, 3, &[1.0, 0.6, 0.0, 0.6, 2.0, -0.5, 0.0, -0.5, 0.5]);
    let mu = DVector::from_column_slice(&[1.0, 2.0, 3.0]);
    let a = DMatrix::from_row_slice(2, 3, &[1.0, -1.0, 2.0, 0.5, 0.5, 0.0]);
    let model = Linear { a: a.clone(), x: MultivariateNormal::new(mu.clone(), &v).unwrap() };
    assert!((model.x.covariance() - &v).abs().max() < 1e-12);
    let gum = propagate(&a, &v).unwrap();
    let mean = &a * &mu;
    let delta = 0.01;
    let mut s = McSettings::new(0.95, delta);
    s.seed = 41;
    let r = run_adaptive(&model, &s, &mut |_, _| {}).unwrap();
    for j in 0..2 {
        assert!((r.outputs[j].mean - mean[j]).abs() < delta);
        assert!((r.outputs[j].std_uncertainty - gum[(j, j)].sqrt()).abs() < delta);
    }
    assert!((r.covariance[(0, 1)] - gum[(0, 1)]).abs() < 0.01 * gum.diagonal().max());
    // a singular covariance (rank 1) is accepted; an indefinite one is refused
    assert!(MultivariateNormal::new(DVector::zeros(2), &DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0])).is_ok());
    assert!(MultivariateNormal::new(DVector::zeros(2), &DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0])).is_err());
}

#[test]
fn bad_designs_and_sources_are_reported() {
    // a column that repeats another is rank deficient: a failed computation naming the parameters
    let mut d = design();
    let col = d.x.column(0).into_owned();
    d.x.set_column(1, &(col * 2.0));
    let err = IdentificationMap::new(d).unwrap_err();
    assert!(err.kind() == trueaxis::ErrorKind::Computation && err.to_string().contains("cannot be separated"), "{err}");
    // a source on a channel the design does not have is bad input
    let map = IdentificationMap::new(design()).unwrap();
    let err = map.model(&[&noise("s", &[("w", Distribution::Normal { mean: 0.0, u: 1.0 })])], Evaluation::Reduced).err().unwrap();
    assert!(err.kind() == trueaxis::ErrorKind::Input && err.to_string().contains("channel `w`"), "{err}");
    // the CSV form round-trips
    let text = map.design.to_csv();
    let back = DesignMatrix::from_csv_reader(text.as_bytes(), "design.csv").unwrap();
    assert_eq!(back.parameters, map.design.parameters);
    assert_eq!(back.channel, map.design.channel);
    assert!((&back.x - &map.design.x).abs().max() == 0.0);
    assert_eq!(back.weight, map.design.weight);
    // and names the line of a bad number
    let err = DesignMatrix::from_csv_reader("channel,t,a,b\nx,0,1,2\nx,1,zz,2\nx,2,1,3\n".as_bytes(), "d.csv").unwrap_err();
    assert!(err.to_string().contains("d.csv: line 3: column a: `zz`"), "{err}");
}

#[test]
fn a_block_of_trials_equals_the_trials_one_by_one_bit_for_bit() {
    // the reduced model computes a block at once (normals drawn in stream order, the Gaussian
    // factor and the drift harmonics applied output-major); the provided form calls `trial` per
    // trial. Both start phases, with and without a non-Gaussian source (which takes the one-by-one
    // path), whole and partial blocks, late trials (large drift times)
    let map = IdentificationMap::new(design()).unwrap();
    let gaussian =
        noise("sensors", &[("x", Distribution::Normal { mean: 0.1, u: 0.3 }), ("z", Distribution::Normal { mean: 0.0, u: 0.5 })]);
    let rectangular = noise("rect", &[("y", Distribution::Rectangular { low: -0.5, high: 0.5 })]);
    let stat = Source { name: "stat".into(), kind: SourceKind::StatisticalDrift { channels: vec![("z".into(), 3.0)] } };
    let mut checked = 0;
    for phase in [StartPhase::Sequence, StartPhase::Trial] {
        let drift = cyclic(phase);
        for sources in [vec![&gaussian, &drift], vec![&gaussian, &stat, &drift, &rectangular], vec![&drift], vec![&gaussian]] {
            let model = map.model(&sources, Evaluation::Reduced).unwrap();
            let n_out = model.outputs();
            for (block, trials) in [(0u64, 500usize), (3, 500), (7, 137), (40_000, 64)] {
                let first = block as usize * 500;
                let t0 = model.begin_sequence(&mut trial_rng(11, 2, u64::from(u32::MAX)));
                let (mut ws_a, mut ws_b) = (model.workspace(), model.workspace());
                let (mut a, mut b) = (vec![0.0; trials * n_out], vec![0.0; trials * n_out]);
                model.trial_block(&t0, first, &mut trial_rng(11, 2, block), &mut ws_a, &mut a);
                trials_one_by_one(&model, &t0, first, &mut trial_rng(11, 2, block), &mut ws_b, &mut b);
                assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()), "{phase:?}, {} sources, block {block}", sources.len());
                assert!(a.iter().all(|v| v.is_finite()) && a.iter().any(|v| *v != a[0]));
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 32);
}

#[test]
fn a_run_split_into_chunks_equals_one_process_bit_for_bit() {
    // chunks of 1 and 3 blocks (trial-major values, as the Python/Dask driver takes them) pushed
    // in order give the run of one process, with M not a multiple of the block
    let map = IdentificationMap::new(design()).unwrap();
    let sources = all_sources();
    let by_blocks = [&sources[1], &sources[2]];
    let model = map.model(&by_blocks, Evaluation::Reduced).unwrap();
    let mut s = settings(3);
    s.trials_per_sequence = 2300;
    let whole = run_sequences(&model, &s, 3).unwrap();
    for per_chunk in [1, 3] {
        let mut run = AdaptiveRun::new(model.outputs(), &s, Some(3)).unwrap();
        while let Some(h) = run.next_sequence() {
            let chunks: Vec<_> = Chunk::of_sequence(&s, h, per_chunk).into_iter().map(|c| (c, run_chunk(&model, &s, &c))).collect();
            run.push_chunks(&chunks).unwrap();
        }
        let merged = run.finish();
        assert_eq!(merged.samples, whole.samples, "{per_chunk} blocks per chunk");
        assert_eq!(
            format!("{:?}{:?}{:?}", merged.outputs, merged.covariance, merged.history),
            format!("{:?}{:?}{:?}", whole.outputs, whole.covariance, whole.history)
        );
    }
}
