//! `trueaxis demo`: the main job end to end on the built-in machine, the Huron KX8-Five of Andolfatto et al. 2011
//! (structure `WCAYFXZT`, A tilted 45 deg) with the link and setup errors of Andolfatto et al. 2011 Table 1:
//!
//! 1. a CapBall campaign of 807 poses (Andolfatto et al. 2011 §3.2) simulated on the exact chain with the sensor
//!    noise of Table 3 and a cyclic drift of the measuring chain (§4.4.2, peak-to-valley of Table 4);
//! 2. ISO 230-4 ballbar circles (CW and CCW) in the XY plane, with noise, and their diagnostics;
//! 3. identification of the separable link and setup errors with the identifiability report;
//! 4. adaptive Monte Carlo uncertainty (JCGM 101) with the statistical sources and the cyclic drift,
//!    and the per-source budget (Andolfatto et al. 2011 Table 5);
//! 5. compensation tables from the identified errors, and the volumetric error over the work volume
//!    before compensation and after (the true machine driven to the set-points the tables correct);
//! 6. a self-contained HTML report, built by `report::calibration` like `trueaxis report`.
//!
//! Everything it writes goes to the output directory, with the inputs, so that each step can be
//! repeated with the individual `trueaxis` commands. The directory is built in a temporary beside
//! it and swapped in whole at the end (`trueaxis::data::WorkingDirectory`): a run that fails (a
//! full disk) or is stopped leaves the directory as it was.

mod ballbar;
mod campaign;
mod report;

use crate::calibration::{
    CalibrationError, CalibrationReport, CertificateFile, CirclePart, CompensationPart, IdentificationPart, InputFile, ParameterRow,
    Traceability, UncertaintyPart, VolumePart, GRID_NODES, POINTS,
};
use std::path::{Path, PathBuf};
use thiserror::Error;
use trueaxis::data::{DataError, WorkingDirectory};
use trueaxis::error_model::{ErrorModel, ErrorModelError};
use trueaxis::identify::{identification_json, IdentifyError};
use trueaxis::instruments::ballbar::BallbarError;
use trueaxis::machine::{Machine, MachineError};

/// The built-in machine (`examples/machines/kx8five.toml`).
pub const MACHINE_TOML: &str = include_str!("../../../../examples/machines/kx8five.toml");
/// The errors the machine is simulated with: Andolfatto et al. 2011 Table 1 (`examples/errors/kx8five_table1.toml`).
pub const ERRORS_TOML: &str = include_str!("../../../../examples/errors/kx8five_table1.toml");
/// The campaign: 807 CapBall poses (`examples/campaigns/kx8five/`).
pub const CAMPAIGN_TOML: &str = include_str!("../../../../examples/campaigns/kx8five/campaign.toml");
pub const CAMPAIGN_POSES_CSV: &str = include_str!("../../../../examples/campaigns/kx8five/capball.csv");
/// The uncertainty sources: Andolfatto et al. 2011 Tables 3 and 4 with a cyclic drift (`examples/uncertainty/`).
pub const SOURCES_TOML: &str = include_str!("../../../../examples/uncertainty/kx8five_cyclic.toml");
/// The certificate particulars, instruments, decision rule and tolerances (`examples/report/`).
pub const CERTIFICATE_TOML: &str = include_str!("../../../../examples/report/kx8five_demo.toml");
/// The controller format whose tables the after-compensation map shows.
pub const CONTROLLER: &str = "heidenhain";

/// Steps reported to the progress callback.
pub const STEPS: usize = 7;

#[derive(Debug, Error)]
pub enum DemoError {
    #[error(transparent)]
    Machine(#[from] MachineError),
    #[error(transparent)]
    Errors(#[from] ErrorModelError),
    #[error(transparent)]
    Data(#[from] DataError),
    #[error(transparent)]
    Identify(#[from] IdentifyError),
    #[error(transparent)]
    Uncertainty(#[from] trueaxis::Error),
    #[error(transparent)]
    Ballbar(#[from] BallbarError),
    #[error(transparent)]
    Report(#[from] CalibrationError),
    /// The output directory could not be written: nothing was (the directory is as it was).
    #[error("{0}; nothing was written")]
    Output(#[source] DataError),
}

impl From<DemoError> for trueaxis::Error {
    /// An output directory that cannot be written is bad input (a bad `--out`, or the environment:
    /// a full disk, a permission, found in the cause); anything else is a failed computation, since
    /// the demo's inputs are built in.
    fn from(e: DemoError) -> trueaxis::Error {
        let kind = match e {
            DemoError::Output(_) | DemoError::Data(DataError::Write { .. }) => trueaxis::ErrorKind::Input,
            _ => trueaxis::ErrorKind::Computation,
        };
        trueaxis::Error::new(kind, e.to_string()).caused_by(e)
    }
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
    /// The same after compensation: the true machine at the set-points corrected for the identified
    /// errors on the exact chain.
    pub max_after_um: f64,
    pub rms_after_um: f64,
    /// Identified parameters with their true values, least-squares standard uncertainties and
    /// Monte Carlo intervals.
    pub parameters: Vec<ParameterRow>,
    pub residual_rms_um: f64,
    pub monte_carlo_sequences: usize,
    /// Circular deviation G (um) of the CCW and CW ballbar runs.
    pub ballbar_g_um: Vec<f64>,
    pub files: Vec<PathBuf>,
}

/// The built-in machine and its true errors.
pub fn builtin() -> Result<(Machine, ErrorModel), DemoError> {
    let machine = Machine::from_toml_str(MACHINE_TOML, "built-in kx8five.toml")?;
    let errors = ErrorModel::from_toml_str(ERRORS_TOML, "built-in kx8five errors", &machine)?;
    Ok((machine, errors))
}

/// Files are written through this, into the working directory, so that the summary lists them all.
pub(crate) struct Output {
    work: WorkingDirectory,
}

impl Output {
    /// The path of `name` while the demo runs (to read it back).
    pub fn path(&self, name: &str) -> PathBuf {
        self.work.path(name)
    }

    /// The path of `name` in the output folder, as the user will find it.
    pub fn final_path(&self, name: &str) -> PathBuf {
        self.work.final_path(name)
    }

    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<PathBuf, DemoError> {
        self.work.write(name, bytes).map_err(DemoError::Output)
    }

    /// An input of the report, named relative to the output folder.
    fn input(&self, role: &str, name: &str) -> Result<InputFile, DemoError> {
        let bytes = std::fs::read(self.path(name))
            .map_err(|source| DataError::Read { path: self.final_path(name).display().to_string(), source })?;
        Ok(InputFile::of_bytes(role, name, &bytes))
    }
}

/// The true errors of the machine alone: [`ERRORS_TOML`] without the set-up errors of the CapBall
/// campaign (`TX TY TZ WX WY WZ`: where the balls sat), which the volumetric maps leave out
/// (`VolumePart::compute`).
pub fn machine_errors_toml() -> String {
    let setup = |line: &str| ["TX", "TY", "TZ", "WX", "WY", "WZ"].iter().any(|p| line.split('=').next().map(str::trim) == Some(*p));
    let mut text = String::from("# errors_true.toml without the set-up errors of the campaign (TX TY TZ WX WY WZ)\n");
    for line in ERRORS_TOML.lines().filter(|l| !setup(l)) {
        text.push_str(line);
        text.push('\n');
    }
    text
}

/// Runs the demo into `out_dir`; `progress(step, STEPS, message)` is called before each step.
pub fn run(out_dir: &Path, progress: &mut dyn FnMut(usize, usize, &str)) -> Result<DemoSummary, DemoError> {
    let (machine, truth) = builtin()?;
    let mut out = Output { work: WorkingDirectory::create(out_dir).map_err(DemoError::Output)? };
    out.write("machine.toml", MACHINE_TOML.as_bytes())?;
    out.write("errors_true.toml", ERRORS_TOML.as_bytes())?;
    out.write("errors_true_machine.toml", machine_errors_toml().as_bytes())?;

    progress(1, STEPS, "simulating the CapBall campaign (807 poses, sensor noise, cyclic drift)");
    let simulated = campaign::simulate(&machine, &truth, &mut out)?;
    progress(2, STEPS, "simulating ISO 230-4 ballbar circles and their diagnostics");
    let circle_input = ballbar::simulate(&machine, &truth, &mut out)?;
    out.write("report.toml", CERTIFICATE_TOML.as_bytes())?;
    let certificate = CertificateFile::from_toml_str(CERTIFICATE_TOML, "built-in report.toml").map_err(CalibrationError::Input)?;
    let mut circle = CirclePart::evaluate(&machine, circle_input)?;
    circle.input.path = out.final_path(ballbar::FILE);
    circle.reading_u_um = certificate.reading_uncertainty_um("ballbar");
    circle.description.push(report::circle_description());
    out.write("ballbar/xy_circle.svg", circle.svg.as_bytes())?;

    progress(3, STEPS, "identifying the link and setup errors");
    let mut identification = IdentificationPart::identify(&machine, &simulated.campaign_path, false)?;
    // the report names the campaign where the user finds it
    identification.campaign.origin = out.final_path("campaign/campaign.toml").display().to_string();
    identification.truth = Some(campaign::equivalent_truth(&machine, &truth, &identification)?);
    identification.description.push(report::campaign_description(&simulated));
    identification.notes.push(report::IDENTIFIABILITY_NOTE.into());
    out.write("identified.toml", identification.errors_text.as_bytes())?;

    progress(4, STEPS, "adaptive Monte Carlo uncertainty and budget (JCGM 101)");
    out.write("uncertainty/sources.toml", SOURCES_TOML.as_bytes())?;
    let sources = campaign::sources()?;
    let uncertainty =
        UncertaintyPart::evaluate(&identification, sources, "uncertainty/sources.toml", campaign::POINT_TIME_S, &mut |_, _| {})?;
    out.write("uncertainty/design.csv", uncertainty.design.to_csv().as_bytes())?;
    out.write("uncertainty/histograms.svg", uncertainty.histograms_svg.as_bytes())?;
    if let Some(svg) = &uncertainty.convergence_svg {
        out.write("uncertainty/convergence.svg", svg.as_bytes())?;
    }
    let mut json = identification_json(&identification.result, &identification.campaign);
    quote_the_report(&mut json, &identification.parameter_rows(Some(&uncertainty)));
    out.write("identification.json", format!("{json:#}\n").as_bytes())?;

    progress(5, STEPS, "compensation tables");
    let mut compensation =
        CompensationPart::compute(&machine, &identification.errors, "the identified errors (identified.toml)", POINTS, GRID_NODES)?;
    for f in compensation.csv_files(&machine, &identification.errors)? {
        out.write(&format!("compensation/{}", f.name), f.contents.as_bytes())?;
        compensation.files.push(format!("compensation/{}", f.name));
    }

    progress(6, STEPS, "volumetric error before and after compensation");
    // the controller's files from the identified errors, as `trueaxis compensate` writes and judges them
    let controller = compensation.controller(&machine, &identification.errors, CONTROLLER, None)?;
    for f in &controller.files {
        let name = format!("compensation-{CONTROLLER}/{}", f.name);
        out.write(&name, f.contents.as_bytes())?;
        compensation.files.push(name);
    }
    let mut volume = VolumePart::compute(&machine, &truth, &identification.errors, &compensation, None)?
        .ok_or_else(|| CalibrationError::Computation("the built-in machine has no linear axes to map".into()))?;
    volume.description.push(report::VOLUME_NOTE.into());
    out.write("volumetric_map.csv", volume.map.csv(&machine, &volume.before)?.as_bytes())?;
    out.write("volumetric_map.svg", volume.before_svg.as_bytes())?;
    out.write("volumetric_map_compensated.csv", volume.map.csv(&machine, &volume.after)?.as_bytes())?;
    out.write("volumetric_map_compensated.svg", volume.after_svg.as_bytes())?;

    progress(7, STEPS, "HTML report");
    let inputs = [
        ("machine", "machine.toml"),
        ("true errors (simulation)", "errors_true.toml"),
        ("true errors of the machine, without the campaign's set-up", "errors_true_machine.toml"),
        ("campaign", "campaign/campaign.toml"),
        ("campaign data (simulated)", "campaign/capball.csv"),
        ("uncertainty sources", "uncertainty/sources.toml"),
        ("ballbar circle (simulated)", ballbar::FILE),
        ("certificate particulars and tolerances", "report.toml"),
    ]
    .iter()
    .map(|(role, name)| out.input(role, name))
    .collect::<Result<Vec<_>, _>>()?;
    let parameters = identification.parameter_rows(Some(&uncertainty));
    let summary = DemoSummary {
        machine: machine.name.clone(),
        poses: volume.poses,
        max_um: volume.before_um.0,
        max_pose: volume.max_pose.clone(),
        rms_um: volume.before_um.1,
        max_after_um: volume.after_um.0,
        rms_after_um: volume.after_um.1,
        parameters,
        residual_rms_um: identification.result.residual_rms_um,
        monte_carlo_sequences: uncertainty.budget.total.sequences,
        ballbar_g_um: circle.result.runs.iter().map(|r| r.g_um).collect(),
        files: Vec::new(),
    };
    let extra = vec![report::reproduce_section(&circle.input, &compensation)];
    let traceability = Traceability::now(inputs, Some(format!("trueaxis demo --out {}", out_dir.display())));
    let calibration = CalibrationReport {
        title: certificate.certificate.title.clone().unwrap_or_else(|| "Calibration report (specimen)".into()),
        subtitle: format!(
            "{}: specimen of a simulated calibration with known errors; date of issue {}; trueaxis {}",
            machine.name,
            certificate.issue_date(&traceability.date),
            env!("CARGO_PKG_VERSION")
        ),
        machine: &machine,
        machine_notes: vec![report::MACHINE_NOTE.into()],
        identification: Some(identification),
        uncertainty: Some(uncertainty),
        volume: Some(volume),
        thermal_modes: None,
        thermal_drift: None,
        circles: vec![circle],
        rotary_ballbar: None,
        tmbb: None,
        fits: Vec::new(),
        positioning: Vec::new(),
        data_quality: None,
        compensation: Some(compensation),
        controller: Some(controller),
        extra,
        traceability,
        certificate,
    };
    calibration.check_tolerances("built-in report.toml")?;
    out.write("report.html", calibration.to_html().as_bytes())?;
    out.write("report.pdf", &calibration.to_pdf()?)?;
    let files = out.work.files();
    out.work.commit().map_err(DemoError::Output)?;
    Ok(DemoSummary { files, ..summary })
}

/// The identification's JSON with the report's one uncertainty per parameter (`ParameterRow::json`):
/// `expanded_uncertainty` (k = 2) and its method; the least-squares standard uncertainty of
/// `trueaxis identify` renamed to say what it is.
fn quote_the_report(json: &mut serde_json::Value, rows: &[ParameterRow]) {
    for row in rows {
        let Some(entry) = json["parameters"].get_mut(&row.name).and_then(|e| e.as_object_mut()) else { continue };
        if let Some(u) = entry.remove("std_uncertainty") {
            entry.insert("least_squares_std_uncertainty".into(), u);
        }
        let quoted = row.json();
        for key in ["expanded_uncertainty", "coverage_factor", "uncertainty_method"] {
            entry.insert(key.into(), quoted[key].clone());
        }
    }
}
