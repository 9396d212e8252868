//! Every placement method with the same number of sensors, scored by the error of the elongation
//! model it leads to ([`super::placement_score`], Zhu 2008 §3.4.2-3.4.3): the modal rule, effective
//! independence (when there are at least as many sensors as dominant modes), the Gauss-Legendre
//! points as the baseline, and the exhaustive search for the smallest training error as the
//! yardstick (when there are at most 200,000 subsets). Errors in um, the expansion coefficient in
//! um/m/K; `trueaxis thermal place --score` and `trueaxis.thermal_place(score=True)`.

use super::model_file::ThermalModel;
use super::placement::{effective_independence, modal_rule};
use super::placement_score::{gauss_points, score_placement, simulate_cycles, PlacementScore, SimulatedCycle};
use super::{modal_analysis, ModalBasis, ModalOptions, SpectrumMethod};
use crate::error::Error;
use serde_json::{json, Value};

/// Most candidate subsets the error yardstick tries.
const MAX_SUBSETS: u64 = 200_000;

/// The most nodes a model may have to be scored (the simulation uses every mode).
const MAX_NODES: usize = 1500;

/// The scores of each method, by its name (`modal`, `efi`, `gauss (baseline)`, `exhaustive
/// (smallest training error)`).
#[derive(Clone, Debug)]
pub struct PlacementComparison {
    /// The expansion coefficient of the bar (um/m/K).
    pub alpha: f64,
    pub rows: Vec<(String, PlacementScore)>,
}

/// The scores of the modal rule, effective independence, Gauss points and the exhaustive search
/// for `count` sensors serving the `dominant` modes of `basis`; `reuse` and `distance` (to the
/// heat source) as the modal rule takes them.
pub fn compare_placements(
    model: &ThermalModel,
    basis: &ModalBasis,
    dominant: &[usize],
    count: usize,
    reuse: f64,
    alpha: f64,
    distance: &dyn Fn(usize) -> f64,
) -> Result<PlacementComparison, Error> {
    let cycles = scoring_cycles(model, alpha)?;
    let mut rows: Vec<(String, PlacementScore)> = Vec::new();
    let modal: Vec<usize> = modal_rule(basis, dominant, &model.candidates, reuse, distance)?.into_iter().map(|p| p.node).collect();
    rows.push(("modal".into(), score_placement(&cycles, &modal)?));
    // effective independence needs at least one sensor per dominant mode
    if count >= dominant.len() {
        rows.push(("efi".into(), score_placement(&cycles, &effective_independence(basis, dominant, &model.candidates, count)?)?));
    }
    rows.push(("gauss (baseline)".into(), score_placement(&cycles, &gauss_points(model, count)?)?));
    if let Some(best) = smallest_training_error(model, &cycles, count) {
        rows.push(("exhaustive (smallest training error)".into(), best));
    }
    Ok(PlacementComparison { alpha, rows })
}

/// The on/off cycles of the step flux simulated over every mode of the model.
fn scoring_cycles(model: &ThermalModel, alpha: f64) -> Result<Vec<SimulatedCycle>, Error> {
    if !(alpha.is_finite() && alpha > 0.0) {
        return Err(Error::input(format!("--expansion {alpha}: expected a positive coefficient in um/m/K")));
    }
    if model.system.node_count() > MAX_NODES {
        return Err(Error::input(format!(
            "--score simulates with every mode: at most {MAX_NODES} nodes (the model has {})",
            model.system.node_count()
        )));
    }
    let all = modal_analysis(&model.system, &ModalOptions { count: None, method: SpectrumMethod::Dense, ..Default::default() })?;
    simulate_cycles(model, &all, alpha)
}

/// The yardstick: of every subset of `count` candidates, the one of the smallest training error;
/// `None` when there are more than [`MAX_SUBSETS`] subsets or none can be scored.
fn smallest_training_error(model: &ThermalModel, cycles: &[SimulatedCycle], count: usize) -> Option<PlacementScore> {
    let n = model.candidates.len() as u64;
    let subsets = (0..count as u64).fold(1u64, |acc, k| acc.saturating_mul(n - k) / (k + 1));
    if subsets > MAX_SUBSETS {
        return None;
    }
    let mut best: Option<PlacementScore> = None;
    let mut idx: Vec<usize> = (0..count).collect();
    loop {
        let sensors: Vec<usize> = idx.iter().map(|&i| model.candidates[i]).collect();
        if let Ok(s) = score_placement(cycles, &sensors) {
            if best.as_ref().is_none_or(|b| s.training_rms < b.training_rms) {
                best = Some(s);
            }
        }
        // next combination
        let Some(i) = (0..count).rev().find(|&i| idx[i] < model.candidates.len() - count + i) else { break };
        idx[i] += 1;
        for j in i + 1..count {
            idx[j] = idx[j - 1] + 1;
        }
    }
    best
}

impl PlacementComparison {
    /// The `scores` of `trueaxis thermal place --json`: per method its sensors, the training RMS
    /// and per validation cycle the RMS and largest error (um).
    pub fn to_json(&self) -> Value {
        json!(self
            .rows
            .iter()
            .map(|(m, s)| json!({"method": m, "sensors": s.sensors, "training_rms_um": s.training_rms,
            "validation": s.validation.iter().map(|(n, r, x)| json!({"cycle": n, "rms_um": r, "max_um": x})).collect::<Vec<_>>()}))
            .collect::<Vec<_>>())
    }
}
