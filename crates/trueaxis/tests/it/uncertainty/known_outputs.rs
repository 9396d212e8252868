//! JCGM 101 behaviour on models whose output distribution is known in closed form (docs/design.md
//! section 6): sums of normal inputs (normal output), sums of rectangular inputs (triangular and
//! trapezoidal outputs, JCGM 101 §9.2), a Student t input, and a chi-square output that tells the
//! shortest interval from the symmetric one. Also: the same result for any number of threads.

use rand_chacha::ChaCha8Rng;
use statrs::distribution::{ContinuousCDF, StudentsT};
use trueaxis::uncertainty::{normal_coverage_factor, run_adaptive, Distribution, McResult, McSettings, TrialModel};

/// `Y = sum_i X_i` (or `sum_i X_i^2` with `squares`), the inputs independent.
struct Sum {
    inputs: Vec<Distribution>,
    squares: bool,
}

impl TrialModel for Sum {
    type Sequence = ();
    type Workspace = ();
    fn outputs(&self) -> usize {
        1
    }
    fn workspace(&self) {}
    fn begin_sequence(&self, _: &mut ChaCha8Rng) {}
    fn trial(&self, _: &(), _: usize, rng: &mut ChaCha8Rng, _: &mut (), out: &mut [f64]) {
        out[0] = self.inputs.iter().map(|d| d.sample(rng)).map(|x| if self.squares { x * x } else { x }).sum();
    }
}

fn adaptive(inputs: Vec<Distribution>, squares: bool, tolerance: f64, seed: u64) -> McResult {
    let mut settings = McSettings::new(0.95, tolerance);
    settings.seed = seed;
    let result = run_adaptive(&Sum { inputs, squares }, &settings, &mut |_, _| {}).unwrap();
    assert!(result.converged, "did not converge in {} sequences", result.sequences);
    result
}

#[test]
fn sum_of_normals_is_normal() {
    // Y = X1 + X2 + X3, u = 0.6, 0.8, 0 -> N(1.5, 1.0^2); 95 % interval 1.5 +- 1.959964
    let inputs = vec![
        Distribution::Normal { mean: 1.0, u: 0.6 },
        Distribution::Normal { mean: 0.5, u: 0.8 },
        Distribution::Normal { mean: 0.0, u: 0.0 },
    ];
    let delta = 0.01;
    let r = adaptive(inputs, false, delta, 7);
    let y = &r.outputs[0];
    let k = normal_coverage_factor(0.95);
    // the adaptive loop stops when twice the standard deviation of each result is below delta
    assert!((y.mean - 1.5).abs() < delta, "mean {}", y.mean);
    assert!((y.std_uncertainty - 1.0).abs() < delta, "u {}", y.std_uncertainty);
    assert!((y.symmetric.low - (1.5 - k)).abs() < 2.0 * delta, "low {}", y.symmetric.low);
    assert!((y.symmetric.high - (1.5 + k)).abs() < 2.0 * delta, "high {}", y.symmetric.high);
    assert!(y.excess_kurtosis.abs() < 0.03 && y.skewness.abs() < 0.03);
    // the history ends with every control variable within the tolerance
    let last = r.history.last().unwrap();
    assert!(last.max.iter().all(|s| 2.0 * s <= delta));
    assert_eq!(r.trials, r.sequences * 10_000);
}

#[test]
fn two_equal_rectangulars_give_a_triangle() {
    // X1, X2 ~ R(-1, 1): Y triangular on [-2, 2]; P(|Y| <= y) = 1 - (1 - y/2)^2 = 0.95
    // -> y = 2 (1 - sqrt 0.05) = 1.552786; u = 2 / sqrt 6 = 0.816497
    let r = Distribution::Rectangular { low: -1.0, high: 1.0 };
    let out = adaptive(vec![r.clone(), r], false, 0.005, 11);
    let y = &out.outputs[0];
    let expected = 2.0 * (1.0 - 0.05f64.sqrt());
    assert!((y.std_uncertainty - 2.0 / 6f64.sqrt()).abs() < 0.005);
    assert!((y.symmetric.high - expected).abs() < 0.01, "high {}", y.symmetric.high);
    assert!((y.symmetric.low + expected).abs() < 0.01, "low {}", y.symmetric.low);
    // symmetric and unimodal: the shortest interval is the symmetric one
    assert!((y.shortest.width() - y.symmetric.width()).abs() < 0.01);
    // excess kurtosis of a triangle: -0.6
    assert!((y.excess_kurtosis + 0.6).abs() < 0.01);
}

#[test]
fn rectangulars_of_different_widths_give_a_trapezoid_narrower_than_the_gum_interval() {
    // JCGM 101 §9.2: X1 ~ R(-1, 1), X2 ~ R(-0.5, 0.5); the 95 % endpoint lies on the sloping side:
    // (a1 + a2 - y)^2 / (4 a1 a2) = 0.05 -> y = 1.5 - sqrt(0.1) = 1.183772.
    // The GUM gives u = sqrt(1.25 / 3) = 0.645497 and +-1.265 (6.9 % too wide).
    let inputs = vec![Distribution::Rectangular { low: -1.0, high: 1.0 }, Distribution::Rectangular { low: -0.5, high: 0.5 }];
    let out = adaptive(inputs, false, 0.005, 13);
    let y = &out.outputs[0];
    let expected = 1.5 - 0.1f64.sqrt();
    let u = (1.25f64 / 3.0).sqrt();
    assert!((y.std_uncertainty - u).abs() < 0.005);
    assert!((y.symmetric.high - expected).abs() < 0.01, "high {}", y.symmetric.high);
    assert!((y.symmetric.low + expected).abs() < 0.01);
    let gum_half_width = normal_coverage_factor(0.95) * u;
    assert!(gum_half_width / expected > 1.06);
}

#[test]
fn student_t_input_reproduces_its_quantiles() {
    // X = 2 + 0.5 t_5: 95 % interval 2 +- 0.5 * 2.570582; u = 0.5 sqrt(5/3)
    let d = Distribution::StudentT { mean: 2.0, scale: 0.5, dof: 5.0 }.validated().unwrap();
    let out = adaptive(vec![d.clone()], false, 0.01, 17);
    let y = &out.outputs[0];
    let t = StudentsT::new(0.0, 1.0, 5.0).unwrap().inverse_cdf(0.975);
    assert!((t - 2.570582).abs() < 1e-5);
    assert!((y.symmetric.high - (2.0 + 0.5 * t)).abs() < 0.02, "high {}", y.symmetric.high);
    assert!((y.symmetric.low - (2.0 - 0.5 * t)).abs() < 0.02);
    assert!((y.std_uncertainty - d.standard_uncertainty()).abs() < 0.02);
    assert!((d.standard_uncertainty() - 0.5 * (5.0f64 / 3.0).sqrt()).abs() < 1e-12);
}

#[test]
fn chi_square_output_separates_shortest_and_symmetric_intervals() {
    // Y = X1^2 + X2^2, Xi ~ N(0, 1): Y is exponential with mean 2.
    // shortest 95 %: [0, -2 ln 0.05] = [0, 5.991465]; symmetric: [-2 ln 0.975, -2 ln 0.025] = [0.050636, 7.377759]
    let n = Distribution::Normal { mean: 0.0, u: 1.0 };
    let out = adaptive(vec![n.clone(), n], true, 0.02, 19);
    let y = &out.outputs[0];
    assert!(y.shortest.low >= 0.0 && y.shortest.low < 0.002, "shortest low {}", y.shortest.low);
    assert!((y.shortest.high - 5.991465).abs() < 0.04, "shortest high {}", y.shortest.high);
    assert!((y.symmetric.low - 0.050636).abs() < 0.02, "symmetric low {}", y.symmetric.low);
    assert!((y.symmetric.high - 7.377759).abs() < 0.04, "symmetric high {}", y.symmetric.high);
    assert!((y.mean - 2.0).abs() < 0.02 && (y.std_uncertainty - 2.0).abs() < 0.02);
}

#[test]
fn arcsine_and_triangular_inputs_have_their_standard_uncertainties() {
    // JCGM 101 Table 1: arc sine on [-a, a] has u = a / sqrt 2; symmetric triangle u = a / sqrt 6
    let arcsine = Distribution::Arcsine { low: -2.0, high: 2.0 };
    let triangle = Distribution::Triangular { low: -3.0, mode: 0.0, high: 3.0 };
    assert!((arcsine.standard_uncertainty() - 2.0 / 2f64.sqrt()).abs() < 1e-12);
    assert!((triangle.standard_uncertainty() - 3.0 / 6f64.sqrt()).abs() < 1e-12);
    for (d, kurtosis) in [(arcsine, -1.5), (triangle, -0.6)] {
        let y = &adaptive(vec![d.clone()], false, 0.02, 23).outputs[0];
        assert!((y.std_uncertainty - d.standard_uncertainty()).abs() < 0.01);
        assert!((y.excess_kurtosis - kurtosis).abs() < 0.02, "{d:?}: {}", y.excess_kurtosis);
    }
    // an asymmetric triangle: mean (a + b + c)/3, u^2 = (a^2 + b^2 + c^2 - ab - ac - bc)/18
    let d = Distribution::Triangular { low: 0.0, mode: 1.0, high: 4.0 };
    let y = &adaptive(vec![d.clone()], false, 0.02, 29).outputs[0];
    assert!((y.mean - 5.0 / 3.0).abs() < 0.01);
    assert!((y.std_uncertainty - (13.0f64 / 18.0).sqrt()).abs() < 0.01);
}

#[test]
fn same_result_for_any_number_of_threads() {
    let inputs = vec![Distribution::Rectangular { low: -1.0, high: 1.0 }, Distribution::Normal { mean: 0.0, u: 0.3 }];
    let mut settings = McSettings::new(0.95, 0.02);
    settings.seed = 31;
    let model = Sum { inputs, squares: false };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| run_adaptive(&model, &settings, &mut |_, _| {}).unwrap())
    };
    let (one, four) = (run(1), run(4));
    assert_eq!(one.sequences, four.sequences);
    assert_eq!(one.samples, four.samples, "bitwise identical trials");
    assert_eq!(one.outputs, four.outputs);
    settings.seed = 32;
    let other = run_adaptive(&model, &settings, &mut |_, _| {}).unwrap();
    assert_ne!(other.outputs[0].mean, one.outputs[0].mean, "another seed gives other trials");
}
