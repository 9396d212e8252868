//! The demo's steps in order, each writing its files into the output folder: the built-in machine
//! and its true errors; the simulated CapBall campaign and ballbar circle (`trueaxis::simulation`);
//! identification, adaptive Monte Carlo uncertainty (JCGM 101), compensation tables and the
//! volumetric error before and after compensation, each computed by the part of the calibration
//! report that `trueaxis report` computes it with (`trueaxis_report::calibration`); the report
//! itself ([`super::specimen`]).

use super::error::DemoError;
use super::folder::Output;
use super::notes;
use super::specimen;
use super::summary::DemoSummary;
use std::path::{Path, PathBuf};
use trueaxis::error_model::ErrorModel;
use trueaxis::identify::{identification_json, Campaign};
use trueaxis::instruments::ballbar::Plane;
use trueaxis::machine::Machine;
use trueaxis::simulation::capball::{self, SimulatedCampaign, POINT_TIME_S};
use trueaxis::simulation::{circle, kx8five};
use trueaxis_report::calibration::{
    CalibrationError, CertificateFile, CircleInput, CirclePart, CompensationPart, ControllerPart, IdentificationPart, ParameterRow,
    UncertaintyPart, VolumePart, GRID_NODES, POINTS,
};

/// The certificate particulars, instruments, decision rule and tolerances (`examples/report/`).
pub const CERTIFICATE_TOML: &str = include_str!("../../../../examples/report/kx8five_demo.toml");
/// The controller format whose tables the after-compensation map shows.
pub const CONTROLLER: &str = "heidenhain";
/// The circle file, relative to the output folder.
pub const CIRCLE_FILE: &str = "ballbar/xy_circle.csv";
const CAMPAIGN_FILE: &str = "campaign/campaign.toml";

/// Steps reported to the progress callback.
pub const STEPS: usize = 7;

/// Runs the demo into `out_dir`; `progress(step, STEPS, message)` is called before each step.
pub fn run(out_dir: &Path, progress: &mut dyn FnMut(usize, usize, &str)) -> Result<DemoSummary, DemoError> {
    let machine = kx8five::machine()?;
    let truth = kx8five::true_errors(&machine)?;
    let mut out = Output::create(out_dir)?;
    out.write("machine.toml", kx8five::MACHINE_TOML.as_bytes())?;
    out.write("errors_true.toml", kx8five::ERRORS_TOML.as_bytes())?;
    out.write("errors_true_machine.toml", kx8five::machine_errors_toml().as_bytes())?;

    progress(1, STEPS, "simulating the CapBall campaign (807 poses, sensor noise, cyclic drift)");
    let (campaign_path, simulated) = simulate_campaign(&machine, &truth, &mut out)?;
    progress(2, STEPS, "simulating ISO 230-4 ballbar circles and their diagnostics");
    let (certificate, circle) = ballbar(&machine, &truth, &mut out)?;
    progress(3, STEPS, "identifying the link and setup errors");
    let identification = identify(&machine, &truth, &campaign_path, &simulated, &mut out)?;
    progress(4, STEPS, "adaptive Monte Carlo uncertainty and budget (JCGM 101)");
    let uncertainty = uncertainty(&identification, &mut out)?;
    progress(5, STEPS, "compensation tables");
    let mut compensation = compensation_tables(&machine, &identification.errors, &mut out)?;
    progress(6, STEPS, "volumetric error before and after compensation");
    let controller = controller_files(&machine, &identification.errors, &mut compensation, &mut out)?;
    let volume = volume(&machine, &truth, &identification.errors, &compensation, &mut out)?;
    progress(7, STEPS, "HTML report");
    let parts = specimen::Parts { certificate, circle, identification, uncertainty, compensation, controller, volume };
    specimen::write(&machine, parts, out_dir, out)
}

/// Step 1: the campaign and its poses, and the readings simulated on them as its data.
fn simulate_campaign(machine: &Machine, truth: &ErrorModel, out: &mut Output) -> Result<(PathBuf, SimulatedCampaign), DemoError> {
    let campaign_path = out.write(CAMPAIGN_FILE, kx8five::CAMPAIGN_TOML.as_bytes())?;
    out.write("campaign/capball.csv", kx8five::CAMPAIGN_POSES_CSV.as_bytes())?;
    let campaign = Campaign::load(&campaign_path, machine)?;
    let simulated = capball::simulate(&campaign, machine, truth, &kx8five::sources()?)?;
    out.write("campaign/capball.csv", simulated.csv.as_bytes())?;
    Ok((campaign_path, simulated))
}

/// Step 2: the simulated circle, its file and its evaluation; the certificate (its reading
/// uncertainty of the ballbar).
fn ballbar(machine: &Machine, truth: &ErrorModel, out: &mut Output) -> Result<(CertificateFile, CirclePart), DemoError> {
    let input = CircleInput { path: out.path(CIRCLE_FILE), plane: Plane::Xy, radius: circle::RADIUS_MM, centre: circle::centre(machine) };
    let csv = circle::simulate(machine, truth, input.centre, input.centre_pose(machine))?;
    out.write(CIRCLE_FILE, csv.as_bytes())?;
    out.write("report.toml", CERTIFICATE_TOML.as_bytes())?;
    let certificate = CertificateFile::from_toml_str(CERTIFICATE_TOML, "built-in report.toml")?;
    let mut part = CirclePart::evaluate(machine, input)?;
    part.input.path = out.final_path(CIRCLE_FILE);
    part.reading_u_um = certificate.reading_uncertainty_um("ballbar");
    part.description.push(notes::circle_description());
    out.write("ballbar/xy_circle.svg", part.svg.as_bytes())?;
    Ok((certificate, part))
}

/// Step 3: the identification, with the true values in the campaign's parameter set.
fn identify(
    machine: &Machine,
    truth: &ErrorModel,
    campaign_path: &Path,
    simulated: &SimulatedCampaign,
    out: &mut Output,
) -> Result<IdentificationPart, DemoError> {
    let mut identification = IdentificationPart::identify(machine, campaign_path, false)?;
    // the report names the campaign where the user finds it
    identification.campaign.origin = out.final_path(CAMPAIGN_FILE).display().to_string();
    identification.truth = Some(capball::equivalent_truth(machine, truth, &identification.campaign)?);
    identification.description.push(notes::campaign_description(simulated));
    identification.notes.push(notes::IDENTIFIABILITY_NOTE.into());
    out.write("identified.toml", identification.errors_text.as_bytes())?;
    Ok(identification)
}

/// Step 4: the Monte Carlo uncertainty with the built-in sources, and the identification's JSON
/// with the report's uncertainty of each parameter.
fn uncertainty(identification: &IdentificationPart, out: &mut Output) -> Result<UncertaintyPart, DemoError> {
    out.write("uncertainty/sources.toml", kx8five::SOURCES_TOML.as_bytes())?;
    let sources = kx8five::sources()?;
    let uncertainty = UncertaintyPart::evaluate(identification, sources, "uncertainty/sources.toml", POINT_TIME_S, &mut |_, _| {})?;
    out.write("uncertainty/design.csv", uncertainty.design.to_csv().as_bytes())?;
    out.write("uncertainty/histograms.svg", uncertainty.histograms_svg.as_bytes())?;
    if let Some(svg) = &uncertainty.convergence_svg {
        out.write("uncertainty/convergence.svg", svg.as_bytes())?;
    }
    let mut json = identification_json(&identification.result, &identification.campaign);
    quote_the_report(&mut json, &identification.parameter_rows(Some(&uncertainty)));
    out.write("identification.json", format!("{json:#}\n").as_bytes())?;
    Ok(uncertainty)
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

/// Step 5: the compensation tables of the identified errors, as CSV.
fn compensation_tables(machine: &Machine, identified: &ErrorModel, out: &mut Output) -> Result<CompensationPart, DemoError> {
    let mut compensation = CompensationPart::compute(machine, identified, "the identified errors (identified.toml)", POINTS, GRID_NODES)?;
    for f in compensation.csv_files(machine, identified)? {
        out.write(&format!("compensation/{}", f.name), f.contents.as_bytes())?;
        compensation.files.push(format!("compensation/{}", f.name));
    }
    Ok(compensation)
}

/// Step 6, first half: the controller's files from the identified errors, as `trueaxis compensate`
/// writes and judges them.
fn controller_files(
    machine: &Machine,
    identified: &ErrorModel,
    compensation: &mut CompensationPart,
    out: &mut Output,
) -> Result<ControllerPart, DemoError> {
    let controller = compensation.controller(machine, identified, CONTROLLER, None)?;
    for f in &controller.files {
        let name = format!("compensation-{CONTROLLER}/{}", f.name);
        out.write(&name, f.contents.as_bytes())?;
        compensation.files.push(name);
    }
    Ok(controller)
}

/// Step 6: the volumetric error of the true machine before compensation and after, driven to the
/// set-points the identified errors correct.
fn volume(
    machine: &Machine,
    truth: &ErrorModel,
    identified: &ErrorModel,
    compensation: &CompensationPart,
    out: &mut Output,
) -> Result<VolumePart, DemoError> {
    let mut volume = VolumePart::compute(machine, truth, identified, compensation, None)?
        .ok_or_else(|| CalibrationError::Computation("the built-in machine has no linear axes to map".into()))?;
    volume.description.push(notes::VOLUME_NOTE.into());
    out.write("volumetric_map.csv", volume.map.csv(machine, &volume.before)?.as_bytes())?;
    out.write("volumetric_map.svg", volume.before_svg.as_bytes())?;
    out.write("volumetric_map_compensated.csv", volume.map.csv(machine, &volume.after)?.as_bytes())?;
    out.write("volumetric_map_compensated.svg", volume.after_svg.as_bytes())?;
    Ok(volume)
}
