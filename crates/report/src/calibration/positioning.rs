//! The positioning part of a calibration report: ISO 230-2 tests of linear and rotary axes read
//! from their files (a table or a Renishaw `.rtl`) and evaluated as `trueaxis iso230-2` evaluates
//! them (the correction to 20 degC from the file's recorded environment), each result with one
//! expanded uncertainty U (k = 2) from the contributors of ISO 230-2 Annex A
//! ([`trueaxis::evaluate::positioning_uncertainty`]), its budget, and the plot of the readings.

use super::super::html::Section;
use super::super::iso230_2_svg;
use super::ballbar::file_name;
use super::certificate::CertificateFile;
use super::conformity::{DecisionRule, Item};
use super::quantity::{quantity, with_uncertainty};
use super::CalibrationError;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use trueaxis::evaluate::positioning_test::{evaluate_file, PositioningTest};
use trueaxis::evaluate::positioning_uncertainty::{positioning_uncertainty, PositioningUncertainty, PositioningUncertaintyInputs};
use trueaxis::instruments::TemperatureOptions;

/// The results a positioning tolerance may name (ISO 230-2:2014 clause 3).
pub const POSITIONING_RESULTS: [&str; 11] = ["A", "A+", "A-", "R", "R+", "R-", "E", "E+", "E-", "M", "B"];

/// An evaluated positioning test.
pub struct PositioningPart {
    pub path: PathBuf,
    pub test: PositioningTest,
    pub uncertainty: PositioningUncertainty,
    /// What the uncertainty was estimated from.
    pub inputs: PositioningUncertaintyInputs,
    pub svg: String,
}

impl PositioningPart {
    /// Reads and evaluates the test in `path`; the uncertainty from the instruments and settings of
    /// `certificate` and the temperatures the file records.
    pub fn evaluate(path: &Path, certificate: &CertificateFile) -> Result<PositioningPart, CalibrationError> {
        let test = evaluate_file(path, &TemperatureOptions::default())?;
        let inputs = certificate.positioning_inputs(&test.data.metadata.environment);
        let uncertainty = positioning_uncertainty(&test.result, &inputs, test.data.rotary);
        let title = format!("Positioning test (ISO 230-2): {}", file_name(path));
        let svg = iso230_2_svg(&test.result, &test.data, &title)?;
        Ok(PositioningPart { path: path.to_path_buf(), test, uncertainty, inputs, svg })
    }

    /// The axis the file names, else the file's name.
    pub fn axis(&self) -> String {
        self.test.data.metadata.axis.clone().unwrap_or_else(|| file_name(&self.path))
    }

    /// Toleranced results (`A`, `E`, `M`, `R`, `B`, and the unidirectional `A+` ...), in the
    /// test's unit, decided under `rule` with their expanded uncertainty.
    pub fn conformity(&self, tolerances: &BTreeMap<String, f64>, rule: DecisionRule) -> Vec<Item> {
        let unit = self.test.result.unit;
        let mut items = Vec::new();
        for (symbol, name, value) in self.test.result.axis_table() {
            if let Some(&tol) = tolerances.get(symbol) {
                items.push(Item::new(
                    format!("{}: {name} {symbol} (ISO 230-2)", self.axis()),
                    "positioning",
                    value,
                    self.uncertainty.of(symbol),
                    tol,
                    unit,
                    rule,
                ));
            }
        }
        items
    }
}

/// One section with every test: its conditions, the plot, the results with U and the budget.
pub fn section(parts: &[PositioningPart]) -> Section {
    let mut s = Section::new("positioning", "Positioning accuracy and repeatability (ISO 230-2)").paragraph(
        "Accuracy A, repeatability R, systematic positional deviation E, range of the mean bidirectional deviation M and reversal value B of each axis, as ISO 230-2:2014 defines them from the runs of the test. Each result carries one expanded uncertainty U (k = 2, about 95 %) estimated as ISO 230-2 Annex A describes: the measuring device's calibration, the machine temperature measurement and the expansion coefficient behind the correction to 20 degC, the beam's misalignment, the environmental variation error, and the statistical uncertainty of the means and standard deviations of the runs. The budget of each test lists these contributors.",
    );
    for p in parts {
        let r = &p.test.result;
        let unit = r.unit;
        let correction = if p.test.temperature_correction.is_null() {
            "readings as recorded (no correction to 20 degC: the file records no material temperature)".to_string()
        } else {
            "readings corrected to 20 degC from the material temperature and expansion coefficient the file records".to_string()
        };
        s = s.paragraph(format!(
            "{}: axis {}, {} targets over {} {}, {} runs in each direction; {correction}.",
            p.path.display(),
            p.axis(),
            r.positions.len(),
            quantity(p.uncertainty.length, 1, ""),
            r.position_unit,
            r.runs
        ));
        for n in &p.test.notes {
            s = s.note(n.clone());
        }
        for w in &p.test.warnings {
            s = s.note(w.clone());
        }
        s = s.figure(
            "Every reading against its target (+ runs and - runs), the mean deviation of each direction and its band of plus or minus two standard deviations.",
            p.svg.clone(),
        );
        let rows = r
            .axis_table()
            .iter()
            .filter(|(symbol, _, _)| *symbol != "B_mean")
            .map(|(symbol, name, value)| {
                vec![symbol.to_string(), name.to_string(), with_uncertainty(*value, p.uncertainty.of(symbol), unit, 3)]
            })
            .collect();
        s = s.table(format!("ISO 230-2 results of axis {}", p.axis()), &["result", "meaning", "value ± U (k = 2)"], rows);
        let budget = p.uncertainty.budget.iter().map(|c| vec![c.name.to_string(), quantity(c.standard_uncertainty, 3, unit)]).collect();
        s = s.table(
            format!(
                "Uncertainty budget of axis {} (standard uncertainties, k = 1; measured length {} {})",
                p.axis(),
                quantity(p.uncertainty.length, 1, ""),
                r.position_unit
            ),
            &["contributor", "standard uncertainty"],
            budget,
        );
    }
    s
}
