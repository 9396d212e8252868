//! An ISO 230-4 ballbar circle of 150 mm radius in the XY plane, CCW then CW, one reading per
//! degree, simulated on the exact chain with the true errors and 0.3 um of Gaussian noise (seeded
//! ChaCha8), as a circle file (`angle,dL,dir`: deg, um, run) that `trueaxis ballbar iso230-4` and
//! the report evaluate like any measured circle.

use crate::error_model::ErrorModel;
use crate::geometry::Vec3;
use crate::instruments::ballbar::{circle_test, BallbarError, CircleSpec, Plane, Rotation};
use crate::machine::Machine;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

pub const RADIUS_MM: f64 = 150.0;
pub const NOISE_UM: f64 = 0.3;
/// The feed the file states (the simulation is quasi-static: no servo lag at any feed).
pub const FEED_MM_PER_MIN: f64 = 1000.0;
const SEED: u64 = 230;

/// The centre of the circle: the middle of the travel of X, Y and Z (mm; 0 for an axis without a
/// range or absent).
pub fn centre(machine: &Machine) -> Vec3 {
    let mid = |letter: char| machine.axis_index(letter).and_then(|k| machine.axes()[k].range).map_or(0.0, |[lo, hi]| 0.5 * (lo + hi));
    Vec3::new(mid('X'), mid('Y'), mid('Z'))
}

/// The circle file of the two runs around `centre` (mm), whose pose in the machine's axes is
/// `centre_pose`.
pub fn simulate(machine: &Machine, truth: &ErrorModel, centre: Vec3, centre_pose: Vec<f64>) -> Result<String, BallbarError> {
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    let noise = Normal::new(0.0, NOISE_UM * 1e-3).expect("a positive standard deviation");
    let mut csv = format!(
        "# ISO 230-4 circle simulated by `trueaxis demo`: XY plane, R {RADIUS_MM} mm, centre ({}, {}, {}) mm\n# Feed rate: {FEED_MM_PER_MIN} mm/min\nangle,dL,dir\n",
        centre.x, centre.y, centre.z
    );
    for rotation in [Rotation::Ccw, Rotation::Cw] {
        let sign = rotation.sign();
        let angles: Vec<f64> = (0..=360).map(|k| sign * (k as f64).to_radians()).collect();
        let spec = CircleSpec { plane: Plane::Xy, centre: centre_pose.clone(), radius: RADIUS_MM, angles, rotation };
        let test = circle_test(machine, &spec)?;
        for (t, d) in test.angles.iter().zip(test.simulate(machine, truth)) {
            let dl = d + noise.sample(&mut rng);
            csv.push_str(&format!("{:.3},{:.4},{}\n", t.to_degrees(), dl * 1e3, rotation.name()));
        }
    }
    Ok(csv)
}
