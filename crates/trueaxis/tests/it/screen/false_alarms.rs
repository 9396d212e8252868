//! False-alarm rates of the checks on 1,000 simulated clean data sets each (fixed seeds): every
//! check must flag under 1 % of them. The data sets are shaped like the shipped examples: an
//! ISO 230-2 test (11 targets over 500 mm, 5 bidirectional runs, pitch error, screw wave,
//! backlash, drift per run, noise), ballbar circles (720 samples of a first-harmonic ellipse with
//! noise), 3D-ball trajectories (807 smooth readings with noise at 4 decimals) and thermal warm-up
//! curves (two time constants, sampled every 2 min, noise at 3 decimals).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use trueaxis::evaluate::iso230_2::{Direction, PositioningData, Reading};
use trueaxis::evaluate::positioning_screening::positioning;
use trueaxis::screen::series::{neighbour_outliers, steps, stuck_runs};

const SETS: usize = 1000;
/// At most 1 % of the clean data sets may give a finding.
const ALLOWED: usize = SETS / 100;

fn positioning_set(rng: &mut ChaCha8Rng) -> PositioningData {
    let noise = Normal::new(0.0, rng.gen_range(0.1..0.5)).unwrap();
    let (scale, bow, wave, backlash, drift) =
        (rng.gen_range(-0.02..0.02), rng.gen_range(-3.0..3.0), rng.gen_range(0.0..1.0), rng.gen_range(0.0..4.0), rng.gen_range(0.0..0.3));
    let mut readings = Vec::new();
    let mut line = 2;
    for run in 1..=5i64 {
        for direction in [Direction::Plus, Direction::Minus] {
            for k in 0..11 {
                let target = 50.0 * k as f64 + rng.gen_range(-3.0..3.0f64).round();
                let target = if k == 0 { 0.0 } else { target };
                let x = target / 500.0;
                let sign = if direction == Direction::Plus { 0.5 } else { -0.5 };
                let dev = scale * target
                    + bow * 4.0 * x * (1.0 - x)
                    + wave * (target / 125.0 * std::f64::consts::TAU).sin()
                    + sign * backlash
                    + drift * run as f64 * x
                    + noise.sample(rng);
                line += 1;
                readings.push(Reading { target, dev: (dev * 1000.0).round() / 1000.0, direction, run, line });
            }
        }
    }
    // the same targets in every run
    for i in 0..readings.len() {
        readings[i].target = readings[i % 11].target;
    }
    PositioningData { origin: "sim.csv".into(), readings, rotary: false, metadata: Default::default() }
}

#[test]
fn positioning_checks_rarely_flag_clean_tests() {
    let mut rng = ChaCha8Rng::seed_from_u64(2302);
    let flagged = (0..SETS).filter(|_| !positioning(&positioning_set(&mut rng), None).is_empty()).count();
    eprintln!("false alarms: ISO 230-2 (runs, readings, targets) {flagged} of {SETS}");
    assert!(flagged <= ALLOWED, "{flagged} of {SETS} clean positioning tests flagged");
}

#[test]
fn spikes_stuck_readings_and_steps_rarely_flag_clean_series() {
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let (mut spikes, mut stuck, mut jumps) = (0, 0, 0);
    for _ in 0..SETS {
        // a ballbar circle: out-of-roundness of a few um, noise 0.05 ... 0.3 um, 4 decimals
        let noise = Normal::new(0.0, rng.gen_range(0.05..0.3)).unwrap();
        let (a, phase) = (rng.gen_range(1.0..8.0), rng.gen_range(0.0..6.3));
        let circle: Vec<f64> = (0..720)
            .map(|i| {
                let t = (i as f64 + 0.5).to_radians();
                ((a * (2.0 * t + phase).sin() + 0.5 * a * (3.0 * t).cos() + noise.sample(&mut rng)) * 1e4).round() / 1e4
            })
            .collect();
        spikes += usize::from(
            !neighbour_outliers(
                &circle,
                trueaxis::evaluate::ballbar_screening::SPIKE_LIMIT,
                trueaxis::evaluate::ballbar_screening::SPIKE_FLOOR_UM,
            )
            .is_empty(),
        );
        // a 3D-ball channel along a trajectory: smooth tens of um, noise 0.2 ... 0.5 um, 4 decimals
        let noise = Normal::new(0.0, rng.gen_range(0.2..0.5)).unwrap();
        let reading: Vec<f64> =
            (0..807).map(|i| ((a * 5.0 * (i as f64 / 60.0 + phase).sin() + noise.sample(&mut rng)) * 1e4).round() / 1e4).collect();
        stuck += usize::from(!stuck_runs(&reading).is_empty());
        // a thermal warm-up: two time constants, noise 0.005 ... 0.02 degC, 3 decimals
        let noise = Normal::new(0.0, rng.gen_range(0.005..0.02)).unwrap();
        let (tau1, tau2, rise) = (rng.gen_range(300.0..1200.0), rng.gen_range(3000.0..12000.0), rng.gen_range(2.0..15.0));
        let t: Vec<f64> = (0..241).map(|i| 120.0 * i as f64).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|t| {
                ((20.0 + rise * (0.6 * (1.0 - (-t / tau1).exp()) + 0.4 * (1.0 - (-t / tau2).exp())) + noise.sample(&mut rng)) * 1e3).round()
                    / 1e3
            })
            .collect();
        jumps += usize::from(
            !steps(&t, &x, trueaxis::thermal::thermal_screening::STEP_LIMIT, trueaxis::thermal::thermal_screening::STEP_FLOOR_DEGC)
                .is_empty(),
        );
    }
    eprintln!("false alarms: ballbar spikes {spikes}, stuck 3D-ball channels {stuck}, thermal steps {jumps} of {SETS}");
    assert!(spikes <= ALLOWED, "{spikes} of {SETS} clean circles flagged with a spike");
    assert!(stuck <= ALLOWED, "{stuck} of {SETS} clean 3D-ball channels flagged as stuck");
    assert!(jumps <= ALLOWED, "{jumps} of {SETS} clean warm-ups flagged with a step");
}

/// The outlier check of `trueaxis fit` (`identify::direct_screening`) on the readings of the same simulated
/// ISO 230-2 tests, written as the test's CSV: a data set counts as flagged when the fit of both
/// directions or that of the + direction gives a finding.
#[test]
fn the_direct_fit_rarely_flags_clean_tests() {
    let mut rng = ChaCha8Rng::seed_from_u64(2303);
    let flagged = (0..SETS)
        .filter(|_| {
            let data = positioning_set(&mut rng);
            let mut text = String::from("target,dev,dir,run\n");
            for r in &data.readings {
                text += &format!("{},{},{},{}\n", r.target, r.dev, if r.direction == Direction::Plus { "+" } else { "-" }, r.run);
            }
            [None, Some('+')].iter().any(|&d| !crate::identify::direct_screening::direct_fit_of(&text, d).findings.is_empty())
        })
        .count();
    eprintln!("false alarms: fit (studentized residual, Cook's distance) {flagged} of {SETS}");
    assert!(flagged <= ALLOWED, "{flagged} of {SETS} clean direct fits flagged");
}
