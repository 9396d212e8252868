//! The calibration report assembled from a [`ReportRequest`]: each part computed from its files by
//! the code of the command that does it alone (identify, uncertainty, iso230-2, ballbar iso230-4,
//! ballbar identify and tmbb, thermal, fit, compensate, predict --frame machine), in the order of
//! the report, with the data quality of every input and the list of input files; checked against
//! the tolerances of report.toml. The command line, a script and the Python package make the same
//! report from the same request.

mod input_files;
mod request;
mod rotary;
mod thermal_parts;

pub use request::{ReportRequest, POINT_TIME_S, ROTARY_BARS_MM, THERMAL_MODES, TMBB_SETUP_MM};

use super::{
    CalibrationError, CalibrationReport, CertificateFile, CircleInput, CirclePart, CompensationPart, ControllerPart, DataQualityPart,
    FitPart, IdentificationPart, PositioningPart, Traceability, UncertaintyPart, VolumePart, CONTROLLER_FORMATS, GRID_NODES,
};
use request::bad;
use std::path::Path;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::screen::Finding;
use trueaxis::uncertainty::Sources;

/// Fits the `[[fit]]` tables of report.toml (given the certificate and its path) by the
/// definition of `trueaxis fit`, which the caller holds.
pub type FitTables<'f, E> = dyn FnMut(&CertificateFile, &Path) -> Result<Vec<FitPart>, E> + 'f;

/// Computes every part the request allows, on `machine` (loaded from `request.machine`).
/// `progress` is told what is being computed; `fits` fits the `[[fit]]` tables of report.toml.
pub fn assemble<'a, E: From<CalibrationError>>(
    request: &ReportRequest,
    machine: &'a Machine,
    progress: &mut dyn FnMut(&str),
    fits: &mut FitTables<'_, E>,
) -> Result<CalibrationReport<'a>, E> {
    let circle_inputs = request.circles()?;
    if !(request.point_time.is_finite() && request.point_time >= 0.0) {
        return Err(bad(format!("--point-time must be a non-negative number of seconds, got {}", request.point_time)).into());
    }
    let certificate = certificate(request)?;
    let identification = identification(request, machine, progress)?;
    let uncertainty = uncertainty(request, identification.as_ref(), progress)?;
    progress("positioning tests");
    let positioning = request.positioning.iter().map(|p| PositioningPart::evaluate(p, &certificate)).collect::<Result<Vec<_>, _>>()?;
    progress("ballbar circles");
    let circles = circles(machine, circle_inputs, &certificate)?;
    progress("rotary-axis ballbar steps");
    let rotary_ballbar = rotary::rotary_ballbar(request, machine)?;
    progress("two-length rotary-table test");
    let tmbb = rotary::tmbb(request)?;
    let (compensation, controller, volume) = compensation(request, machine, identification.as_ref(), progress)?;
    let (thermal_modes, thermal_drift, thermal_findings) = thermal_parts::thermal_parts(request, progress)?;
    progress("direct measurements");
    let fits = match &request.certificate {
        Some(path) => fits(&certificate, path)?,
        None => Vec::new(),
    };
    let mut data_quality = DataQualityPart::of_parts(&positioning, &circles, identification.as_ref())?;
    add_findings(&mut data_quality, &fits, request.thermal_data.as_deref().zip(thermal_findings))?;
    let inputs = input_files::input_files(request, identification.as_ref(), &fits)?;
    let traceability = Traceability::now(inputs, request.command.clone());
    let issued = certificate.issue_date(&traceability.date);
    let report = CalibrationReport {
        title: request
            .title
            .clone()
            .or_else(|| certificate.certificate.title.clone())
            .unwrap_or_else(|| format!("Calibration report: {}", machine.name)),
        subtitle: format!("Date of issue {issued}; {}", traceability.software),
        machine,
        machine_notes: Vec::new(),
        identification,
        uncertainty,
        volume,
        thermal_modes,
        thermal_drift,
        circles,
        rotary_ballbar,
        tmbb,
        fits,
        positioning,
        data_quality: (!data_quality.files.is_empty()).then_some(data_quality),
        compensation: Some(compensation),
        controller,
        extra: Vec::new(),
        traceability,
        certificate,
    };
    if let Some(path) = &request.certificate {
        report.check_tolerances(&path.display().to_string())?;
    }
    Ok(report)
}

/// The screening findings of the direct measurements and of the thermal campaign.
fn add_findings(
    data_quality: &mut DataQualityPart,
    fits: &[FitPart],
    thermal: Option<(&Path, Vec<Finding>)>,
) -> Result<(), CalibrationError> {
    for f in fits {
        let role = format!("direct measurement ({})", f.name());
        data_quality.add(&f.file.display().to_string(), &role, f.report.findings.clone())?;
    }
    if let Some((path, findings)) = thermal {
        data_quality.add(&path.display().to_string(), "thermal campaign", findings)?;
    }
    Ok(())
}

/// report.toml (or the default certificate), and a known controller format.
fn certificate(request: &ReportRequest) -> Result<CertificateFile, CalibrationError> {
    let certificate = match &request.certificate {
        Some(path) => CertificateFile::load(path)?,
        None => CertificateFile::default(),
    };
    if let Some(c) = &request.controller {
        if !CONTROLLER_FORMATS.contains(&c.as_str()) {
            return Err(bad(format!("--controller `{c}` is not a controller format; give one of {}", CONTROLLER_FORMATS.join(", "))));
        }
    }
    Ok(certificate)
}

/// The identification of the campaign, if given.
fn identification(
    request: &ReportRequest,
    machine: &Machine,
    progress: &mut dyn FnMut(&str),
) -> Result<Option<IdentificationPart>, CalibrationError> {
    let Some(path) = &request.campaign else { return Ok(None) };
    progress("identification");
    Ok(Some(IdentificationPart::identify(machine, path, request.allow_rank_deficient)?))
}

/// The Monte Carlo uncertainty of the identification with the sources, if given.
fn uncertainty(
    request: &ReportRequest,
    identification: Option<&IdentificationPart>,
    progress: &mut dyn FnMut(&str),
) -> Result<Option<UncertaintyPart>, CalibrationError> {
    let (Some(path), Some(id)) = (&request.sources, identification) else { return Ok(None) };
    let sources = Sources::load(path)?;
    let origin = path.display().to_string();
    let mut sequences = |stage: Option<&str>, sequence: usize| {
        progress(&format!("Monte Carlo, {}: sequence {sequence}", stage.map_or("all sources".into(), |s| format!("`{s}` alone"))));
    };
    Ok(Some(UncertaintyPart::evaluate(id, sources, &origin, request.point_time, &mut sequences)?))
}

/// The circles evaluated, each with the ballbar's reading uncertainty of report.toml.
fn circles(machine: &Machine, inputs: Vec<CircleInput>, certificate: &CertificateFile) -> Result<Vec<CirclePart>, CalibrationError> {
    let mut circles = inputs.into_iter().map(|c| CirclePart::evaluate(machine, c)).collect::<Result<Vec<_>, _>>()?;
    for c in &mut circles {
        c.reading_u_um = certificate.reading_uncertainty_um("ballbar");
    }
    Ok(circles)
}

/// The compensation of the error values (given, or identified), the controller's files if asked
/// for, and the volumetric error before and after.
fn compensation(
    request: &ReportRequest,
    machine: &Machine,
    identification: Option<&IdentificationPart>,
    progress: &mut dyn FnMut(&str),
) -> Result<(CompensationPart, Option<ControllerPart>, Option<VolumePart>), CalibrationError> {
    let loaded;
    let (errors, origin): (&ErrorModel, String) = match (&request.errors, identification) {
        (Some(path), _) => {
            loaded = ErrorModel::load(path, machine)?;
            (&loaded, format!("the error values of {}", path.display()))
        }
        (None, Some(id)) => (&id.errors, format!("the errors identified from {}", id.campaign.origin)),
        (None, None) => return Err(bad("give --errors or --campaign")),
    };
    progress("compensation tables and volumetric error");
    let compensation = CompensationPart::compute(machine, errors, &origin, request.points, GRID_NODES)?;
    let controller = match &request.controller {
        Some(format) => Some(compensation.controller(machine, errors, format, None)?),
        None => None,
    };
    let volume = VolumePart::compute(machine, errors, errors, &compensation, None)?.map(|mut v| {
        v.description.push(volume_note(&origin, request.controller.as_deref()));
        v
    });
    Ok((compensation, controller, volume))
}

/// What the volumetric maps of given error values show.
fn volume_note(origin: &str, controller: Option<&str>) -> String {
    format!(
        "The machine is taken to have {origin}, and the corrections are computed from them. {} How well the errors themselves are known is the uncertainty of their measurement or identification.",
        match controller {
            Some(c) => format!(
                "The map after compensation shows the exact correction at each pose; what the {} files leave is on the compensation page.",
                super::controller_name(c)
            ),
            None => "The exact correction leaves only the corrector's tolerance; give --controller to see what a controller's files leave.".to_string(),
        }
    )
}
