//! `trueaxis demo`: the main job end to end on the built-in machine, the Huron KX8-Five of seed 004
//! (structure `WCAYFXZT`, A tilted 45 deg) with the link and setup errors of seed 004 Table 1:
//!
//! 1. a CapBall campaign of 807 poses (seed 004 §3.2) simulated on the exact chain with the sensor
//!    noise of Table 3 and a cyclic drift of the measuring chain (§4.4.2, peak-to-valley of Table 4);
//! 2. ISO 230-4 ballbar circles (CW and CCW) in the XY plane, with noise, and their diagnostics;
//! 3. identification of the separable link and setup errors with the identifiability report;
//! 4. adaptive Monte Carlo uncertainty (JCGM 101) with the statistical sources and the cyclic drift,
//!    and the per-source budget (seed 004 Table 5);
//! 5. the volumetric error over the work volume before and after compensation with the identified
//!    model, and compensation tables;
//! 6. a self-contained HTML report.
//!
//! Everything it writes goes to the output directory, with the inputs, so that each step can be
//! repeated with the individual `trueaxis` commands.

mod ballbar;
mod campaign;
mod maps;
mod report;

pub use maps::GRID;

use crate::compensate::CompensateError;
use crate::data::{write_atomically, DataError};
use crate::errors::{ErrorModel, ErrorsError};
use crate::evaluate::EvaluateError;
use crate::identify::IdentifyError;
use crate::instruments::ballbar::BallbarError;
use crate::machine::{Machine, MachineError};
use crate::report::ReportError;
use crate::uncertainty::UncertaintyError;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The built-in machine (`examples/machines/kx8five.toml`).
pub const MACHINE_TOML: &str = include_str!("../../examples/machines/kx8five.toml");
/// The errors the machine is simulated with: seed 004 Table 1 (`examples/errors/kx8five_table1.toml`).
pub const ERRORS_TOML: &str = include_str!("../../examples/errors/kx8five_table1.toml");
/// The campaign: 807 CapBall poses (`examples/campaigns/kx8five/`).
pub const CAMPAIGN_TOML: &str = include_str!("../../examples/campaigns/kx8five/campaign.toml");
pub const CAMPAIGN_POSES_CSV: &str = include_str!("../../examples/campaigns/kx8five/capball.csv");
/// The uncertainty sources: seed 004 Tables 3 and 4 with a cyclic drift (`examples/uncertainty/`).
pub const SOURCES_TOML: &str = include_str!("../../examples/uncertainty/kx8five_cyclic.toml");

/// Steps reported to the progress callback.
pub const STEPS: usize = 7;

#[derive(Debug, Error)]
pub enum DemoError {
    #[error(transparent)]
    Machine(#[from] MachineError),
    #[error(transparent)]
    Errors(#[from] ErrorsError),
    #[error(transparent)]
    Data(#[from] DataError),
    #[error(transparent)]
    Report(#[from] ReportError),
    #[error(transparent)]
    Identify(#[from] IdentifyError),
    #[error(transparent)]
    Uncertainty(#[from] UncertaintyError),
    #[error(transparent)]
    Compensate(#[from] CompensateError),
    #[error(transparent)]
    Evaluate(#[from] EvaluateError),
    #[error(transparent)]
    Ballbar(#[from] BallbarError),
    #[error("{path}: cannot create output directory: {source}")]
    CreateDir { path: String, source: std::io::Error },
}

/// What the demo found, for the command line summary.
#[derive(Clone, Debug)]
pub struct DemoSummary {
    pub machine: String,
    /// Poses of the volumetric map.
    pub poses: usize,
    /// Largest `|d|` over the map (um) before compensation, and where (axis letter, mm or deg).
    pub max_um: f64,
    pub max_pose: Vec<(char, f64)>,
    pub rms_um: f64,
    /// The same after compensation with the identified model.
    pub max_after_um: f64,
    pub rms_after_um: f64,
    /// Identified parameters: name, unit, true value, identified value, least-squares standard
    /// uncertainty, Monte Carlo 95 % interval.
    pub parameters: Vec<ParameterSummary>,
    pub residual_rms_um: f64,
    pub monte_carlo_sequences: usize,
    /// Circular deviation G (um) of the CCW and CW ballbar runs.
    pub ballbar_g_um: Vec<f64>,
    pub files: Vec<PathBuf>,
}

#[derive(Clone, Debug)]
pub struct ParameterSummary {
    pub name: String,
    pub unit: String,
    pub truth: f64,
    pub value: f64,
    pub std_uncertainty: Option<f64>,
    pub interval: (f64, f64),
}

/// The built-in machine and its true errors.
pub fn builtin() -> Result<(Machine, ErrorModel), DemoError> {
    let machine = Machine::from_toml_str(MACHINE_TOML, "built-in kx8five.toml")?;
    let errors = ErrorModel::from_toml_str(ERRORS_TOML, "built-in kx8five errors", &machine)?;
    Ok((machine, errors))
}

/// Files are written through this, so that the summary lists them all.
pub(crate) struct Output {
    dir: PathBuf,
    pub files: Vec<PathBuf>,
}

impl Output {
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<PathBuf, DemoError> {
        let path = self.dir.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|source| DemoError::CreateDir { path: parent.display().to_string(), source })?;
        }
        write_atomically(&path, bytes)?;
        if !self.files.contains(&path) {
            self.files.push(path.clone());
        }
        Ok(path)
    }
}

/// Runs the demo into `out_dir`; `progress(step, STEPS, message)` is called before each step.
pub fn run(out_dir: &Path, progress: &mut dyn FnMut(usize, usize, &str)) -> Result<DemoSummary, DemoError> {
    let (machine, truth) = builtin()?;
    std::fs::create_dir_all(out_dir).map_err(|source| DemoError::CreateDir { path: out_dir.display().to_string(), source })?;
    let mut out = Output { dir: out_dir.to_path_buf(), files: Vec::new() };
    out.write("machine.toml", MACHINE_TOML.as_bytes())?;
    out.write("errors_true.toml", ERRORS_TOML.as_bytes())?;

    progress(1, STEPS, "simulating the CapBall campaign (807 poses, sensor noise, cyclic drift)");
    let simulated = campaign::simulate(&machine, &truth, &mut out)?;
    progress(2, STEPS, "simulating ISO 230-4 ballbar circles and their diagnostics");
    let circles = ballbar::run(&machine, &truth, &mut out)?;
    progress(3, STEPS, "identifying the link and setup errors");
    let identified = campaign::identify(&machine, &truth, &simulated, &mut out)?;
    progress(4, STEPS, "adaptive Monte Carlo uncertainty and budget (JCGM 101)");
    let uncertainty = campaign::uncertainty(&identified, &mut out)?;
    progress(5, STEPS, "volumetric error before and after compensation");
    let volume = campaign::volume(&machine, &truth, &identified, &mut out)?;
    progress(6, STEPS, "compensation tables");
    let tables = campaign::compensation_tables(&machine, &identified, &mut out)?;
    progress(7, STEPS, "HTML report");
    let inputs = report::ReportInputs {
        machine: &machine,
        truth: &truth,
        simulated: &simulated,
        identified: &identified,
        uncertainty: &uncertainty,
        volume: &volume,
        circles: &circles,
        tables: &tables,
    };
    let html = report::html(&inputs)?;
    out.write("report.html", html.as_bytes())?;

    let parameters = report::parameter_rows(&inputs);
    Ok(DemoSummary {
        machine: machine.name.clone(),
        poses: volume.poses,
        max_um: volume.before.0,
        max_pose: volume.max_pose.clone(),
        rms_um: volume.before.1,
        max_after_um: volume.after.0,
        rms_after_um: volume.after.1,
        parameters,
        residual_rms_um: identified.result.residual_rms_um,
        monte_carlo_sequences: uncertainty.budget.total.sequences,
        ballbar_g_um: circles.result.runs.iter().map(|r| r.g_um).collect(),
        files: out.files,
    })
}
