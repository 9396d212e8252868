//! The particulars of a calibration certificate (ISO/IEC 17025 §7.8: laboratory, customer,
//! unique identification, item calibrated, dates, operator and approval, instruments and their
//! own calibration, environment, methods, decision rule) from a small `report.toml`, completed
//! by what the input files record (machine, serial number, date, operator, location, air and
//! material temperatures; `trueaxis::io::Metadata`).
//!
//! ```toml
//! [certificate]
//! number = "TA-2024-0031"
//! laboratory = "Example Metrology Lab, Sheffield"
//! customer = "Example Parts Ltd, Leeds"
//! approved_by = "B. Example, quality manager"
//! issue_date = "2024-03-15"
//! [machine]
//! maker = "Example Machines"
//! model = "VMC 3"
//! controller = "Heidenhain TNC 640"
//! [[instrument]]
//! name = "ballbar"
//! model = "Renishaw QC20-W"
//! serial = "B12345"
//! calibrated = "2023-11-02"
//! certificate = "UKAS 0123-45678"
//! uncertainty = "U = 0.1 um + 0.7 ppm (k = 2)"
//! [decision]
//! rule = "guard-band"          # or "simple"
//! [tolerances]
//! volumetric_um = 30           # largest volumetric error over the mapped work volume
//! [tolerances.ballbar]         # per ISO 230-4 value and diagnostic, in its unit
//! G = 15
//! squareness = 20
//! [tolerances.parameters]      # identified ISO parameters, um or urad
//! EC0Y = 20
//! ```

use super::super::html::Section;
use super::conformity::DecisionRule;
use super::inputs::InputFile;
use super::positioning::POSITIONING_RESULTS;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;
use trueaxis::evaluate::positioning_uncertainty::PositioningUncertaintyInputs;
use trueaxis::io::Metadata;
use trueaxis::Error;

#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CertificateFile {
    #[serde(default)]
    pub certificate: Particulars,
    #[serde(default)]
    pub machine: MachineIdentity,
    #[serde(default, rename = "instrument")]
    pub instruments: Vec<Instrument>,
    #[serde(default)]
    pub environment: EnvironmentRecord,
    #[serde(default)]
    pub decision: Decision,
    #[serde(default)]
    pub tolerances: Tolerances,
    #[serde(default)]
    pub positioning: PositioningSettings,
    /// Direct measurements to fit and report (`[[fit]]`): each table holds the long options of
    /// `trueaxis fit` by name (`data`, `parameter`, `knot_spacing` ...), read by the command line.
    #[serde(default, rename = "fit")]
    pub fits: Vec<toml::Table>,
}

#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Particulars {
    pub number: Option<String>,
    pub title: Option<String>,
    pub laboratory: Option<String>,
    pub customer: Option<String>,
    pub operator: Option<String>,
    pub approved_by: Option<String>,
    pub test_date: Option<String>,
    pub issue_date: Option<String>,
    pub location: Option<String>,
    /// Free remarks (scope, deviations from the method, opinions).
    pub remarks: Option<String>,
    /// A specimen (an example, simulated data): every page says so.
    #[serde(default)]
    pub specimen: bool,
}

#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MachineIdentity {
    pub maker: Option<String>,
    pub model: Option<String>,
    pub serial: Option<String>,
    pub controller: Option<String>,
    pub location: Option<String>,
}

#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Instrument {
    pub name: String,
    pub model: Option<String>,
    pub serial: Option<String>,
    /// Date of the instrument's own calibration.
    pub calibrated: Option<String>,
    /// Its calibration certificate (issuer and number): the traceability to SI.
    pub certificate: Option<String>,
    /// Its stated uncertainty, as written on its certificate.
    pub uncertainty: Option<String>,
    /// The test it serves (`ballbar`): its expanded uncertainty then becomes the uncertainty of
    /// that test's readings.
    pub used_for: Option<String>,
    /// Expanded uncertainty (k = 2) of a reading, um, from its certificate.
    pub expanded_uncertainty_um: Option<f64>,
    /// The length-proportional part of a length instrument's expanded uncertainty (k = 2), um per
    /// metre measured (`U = expanded_uncertainty_um + expanded_uncertainty_um_per_m L`; a laser).
    pub expanded_uncertainty_um_per_m: Option<f64>,
    /// Expanded uncertainty (k = 2) of a temperature reading, K (a thermometer).
    pub expanded_uncertainty_k: Option<f64>,
}

/// What the uncertainty of a positioning test needs beyond the instruments (`[positioning]` of
/// report.toml; ISO 230-2 Annex A).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PositioningSettings {
    /// Half-width of the uncertainty of the machine's expansion coefficient, percent of it
    /// (default 10).
    pub expansion_uncertainty_percent: Option<f64>,
    /// Expansion coefficient of the machine's scale, um/m/K, when the files do not record it.
    pub expansion_um_per_m_k: Option<f64>,
    /// Largest cosine error of the beam's alignment over the measured length, um.
    pub misalignment_um: Option<f64>,
    /// Environmental variation error from the drift check of ISO 230-2, um.
    pub eve_um: Option<f64>,
}

#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentRecord {
    /// Lowest and highest air temperature during the tests, degC.
    pub air_temperature_degc: Option<[f64; 2]>,
    /// Lowest and highest machine (material) temperature, degC.
    pub machine_temperature_degc: Option<[f64; 2]>,
    pub notes: Option<String>,
}

#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Decision {
    #[serde(default)]
    pub rule: DecisionRule,
}

#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Tolerances {
    /// Largest volumetric error |d| over the mapped work volume, um.
    pub volumetric_um: Option<f64>,
    /// ISO 230-4 values (`G`, `F`, `H`) and ballbar diagnostics by name, in their units.
    #[serde(default)]
    pub ballbar: BTreeMap<String, f64>,
    /// Identified parameters by ISO name, um or urad.
    #[serde(default)]
    pub parameters: BTreeMap<String, f64>,
    /// ISO 230-2 results (`A`, `E`, `M`, `R`, `B`, and `A+` ...) of every positioning test, um
    /// (urad for a rotary axis).
    #[serde(default)]
    pub positioning: BTreeMap<String, f64>,
}

impl Tolerances {
    pub fn is_empty(&self) -> bool {
        self.volumetric_um.is_none() && self.ballbar.is_empty() && self.parameters.is_empty() && self.positioning.is_empty()
    }
}

impl CertificateFile {
    /// The date of issue: `issue_date`, else the day the report is `made` (`YYYY-MM-DD hh:mm UTC`).
    pub fn issue_date(&self, made: &str) -> String {
        self.certificate.issue_date.clone().unwrap_or_else(|| made.split(' ').next().unwrap_or(made).to_string())
    }

    /// The expanded uncertainty (k = 2, um) of the readings of the instrument used for `test`.
    pub fn reading_uncertainty_um(&self, test: &str) -> Option<f64> {
        self.instrument_for(test).and_then(|i| i.expanded_uncertainty_um)
    }

    /// The instrument used for `test` (`ballbar`, `laser`, `thermometer`).
    pub fn instrument_for(&self, test: &str) -> Option<&Instrument> {
        self.instruments.iter().find(|i| i.used_for.as_deref() == Some(test))
    }

    /// What the uncertainty of a positioning test is estimated from: the laser's and the
    /// thermometer's certificates (`used_for = "laser"`, `"thermometer"`), `[positioning]`, and the
    /// machine temperature and expansion coefficient the file records (else `[environment]`'s
    /// machine temperature and `[positioning]`'s coefficient).
    pub fn positioning_inputs(&self, recorded: &trueaxis::io::Environment) -> PositioningUncertaintyInputs {
        let laser = self.instrument_for("laser");
        let p = &self.positioning;
        let temperature =
            recorded.material_temperature_degc().or_else(|| self.environment.machine_temperature_degc.map(|[lo, hi]| (lo + hi) / 2.0));
        PositioningUncertaintyInputs {
            device_um: laser.and_then(|l| l.expanded_uncertainty_um).unwrap_or(0.0),
            device_um_per_m: laser.and_then(|l| l.expanded_uncertainty_um_per_m).unwrap_or(0.0),
            temperature_k: self.instrument_for("thermometer").and_then(|t| t.expanded_uncertainty_k).unwrap_or(0.0),
            expansion_um_per_m_k: recorded.expansion_coefficient_um_per_m_k.or(p.expansion_um_per_m_k).unwrap_or(0.0),
            expansion_fraction: p.expansion_uncertainty_percent.unwrap_or(10.0) / 100.0,
            temperature_offset_k: temperature.map_or(0.0, |t| t - 20.0),
            misalignment_um: p.misalignment_um.unwrap_or(0.0),
            eve_um: p.eve_um.unwrap_or(0.0),
        }
    }

    /// Reads and checks `report.toml`; errors name the file (a file that cannot be read: bad input,
    /// or the environment when the system says so).
    pub fn load(path: &Path) -> Result<CertificateFile, Error> {
        let origin = path.display().to_string();
        let text = trueaxis::files::inputs::read_to_string(path).map_err(|e| Error::from(e).context("cannot read").in_file(&origin))?;
        CertificateFile::from_toml_str(&text, &origin)
    }

    /// Parses and checks the text of a `report.toml`; `origin` names it in every error.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<CertificateFile, Error> {
        let parse = || -> Result<CertificateFile, Error> {
            trueaxis::io::toml_numbers::refuse_underflow(text)?;
            let file: CertificateFile = toml::from_str(text).map_err(|e| Error::input(e.to_string().trim_end().replace('\n', " ")))?;
            file.check()?;
            Ok(file)
        };
        parse().map_err(|e| e.in_file(origin))
    }

    /// The values a `report.toml` may hold: positive tolerances of known results, instrument
    /// uncertainties and positioning terms within their ranges, temperatures as [lowest, highest].
    fn check(&self) -> Result<(), Error> {
        let t = &self.tolerances;
        let all = t
            .volumetric_um
            .iter()
            .map(|v| ("volumetric_um".to_string(), *v))
            .chain(t.ballbar.iter().map(|(k, v)| (format!("ballbar.{k}"), *v)))
            .chain(t.parameters.iter().map(|(k, v)| (format!("parameters.{k}"), *v)))
            .chain(t.positioning.iter().map(|(k, v)| (format!("positioning.{k}"), *v)));
        for (name, v) in all {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::input(format!("tolerances.{name} must be a positive number, got {v}")));
            }
        }
        if let Some(k) = t.positioning.keys().find(|k| !POSITIONING_RESULTS.contains(&k.as_str())) {
            return Err(Error::input(format!(
                "tolerances.positioning.{k}: not an ISO 230-2 result; give one of {}",
                POSITIONING_RESULTS.join(", ")
            )));
        }
        for i in &self.instruments {
            for (name, v) in [
                ("expanded_uncertainty_um", i.expanded_uncertainty_um),
                ("expanded_uncertainty_um_per_m", i.expanded_uncertainty_um_per_m),
                ("expanded_uncertainty_k", i.expanded_uncertainty_k),
            ] {
                if let Some(u) = v.filter(|u| !(u.is_finite() && *u >= 0.0 && *u < 1e3)) {
                    return Err(Error::input(format!("instrument `{}`: {name} must be a number from 0 to 1000, got {u}", i.name)));
                }
            }
        }
        let p = &self.positioning;
        for (name, v, hi) in [
            ("expansion_uncertainty_percent", p.expansion_uncertainty_percent, 100.0),
            ("expansion_um_per_m_k", p.expansion_um_per_m_k, 100.0),
            ("misalignment_um", p.misalignment_um, 1e3),
            ("eve_um", p.eve_um, 1e3),
        ] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v >= 0.0 && *v <= hi)) {
                return Err(Error::input(format!("positioning.{name} must be a number from 0 to {hi}, got {v}")));
            }
        }
        for (name, range) in [
            ("air_temperature_degc", self.environment.air_temperature_degc),
            ("machine_temperature_degc", self.environment.machine_temperature_degc),
        ] {
            if let Some([lo, hi]) = range {
                if !(lo.is_finite() && hi.is_finite() && lo <= hi && (-40.0..=80.0).contains(&lo) && (-40.0..=80.0).contains(&hi)) {
                    return Err(Error::input(format!("environment.{name} must be [lowest, highest] in degC, got [{lo}, {hi}]")));
                }
            }
        }
        Ok(())
    }
}

/// The last component of a path.
fn file_name(path: &str) -> String {
    Path::new(path).file_name().map_or_else(|| path.to_string(), |n| n.to_string_lossy().into_owned())
}

/// The first value any input file records for `pick`.
fn recorded<'a>(inputs: &'a [InputFile], pick: impl Fn(&'a Metadata) -> Option<&'a String>) -> Option<String> {
    inputs.iter().filter_map(|f| f.metadata.as_ref()).find_map(|m| pick(m).cloned())
}

fn range_text(values: &[f64]) -> Option<String> {
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !lo.is_finite() {
        return None;
    }
    Some(if (hi - lo).abs() < 0.005 { format!("{lo:.2} degC") } else { format!("{lo:.2} to {hi:.2} degC") })
}

/// What the certificate section shows.
pub struct Certificate<'a> {
    pub file: &'a CertificateFile,
    /// The machine's name in its description file.
    pub machine_name: &'a str,
    pub inputs: &'a [InputFile],
    /// Methods and standards applied (one line each), from the sections present.
    pub methods: Vec<String>,
    /// The date the report was made.
    pub made: &'a str,
}

/// What a specimen's pages say.
pub const SPECIMEN: &str = "SPECIMEN: simulated data, not a calibration certificate";

impl Certificate<'_> {
    /// The item calibrated: maker and model with the machine file's name, else that name.
    fn machine(&self) -> String {
        let m = &self.file.machine;
        let identity = [m.maker.clone(), m.model.clone()].into_iter().flatten().collect::<Vec<_>>().join(" ");
        if identity.is_empty() {
            self.machine_name.to_string()
        } else {
            format!("{identity} ({})", self.machine_name)
        }
    }

    fn serial(&self) -> Option<String> {
        self.file.machine.serial.clone().or_else(|| recorded(self.inputs, |md| md.serial.as_ref()))
    }

    /// The lines every page repeats (ISO/IEC 17025:2017 7.8.2.1 b): the certificate's number and
    /// title, the customer, the machine and its serial number, the date of issue; a specimen says so
    /// first.
    pub fn running(&self, title: &str) -> Vec<String> {
        let c = &self.file.certificate;
        let mut lines = Vec::new();
        if c.specimen {
            lines.push(SPECIMEN.to_string());
        }
        lines.push(format!(
            "Certificate {}, issued {}: {title}",
            c.number.as_deref().unwrap_or("(number not stated)"),
            self.file.issue_date(self.made)
        ));
        lines.push(format!(
            "Customer: {}; machine: {}, serial number {}",
            c.customer.as_deref().unwrap_or("not stated"),
            self.machine(),
            self.serial().unwrap_or_else(|| "not stated".into()),
        ));
        lines
    }

    /// The last words of the report (ISO/IEC 17025:2017 7.8.2.1 d: its end clearly identified).
    pub fn end(&self) -> String {
        match &self.file.certificate.number {
            Some(n) => format!("End of certificate {n}."),
            None => "End of the report.".into(),
        }
    }

    /// The dates of the tests as the files record them, each with its file: `date (file)`.
    fn recorded_dates(&self) -> Option<String> {
        let dates: Vec<String> =
            self.inputs.iter().filter_map(|f| Some(format!("{} ({})", f.metadata.as_ref()?.date.as_ref()?, file_name(&f.path)))).collect();
        (!dates.is_empty()).then(|| dates.join("; "))
    }

    /// Each test's date and environment from its own file (ISO/IEC 17025:2017 7.8.2.1 g, 7.8.4.1 a).
    fn tests_table(&self) -> Option<(Vec<Vec<String>>, usize)> {
        let not = || "not recorded".to_string();
        let rows: Vec<Vec<String>> = self
            .inputs
            .iter()
            .filter_map(|f| {
                let m = f.metadata.as_ref()?;
                let e = &m.environment;
                Some(vec![
                    f.role.clone(),
                    file_name(&f.path),
                    m.date.clone().unwrap_or_else(not),
                    e.air_temperature_degc.map_or_else(not, |t| format!("{t:.1} degC")),
                    range_text(&e.material_temperatures_degc).unwrap_or_else(not),
                ])
            })
            .collect();
        let recorded = rows.iter().filter(|r| r[2..].iter().any(|c| c != "not recorded")).count();
        (!rows.is_empty()).then_some((rows, recorded))
    }

    pub fn section(&self) -> Section {
        let f = self.file;
        let c = &f.certificate;
        let m = &f.machine;
        let not_stated = || "not stated".to_string();
        let mut fields: Vec<(String, String)> = Vec::new();
        let mut push = |name: &str, value: Option<String>| {
            if let Some(v) = value.filter(|v| !v.trim().is_empty()) {
                fields.push((name.to_string(), v));
            }
        };
        push("Certificate number", Some(c.number.clone().unwrap_or_else(not_stated)));
        push("Calibration laboratory", Some(c.laboratory.clone().unwrap_or_else(not_stated)));
        push("Customer", Some(c.customer.clone().unwrap_or_else(not_stated)));
        push("Machine", Some(self.machine()));
        push("Serial number", self.serial().or_else(|| Some(not_stated())));
        push("Controller", m.controller.clone());
        push("Location", m.location.clone().or(c.location.clone()).or_else(|| recorded(self.inputs, |md| md.location.as_ref())));
        push("Date of the tests", c.test_date.clone().or_else(|| self.recorded_dates()).or_else(|| Some(not_stated())));
        push("Date of issue", Some(f.issue_date(self.made)));
        push("Operator", c.operator.clone().or_else(|| recorded(self.inputs, |md| md.operator.as_ref())).or_else(|| Some(not_stated())));
        push("Approved by", c.approved_by.clone());
        let air: Vec<f64> = self.inputs.iter().filter_map(|i| i.metadata.as_ref()?.environment.air_temperature_degc).collect();
        let material: Vec<f64> =
            self.inputs.iter().filter_map(|i| i.metadata.as_ref()).flat_map(|m| m.environment.material_temperatures_degc.clone()).collect();
        let e = &f.environment;
        push(
            "Air temperature",
            e.air_temperature_degc
                .map(|[a, b]| range_text(&[a, b]).unwrap_or_default())
                .or_else(|| range_text(&air).map(|t| format!("{t} (recorded in the files)")))
                .or_else(|| Some(not_stated())),
        );
        push(
            "Machine temperature",
            e.machine_temperature_degc
                .map(|[a, b]| range_text(&[a, b]).unwrap_or_default())
                .or_else(|| range_text(&material).map(|t| format!("{t} (recorded in the files)")))
                .or_else(|| Some(not_stated())),
        );
        push("Environment", e.notes.clone());
        push("Decision rule", Some(f.decision.rule.name().to_string()));
        push("Remarks", c.remarks.clone());
        let mut s = Section::new("certificate", "Certificate").fields(fields).paragraph(
            "The results relate only to the machine identified above, in the condition and on the dates stated; they include no results from external providers. The certificate may be reproduced in full only, unless the laboratory approves otherwise in writing.",
        );
        if let Some((rows, recorded)) = self.tests_table() {
            let caption = if recorded == rows.len() {
                "The tests: date and conditions as each file records them".to_string()
            } else {
                format!(
                    "The tests: date and conditions as each file records them ({} of {} files record none: their conditions are those stated above)",
                    rows.len() - recorded,
                    rows.len()
                )
            };
            s = s.table(caption, &["test", "file", "date", "air temperature", "machine temperature"], rows);
        }
        let rows: Vec<Vec<String>> = f
            .instruments
            .iter()
            .map(|i| {
                let dash = || "-".to_string();
                vec![
                    i.name.clone(),
                    i.model.clone().unwrap_or_else(dash),
                    i.serial.clone().unwrap_or_else(dash),
                    i.calibrated.clone().unwrap_or_else(dash),
                    i.certificate.clone().unwrap_or_else(dash),
                    i.uncertainty.clone().unwrap_or_else(dash),
                ]
            })
            .collect();
        if rows.is_empty() {
            s = s.note("No measuring instruments are stated (give them as [[instrument]] in report.toml): the traceability of the results cannot be shown.");
        } else {
            s = s.table(
                "Measuring instruments and their own calibration (traceability)",
                &["instrument", "model", "serial number", "calibrated", "certificate", "its uncertainty"],
                rows,
            );
        }
        s.table("Methods and standards applied", &["method"], self.methods.iter().map(|m| vec![m.clone()]).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_certificate_file_and_refuses_bad_values() {
        let text = "[certificate]\nnumber = \"A-1\"\n[[instrument]]\nname = \"ballbar\"\nserial = \"B1\"\n[decision]\nrule = \"guard-band\"\n[tolerances]\nvolumetric_um = 30\n[tolerances.ballbar]\nG = 15\n";
        let f = CertificateFile::from_toml_str(text, "r.toml").unwrap();
        assert_eq!(f.decision.rule, DecisionRule::GuardBand);
        assert_eq!(f.tolerances.ballbar["G"], 15.0);
        assert_eq!(f.instruments[0].serial.as_deref(), Some("B1"));
        let bad = CertificateFile::from_toml_str("[tolerances]\nvolumetric_um = -3\n", "r.toml").unwrap_err().to_string();
        assert!(bad.contains("r.toml") && bad.contains("volumetric_um"), "{bad}");
        let unknown = CertificateFile::from_toml_str("[certificate]\nnumbr = \"x\"\n", "r.toml").unwrap_err().to_string();
        assert!(unknown.contains("r.toml") && unknown.contains("numbr"), "{unknown}");
        let rule = CertificateFile::from_toml_str("[decision]\nrule = \"strict\"\n", "r.toml").unwrap_err().to_string();
        assert!(rule.contains("strict"), "{rule}");
    }
}
