//! How a rotary-axis ballbar method reacts to its setup and to bar noise, before it is run (seed
//! 001 §4.1.3 and §6.2: the placement of the pivot and of the spindle cup, the bar calibration, and
//! the short lever of the orientation PIGEs make the methods of chapters 4, 5 and 6 disagree).
//!
//! For each step of the method and each setup error (a ball off its nominal place along X, Y or Z
//! of M, a bar length off its calibration), the four steps are simulated on the exact chain with
//! that error alone and no PIGE, and identified as if the setup were nominal: the PIGEs found are
//! the method's sensitivity to that setup error. The noise sensitivity is the standard
//! uncertainty of each PIGE for bar readings with a standard deviation of 1 um, from the geometry
//! of the circle fits (the propagation of [`super::pige::pige_uncertainty`]).
//!
//! Units: sensitivities in mm (or rad) of PIGE per mm of setup error, i.e. um/um and
//! 1e-3 urad/um; noise sensitivities in mm (or rad) per mm of bar noise.

use super::pige::{centre_covariance_per_unit_variance, identify_piges, propagate_centre_covariances, DbbTrace};
use super::IdentifyError;
use crate::instruments::ballbar::{BallbarTest, JiangStep, RotaryPair};
use crate::machine::{Machine, ParameterId};

/// One setup error of one step.
#[derive(Clone, Debug, PartialEq)]
pub struct SetupSource {
    pub step: JiangStep,
    /// What is off: `workpiece-side ball X` (the pivot of a table test), `tool-side ball Z` (the
    /// spindle cup), `bar length`.
    pub name: String,
    /// Change of each PIGE (mm or rad; the order of `MethodSensitivity::parameters`) per mm.
    pub effect: Vec<f64>,
}

/// The sensitivities of a method (four steps) to its setup and to bar noise.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodSensitivity {
    pub parameters: Vec<ParameterId>,
    pub sources: Vec<SetupSource>,
    /// Standard uncertainty of each PIGE (mm or rad) per mm of bar-reading standard deviation.
    pub noise: Vec<f64>,
}

impl MethodSensitivity {
    /// Standard uncertainty of each PIGE (mm or rad) from independent setup errors of standard
    /// deviation `setup_u` (mm) on every ball of every step, bar calibration errors of `bar_u`
    /// (mm) and bar noise of `noise_u` (mm): the root-sum-square of the sensitivities times their
    /// uncertainties (GUM, independent inputs).
    pub fn combined(&self, setup_u: f64, bar_u: f64, noise_u: f64) -> Vec<f64> {
        (0..self.parameters.len())
            .map(|p| {
                let setup: f64 =
                    self.sources.iter().map(|s| (s.effect[p] * if s.name == BAR_LENGTH { bar_u } else { setup_u }).powi(2)).sum();
                (setup + (self.noise[p] * noise_u).powi(2)).sqrt()
            })
            .collect()
    }
}

const BAR_LENGTH: &str = "bar length";

/// The sensitivities of the method whose four steps are `steps` (the step and its simulated test,
/// as `instruments::ballbar::method_step` builds them: A1 A2 sweep the outer axis, C1 C2 the inner).
pub fn method_sensitivity(
    machine: &Machine,
    pair: RotaryPair,
    steps: &[(JiangStep, BallbarTest)],
) -> Result<MethodSensitivity, IdentifyError> {
    let traces = |readings: &dyn Fn(usize) -> Vec<f64>| -> Result<(Vec<DbbTrace>, Vec<DbbTrace>), IdentifyError> {
        let (mut outer, mut inner) = (Vec::new(), Vec::new());
        for (k, (step, test)) in steps.iter().enumerate() {
            let trace = DbbTrace::of_test(test, readings(k))?;
            if step.is_outer() {
                outer.push(trace)
            } else {
                inner.push(trace)
            }
        }
        Ok((outer, inner))
    };
    let (outer, inner) = traces(&|k| vec![0.0; steps[k].1.len()])?;
    let nominal = identify_piges(machine, pair, &outer, &inner)?;
    let parameters: Vec<ParameterId> = nominal.values.iter().map(|v| v.0).collect();
    let h = 1e-3; // mm: a 1 um setup error, well inside the linear range
    let mut sources = Vec::new();
    let setup_parameters = ["WX", "WY", "WZ", "TX", "TY", "TZ"];
    for (k, (step, test)) in steps.iter().enumerate() {
        let mut errors: Vec<(String, Vec<f64>)> = Vec::new();
        for name in setup_parameters {
            let (_, index) = machine.parse_parameter(name).map_err(|e| IdentifyError::Input(e.to_string()))?;
            let mut p = vec![0.0; machine.parameter_count()];
            p[index] = h;
            let side = if name.starts_with('W') { "workpiece-side" } else { "tool-side" };
            errors.push((format!("{side} ball {}", &name[1..]), test.simulate_params(machine, &p)));
        }
        errors.push((BAR_LENGTH.to_string(), vec![h; test.len()]));
        for (name, readings) in errors {
            let (outer, inner) = traces(&|j| if j == k { readings.clone() } else { vec![0.0; steps[j].1.len()] })?;
            let found = identify_piges(machine, pair, &outer, &inner)?;
            let effect = found.values.iter().zip(&nominal.values).map(|(a, b)| (a.1 - b.1) / h).collect();
            sources.push(SetupSource { step: *step, name, effect });
        }
    }
    // noise: each centre's covariance for unit variance of the readings; for an extended bar a
    // reading dL moves the point's radius r = sqrt(L^2 - D^2) by (L / r) dL
    let covariances = outer
        .iter()
        .chain(&inner)
        .map(|t| {
            let points = t.points()?;
            let centre = t.fit()?.centre;
            let l = t.bar_length;
            let r2 = l * l - t.geometry.axial_separation.powi(2);
            let gain2 = l * l / r2;
            centre_covariance_per_unit_variance(&points, centre)
                .map(|c| c.map(|row| row.map(|v| gain2 * v)))
                .ok_or_else(|| IdentifyError::RankDeficient { message: "a step's circle does not determine its centre".into() })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let noise = propagate_centre_covariances(machine, pair, &outer, &inner, &covariances)?;
    Ok(MethodSensitivity { parameters, sources, noise })
}
