//! The report's data-quality part: every finding of the screening of every input file
//! (`trueaxis::screen`, docs/screening.md), with the file, where in it (run, column, lines), the
//! kind of damage, what was seen and what it means for the result; "no finding" for a clean file.
//! The results of the other parts are of every reading (ISO 230-2 as the standard defines it);
//! the findings stand beside them.

use super::CalibrationError;
use crate::html::Section;
use serde_json::{json, Value};
use trueaxis::screen::{findings_json, Finding};

/// The findings of one input file.
#[derive(Clone, Debug)]
pub struct ScreenedFile {
    pub file: String,
    /// What the file is in this report: "ISO 230-2 positioning test", "identification campaign" ...
    pub role: String,
    pub findings: Vec<Finding>,
}

/// Every screened input of the report.
#[derive(Clone, Debug, Default)]
pub struct DataQualityPart {
    pub files: Vec<ScreenedFile>,
}

impl DataQualityPart {
    /// Adds `file` with its findings (none: screened and clean). A refusing finding refuses the
    /// report (a result from that file would be meaningless).
    pub fn add(&mut self, file: &str, role: &str, findings: Vec<Finding>) -> Result<(), CalibrationError> {
        if let Some(f) = findings.iter().find(|f| f.refuse) {
            return Err(CalibrationError::Input(f.line()));
        }
        self.files.push(ScreenedFile { file: file.into(), role: role.into(), findings });
        Ok(())
    }

    /// The screening of the report's positioning tests, circles and identification campaign (each
    /// measurement's data file).
    pub fn of_parts(
        positioning: &[super::PositioningPart],
        circles: &[super::CirclePart],
        identification: Option<&super::IdentificationPart>,
    ) -> Result<DataQualityPart, CalibrationError> {
        let mut part = DataQualityPart::default();
        for p in positioning {
            part.add(&p.path.display().to_string(), "ISO 230-2 positioning test", p.test.findings.clone())?;
        }
        for c in circles {
            part.add(&c.input.path.display().to_string(), "ISO 230-4 circular test", c.findings.clone())?;
        }
        if let Some(id) = identification {
            use trueaxis::identify::campaign_screening::{after_fit, before_fit};
            let campaign = &id.campaign;
            let mut findings = before_fit(campaign);
            if campaign.measurements.iter().all(|m| m.readings.is_some()) && id.design.rows() == id.result.residuals.len() {
                findings.extend(after_fit(campaign, &id.design, &id.result));
            }
            for m in &campaign.measurements {
                let file = m.data.display().to_string();
                let own = findings.iter().filter(|f| f.file == file).cloned().collect();
                part.add(&file, &format!("identification campaign, measurement {}", m.name), own)?;
            }
        }
        Ok(part)
    }

    /// Number of findings over all files.
    pub fn count(&self) -> usize {
        self.files.iter().map(|f| f.findings.len()).sum()
    }

    pub fn section(&self) -> Section {
        let count = self.count();
        let mut s = Section::new("data-quality", "Data quality").paragraph(format!(
            "Every input file was screened before it was evaluated (docs/screening.md): runs or columns in another unit or of another \
             axis, stuck sensors, repeated records, outlier readings (robust scale: median and MAD), steps and gaps in time series, \
             temperatures by sensor role, a ballbar file whose axes do not describe its circle. {} The results in this report are of \
             every reading, as the standards define them; each finding says what it would change.",
            match count {
                0 => "No file gave a finding.".to_string(),
                1 => "One finding.".to_string(),
                n => format!("{n} findings."),
            }
        ));
        let rows = self
            .files
            .iter()
            .flat_map(|f| {
                let clean = vec![f.file.clone(), f.role.clone(), "-".into(), "-".into(), "no finding".into(), "-".into()];
                let found = f.findings.iter().map(move |x| {
                    let consequence = if x.consequence.is_empty() { "-".into() } else { x.consequence.clone() };
                    vec![f.file.clone(), f.role.clone(), x.place.clone(), x.kind.name().into(), x.message.clone(), consequence]
                });
                let rows: Vec<Vec<String>> = if f.findings.is_empty() { vec![clean] } else { found.collect() };
                rows
            })
            .collect();
        s = s.table(
            "Findings of the screening, by input file",
            &["file", "input", "where", "kind", "what was seen", "what it means for the result"],
            rows,
        );
        s
    }

    /// `data_quality` of `report --json`: per file its role and findings (an empty list: clean).
    pub fn to_json(&self) -> Value {
        self.files.iter().map(|f| json!({"file": f.file, "input": f.role, "findings": findings_json(&f.findings)})).collect()
    }
}
