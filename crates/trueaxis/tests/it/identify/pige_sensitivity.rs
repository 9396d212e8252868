//! Uncertainty of the rotary-axis ballbar methods (Jiang 2014 ch. 4, 5, 6) on the C600U, checked
//! against Monte Carlo and closed forms:
//! - the per-PIGE standard uncertainty from a single run (the scatter of each trace about its
//!   circle, propagated through the axis lines) equals the spread of the PIGEs over 400 simulated
//!   runs with bar noise;
//! - the noise sensitivity of each method (from the geometry of its circle fits) equals the same
//!   spread per um of noise, and ranks the methods as the thesis found: orientation PIGEs are the
//!   weak ones, worst for the short A arc;
//! - setup errors: a spindle-cup error across a full-circle step moves that axis's offset one for
//!   one, along the axis it changes nothing, and a bar calibration error changes no centre.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use trueaxis::identify::pige::{identify_piges, pige_uncertainty, DbbTrace};
use trueaxis::identify::pige_sensitivity::method_sensitivity;
use trueaxis::instruments::ballbar::{method_step, BallbarTest, BarLengths, JiangStep, Method, RotaryPair};
use trueaxis::machine::Machine;

const STEPS: [JiangStep; 4] = [JiangStep::A1, JiangStep::A2, JiangStep::C1, JiangStep::C2];

fn machine() -> Machine {
    Machine::load("../../examples/machines/c600u.toml").unwrap()
}

fn steps(m: &Machine, method: Method) -> Vec<(JiangStep, BallbarTest)> {
    let pair = RotaryPair::of_machine(m).unwrap();
    let bars = BarLengths { normal: 100.0, extended: 150.0 };
    STEPS.iter().map(|&s| (s, method_step(m, pair, method, s, bars, 1.0).unwrap())).collect()
}

/// The traces of one run with independent Gaussian bar noise of `sigma` (mm) and no PIGE.
fn noisy_run(steps: &[(JiangStep, BallbarTest)], sigma: f64, rng: &mut ChaCha8Rng) -> (Vec<DbbTrace>, Vec<DbbTrace>) {
    let normal = Normal::new(0.0, sigma).unwrap();
    let (mut outer, mut inner) = (Vec::new(), Vec::new());
    for (step, test) in steps {
        let dl = (0..test.len()).map(|_| normal.sample(rng)).collect();
        let trace = DbbTrace::of_test(test, dl).unwrap();
        if step.is_outer() {
            outer.push(trace)
        } else {
            inner.push(trace)
        }
    }
    (outer, inner)
}

#[test]
fn single_run_uncertainty_and_noise_sensitivity_equal_the_monte_carlo_spread() {
    let m = machine();
    let pair = RotaryPair::of_machine(&m).unwrap();
    let sigma = 1e-3; // 1 um, the bar's accuracy class
    for method in [Method::ExtendedBar, Method::FourSetup { outer: [-200.0, 250.0], inner: [0.0, 78.0] }] {
        let steps = steps(&m, method);
        let sensitivity = method_sensitivity(&m, pair, &steps).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let runs = 400;
        let mut samples: Vec<Vec<f64>> = Vec::new();
        let mut single = Vec::new();
        for r in 0..runs {
            let (outer, inner) = noisy_run(&steps, sigma, &mut rng);
            samples.push(identify_piges(&m, pair, &outer, &inner).unwrap().values.iter().map(|v| v.1).collect());
            if r < 20 {
                single.push(pige_uncertainty(&m, pair, &outer, &inner).unwrap().unwrap());
            }
        }
        for (p, id) in sensitivity.parameters.iter().enumerate() {
            let mean = samples.iter().map(|s| s[p]).sum::<f64>() / runs as f64;
            let spread = (samples.iter().map(|s| (s[p] - mean).powi(2)).sum::<f64>() / (runs - 1) as f64).sqrt();
            let predicted = sensitivity.noise[p] * sigma;
            // 400 runs: the spread itself is known to about 1 / sqrt(2 x 400) = 3.5 %
            assert!((predicted / spread - 1.0).abs() < 0.12, "{} {id}: predicted {predicted:e}, Monte Carlo {spread:e}", method.name());
            // from a single run: the trace scatter estimates sigma from hundreds of residuals
            for u in &single {
                assert!((u[p] / spread - 1.0).abs() < 0.2, "{} {id}: single run {:e}, Monte Carlo {spread:e}", method.name(), u[p]);
            }
            eprintln!(
                "{} {id}: Monte Carlo {spread:.3e}, noise sensitivity {predicted:.3e}, single run {:.3e}",
                method.name(),
                single[0][p]
            );
        }
    }
}

#[test]
fn orientation_pige_of_the_short_arc_is_the_weakest() {
    // per um of bar noise: positions about 1 um at most (the 90 deg A arc; the full C circle far
    // less), orientations several urad, the tilt of A (90 deg arc, lever D = 111.8 mm) worst
    // (Jiang 2014 §6.2)
    let m = machine();
    let s = method_sensitivity(&m, RotaryPair::of_machine(&m).unwrap(), &steps(&m, Method::ExtendedBar)).unwrap();
    let u = |name: &str| s.noise[s.parameters.iter().position(|p| p.to_string() == name).unwrap()];
    for name in ["EY0A", "EZ0A", "EX0C", "EY0C"] {
        assert!(u(name) < 1.2, "{name}: {} um per um", u(name));
    }
    assert!(u("EX0C") < 0.1 * u("EY0A"), "the full C circle fixes its centre better than the A arc");
    let worst = ["EB0A", "EC0A", "EA0C", "EB0C"].into_iter().max_by(|a, b| u(a).total_cmp(&u(b))).unwrap();
    assert!(worst == "EB0A" || worst == "EC0A", "worst orientation {worst}");
    assert!(u(worst) * 1e3 > 5.0, "{worst}: {} urad per um", u(worst) * 1e3);
}

#[test]
fn setup_errors_act_as_their_closed_forms() {
    let m = machine();
    let pair = RotaryPair::of_machine(&m).unwrap();
    let s = method_sensitivity(&m, pair, &steps(&m, Method::ExtendedBar)).unwrap();
    let index = |name: &str| s.parameters.iter().position(|p| p.to_string() == name).unwrap();
    let effect = |step: JiangStep, source: &str| &s.sources.iter().find(|x| x.step == step && x.name == source).unwrap().effect;
    // the spindle cup off by 1 um along X in the full-circle C1 step: the apparent C axis moves by
    // -1 um in X, which the identification takes as EX0C (and, the line through C1 and C2, a tilt)
    let c1_x = effect(JiangStep::C1, "tool-side ball X");
    assert!((c1_x[index("EX0C")].abs() - 1.0).abs() < 0.05, "{c1_x:?}");
    // ... along the C axis (Z) it changes no C PIGE
    let c1_z = effect(JiangStep::C1, "tool-side ball Z");
    for name in ["EX0C", "EY0C"] {
        assert!(c1_z[index(name)].abs() < 1e-3, "{name}: {}", c1_z[index(name)]);
    }
    for name in ["EA0C", "EB0C"] {
        assert!(c1_z[index(name)].abs() < 1e-6, "{name}: {} rad/mm", c1_z[index(name)]);
    }
    // a bar calibration error is a radius change: no centre moves, in any step
    for source in s.sources.iter().filter(|x| x.name == "bar length") {
        assert!(source.effect.iter().all(|e| e.abs() < 1e-4), "{:?}: {:?}", source.step, source.effect);
    }
    // the combined uncertainty of 1 um setups, 1 um bars and 1 um noise is at least the noise alone
    let combined = s.combined(1e-3, 1e-3, 1e-3);
    for (c, n) in combined.iter().zip(&s.noise) {
        assert!(*c >= n * 1e-3 * (1.0 - 1e-12));
    }
}
