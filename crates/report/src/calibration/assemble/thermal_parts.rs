//! The thermal parts of a request: the modes of a conduction model (time constants in s, weights
//! of the dominant modes up to the share asked for) and the drift of a thermal campaign against the
//! prediction of a fitted thermal error model (um), with the screening findings of that campaign.

use super::super::{CalibrationError, ThermalDriftPart, ThermalModesPart};
use super::request::{bad, ReportRequest};
use std::path::Path;
use trueaxis::screen::Finding;
use trueaxis::thermal::error_model::ThermalErrorModel;
use trueaxis::thermal::model_file::load_model;
use trueaxis::thermal::thermal_screening::read_screened;
use trueaxis::thermal::LanczosProgress;

/// The thermal modes, the drift against the prediction, and the findings of the thermal campaign.
pub type ThermalParts = (Option<ThermalModesPart>, Option<ThermalDriftPart>, Option<Vec<Finding>>);

pub fn thermal_parts(request: &ReportRequest, progress: &mut dyn FnMut(&str)) -> Result<ThermalParts, CalibrationError> {
    let modes = match &request.thermal_model {
        Some(path) => Some(modes(request, path, progress)?),
        None => None,
    };
    let drift = match (&request.thermal_error, &request.thermal_data) {
        (Some(model_path), Some(data_path)) => {
            progress("thermal error model");
            Some(drift(model_path, data_path)?)
        }
        _ => None,
    };
    let (drift, findings) = drift.unzip();
    Ok((modes, drift, findings))
}

fn modes(request: &ReportRequest, path: &Path, progress: &mut dyn FnMut(&str)) -> Result<ThermalModesPart, CalibrationError> {
    progress("thermal modes");
    let model = load_model(path)?;
    let mut lanczos = |p: LanczosProgress| {
        if let LanczosProgress::Iterating { converged, wanted, .. } | LanczosProgress::Refining { converged, wanted, .. } = p {
            progress(&format!("thermal modes: {converged} of {wanted} converged"));
        }
    };
    let origin = path.display().to_string();
    ThermalModesPart::compute(&model, &origin, request.thermal_modes, request.thermal_share, &mut lanczos)
}

fn drift(model_path: &Path, data_path: &Path) -> Result<(ThermalDriftPart, Vec<Finding>), CalibrationError> {
    let text =
        trueaxis::files::inputs::read_to_string(model_path).map_err(|e| bad(format!("{}: cannot read: {e}", model_path.display())))?;
    let model_origin = model_path.display().to_string();
    let model = ThermalErrorModel::from_toml_str(&text, &model_origin)?;
    let (campaign, findings) = read_screened(data_path, false, false)?;
    let part = ThermalDriftPart::compute(&model, &model_origin, &campaign, &data_path.display().to_string())?;
    Ok((part, findings))
}
