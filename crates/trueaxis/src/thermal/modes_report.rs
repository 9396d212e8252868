//! The thermal modes of a model as `trueaxis thermal modes` reports them (and the Python package):
//! the C-orthonormal modes of `C dT/dt = -K T + q` with the longest time constants
//! `tau_i = 1 / lambda_i` ([`super::modal`]), each mode's weight `|xi_i tau_i|` under the model's
//! step load and its share of the computed modes' total ([`super::weights`]), and the dominant
//! modes: the fewest, in order of weight, whose shares reach `share` (Zhu 2008, the modal
//! approach to sensor placement).

use super::model_file::ThermalModel;
use super::{dominant_modes, modal_analysis_with_progress, mode_weights, LanczosProgress, ModalBasis, ModalOptions};
use super::{ModeWeight, SpectrumMethod};
use crate::error::Error;
use serde_json::{json, Value};

/// The modes of a model, their weights and the dominant ones.
pub struct ModesReport {
    pub model: String,
    pub nodes: usize,
    /// The share of the total weight the dominant modes carry (0 < share <= 1).
    pub share: f64,
    pub basis: ModalBasis,
    /// In mode order (longest time constant first).
    pub weights: Vec<ModeWeight>,
    /// Indices of the dominant modes.
    pub dominant: Vec<usize>,
}

impl ModesReport {
    /// The `count` modes of `model` with the longest time constants (at most one per node) by
    /// `method`, and the dominant ones for `share`; `progress` hears from the eigensolver.
    pub fn new(
        model: &ThermalModel,
        count: usize,
        method: SpectrumMethod,
        share: f64,
        progress: &mut dyn FnMut(LanczosProgress),
    ) -> Result<ModesReport, Error> {
        if !(share > 0.0 && share <= 1.0) {
            return Err(Error::input(format!("the share {share} of the weight must lie in (0, 1]")));
        }
        if count == 0 {
            return Err(Error::input("the number of modes must be at least 1"));
        }
        let nodes = model.system.node_count();
        let options = ModalOptions { count: Some(count.min(nodes)), method, ..Default::default() };
        let basis = modal_analysis_with_progress(&model.system, &options, progress)?;
        let weights = mode_weights(&basis, &model.system.load);
        let dominant = dominant_modes(&weights, share);
        Ok(ModesReport { model: model.name.clone(), nodes, share, basis, weights, dominant })
    }

    /// The document of `trueaxis thermal modes --json`: per mode (numbered from 1) the time
    /// constant in min and s, the weight, its share and whether it is dominant.
    pub fn to_json(&self) -> Value {
        let modes: Vec<Value> = self
            .weights
            .iter()
            .map(|w| {
                json!({"mode": w.mode + 1, "tau_min": w.tau_s / 60.0, "tau_s": w.tau_s, "weight": w.weight, "share": w.share,
                       "dominant": self.dominant.contains(&w.mode)})
            })
            .collect();
        json!({"model": self.model, "nodes": self.nodes, "share": self.share,
               "dominant": self.dominant.iter().map(|m| m + 1).collect::<Vec<_>>(), "modes": modes})
    }
}
