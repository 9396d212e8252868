//! The demo's calibration report, a specimen: the parts the steps computed, assembled as
//! `trueaxis report` assembles them (`trueaxis_report::calibration::CalibrationReport`), with the
//! demo's notes and the commands that repeat each step; checked against the tolerances of the
//! built-in report.toml and written as HTML and PDF, with the summary the command prints.

use super::error::DemoError;
use super::folder::Output;
use super::job::CIRCLE_FILE;
use super::notes;
use super::summary::DemoSummary;
use std::path::Path;
use trueaxis::machine::Machine;
use trueaxis_report::calibration::{
    CalibrationReport, CertificateFile, CirclePart, CompensationPart, ControllerPart, IdentificationPart, InputFile, Traceability,
    UncertaintyPart, VolumePart,
};

/// The parts the steps computed.
pub struct Parts {
    pub certificate: CertificateFile,
    pub circle: CirclePart,
    pub identification: IdentificationPart,
    pub uncertainty: UncertaintyPart,
    pub compensation: CompensationPart,
    pub controller: ControllerPart,
    pub volume: VolumePart,
}

/// The report's input files, named relative to the output folder, with their roles.
const INPUTS: [(&str, &str); 8] = [
    ("machine", "machine.toml"),
    ("true errors (simulation)", "errors_true.toml"),
    ("true errors of the machine, without the campaign's set-up", "errors_true_machine.toml"),
    ("campaign", "campaign/campaign.toml"),
    ("campaign data (simulated)", "campaign/capball.csv"),
    ("uncertainty sources", "uncertainty/sources.toml"),
    ("ballbar circle (simulated)", CIRCLE_FILE),
    ("certificate particulars and tolerances", "report.toml"),
];

/// Step 7: the report, written as report.html and report.pdf; the folder swapped in whole.
pub fn write(machine: &Machine, parts: Parts, out_dir: &Path, mut out: Output) -> Result<DemoSummary, DemoError> {
    let inputs = INPUTS.iter().map(|(role, name)| out.input(role, name)).collect::<Result<Vec<InputFile>, _>>()?;
    let summary = DemoSummary::of(machine, &parts.identification, &parts.uncertainty, &parts.volume, &parts.circle);
    let traceability = Traceability::now(inputs, Some(format!("trueaxis demo --out {}", out_dir.display())));
    let calibration = report(machine, parts, traceability);
    calibration.check_tolerances("built-in report.toml")?;
    out.write("report.html", calibration.to_html().as_bytes())?;
    out.write("report.pdf", &calibration.to_pdf()?)?;
    let files = out.commit()?;
    Ok(DemoSummary { files, ..summary })
}

fn report(machine: &Machine, parts: Parts, traceability: Traceability) -> CalibrationReport<'_> {
    let Parts { certificate, circle, identification, uncertainty, compensation, controller, volume } = parts;
    let extra = vec![notes::reproduce_section(&circle.input, &compensation)];
    CalibrationReport {
        title: certificate.certificate.title.clone().unwrap_or_else(|| "Calibration report (specimen)".into()),
        subtitle: format!(
            "{}: specimen of a simulated calibration with known errors; date of issue {}; trueaxis {}",
            machine.name,
            certificate.issue_date(&traceability.date),
            env!("CARGO_PKG_VERSION")
        ),
        machine,
        machine_notes: vec![notes::MACHINE_NOTE.into()],
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
    }
}
