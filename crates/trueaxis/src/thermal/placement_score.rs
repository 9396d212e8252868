//! Sensor placements scored by the error of the thermal model they lead to (Zhu 2008 §3.4.2: the
//! modal placement "compared with other two commonly utilized methods, namely, Gaussian integration
//! method and exhaustive search method"), on a bar whose thermal error is its elongation
//! `e = alpha int T dx` (the free end of the elongation element; eq. 3.16).
//!
//! Protocol (Zhu 2008 §3.4.3, "frequency sensitivity"): the model's step flux switched on and off
//! with a period of 20 min for 4 h trains a regression `e = c0 + sum_i beta_i T_i` on the sensors'
//! temperatures; periods of 10 and 40 min validate it. Temperatures by modal superposition over
//! every mode (exact per sampling interval of 60 s). A placement is scored by the RMS and the
//! largest residual of the elongation on the validation cycles.
//!
//! The Gaussian-integration baseline (eq. 3.16, Buchanan and Turner): N sensors at the Gauss-Legendre
//! points of the bar, the nearest candidate nodes; with a temperature field that is a polynomial of
//! degree 2N - 1, `int T dx = (L/2) sum w_i T(x_i)` is exact.

use super::modal::ModalBasis;
use super::model_file::ThermalModel;
use super::response::{modal_history, LoadHistory};
use crate::error::Error;
use crate::error_model::gauss_legendre;
use crate::identify::fit_linear;
use nalgebra::{DMatrix, DVector};

/// One simulated cycle: its name, the temperatures of every node per sample (K) and the elongation
/// per sample (um).
pub type SimulatedCycle = (String, Vec<Vec<f64>>, Vec<f64>);

/// The error of the model a placement leads to (um).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PlacementScore {
    pub sensors: Vec<usize>,
    pub training_rms: f64,
    /// `(name, RMS, max |residual|)` of each validation cycle.
    pub validation: Vec<(String, f64, f64)>,
}

impl PlacementScore {
    /// The largest validation RMS.
    pub fn worst_rms(&self) -> f64 {
        self.validation.iter().map(|v| v.1).fold(0.0, f64::max)
    }
}

/// Node coordinates along the bar (m) of a `bar1d` model.
fn bar_positions(model: &ThermalModel) -> Result<Vec<f64>, Error> {
    match (&model.mesh, &model.system.coordinates) {
        (Some(mesh), Some(c)) if mesh.dimensions() == 1 => Ok(c.iter().map(|p| p[0]).collect()),
        _ => Err(Error::input("scoring placements by the elongation needs a bar (kind = \"bar1d\")")),
    }
}

/// Weights `w_n` (m) with `int T dx = sum_n w_n T_n` for the linear elements of a bar (exact for
/// the finite-element field).
pub fn elongation_weights(model: &ThermalModel) -> Result<Vec<f64>, Error> {
    let x = bar_positions(model)?;
    let mut w = vec![0.0; x.len()];
    for e in 0..x.len() - 1 {
        let h = x[e + 1] - x[e];
        w[e] += h / 2.0;
        w[e + 1] += h / 2.0;
    }
    Ok(w)
}

/// The candidate nodes nearest the `count` Gauss-Legendre points of the bar (distinct; a point
/// whose nearest candidate is taken goes to the next nearest free one).
pub fn gauss_points(model: &ThermalModel, count: usize) -> Result<Vec<usize>, Error> {
    let x = bar_positions(model)?;
    if count == 0 || count > model.candidates.len() {
        return Err(Error::input(format!("{count} Gauss points cannot be placed on {} candidates", model.candidates.len())));
    }
    let (a, b) = (x.iter().copied().fold(f64::INFINITY, f64::min), x.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    let mut chosen: Vec<usize> = Vec::new();
    for (u, _) in gauss_legendre(count) {
        let p = a + (b - a) * (u + 1.0) / 2.0;
        let mut free: Vec<usize> = model.candidates.iter().copied().filter(|c| !chosen.contains(c)).collect();
        free.sort_by(|i, j| (x[*i] - p).abs().total_cmp(&(x[*j] - p).abs()).then(i.cmp(j)));
        chosen.push(free[0]);
    }
    chosen.sort_unstable();
    Ok(chosen)
}

/// An on/off cycle of the model's step flux with period `period_s` over `duration_s`, sampled every
/// `step_s`: the load history and the sample times.
fn cycle(model: &ThermalModel, period_s: f64, duration_s: f64, step_s: f64) -> LoadHistory {
    let n = (duration_s / step_s).round() as usize;
    let times_s: Vec<f64> = (0..=n).map(|k| k as f64 * step_s).collect();
    let inputs = times_s.iter().map(|t| vec![if ((t + 1e-9) / (period_s / 2.0)) as usize % 2 == 0 { 1.0 } else { 0.0 }]).collect();
    LoadHistory { loads: vec![model.system.load.clone()], times_s, inputs }
}

/// The simulated campaign of the scoring protocol: per cycle (name, node temperatures per sample,
/// elongation per sample in um). `basis` should hold every mode.
pub fn simulate_cycles(model: &ThermalModel, basis: &ModalBasis, alpha_um_per_m_k: f64) -> Result<Vec<SimulatedCycle>, Error> {
    let w = elongation_weights(model)?;
    let nodes: Vec<usize> = (0..w.len()).collect();
    [("training 20 min", 1200.0), ("validation 10 min", 600.0), ("validation 40 min", 2400.0)]
        .into_iter()
        .map(|(name, period)| {
            let temps = modal_history(basis, &cycle(model, period, 4.0 * 3600.0, 60.0), &nodes)?;
            // e (um) = alpha (um/m/K) * int T dx (K m)
            let e = temps.iter().map(|t| alpha_um_per_m_k * t.iter().zip(&w).map(|(t, w)| t * w).sum::<f64>()).collect();
            Ok((name.to_string(), temps, e))
        })
        .collect()
}

/// Scores the placement `sensors` on the simulated cycles (module documentation).
pub fn score_placement(cycles: &[SimulatedCycle], sensors: &[usize]) -> Result<PlacementScore, Error> {
    let design =
        |temps: &[Vec<f64>]| DMatrix::from_fn(temps.len(), sensors.len() + 1, |r, c| if c == 0 { 1.0 } else { temps[r][sensors[c - 1]] });
    let (_, train_temps, train_e) = &cycles[0];
    let names: Vec<String> = std::iter::once("intercept".to_string()).chain(sensors.iter().map(|s| format!("node {s}"))).collect();
    let fit = fit_linear(&design(train_temps), train_e, None, &names).map_err(|e| Error::input(format!("sensors {sensors:?}: {e}")))?;
    let beta = DVector::from_column_slice(&fit.coefficients);
    let stats = |temps: &[Vec<f64>], e: &[f64]| -> (f64, f64) {
        let p = design(temps) * &beta;
        let r: Vec<f64> = e.iter().zip(&p).map(|(a, b)| a - b).collect();
        ((r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt(), r.iter().map(|v| v.abs()).fold(0.0, f64::max))
    };
    let training_rms = stats(train_temps, train_e).0;
    let validation = cycles[1..].iter().map(|(name, temps, e)| {
        let (rms, max) = stats(temps, e);
        (name.clone(), rms, max)
    });
    Ok(PlacementScore { sensors: sensors.to_vec(), training_rms, validation: validation.collect() })
}
