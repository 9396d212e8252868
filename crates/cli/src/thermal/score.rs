//! `thermal place --score`: every placement method with the same number of sensors, scored by the
//! error of the elongation model it leads to (`thermal::placement_score`), Gauss points as the
//! baseline and the exhaustive search for the smallest training error as the yardstick.

use crate::Failure;
use serde_json::{json, Value};
use std::fmt::Write;
use trueaxis::thermal::model_file::ThermalModel;
use trueaxis::thermal::placement::{effective_independence, modal_rule};
use trueaxis::thermal::placement_score::{gauss_points, score_placement, simulate_cycles, PlacementScore};
use trueaxis::thermal::{modal_analysis, ModalBasis, ModalOptions, SpectrumMethod};

/// Most candidate subsets the error yardstick tries.
const MAX_SUBSETS: u64 = 200_000;

/// The scores of the modal rule, effective independence, Gauss points and the exhaustive search
/// for the smallest training error (JSON and text).
pub fn score_methods(
    model: &ThermalModel,
    basis: &ModalBasis,
    dominant: &[usize],
    count: usize,
    reuse: f64,
    alpha: f64,
    distance: &dyn Fn(usize) -> f64,
) -> Result<(Value, String), Failure> {
    if !(alpha.is_finite() && alpha > 0.0) {
        return Err(Failure::input(anyhow::anyhow!("--expansion {alpha}: expected a positive coefficient in um/m/K")));
    }
    if model.system.node_count() > 1500 {
        return Err(Failure::input(anyhow::anyhow!(
            "--score simulates with every mode: at most 1500 nodes (the model has {})",
            model.system.node_count()
        )));
    }
    let all = modal_analysis(&model.system, &ModalOptions { count: None, method: SpectrumMethod::Dense, ..Default::default() })
        .map_err(Failure::of)?;
    let cycles = simulate_cycles(model, &all, alpha).map_err(Failure::of)?;
    let mut rows: Vec<(String, PlacementScore)> = Vec::new();
    let modal: Vec<usize> =
        modal_rule(basis, dominant, &model.candidates, reuse, distance).map_err(Failure::of)?.into_iter().map(|p| p.node).collect();
    rows.push(("modal".into(), score_placement(&cycles, &modal).map_err(Failure::of)?));
    // effective independence needs at least one sensor per dominant mode
    if count >= dominant.len() {
        rows.push((
            "efi".into(),
            score_placement(&cycles, &effective_independence(basis, dominant, &model.candidates, count).map_err(Failure::of)?)
                .map_err(Failure::of)?,
        ));
    }
    rows.push((
        "gauss (baseline)".into(),
        score_placement(&cycles, &gauss_points(model, count).map_err(Failure::of)?).map_err(Failure::of)?,
    ));
    // the yardstick: every subset of `count` candidates, the smallest training error
    let n = model.candidates.len() as u64;
    let subsets = (0..count as u64).fold(1u64, |acc, k| acc.saturating_mul(n - k) / (k + 1));
    if subsets <= MAX_SUBSETS {
        let mut best: Option<PlacementScore> = None;
        let mut idx: Vec<usize> = (0..count).collect();
        loop {
            let sensors: Vec<usize> = idx.iter().map(|&i| model.candidates[i]).collect();
            if let Ok(s) = score_placement(&cycles, &sensors) {
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
        if let Some(b) = best {
            rows.push(("exhaustive (smallest training error)".into(), b));
        }
    }
    let doc = json!(rows
        .iter()
        .map(|(m, s)| json!({"method": m, "sensors": s.sensors, "training_rms_um": s.training_rms,
        "validation": s.validation.iter().map(|(n, r, x)| json!({"cycle": n, "rms_um": r, "max_um": x})).collect::<Vec<_>>()}))
        .collect::<Vec<_>>());
    let mut text = format!(
        "placements scored by the elongation model (alpha {alpha} um/m/K): trained on a 20-min on/off cycle, validated on 10 and 40 min\n  {:<38} {:<16} {:>10} {:>10} {:>10}\n",
        "method", "nodes", "train RMS", "10 min", "40 min"
    );
    for (m, s) in &rows {
        let v: Vec<String> = s.validation.iter().map(|(_, r, _)| format!("{r:>10.4}")).collect();
        let _ = writeln!(text, "  {m:<38} {:<16} {:>10.4} {} um", format!("{:?}", s.sensors), s.training_rms, v.join(" "));
    }
    Ok((doc, text))
}
