//! The thermal parts of a calibration report, each computed as the `thermal` command that does it
//! alone: a conduction model's modes (`thermal modes --plot`: time constants, weights `|xi tau|`
//! and their shares, the dominant modes up to a cumulative share, Zhu 2008 §3.3) and a thermal
//! error model's prediction of a measured campaign (`thermal predict --plot`: drift against
//! prediction per run, residual RMS, largest value and band).

use super::super::html::Section;
use super::super::{drift_plot, drift_svg, mode_shapes_plot, modes_svg, time_constants_plot};
use super::{number, CalibrationError};
use trueaxis::thermal::error_model::ThermalErrorModel;
use trueaxis::thermal::model_file::ThermalModel;
use trueaxis::thermal::thermal_campaign::Campaign;
use trueaxis::thermal::validation::{evaluate_segments, prediction_segments, ResidualStats};
use trueaxis::thermal::{dominant_modes, modal_analysis_with_progress, mode_weights, LanczosProgress, ModalOptions, ModeWeight};

/// The modes of a thermal conduction model.
pub struct ThermalModesPart {
    pub model: String,
    /// Where the model came from (a file name).
    pub origin: String,
    pub nodes: usize,
    pub weights: Vec<ModeWeight>,
    /// Dominant modes (indices into `weights`), up to `share` of the summed weight.
    pub dominant: Vec<usize>,
    pub share: f64,
    pub svg: String,
}

impl ThermalModesPart {
    /// The first `count` modes (seconds for time constants, as `thermal modes --count`), weights
    /// for the model's flux load, dominant modes up to `share` (0 < share <= 1).
    pub fn compute(
        model: &ThermalModel,
        origin: &str,
        count: usize,
        share: f64,
        progress: &mut dyn FnMut(LanczosProgress),
    ) -> Result<ThermalModesPart, CalibrationError> {
        if count == 0 {
            return Err(CalibrationError::Input("the number of thermal modes must be at least 1".into()));
        }
        if !(share > 0.0 && share <= 1.0) {
            return Err(CalibrationError::Input(format!("the share of the dominant modes must lie in (0, 1], got {share}")));
        }
        let options = ModalOptions { count: Some(count.min(model.system.node_count())), ..Default::default() };
        let basis = modal_analysis_with_progress(&model.system, &options, progress)?;
        let weights = mode_weights(&basis, &model.system.load);
        let dominant = dominant_modes(&weights, share);
        let all: Vec<usize> = (0..basis.len()).collect();
        let svg = modes_svg(&mode_shapes_plot(model, &basis, &all, &[]), &time_constants_plot(&model.name, &weights, &dominant, share))?;
        Ok(ThermalModesPart {
            model: model.name.clone(),
            origin: origin.into(),
            nodes: model.system.node_count(),
            weights,
            dominant,
            share,
            svg,
        })
    }

    pub fn section(&self) -> Section {
        let rows = self
            .weights
            .iter()
            .map(|w| {
                vec![
                    (w.mode + 1).to_string(),
                    number(w.tau_s / 60.0, 2),
                    number(w.weight, 4),
                    format!("{} %", number(100.0 * w.share, 1)),
                    if self.dominant.contains(&w.mode) { "yes".into() } else { String::new() },
                ]
            })
            .collect();
        let dominant: Vec<String> = self.dominant.iter().map(|m| (m + 1).to_string()).collect();
        Section::new("thermal-modes", "Thermal modes")
            .paragraph(format!(
                "{} ({}, {} nodes): the generalised eigenproblem K phi = lambda C phi with C-orthonormal modes, time constants tau = 1/lambda. \
                 The weight |xi tau| of a mode is the steady-state amplitude of its coordinate under the model's heat flux; the dominant modes \
                 (here {}) carry {} % of the summed weight, and temperature sensors should see them (trueaxis thermal place; docs/thermal.md).",
                self.model,
                self.origin,
                self.nodes,
                dominant.join(", "),
                number(100.0 * self.share, 0)
            ))
            .table("Modes: time constant, weight and share", &["mode", "tau (min)", "weight |xi tau|", "share", "dominant"], rows)
            .figure("Mode shapes (each scaled to a largest magnitude of 1) and time constants with their weights", self.svg.clone())
    }
}

/// A thermal error model's prediction of a measured campaign.
pub struct ThermalDriftPart {
    /// The modelled error (a campaign column, e.g. `dz`).
    pub error: String,
    pub model_origin: String,
    pub data_origin: String,
    /// Residual statistics (um) per run.
    pub runs: Vec<(String, ResidualStats)>,
    pub svg: String,
}

impl ThermalDriftPart {
    /// Each run of `campaign` predicted from its own start by `model`, against the measured error.
    pub fn compute(
        model: &ThermalErrorModel,
        model_origin: &str,
        campaign: &Campaign,
        data_origin: &str,
    ) -> Result<ThermalDriftPart, CalibrationError> {
        let evaluated = evaluate_segments(campaign, model, &prediction_segments(campaign))?;
        let runs: Vec<(String, ResidualStats)> = evaluated.iter().filter_map(|e| e.stats().map(|s| (e.segment.name.clone(), s))).collect();
        if runs.is_empty() {
            return Err(CalibrationError::Input(format!(
                "{data_origin}: no measured `{}` column to compare the thermal model's prediction with",
                model.error()
            )));
        }
        let error = model.error().to_string();
        let svg = drift_svg(&drift_plot(&error, &evaluated))?;
        Ok(ThermalDriftPart { error, model_origin: model_origin.into(), data_origin: data_origin.into(), runs, svg })
    }

    pub fn section(&self) -> Section {
        let rows = self
            .runs
            .iter()
            .map(|(run, s)| {
                vec![
                    run.clone(),
                    s.samples.to_string(),
                    number(s.rms, 3),
                    number(s.max_abs, 3),
                    number(s.range, 3),
                    format!("[{}, {}]", number(s.min, 3), number(s.max, 3)),
                ]
            })
            .collect();
        Section::new("thermal-drift", "Thermal error model: drift and prediction")
            .paragraph(format!(
                "The thermal error model {} predicts {} from the temperatures of {}, each run from its own start (as trueaxis thermal predict does). \
                 The residual (measured minus predicted) is what compensation with this model would leave.",
                self.model_origin, self.error, self.data_origin
            ))
            .table(
                format!("Residuals of {} per run (um)", self.error),
                &["run", "samples", "RMS", "largest |r|", "range", "band [min, max]"],
                rows,
            )
            .figure("Measured drift (points) and prediction (line) per run, and the residual with its band", self.svg.clone())
    }
}
