//! The input files of a request with their roles, as the inputs section lists them (size in
//! bytes and SHA-256 of each): the machine, errors, campaign (its data and nominal errors), sources,
//! report.toml, positioning tests, circles, rotary-axis steps, direct measurements, the two-length
//! test, the thermal files.

use super::super::{CalibrationError, FitPart, IdentificationPart, InputFile};
use super::request::ReportRequest;
use std::path::PathBuf;

pub fn input_files(
    request: &ReportRequest,
    identification: Option<&IdentificationPart>,
    fits: &[FitPart],
) -> Result<Vec<InputFile>, CalibrationError> {
    let mut files: Vec<(&str, PathBuf)> = vec![("machine", request.machine.clone())];
    if let Some(e) = &request.errors {
        files.push(("error values", e.clone()));
    }
    if let (Some(c), Some(id)) = (&request.campaign, identification) {
        files.push(("campaign", c.clone()));
        if let Some(n) = &id.campaign.nominal_errors {
            files.push(("campaign nominal errors", n.clone()));
        }
        for m in &id.campaign.measurements {
            files.push(("campaign data", m.data.clone()));
        }
    }
    if let Some(s) = &request.sources {
        files.push(("uncertainty sources", s.clone()));
    }
    if let Some(c) = &request.certificate {
        files.push(("certificate particulars and tolerances", c.clone()));
    }
    for p in &request.positioning {
        files.push(("positioning test", p.clone()));
    }
    for c in &request.ballbar {
        files.push(("ballbar circle", c.clone()));
    }
    for (c, step) in request.rotary_ballbar.iter().zip(["A1", "A2", "C1", "C2"]) {
        files.push((step_role(step), c.clone()));
    }
    for f in fits.iter().filter(|f| f.direction != Some('-')) {
        files.push(("direct measurement (fit)", f.file.clone()));
    }
    for (c, role) in request.tmbb.iter().zip(["two-length ballbar test, short bar", "two-length ballbar test, long bar"]) {
        files.push((role, c.clone()));
    }
    for (role, path) in [
        ("thermal model", &request.thermal_model),
        ("thermal error model", &request.thermal_error),
        ("thermal campaign", &request.thermal_data),
    ] {
        if let Some(p) = path {
            files.push((role, p.clone()));
        }
    }
    files.iter().map(|(role, path)| Ok(InputFile::read(role, path)?)).collect()
}

fn step_role(step: &str) -> &'static str {
    match step {
        "A1" => "rotary-axis ballbar step A1",
        "A2" => "rotary-axis ballbar step A2",
        "C1" => "rotary-axis ballbar step C1",
        _ => "rotary-axis ballbar step C2",
    }
}
