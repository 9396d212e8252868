//! The calibration report: one self-contained HTML document (inline SVG, no network, printable)
//! from what is known about a machine. Each part is computed from its inputs by the same code as the
//! command that does that step alone (`identify`, `uncertainty`, `ballbar iso230-4`, `predict`,
//! `compensate`), and a section appears only for the inputs given:
//!
//! | input | section(s) |
//! |---|---|
//! | always (`report.toml` when given) | `certificate` (particulars, instruments, methods), `conformity` (with tolerances) |
//! | machine | `machine` |
//! | campaign | `campaign` (residuals), `identification` (parameters, uncertainties, identifiability) |
//! | uncertainty sources (with a campaign) | `uncertainty` (Monte Carlo budget, histograms, convergence) |
//! | error values (or the identified ones) | `volumetric` (maps before / after), `compensation` |
//! | thermal conduction model | `thermal-modes` (time constants, weights, mode shapes; [`ThermalModesPart`]) |
//! | thermal error model and a campaign | `thermal-drift` (drift vs prediction per run; [`ThermalDriftPart`]) |
//! | ISO 230-2 positioning tests | `positioning` (A, R, E, M, B with U and its budget, plots) |
//! | ballbar circles | `ballbar` (polar plots, ISO 230-4 values, diagnostics) |
//! | rotary-axis ballbar steps A1 A2 C1 C2 | `rotary-ballbar` (location errors with U, traces; [`RotaryBallbarPart`]) |
//! | a two-length rotary-table ballbar test | `tmbb` (table tilts and axial error with U, traces; [`TmbbPart`]) |
//! | direct measurements of error motions (laser, level) | `fits` (the fitted functions with U, residuals; [`FitPart`]) |
//! | always | `inputs` (files with size and SHA-256, date, version) |
//!
//! [`assemble`] builds it from a [`ReportRequest`] (a user's files and the options of `trueaxis
//! report`); `trueaxis demo` from the files it simulates.

pub mod assemble;
mod ballbar;
mod certificate;
mod compensation;
pub mod conformity;
mod data_quality;
mod fit_tables;
mod fits;
mod identification;
mod inputs;
mod maps;
mod positioning;
pub mod quantity;
mod rotary_ballbar;
mod summary;
mod thermal;
mod tmbb;
mod uncertainty;
mod volume;

pub use assemble::{assemble, FitTables, ReportRequest};
pub use ballbar::{section as ballbar_section, CircleInput, CirclePart, SPIKE_WIDTH_DEG};
pub use certificate::{Certificate, CertificateFile, Instrument, Tolerances, SPECIMEN};
pub use compensation::{controller_name, CompensationPart, ControllerPart, CONTROLLER_FORMATS, GRID_NODES, POINTS};
pub use conformity::{decide, DecisionRule, Item};
pub use data_quality::{DataQualityPart, ScreenedFile};
pub use fit_tables::fit_arguments;
pub use fits::{FitPart, Range};
pub use identification::{IdentificationPart, ParameterRow, UncertaintyMethod};
pub use inputs::{sha256, utc_date_time, InputFile, Traceability};
pub use maps::{magnitudes_um, statistics, VolumeMap, GRID};
pub use positioning::{section as positioning_section, PositioningPart, POSITIONING_RESULTS};
pub use rotary_ballbar::{IdentifiedError, RotaryBallbarPart};
pub use summary::summary_json;
pub use thermal::{ThermalDriftPart, ThermalModesPart};
pub use tmbb::TmbbPart;
pub use uncertainty::UncertaintyPart;
pub use volume::{error_at_setpoints, VolumePart};

use super::html::{HtmlReport, Section};
use thiserror::Error;
use trueaxis::machine::{AxisKind, Machine};

/// Why a part of a report could not be made. [`CalibrationError::is_input`] tells bad input from
/// a failed computation; the command line rewrites the messages of [`CalibrationError::Input`].
#[derive(Debug, Error)]
pub enum CalibrationError {
    #[error(transparent)]
    Machine(#[from] trueaxis::machine::MachineError),
    #[error(transparent)]
    Errors(#[from] trueaxis::error_model::ErrorModelError),
    #[error(transparent)]
    Data(#[from] trueaxis::data::DataError),
    #[error(transparent)]
    Identify(#[from] trueaxis::identify::IdentifyError),
    #[error(transparent)]
    Compensate(#[from] trueaxis::compensate::CompensateError),
    #[error(transparent)]
    Plot(#[from] super::ReportError),
    /// An error of the core that is not one of the above (uncertainty, the thermal parts).
    #[error(transparent)]
    Core(#[from] trueaxis::Error),
    #[error("{0}")]
    Input(String),
    #[error("{0}")]
    Computation(String),
}

impl CalibrationError {
    pub fn is_input(&self) -> bool {
        use trueaxis::identify::IdentifyError;
        match self {
            CalibrationError::Machine(_) | CalibrationError::Errors(_) | CalibrationError::Data(_) | CalibrationError::Input(_) => true,
            CalibrationError::Identify(e) => !matches!(e, IdentifyError::RankDeficient { .. }),
            CalibrationError::Compensate(e) => e.kind() == trueaxis::ErrorKind::Input,
            CalibrationError::Core(e) => e.kind() != trueaxis::ErrorKind::Computation,
            CalibrationError::Plot(_) | CalibrationError::Computation(_) => false,
        }
    }
}

impl From<CalibrationError> for trueaxis::Error {
    /// Bad input or a failed computation ([`CalibrationError::is_input`]), the message unchanged
    /// and the error kept as the cause (a full disk in its chain is still the environment).
    fn from(e: CalibrationError) -> trueaxis::Error {
        let kind = if e.is_input() { trueaxis::ErrorKind::Input } else { trueaxis::ErrorKind::Computation };
        trueaxis::Error::new(kind, e.to_string()).caused_by(e)
    }
}

/// A number with `decimals` decimals, `-` when it is not finite (a report never shows NaN).
pub fn number(v: f64, decimals: usize) -> String {
    if v.is_finite() {
        format!("{v:.decimals$}")
    } else {
        "-".into()
    }
}

/// Everything a report shows; `None` / empty parts have no section.
pub struct CalibrationReport<'a> {
    pub title: String,
    pub subtitle: String,
    pub machine: &'a Machine,
    /// Paragraphs after the machine's description (what its errors are, where M is).
    pub machine_notes: Vec<String>,
    pub identification: Option<IdentificationPart>,
    pub uncertainty: Option<UncertaintyPart>,
    pub volume: Option<VolumePart>,
    /// A thermal conduction model's modes.
    pub thermal_modes: Option<ThermalModesPart>,
    /// A thermal error model against a measured campaign.
    pub thermal_drift: Option<ThermalDriftPart>,
    pub circles: Vec<CirclePart>,
    /// The rotary-axis ballbar test of a five-axis machine (Jiang 2014).
    pub rotary_ballbar: Option<RotaryBallbarPart>,
    /// The two-length ballbar test of a rotary table (Zhu 2008).
    pub tmbb: Option<TmbbPart>,
    /// Error motions fitted to direct measurements (laser, level).
    pub fits: Vec<FitPart>,
    /// ISO 230-2 positioning tests.
    pub positioning: Vec<PositioningPart>,
    pub compensation: Option<CompensationPart>,
    /// What the controller format the user chose leaves over the travel.
    pub controller: Option<ControllerPart>,
    /// The screening of every input file (docs/screening.md); `None`: not screened.
    pub data_quality: Option<DataQualityPart>,
    /// Further sections before the inputs (the demo's "repeat each step").
    pub extra: Vec<Section>,
    pub traceability: Traceability,
    /// The certificate's particulars, decision rule and tolerances (`report.toml`; default: none
    /// stated).
    pub certificate: CertificateFile,
}

impl CalibrationReport<'_> {
    /// The methods and standards applied, from the parts present.
    pub fn methods(&self) -> Vec<String> {
        let mut m = Vec::new();
        if self.identification.is_some() {
            m.push("Identification of geometric errors from a measurement campaign on the machine's kinematic model, weighted least squares (ISO 230-1 error names; docs/identification.md)".to_string());
        }
        if self.uncertainty.is_some() {
            m.push(
                "Measurement uncertainty by the adaptive Monte Carlo method, JCGM 101:2008 and JCGM 102:2011 (GUM supplements 1 and 2)"
                    .to_string(),
            );
        }
        if !self.positioning.is_empty() {
            m.push("Positioning accuracy and repeatability of numerically controlled axes, ISO 230-2:2014, with the measurement uncertainty of its Annex A".to_string());
        }
        if !self.circles.is_empty() {
            m.push("Circular tests with a ballbar, ISO 230-4:2005".to_string());
        }
        if let Some(r) = &self.rotary_ballbar {
            m.push(format!(
                "Location errors of the rotary axes from four ballbar tests by {} (ISO 230-7 terms; docs/ballbar.md)",
                r.method_text()
            ));
        }
        if !self.fits.is_empty() {
            m.push("Error motions of the axes from direct measurements (laser interferometer, level), fitted as parametric functions, Soons (1993) §3.2 (ISO 230-1 terms; docs/laser.md)".to_string());
        }
        if self.tmbb.is_some() {
            m.push("Tilts and axial error of a rotary table from a two-length telescopic ballbar test, the method of Zhu (2008) ch. 5 (ISO 230-1 terms; docs/ballbar.md)".to_string());
        }
        if self.volume.is_some() {
            m.push("Volumetric error over the work volume from the error model, ISO/TR 230-11 terms (docs/user-guide.md)".to_string());
        }
        if self.thermal_modes.is_some() || self.thermal_drift.is_some() {
            m.push("Thermal effects, ISO 230-3:2020 (docs/thermal.md)".to_string());
        }
        if self.compensation.is_some() {
            m.push("Compensation tables solved on the exact kinematic chain (docs/compensation.md)".to_string());
        }
        if !self.certificate.tolerances.is_empty() {
            m.push(format!("Conformity decisions: {}, ISO 14253-1:2017", self.certificate.decision.rule.name()));
        }
        m
    }

    /// Every toleranced item of `report.toml` with its decision.
    pub fn conformity_items(&self) -> Vec<Item> {
        let t = &self.certificate.tolerances;
        let rule = self.certificate.decision.rule;
        let mut items = Vec::new();
        if let Some(id) = &self.identification {
            for p in id.parameter_rows(self.uncertainty.as_ref()) {
                if let Some(&tol) = t.parameters.get(&p.name) {
                    items.push(Item::new(format!("identified {}", p.name), "identification", p.value, p.expanded, tol, &p.unit, rule));
                }
            }
        }
        for p in &self.positioning {
            items.extend(p.conformity(&t.positioning, rule));
        }
        for c in &self.circles {
            items.extend(c.conformity(&t.ballbar, rule));
        }
        if let Some(r) = &self.rotary_ballbar {
            items.extend(r.conformity(&t.parameters, rule));
        }
        if let Some(r) = &self.tmbb {
            items.extend(r.conformity(&t.parameters, rule));
        }
        for f in &self.fits {
            items.extend(f.conformity(&t.parameters, rule));
        }
        if let (Some(tol), Some(v)) = (t.volumetric_um, &self.volume) {
            items.push(
                Item::new("largest volumetric error |d| before compensation".into(), "volumetric", v.before_um.0, None, tol, "um", rule)
                    .without_u("the map is computed from error values without a propagated uncertainty; state U with the error values' [uncertainty] table and decide by simple acceptance meanwhile"),
            );
        }
        items
    }

    /// Every tolerance of `report.toml` is decided or refused by name: a tolerance for a result this
    /// report does not have (a parameter the campaign does not identify, a diagnostic no circle
    /// gives, a test not given) is bad input, never silently left out.
    pub fn check_tolerances(&self, origin: &str) -> Result<(), CalibrationError> {
        let t = &self.certificate.tolerances;
        let rule = self.certificate.decision.rule;
        let mut refused = Vec::new();
        let identified: Vec<String> = (self.identification.iter().flat_map(|id| id.parameter_rows(None).into_iter().map(|p| p.name)))
            .chain(self.rotary_ballbar.iter().flat_map(|r| r.errors().into_iter().map(|e| e.name)))
            .chain(self.tmbb.iter().flat_map(|r| r.errors().into_iter().map(|e| e.name)))
            .chain(self.fits.iter().map(|f| f.report.parameter.to_string()))
            .collect();
        for name in t.parameters.keys().filter(|n| !identified.contains(n)) {
            refused.push(match identified.is_empty() {
                true => format!(
                    "tolerances.parameters.{name}: no parameters are identified in this report (give --campaign, --rotary-ballbar, --tmbb or a [[fit]])"
                ),
                false => format!("tolerances.parameters.{name}: not identified in this report (it identifies {})", identified.join(", ")),
            });
        }
        for (key, &tol) in &t.ballbar {
            let one = std::collections::BTreeMap::from([(key.clone(), tol)]);
            if self.circles.iter().all(|c| c.conformity(&one, rule).is_empty()) {
                refused.push(match self.circles.is_empty() {
                    true => format!("tolerances.ballbar.{key}: no ballbar test in this report (give --ballbar)"),
                    false => format!("tolerances.ballbar.{key}: not an ISO 230-4 value (G, F, H) or a diagnostic of the circles"),
                });
            }
        }
        if let (Some(key), true) = (t.positioning.keys().next(), self.positioning.is_empty()) {
            refused.push(format!("tolerances.positioning.{key}: no positioning test in this report (give --positioning)"));
        }
        if t.volumetric_um.is_some() && self.volume.is_none() {
            refused.push("tolerances.volumetric_um: no volumetric map in this report".into());
        }
        match refused.is_empty() {
            true => Ok(()),
            false => Err(CalibrationError::Input(format!("{origin}: {}", refused.join("; ")))),
        }
    }

    /// The sections in order; a part that is absent has none.
    pub fn sections(&self) -> Vec<Section> {
        let mut out = vec![self.particulars().section()];
        if !self.certificate.tolerances.is_empty() {
            out.push(conformity::section(&self.conformity_items(), self.certificate.decision.rule));
        }
        out.push(machine_section(self.machine, &self.machine_notes));
        if let Some(id) = &self.identification {
            out.push(id.campaign_section());
            out.push(id.parameter_section(self.uncertainty.as_ref()));
        }
        if let Some(u) = &self.uncertainty {
            out.push(u.section());
        }
        if let Some(v) = &self.volume {
            out.push(v.section());
        }
        out.extend(self.thermal_modes.iter().map(ThermalModesPart::section));
        out.extend(self.thermal_drift.iter().map(ThermalDriftPart::section));
        if !self.positioning.is_empty() {
            out.push(positioning_section(&self.positioning));
        }
        if !self.circles.is_empty() {
            out.push(ballbar_section(&self.circles));
        }
        out.extend(self.rotary_ballbar.iter().map(RotaryBallbarPart::section));
        out.extend(self.tmbb.iter().map(TmbbPart::section));
        if !self.fits.is_empty() {
            out.push(fits::section(&self.fits));
        }
        if let Some(c) = &self.compensation {
            out.push(c.section(self.controller.as_ref()));
        }
        out.extend(self.data_quality.iter().map(DataQualityPart::section));
        out.extend(self.extra.iter().cloned());
        out.push(self.traceability.section().paragraph(self.particulars().end()));
        out
    }

    /// The certificate's particulars with what the files record.
    fn particulars(&self) -> Certificate<'_> {
        Certificate {
            file: &self.certificate,
            machine_name: &self.machine.name,
            inputs: &self.traceability.inputs,
            methods: self.methods(),
            made: &self.traceability.date,
        }
    }

    /// The date of issue: the certificate's, else the day the report is made.
    pub fn issue_date(&self) -> String {
        self.certificate.issue_date(&self.traceability.date)
    }

    /// The document (sections in order), from which the HTML and the PDF are made; every page of
    /// both repeats the certificate's identification.
    pub fn document(&self) -> HtmlReport {
        HtmlReport {
            title: self.title.clone(),
            subtitle: self.subtitle.clone(),
            sections: self.sections(),
            running: self.particulars().running(&self.title),
        }
    }

    /// The complete HTML document.
    pub fn to_html(&self) -> String {
        self.document().to_html()
    }

    /// The same content as a PDF (A4).
    pub fn to_pdf(&self) -> Result<Vec<u8>, CalibrationError> {
        Ok(crate::pdf::report_pdf(&self.document())?)
    }
}

/// The machine: name, structure, axes.
fn machine_section(m: &Machine, notes: &[String]) -> Section {
    let v = |x: &trueaxis::geometry::Vec3| format!("[{}, {}, {}]", short(x.x), short(x.y), short(x.z));
    let rows = m
        .axes()
        .iter()
        .map(|a| {
            let rotary = a.kind == AxisKind::Rotary;
            vec![
                a.letter.to_string(),
                if rotary { "rotary".into() } else { "linear".into() },
                v(&a.direction),
                format!("{} mm", v(&a.point)),
                a.range.map_or("continuous".into(), |[lo, hi]| format!("{lo} .. {hi} {}", if rotary { "deg" } else { "mm" })),
            ]
        })
        .collect();
    let mut s = Section::new("machine", "Machine").paragraph(format!(
        "{} (kinematic structure {}, read from the workpiece to the tool; docs/user-guide.md). Tool point at home [{}, {}, {}] mm in the machine frame M.",
        m.name, m.structure, m.tool_point.x, m.tool_point.y, m.tool_point.z
    ));
    for n in notes {
        s = s.paragraph(n.clone());
    }
    s.table("Axes (directions and points in M at home)", &["axis", "kind", "direction", "point", "travel"], rows)
}

/// A coordinate with at most 4 decimals, trailing zeros dropped.
fn short(v: f64) -> String {
    let t = format!("{v:.4}");
    let t = t.trim_end_matches('0').trim_end_matches('.');
    if t == "-0" {
        "0".into()
    } else {
        t.to_string()
    }
}
