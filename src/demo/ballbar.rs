//! The demo's ballbar test: an ISO 230-4 circle of 150 mm radius in the XY plane at the middle of
//! the travel, CCW then CW, simulated on the exact chain with the true errors and 0.3 um of noise;
//! evaluated (G, F, H) with the diagnostics fitted on the machine's Jacobian; polar plot.

use super::{DemoError, Output};
use crate::errors::ErrorModel;
use crate::evaluate::ballbar_diagnostics::{CircularRun, DiagnosticOptions};
use crate::evaluate::iso230_4::{evaluate, Iso2304Result};
use crate::instruments::ballbar::{circle_test, CircleSpec, Plane, Rotation};
use crate::machine::Machine;
use crate::report::circular_runs_svg;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

pub const RADIUS_MM: f64 = 150.0;
pub const NOISE_UM: f64 = 0.3;
const SEED: u64 = 230;

pub struct Circles {
    pub result: Iso2304Result,
    pub centre: Vec<f64>,
    pub svg: String,
    pub lines: Vec<String>,
}

pub fn run(machine: &Machine, truth: &ErrorModel, out: &mut Output) -> Result<Circles, DemoError> {
    let centre: Vec<f64> =
        machine.axes().iter().map(|a| a.range.map_or(0.0, |[lo, hi]| if a.letter == 'A' { 0.0 } else { 0.5 * (lo + hi) })).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    let noise = Normal::new(0.0, NOISE_UM * 1e-3).expect("a positive standard deviation");
    let mut runs = Vec::new();
    let mut csv = String::from("# ISO 230-4 circle simulated by `trueaxis demo`: XY plane, R 150 mm, pivot at the centre\nangle,dL,dir\n");
    for rotation in [Rotation::Ccw, Rotation::Cw] {
        let sign = rotation.sign();
        let angles: Vec<f64> = (0..=360).map(|k| sign * (k as f64).to_radians()).collect();
        let spec = CircleSpec { plane: Plane::Xy, centre: centre.clone(), radius: RADIUS_MM, angles, rotation };
        let test = circle_test(machine, &spec)?;
        let dl: Vec<f64> = test.simulate(machine, truth).into_iter().map(|v| v + noise.sample(&mut rng)).collect();
        for (t, d) in test.angles.iter().zip(&dl) {
            csv.push_str(&format!("{:.3},{:.4},{}\n", t.to_degrees(), d * 1e3, rotation.name()));
        }
        runs.push(CircularRun { rotation, test, dl });
    }
    let (ix, iy) = (machine.axis_index('X').unwrap_or(0), machine.axis_index('Y').unwrap_or(1));
    let options = DiagnosticOptions {
        plane: Plane::Xy,
        radius: RADIUS_MM,
        centre: [centre[ix], centre[iy]],
        pitch: None,
        spike_width: 5f64.to_radians(),
        feed: None,
    };
    let result = evaluate(machine, &runs, &options)?;
    let lines = result.summary_lines();
    let svg = circular_runs_svg("ISO 230-4 circular test, XY plane, R 150 mm (simulated)", ("+X", "+Y"), &runs, None, &lines)?;
    out.write("ballbar/xy_circle.csv", csv.as_bytes())?;
    out.write("ballbar/xy_circle.svg", svg.as_bytes())?;
    Ok(Circles { result, centre, svg, lines })
}
