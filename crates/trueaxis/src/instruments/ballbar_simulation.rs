//! Simulated ballbar readings, as `trueaxis ballbar simulate` writes them: the runs of an ISO 230-4
//! circle (CCW, CW or both) or one step of a rotary-axis method of Jiang 2014, each bar reading
//! `dL = |actual| - |nominal|` of the pivot-to-spindle-ball vector on the exact chain
//! ([`BallbarTest::simulate`], mm), written in um with seeded Gaussian noise added.
//!
//! Noise: the reading `i` of run `k` gets `0 + sigma z_i` (um) with `z_i` standard normal drawn from
//! the ChaCha8 generator of the seed on stream `(noise_stream(test) + k) * 2^32`, the stream that
//! `uncertainty::trial_rng(seed, noise_stream(test) + k, 0)` gives the Monte Carlo method; so
//! different seeds, tests and runs draw independent numbers, and a seed gives the same file on
//! every machine.
//!
//! The CSV: a comment line naming the runs, then the axis columns (mm, deg), `angle` (deg, in the
//! plane of the test), `dir` (ccw/cw) and `dL` (um, 4 decimals); positions and angles rounded to
//! 1e-9.

use super::ballbar::{circle_test, sweep_angles, BallbarError, BallbarTest, CircleSpec, JiangStep, Plane, Rotation};
use crate::error_model::ErrorModel;
use crate::machine::Machine;
use crate::{bail, ensure, Error};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// Most samples one simulated run may have (1 deg steps give 360; 0.001 deg 360 000).
pub const MAX_SAMPLES: f64 = 1e6;

/// How the readings are sampled and disturbed; the circle's radius and start angle are checked
/// for every test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulationSettings {
    /// Angle step (deg), in (0, 90].
    pub step_deg: f64,
    /// Standard deviation of the noise added to every reading (um).
    pub noise_um: f64,
    /// Seed of the noise.
    pub seed: u64,
    /// Radius of a circle (mm).
    pub radius_mm: f64,
    /// Start angle of a circle (deg).
    pub start_deg: f64,
}

impl SimulationSettings {
    /// Checks the settings as the command line states them (its options named in the messages).
    pub fn check(&self) -> Result<(), Error> {
        let step = self.step_deg;
        ensure!(step > 0.0 && step <= 90.0, input, "--step must be in (0, 90] deg, got {step}");
        if 360.0 / step > MAX_SAMPLES {
            bail!(
                input,
                "--step {step} deg gives {:.0} samples per turn; at most {MAX_SAMPLES:.0} are simulated (use --step >= {} deg)",
                360.0 / step,
                360.0 / MAX_SAMPLES
            );
        }
        let (noise, radius, start) = (self.noise_um, self.radius_mm, self.start_deg);
        ensure!(noise >= 0.0 && noise.is_finite(), input, "--noise must be a finite standard deviation >= 0 um, got {noise}");
        ensure!(radius > 0.0 && radius.is_finite(), input, "--radius must be a positive number of mm, got {radius}");
        ensure!(start.is_finite(), input, "--start must be a finite angle (deg), got {start}");
        Ok(())
    }
}

/// The runs of a circle in `plane` about `centre` (a pose of every axis, mm and deg), one per
/// rotation, each a full turn from the start angle in steps of the settings.
pub fn circle_runs(
    machine: &Machine,
    plane: Plane,
    centre: &[f64],
    settings: &SimulationSettings,
    rotations: &[Rotation],
) -> Result<Vec<(Rotation, BallbarTest)>, BallbarError> {
    let mut runs = Vec::new();
    for &rotation in rotations {
        let angles = sweep_angles(settings.start_deg, 360.0 * rotation.sign(), settings.step_deg).iter().map(|d| d.to_radians()).collect();
        let spec = CircleSpec { plane, centre: centre.to_vec(), radius: settings.radius_mm, angles, rotation };
        runs.push((rotation, circle_test(machine, &spec)?));
    }
    Ok(runs)
}

/// The first noise stream of a test: a step of Jiang 2014 (`Some`) or a circle (`None`); its runs
/// take the streams that follow.
pub fn noise_stream(step: Option<JiangStep>) -> u64 {
    match step {
        Some(JiangStep::A1) => 0,
        Some(JiangStep::A2) => 2,
        Some(JiangStep::C1) => 4,
        Some(JiangStep::C2) => 6,
        None => 8,
    }
}

/// Gaussian noise (um, standard deviation `sigma`) of `n` readings on noise stream `stream` of
/// `seed` (module documentation).
pub fn noise(seed: u64, stream: u64, n: usize, sigma: f64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream << 32);
    let mean = 0.0;
    (0..n)
        .map(|_| {
            let z: f64 = StandardNormal.sample(&mut rng);
            mean + sigma * z
        })
        .collect()
}

/// The CSV of the simulated `runs` of `machine` with `errors` (module documentation), the noise of
/// run `k` on stream `first_stream + k`. A reading that is not finite is a failed computation.
pub fn readings_csv(
    machine: &Machine,
    errors: &ErrorModel,
    runs: &[(Rotation, BallbarTest)],
    settings: &SimulationSettings,
    first_stream: u64,
) -> Result<String, Error> {
    let names: Vec<String> = runs.iter().map(|(_, test)| test.name.clone()).collect();
    let letters: Vec<String> = machine.axes().iter().map(|x| x.letter.to_string()).collect();
    let mut out = format!("# trueaxis ballbar simulate: {}\n{},angle,dir,dL\n", names.join("; "), letters.join(","));
    for (k, (rotation, test)) in runs.iter().enumerate() {
        let dl = test.simulate(machine, errors);
        let extra = noise(settings.seed, first_stream + k as u64, dl.len(), settings.noise_um);
        for i in 0..test.len() {
            let user: Vec<String> =
                machine.axes().iter().zip(test.pose(i)).map(|(ax, q)| format!("{}", round(ax.position_to_user(*q), 9))).collect();
            let v = dl[i] * 1e3 + extra[i];
            ensure!(v.is_finite(), computation, "the reading at sample {} is not a finite number", i + 1);
            out.push_str(&format!("{},{},{},{:.4}\n", user.join(","), round(test.angles[i].to_degrees(), 9), rotation.name(), v));
        }
    }
    Ok(out)
}

/// `v` rounded to `digits` decimals.
fn round(v: f64, digits: i32) -> f64 {
    let f = 10f64.powi(digits);
    (v * f).round() / f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uncertainty::{trial_rng, Distribution as Law};

    fn settings(noise_um: f64) -> SimulationSettings {
        SimulationSettings { step_deg: 90.0, noise_um, seed: 7, radius_mm: 100.0, start_deg: 0.0 }
    }

    fn vmc3() -> Machine {
        Machine::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/machines/vmc3.toml")).unwrap()
    }

    /// The noise is the Gaussian of the Monte Carlo method (`uncertainty::Distribution::Normal`)
    /// drawn on its trial stream, number for number.
    #[test]
    fn noise_is_the_monte_carlo_gaussian_on_its_stream() {
        for (seed, stream) in [(1, 0), (1, 9), (42, 8)] {
            let mut rng = trial_rng(seed, stream, 0);
            let law = Law::Normal { mean: 0.0, u: 1.5 };
            let expected: Vec<f64> = (0..50).map(|_| law.sample(&mut rng)).collect();
            assert_eq!(noise(seed, stream, 50, 1.5), expected);
        }
        assert!(noise(3, 0, 10, 0.0).iter().all(|v| *v == 0.0 && v.is_sign_positive()));
    }

    /// An error-free machine reads its bar length: dL = 0 at every sample; a full CCW turn in
    /// 90 deg steps visits centre + R (cos t, sin t) at t = 0, 90, 180, 270 deg (R cos 270 deg rounds
    /// to -0, written as the command line always wrote it).
    #[test]
    fn an_error_free_circle_reads_zero_on_the_circle() {
        let m = vmc3();
        let centre = [0.0, 0.0, -200.0];
        let runs = circle_runs(&m, Plane::Xy, &centre, &settings(0.0), &[Rotation::Ccw]).unwrap();
        let csv = readings_csv(&m, &ErrorModel::zero(&m), &runs, &settings(0.0), noise_stream(None)).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert!(lines[0].starts_with("# trueaxis ballbar simulate: "), "{csv}");
        assert_eq!(lines[1], "X,Y,Z,angle,dir,dL");
        assert_eq!(
            &lines[2..],
            ["100,0,-200,0,ccw,0.0000", "0,100,-200,90,ccw,0.0000", "-100,0,-200,180,ccw,0.0000", "-0,-100,-200,270,ccw,0.0000"]
        );
    }

    /// With noise only, the readings are the noise of the circle's stream, rounded to 4 decimals.
    #[test]
    fn noise_alone_is_what_the_readings_show() {
        let m = vmc3();
        let s = settings(2.0);
        let runs = circle_runs(&m, Plane::Xy, &[0.0, 0.0, -200.0], &s, &[Rotation::Cw]).unwrap();
        let csv = readings_csv(&m, &ErrorModel::zero(&m), &runs, &s, noise_stream(None)).unwrap();
        let read: Vec<f64> = csv.lines().skip(2).map(|l| l.rsplit(',').next().unwrap().parse().unwrap()).collect();
        let expected = noise(7, 8, 4, 2.0);
        for (r, e) in read.iter().zip(&expected) {
            assert!((r - e).abs() <= 5e-5, "{r} {e}");
        }
    }

    #[test]
    fn settings_are_checked_with_the_options_named() {
        let bad = |f: fn(&mut SimulationSettings)| {
            let mut s = settings(0.0);
            f(&mut s);
            s.check().unwrap_err().to_string()
        };
        assert_eq!(bad(|s| s.step_deg = 0.0), "--step must be in (0, 90] deg, got 0");
        assert!(bad(|s| s.step_deg = 1e-4).starts_with("--step 0.0001 deg gives 3600000 samples per turn"));
        assert_eq!(bad(|s| s.noise_um = -1.0), "--noise must be a finite standard deviation >= 0 um, got -1");
        assert_eq!(bad(|s| s.radius_mm = 0.0), "--radius must be a positive number of mm, got 0");
        assert_eq!(bad(|s| s.start_deg = f64::NAN), "--start must be a finite angle (deg), got NaN");
        assert!(settings(0.0).check().is_ok());
    }
}
