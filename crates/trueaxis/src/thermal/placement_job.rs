//! Temperature-sensor placement end to end, as `trueaxis thermal place` and
//! `trueaxis.thermal_place` run it (Zhu 2008 §3.4): the lowest modes of a thermal model, their
//! weights under the model's step flux and the dominant ones that carry a share of the weight
//! (eq. 3.11), the sensors of one method (the modal rule, effective independence, the exhaustive
//! search for the largest det(Phi_s^T Phi_s), or the Gauss-Legendre points of a bar), the rank and
//! condition number of the sensor-mode matrix Phi_s, and on request every method scored by the
//! error of the elongation model it leads to ([`super::placement_comparison`]). Positions in m
//! (the model's coordinates), time constants in s, errors in um, expansion in um/m/K.

use super::model_file::ThermalModel;
use super::placement::{conditioning, effective_independence, exhaustive, log_det_information, modal_rule, Conditioning};
use super::placement_comparison::{compare_placements, PlacementComparison};
use super::placement_score::gauss_points;
use super::{dominant_modes, modal_analysis_with_progress, mode_weights, LanczosProgress, ModalBasis, ModalOptions};
use crate::error::Error;
use serde_json::{json, Value};

/// A placement method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlaceMethod {
    /// Zhu (2008): one sensor at the extreme of each dominant mode, reused where it serves several.
    Modal,
    /// Effective independence (Kammer).
    Efi,
    /// Every subset of the sensors' number of candidates, the largest det(Phi_s^T Phi_s).
    Exhaustive,
    /// The candidates nearest the Gauss-Legendre points of a bar (Gaussian integration).
    Gauss,
}

impl PlaceMethod {
    pub const NAMES: [&'static str; 4] = ["modal", "efi", "exhaustive", "gauss"];

    pub fn name(self) -> &'static str {
        match self {
            PlaceMethod::Modal => "modal",
            PlaceMethod::Efi => "efi",
            PlaceMethod::Exhaustive => "exhaustive",
            PlaceMethod::Gauss => "gauss",
        }
    }

    pub fn parse(name: &str) -> Result<PlaceMethod, Error> {
        match name {
            "modal" => Ok(PlaceMethod::Modal),
            "efi" => Ok(PlaceMethod::Efi),
            "exhaustive" => Ok(PlaceMethod::Exhaustive),
            "gauss" => Ok(PlaceMethod::Gauss),
            other => Err(Error::input(format!("method `{other}`: expected one of {}", PlaceMethod::NAMES.join(", ")))),
        }
    }
}

/// What to place and how (the options of `trueaxis thermal place`).
#[derive(Clone, Debug)]
pub struct PlacementRequest {
    /// Modes computed before truncation.
    pub count: usize,
    /// Cumulative weight share of the dominant modes (0 < share <= 1).
    pub share: f64,
    pub method: PlaceMethod,
    /// Number of sensors (efi, exhaustive, gauss; default one per dominant mode).
    pub sensors: Option<usize>,
    /// Modal rule: reuse a sensor reaching this fraction of a mode's extreme (0 < reuse <= 1).
    pub reuse: f64,
    /// Score every method with this expansion coefficient of the bar (um/m/K).
    pub score: Option<f64>,
}

/// The placed sensors, what they serve and how well they separate the dominant modes.
pub struct SensorPlacement {
    pub method: PlaceMethod,
    pub basis: ModalBasis,
    /// The dominant modes (indices into the basis, in order of weight).
    pub dominant: Vec<usize>,
    /// The sensor nodes, and the dominant modes each serves (the modal rule; empty otherwise).
    pub sensors: Vec<usize>,
    pub served: Vec<Vec<usize>>,
    pub conditioning: Conditioning,
    pub scores: Option<PlacementComparison>,
}

/// Refuses a share or fraction `value` of option `name` outside (0, 1] (NaN included).
pub fn check_fraction(name: &str, value: f64) -> Result<(), Error> {
    if value > 0.0 && value <= 1.0 {
        Ok(())
    } else {
        Err(Error::input(format!("{name} {value} must lie in (0, 1]")))
    }
}

impl PlacementRequest {
    /// Refuses a share or a reuse fraction outside (0, 1] (before any model is read).
    pub fn check(&self) -> Result<(), Error> {
        check_fraction("--share", self.share)?;
        check_fraction("--reuse", self.reuse)
    }
}

/// The lowest `count` modes of the model (at most one per node), `progress` told as they converge.
pub fn placement_modes(model: &ThermalModel, count: usize, progress: &mut dyn FnMut(LanczosProgress)) -> Result<ModalBasis, Error> {
    crate::ensure!(count > 0, input, "--count must be at least 1");
    let count = count.min(model.system.node_count());
    let options = ModalOptions { count: Some(count), ..Default::default() };
    modal_analysis_with_progress(&model.system, &options, progress)
}

/// The distance of a node to the nearest node where the step flux enters (m; in nodes for a
/// model without coordinates): the modal rule's tie-break.
fn flux_distance(model: &ThermalModel) -> impl Fn(usize) -> f64 + '_ {
    move |node: usize| -> f64 {
        model
            .flux_nodes
            .iter()
            .map(|&f| match &model.system.coordinates {
                Some(c) => (0..3).map(|d| (c[node][d] - c[f][d]).powi(2)).sum::<f64>().sqrt(),
                None => (node as f64 - f as f64).abs(),
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// The sensors of the request's method for the dominant modes of `basis` (from
/// [`placement_modes`]), their conditioning and, when asked, the scores of every method.
pub fn place_sensors(model: &ThermalModel, basis: ModalBasis, request: &PlacementRequest) -> Result<SensorPlacement, Error> {
    request.check()?;
    let weights = mode_weights(&basis, &model.system.load);
    let dominant = dominant_modes(&weights, request.share);
    let distance = flux_distance(model);
    let count = request.sensors.unwrap_or(dominant.len());
    let (sensors, served) = sensors_of_method(model, &basis, &dominant, count, request, &distance)?;
    let scores = match request.score {
        Some(alpha) => Some(compare_placements(model, &basis, &dominant, count, request.reuse, alpha, &distance)?),
        None => None,
    };
    let conditioning = conditioning(&basis, &dominant, &sensors);
    Ok(SensorPlacement { method: request.method, basis, dominant, sensors, served, conditioning, scores })
}

/// The sensor nodes of the method, with the modes each serves (the modal rule only).
fn sensors_of_method(
    model: &ThermalModel,
    basis: &ModalBasis,
    dominant: &[usize],
    count: usize,
    request: &PlacementRequest,
    distance: &dyn Fn(usize) -> f64,
) -> Result<(Vec<usize>, Vec<Vec<usize>>), Error> {
    let nodes = match request.method {
        PlaceMethod::Modal => {
            let placed = modal_rule(basis, dominant, &model.candidates, request.reuse, distance)?;
            return Ok(placed.into_iter().map(|p| (p.node, p.modes)).unzip());
        }
        PlaceMethod::Efi => effective_independence(basis, dominant, &model.candidates, count)?,
        PlaceMethod::Exhaustive => {
            crate::ensure!(
                count >= dominant.len(),
                input,
                "exhaustive search maximises det(Phi_s^T Phi_s): it needs at least {} sensors (one per dominant mode)",
                dominant.len()
            );
            exhaustive(&model.candidates, count, |s| log_det_information(basis, dominant, s))?.0
        }
        PlaceMethod::Gauss => gauss_points(model, count)?,
    };
    let n = nodes.len();
    Ok((nodes, vec![Vec::new(); n]))
}

impl SensorPlacement {
    /// The position of a node (m), for a model with coordinates.
    pub fn position(model: &ThermalModel, node: usize) -> Option<Vec<f64>> {
        model.system.coordinates.as_ref().map(|c| c[node].to_vec())
    }

    /// The document of `trueaxis thermal place --json`: the sensors (node, position in m, modes
    /// served, numbered from 1), the dominant modes, the rank and condition number of Phi_s (null
    /// when infinite) with its explanation, and the scores (null unless asked).
    pub fn to_json(&self, model: &ThermalModel) -> Value {
        let list: Vec<Value> = self
            .sensors
            .iter()
            .zip(&self.served)
            .map(|(n, m)| json!({"node": n, "position_m": Self::position(model, *n), "modes": m.iter().map(|i| i + 1).collect::<Vec<_>>()}))
            .collect();
        let cond = &self.conditioning;
        json!({"model": model.name, "method": self.method.name(), "dominant_modes": self.dominant.iter().map(|m| m + 1).collect::<Vec<_>>(),
               "sensors": list, "condition_number": cond.condition_number, "rank": cond.rank,
               "conditioning": cond.explanation(), "scores": self.scores.as_ref().map(|s| s.to_json())})
    }
}
