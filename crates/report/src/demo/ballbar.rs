//! The demo's ballbar test: an ISO 230-4 circle of 150 mm radius in the XY plane at the middle of
//! the travel, CCW then CW, simulated on the exact chain with the true errors and 0.3 um of noise,
//! written as a circle CSV (`angle,dL,dir`) that the report evaluates like any measured circle.

use super::{DemoError, Output};
use crate::calibration::CircleInput;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use trueaxis::error_model::ErrorModel;
use trueaxis::geometry::Vec3;
use trueaxis::instruments::ballbar::{circle_test, CircleSpec, Plane, Rotation};
use trueaxis::machine::Machine;

pub const RADIUS_MM: f64 = 150.0;
pub const NOISE_UM: f64 = 0.3;
/// The feed the file states (the simulation is quasi-static: no servo lag at any feed).
pub const FEED_MM_PER_MIN: f64 = 1000.0;
/// The circle file, relative to the output folder.
pub const FILE: &str = "ballbar/xy_circle.csv";
const SEED: u64 = 230;

/// Simulates the two runs and writes them; the circle as the report reads it.
pub fn simulate(machine: &Machine, truth: &ErrorModel, out: &mut Output) -> Result<CircleInput, DemoError> {
    let mid = |letter: char| machine.axis_index(letter).and_then(|k| machine.axes()[k].range).map_or(0.0, |[lo, hi]| 0.5 * (lo + hi));
    let circle = CircleInput { path: out.path(FILE), plane: Plane::Xy, radius: RADIUS_MM, centre: Vec3::new(mid('X'), mid('Y'), mid('Z')) };
    let centre = circle.centre_pose(machine);
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    let noise = Normal::new(0.0, NOISE_UM * 1e-3).expect("a positive standard deviation");
    let mut csv = format!(
        "# ISO 230-4 circle simulated by `trueaxis demo`: XY plane, R {RADIUS_MM} mm, centre ({}, {}, {}) mm\n# Feed rate: {FEED_MM_PER_MIN} mm/min\nangle,dL,dir\n",
        circle.centre.x, circle.centre.y, circle.centre.z
    );
    for rotation in [Rotation::Ccw, Rotation::Cw] {
        let sign = rotation.sign();
        let angles: Vec<f64> = (0..=360).map(|k| sign * (k as f64).to_radians()).collect();
        let spec = CircleSpec { plane: Plane::Xy, centre: centre.clone(), radius: RADIUS_MM, angles, rotation };
        let test = circle_test(machine, &spec)?;
        for (t, d) in test.angles.iter().zip(test.simulate(machine, truth)) {
            let dl = d + noise.sample(&mut rng);
            csv.push_str(&format!("{:.3},{:.4},{}\n", t.to_degrees(), dl * 1e3, rotation.name()));
        }
    }
    out.write(FILE, csv.as_bytes())?;
    Ok(circle)
}
