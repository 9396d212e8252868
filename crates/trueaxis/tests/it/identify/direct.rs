//! Round trips of direct characterisation (Soons 1993 ch. 3): simulate an error with known
//! parametric form plus noise, fit it, recover it.

use trueaxis::error_model::{integrate, set_error_function, Basis, BasisSpec, ErrorFunction, ErrorModel, PeriodicSpec};
use trueaxis::identify::{
    alias_wavelength, dominant_period, fit_error_function, refine_wavelength, remove_cycle_drift, residual_period, sampling_step,
    FitOptions,
};
use trueaxis::machine::{Machine, ParameterId};

/// Deterministic standard-normal noise (Box-Muller on a fixed LCG), so the tests are reproducible.
fn noise(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut uniform = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..n).map(|_| sigma * (-2.0 * uniform().ln()).sqrt() * (2.0 * std::f64::consts::PI * uniform()).cos()).collect()
}

const SCALE_PITCH: f64 = 0.635025; // mm, Soons 1993 §3.2.4

fn periodic_spec() -> PeriodicSpec {
    PeriodicSpec { wavelength: SCALE_PITCH, phase: 0.0, degree: 2, knots: vec![1.0 / 3.0, 2.0 / 3.0], continuity: 1 }
}

/// Trend: a C1 quadratic piecewise polynomial with knots at 10 and 30 mm; the scale error: a C1
/// periodic term of the scale pitch (Soons 1993 §3.2.4: quadratic pieces, C1).
fn truth() -> (Basis, Vec<f64>) {
    let spec = BasisSpec {
        family: "piecewise".into(),
        degree: 2,
        knots: vec![10.0, 30.0],
        continuity: vec![1],
        constant: false,
        constraint: "none".into(),
        domain: [0.0, 50.0],
        periodic: vec![periodic_spec()],
    };
    let basis = Basis::new(spec).unwrap();
    // x, x^2, (x-10)_+^2, (x-30)_+^2, then the periodic functions
    let mut c = vec![0.08, -0.004, 0.010, -0.012];
    let periodic_count = basis.len() - 4;
    c.extend((0..periodic_count).map(|k| [8.0, -12.0, 9.5][k % 3]));
    (basis, c)
}

/// The truth over 50 mm sampled every 0.01 mm (Soons 1993 §3.2.4) with 0.05 um of noise (`seed`):
/// the positions and the readings.
fn sampled(basis: &Basis, coefficients: &[f64], seed: u64) -> (Vec<f64>, Vec<f64>) {
    let positions: Vec<f64> = (0..=5000).map(|i| 0.01 * i as f64 + 1e-4).collect();
    let e = noise(positions.len(), 0.05, seed);
    let values: Vec<f64> = positions.iter().zip(&e).map(|(x, n)| basis.eval(coefficients, *x) + n).collect();
    (positions, values)
}

#[test]
fn piecewise_trend_and_scale_pitch_error_are_recovered_by_stepwise_fitting() {
    let (basis, coefficients) = truth();
    let (positions, values) = sampled(&basis, &coefficients, 7);
    // a generous candidate model: knots every 5 mm (only 10 and 30 are real)
    let mut spec = basis.spec.clone();
    spec.knots = (1..10).map(|k| 5.0 * k as f64).collect();
    let fitted =
        fit_error_function(&positions, &values, &FitOptions { spec, stepwise_level: Some(0.9999), prediction_level: 0.95 }).unwrap();
    // residual RMS matches the noise (5000 dof: within 5 %)
    assert!((fitted.rms - 0.05).abs() < 0.0025, "rms {}", fitted.rms);
    // the function is recovered everywhere within 0.02 um (about 4 standard deviations of the fit)
    for i in 0..500 {
        let x = 0.1 * i as f64 + 0.003;
        let got = fitted.function.evaluate(x);
        let want = basis.eval(&coefficients, x);
        assert!((got - want).abs() < 0.02, "at {x}: {got} vs {want}");
    }
    // stepwise removed most of the knots that carry nothing
    assert!(fitted.removed.len() >= 4, "removed {:?}", fitted.removed);
    // the 95 % prediction half-width is about 1.96 sigma
    assert!((fitted.max_prediction_half_width / 0.05 - 1.96).abs() < 0.1, "{}", fitted.max_prediction_half_width);
}

#[test]
fn wavelength_is_refined_from_a_wrong_start() {
    let (basis, coefficients) = truth();
    let (positions, values) = sampled(&basis, &coefficients, 11);
    let mut spec = basis.spec.clone();
    spec.periodic[0].wavelength = SCALE_PITCH * 1.0008; // 0.08 % off: 6 % of a period at 50 mm
    let refined = refine_wavelength(&positions, &values, &spec, 0, 0.002).unwrap();
    let w = refined.periodic[0].wavelength;
    // accumulated phase error over the 50 mm of data (78.7 periods) below 1 % of a period
    let periods = 50.0 / SCALE_PITCH;
    assert!(((w - SCALE_PITCH) / SCALE_PITCH).abs() * periods < 0.01, "refined wavelength {w}");
    // and the search found the least-squares optimum: no worse than the true wavelength
    let rss = |spec: BasisSpec| {
        fit_error_function(&positions, &values, &FitOptions { spec, stepwise_level: None, prediction_level: 0.95 }).unwrap().fit.rss
    };
    let mut at_truth = spec.clone();
    at_truth.periodic[0].wavelength = SCALE_PITCH;
    assert!(rss(refined) <= rss(at_truth) * (1.0 + 1e-12));
}

#[test]
fn aliasing_at_10_mm_sampling_is_detected() {
    let (basis, coefficients) = truth();
    // the seed's apparent 40 mm period: 0.635025 mm seen every 10 mm
    let alias = alias_wavelength(SCALE_PITCH, 10.0).unwrap();
    assert!((alias - 39.59).abs() < 0.01, "alias {alias}");
    assert!(alias_wavelength(SCALE_PITCH, 0.01).is_none());

    // a periodic term cannot be fitted from 10 mm samples: a clear error names the alias
    let positions: Vec<f64> = (0..=50).map(|i| 10.0 * i as f64 + 0.37).collect();
    let values: Vec<f64> = positions.iter().map(|x| basis.eval(&coefficients, (*x).rem_euclid(50.0))).collect();
    let mut spec = basis.spec.clone();
    spec.domain = [0.0, 510.0];
    let err = fit_error_function(&positions, &values, &FitOptions { spec: spec.clone(), stepwise_level: None, prediction_level: 0.95 })
        .unwrap_err()
        .to_string();
    assert!(err.contains("cannot be resolved") && err.contains("39.59"), "{err}");

    // without it, the residuals of a smooth fit carry the alias period
    let periodic_only: Vec<f64> = positions
        .iter()
        .map(|x| {
            let mut b = basis.spec.clone();
            b.family = "none".into();
            b.knots.clear();
            let pb = Basis::new(b).unwrap();
            pb.eval(&coefficients[4..], *x)
        })
        .collect();
    let (period, amplitude) = dominant_period(&positions, &periodic_only, 20.0, 200.0).unwrap();
    assert!((period - alias).abs() / alias < 0.03, "dominant residual period {period} vs alias {alias}");
    assert!(amplitude > 0.05);
}

#[test]
fn straightness_constrained_fit_has_no_trend_and_matches_the_truth() {
    let spec = BasisSpec {
        family: "piecewise".into(),
        degree: 2,
        knots: vec![-150.0, 0.0, 150.0],
        continuity: vec![1],
        constant: false,
        constraint: "straightness".into(),
        domain: [-300.0, 300.0],
        periodic: vec![],
    };
    let basis = Basis::new(spec.clone()).unwrap();
    let truth: Vec<f64> = (0..basis.len()).map(|k| [2e-5, -3e-5, 4e-5, -1e-5][k % 4]).collect();
    let positions: Vec<f64> = (0..=60).map(|i| -300.0 + 10.0 * i as f64).collect();
    let e = noise(positions.len(), 0.1, 3);
    let values: Vec<f64> = positions.iter().zip(&e).map(|(x, n)| basis.eval(&truth, *x) + n).collect();
    let fitted = fit_error_function(&positions, &values, &FitOptions { spec, stepwise_level: None, prediction_level: 0.95 }).unwrap();
    // fitted coefficients within 3 standard uncertainties
    for ((c, u), t) in fitted.coefficients.iter().zip(&fitted.std_uncertainties).zip(&truth) {
        assert!((c - t).abs() < 3.0 * u, "{c} +- {u} vs {t}");
    }
    // no linear trend over the range (Soons 1993 eqs. 3.6-3.7): integral f = integral f x = 0
    let knots = [-150.0, 0.0, 150.0];
    let m0 = integrate(|x| fitted.function.evaluate(x), -300.0, 300.0, &knots, 8);
    let m1 = integrate(|x| fitted.function.evaluate(x) * x, -300.0, 300.0, &knots, 8);
    let peak = (0..=600).map(|i| fitted.function.evaluate(-300.0 + i as f64).abs()).fold(0.0, f64::max);
    assert!(peak > 0.5, "a visible straightness error ({peak} um)");
    assert!(m0.abs() < 1e-9 * peak * 600.0 && m1.abs() < 1e-9 * peak * 600.0 * 300.0, "{m0} {m1}");
}

#[test]
fn drift_removal_then_fit_recovers_the_error() {
    // five back-and-forth runs over 0..500 mm every 25 mm, drift 0.4 um per run, e(x) = 0.02 x - 2e-5 x^2
    let e = |x: f64| 0.02 * x - 2e-5 * x * x;
    let (mut pos, mut t, mut cyc, mut val) = (vec![], vec![], vec![], vec![]);
    let mut time = 0.0;
    for run in 0..5 {
        let forward: Vec<f64> = (0..=20).map(|i| 25.0 * i as f64).collect();
        for x in forward.iter().chain(forward.iter().rev()) {
            pos.push(*x);
            t.push(time);
            cyc.push(run);
            val.push(e(*x) + 0.4 / 420.0 * time);
            time += 10.0;
        }
    }
    let (clean, drifts) = remove_cycle_drift(&cyc, &t, &val, None).unwrap();
    for d in &drifts {
        assert!((d.rate - 0.4 / 420.0).abs() < 1e-12);
    }
    let spec = BasisSpec {
        family: "piecewise".into(),
        degree: 2,
        knots: vec![],
        continuity: vec![1],
        constant: true,
        constraint: "none".into(),
        domain: [0.0, 500.0],
        periodic: vec![],
    };
    let fitted = fit_error_function(&pos, &clean, &FitOptions { spec, stepwise_level: None, prediction_level: 0.95 }).unwrap();
    // the shape is recovered exactly (the drift between runs is removed too: no residual left)
    let c = &fitted.coefficients;
    assert!((c[1] - 0.02).abs() < 1e-9 && (c[2] + 2e-5).abs() < 1e-12, "{c:?}");
    assert!(fitted.rms < 1e-9, "{}", fitted.rms);
}

#[test]
fn a_fitted_function_round_trips_through_the_error_values_file() {
    let machine = Machine::from_toml_str(include_str!("../../../../../examples/machines/vmc3.toml"), "vmc3").unwrap();
    let (basis, coefficients) = truth();
    let mut spec = basis.spec.clone();
    spec.domain = [-400.0, 400.0];
    spec.knots = vec![-100.0, 200.0];
    let b = Basis::new(spec).unwrap();
    let f = ErrorFunction::basis(b.clone(), coefficients[..b.len()].to_vec()).unwrap();
    let original = "# my machine's errors\n[constant]\nEC0X = 12.0  # squareness\n[polynomial.EXX]\ncoefficients = [0.0, 0.01]\n";
    let exx = ParameterId::parse("EXX").unwrap();
    let text = set_error_function(original, &exx, None, &f).unwrap();
    assert!(text.contains("# my machine's errors") && text.contains("EC0X = 12.0  # squareness"), "comments kept:\n{text}");
    assert!(!text.contains("[polynomial.EXX]"), "the old EXX is replaced:\n{text}");
    let model = ErrorModel::from_toml_str(&text, "updated.toml", &machine).unwrap();
    let (_, back) = model.entries().find(|(id, _)| **id == exx).unwrap();
    for x in [-400.0, -123.4, 0.0, 0.3, 250.0, 399.0] {
        assert!((back.evaluate(x) - f.evaluate(x)).abs() < 1e-12, "at {x}");
    }
    // and the constant is untouched
    let ec0x = ParameterId::parse("EC0X").unwrap();
    assert_eq!(model.entries().find(|(id, _)| **id == ec0x).unwrap().1, &ErrorFunction::Constant(12.0));
}

#[test]
fn residual_periods_are_searched_from_twice_the_sampling_step() {
    // a rotary axis every 5 deg over a turn, 3 runs: the shortest period that can be seen is 10 deg
    // (the old bound, span / readings = 360 / 219 deg, reported 3.97 deg)
    let positions: Vec<f64> = (0..3).flat_map(|_| (0..=72).map(|i| 5.0 * i as f64)).collect();
    assert_eq!(sampling_step(&positions), Some(5.0));
    let e = noise(positions.len(), 0.5, 17);
    let r = residual_period(&positions, &e, 0.5).unwrap();
    assert_eq!(r.limit, 10.0);
    assert!(r.period >= 10.0 && r.period <= 360.0, "period {}", r.period);
    // white noise: not significant (1 % false alarms)
    assert!(!r.significant, "amplitude {}", r.amplitude);
    // a 24 deg wave of 1 urad is found and significant; its aliases lie below 10 deg
    let wave: Vec<f64> = positions.iter().zip(&e).map(|(x, n)| (2.0 * std::f64::consts::PI * x / 24.0).sin() + n).collect();
    let r = residual_period(&positions, &wave, 0.5).unwrap();
    assert!((r.period - 24.0).abs() < 0.1 && r.significant, "{r:?}");
    assert!((r.amplitude - 1.0).abs() < 0.15, "{r:?}");
    let aliases = r.aliases(3);
    assert!((aliases[0] - 1.0 / (0.2 - 1.0 / 24.0)).abs() < 0.01 && aliases.iter().all(|a| *a < 10.0), "{aliases:?}");
    // irregular sampling has no exact alias family
    let irregular: Vec<f64> = (0..100).map(|i| 3.6 * i as f64 + 1.7 * ((i * 7919) % 13) as f64 / 13.0).collect();
    let r = residual_period(&irregular, &noise(100, 1.0, 3), 1.0).unwrap();
    assert!(r.uniform_step.is_none() && r.aliases(3).is_empty());
}

#[test]
fn a_screw_wave_sampled_every_10_mm_is_reported_with_the_true_pitch_in_its_alias_family() {
    // Soons 1993 §3.2.4: the 0.635025 mm scale error sampled every 10 mm shows at 39.59 mm; the report
    // marks it significant and gives the family 1/|k/10 +- 1/39.59|, which holds the true pitch at k = 16
    let positions: Vec<f64> = (0..=50).map(|i| 10.0 * i as f64 + 0.37).collect();
    let values: Vec<f64> = positions.iter().map(|x| 0.8 * (2.0 * std::f64::consts::PI * x / SCALE_PITCH).sin()).collect();
    let r = residual_period(&positions, &values, 0.57).unwrap();
    let alias = alias_wavelength(SCALE_PITCH, 10.0).unwrap();
    assert!((r.period - alias).abs() < 0.01 * alias && r.significant, "{r:?}");
    assert_eq!(r.uniform_step, Some(10.0));
    let family = r.aliases(16);
    assert!(family.iter().any(|w| (w - SCALE_PITCH).abs() < 0.01 * SCALE_PITCH), "{family:?}");
}
