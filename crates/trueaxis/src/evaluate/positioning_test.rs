//! An ISO 230-2 positioning test from its file, end to end: the table read forgivingly (CSV or a
//! Renishaw `.rtl`), the plausibility checks of its readings, the correction to 20 degC (the
//! options given, else the file's recorded environment), the evaluation, and the document of
//! `trueaxis iso230-2 --json`, with the screening of the readings (`evaluate::positioning_screening`). The command line and the Python package both call [`evaluate_file`],
//! so that they give the same result, warnings and document.
//!
//! Units: targets in mm (deg for a rotary axis), deviations and results in um (urad), coverage
//! factor 2 (ISO 230-2:2014); temperatures in degC, expansion coefficients in um/m/K.

use super::iso230_2::{evaluate, plausibility, runs_of, Iso2302Result, PositioningData};
use super::EvaluateError;
use crate::data::CsvTable;
use crate::instruments::{TableCorrection, TableCorrectionError, TemperatureOptions};
use crate::io::plausibility::split_findings;
use serde_json::Value;

/// The outcome of a positioning test.
#[derive(Clone, Debug)]
pub struct PositioningTest {
    /// The readings as evaluated (corrected to 20 degC when a correction applied), with the file's
    /// metadata.
    pub data: PositioningData,
    pub result: Iso2302Result,
    /// Warnings of reading the file and of the plausibility checks, each naming the file.
    pub warnings: Vec<String>,
    /// Notes on the correction to 20 degC (what the file's environment did).
    pub notes: Vec<String>,
    /// Where the correction to 20 degC came from (`AppliedCorrection::json`): null for none.
    pub temperature_correction: Value,
    /// What screening found suspect in the readings (`evaluate::positioning_screening`), each with the result
    /// without it; the evaluation above is ISO 230-2's, of all readings.
    pub findings: Vec<crate::screen::Finding>,
}

impl PositioningTest {
    /// The document of `trueaxis iso230-2 --json`: the results ([`Iso2302Result::to_json`]), the
    /// file's `metadata` and the `temperature_correction`.
    pub fn to_json(&self) -> Value {
        let mut doc = self.result.to_json();
        doc["metadata"] = self.data.metadata.to_json();
        doc["temperature_correction"] = self.temperature_correction.clone();
        doc["data_quality"] = crate::screen::findings_json(&self.findings);
        doc
    }
}

/// Reads and evaluates the positioning test in `path` (a table or a Renishaw `.rtl` file; see
/// [`super::iso230_2::read_runs`]) with the correction to 20 degC of `temperature`.
pub fn evaluate_file(path: impl AsRef<std::path::Path>, temperature: &TemperatureOptions) -> Result<PositioningTest, EvaluateError> {
    evaluate_table(&CsvTable::read(path)?, temperature)
}

/// As [`evaluate_file`], for a table already read (its origin names it in messages). A plausibility
/// check that refuses the readings (e.g. deviations 1000 times too small: mm written as um) is an
/// input error; one that warns is returned in [`PositioningTest::warnings`]. A correction to 20
/// degC applies to linear axes only; its temperature columns are read from `table`.
pub fn evaluate_table(table: &CsvTable, temperature: &TemperatureOptions) -> Result<PositioningTest, EvaluateError> {
    let name = table.origin().to_string();
    let mut data = runs_of(table)?;
    let warnings = split_findings(plausibility(table, &data)?, table.warnings()).map_err(EvaluateError::Input)?;
    let applied = temperature.resolve(&data.metadata, &name).map_err(|e| EvaluateError::Input(e.to_string()))?;
    if !applied.corrections.is_empty() {
        if data.rotary {
            return Err(EvaluateError::Invalid {
                origin: name,
                message: "a correction to 20 degC (thermal expansion) applies to linear axes; this test is of a rotary axis (--no-file-temperature)"
                    .into(),
            });
        }
        // the readings are the table's rows in order
        let targets: Vec<f64> = data.readings.iter().map(|r| r.target).collect();
        let devs: Vec<f64> = data.readings.iter().map(|r| r.dev).collect();
        let corrected = TableCorrection::apply_all(&applied.corrections, table, &targets, &devs).map_err(|e| match e {
            TableCorrectionError::Data(d) => EvaluateError::Data(d),
            TableCorrectionError::Scale(s) => EvaluateError::Invalid { origin: name.clone(), message: s.to_string() },
        })?;
        for (r, dev) in data.readings.iter_mut().zip(corrected) {
            r.dev = dev;
        }
    }
    let findings = crate::evaluate::positioning_screening::positioning(&data, Some(table));
    if let Some(f) = findings.iter().find(|f| f.refuse) {
        return Err(EvaluateError::Input(f.line()));
    }
    let result = evaluate(&data)?;
    Ok(PositioningTest { data, result, warnings, notes: applied.notes, temperature_correction: applied.json, findings })
}
