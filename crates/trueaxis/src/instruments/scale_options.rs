//! Which correction to 20 degC a positioning file gets: the one asked for (the machine scale's and
//! a reference artefact's temperature and expansion coefficient), or else the one the file's
//! recorded environment gives (a laser file's material temperature and expansion coefficient: the
//! machine scale expands). Used alike by `trueaxis iso230-2`, `trueaxis fit` and the Python package.
//!
//! Units: temperatures in degC, expansion coefficients in um/m/K, the datum in mm. The correction
//! itself is [`super::scale::TableCorrection`] (Soons 1993 §3.2.4; ISO 1 reference temperature).

use super::scale::{ExpandingBody, ScaleError, TableCorrection, TemperatureSource};
use crate::io::plausibility::{temperature_degc, Place};
use crate::io::{Metadata, Severity};
use serde_json::{json, Value};

/// The options of a correction to 20 degC (`--scale-temperature`, `--scale-expansion`,
/// `--artefact-temperature`, `--artefact-expansion`, `--temperature-datum`,
/// `--no-file-temperature`). A temperature without its coefficient (or the reverse) is no
/// correction: callers require both.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TemperatureOptions {
    /// Temperature of the machine scale (the material temperature of laser software), degC or a column.
    pub scale_temperature: Option<TemperatureSource>,
    /// Expansion coefficient of the machine scale, um/m/K.
    pub scale_expansion: Option<f64>,
    /// Temperature of a reference artefact measured by the machine, degC or a column.
    pub artefact_temperature: Option<TemperatureSource>,
    /// Expansion coefficient of the reference artefact, um/m/K.
    pub artefact_expansion: Option<f64>,
    /// Position (mm) of the fixed point the scale and the artefact expand from.
    pub datum_mm: f64,
    /// Keep the readings as they are although the file records a material temperature.
    pub no_file_temperature: bool,
}

/// The correction to 20 degC resolved for one file, and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct AppliedCorrection {
    /// The corrections to apply in turn (none: the readings stay as they are).
    pub corrections: Vec<TableCorrection>,
    /// `{"source": "file", "material_temperature_degc": .., "expansion_coefficient_um_per_m_k": ..}`
    /// when the file's environment was used, `{"source": "options", "corrections": [..]}` for the
    /// options, null for none: the `temperature_correction` of the JSON documents.
    pub json: Value,
    /// Notes for the user (what the file's environment did; printed on stderr by the command line).
    pub notes: Vec<String>,
}

impl TemperatureSource {
    /// A temperature as given on the command line: a number of degC, else the name of a column.
    pub fn parse(text: &str) -> TemperatureSource {
        match text.trim().parse::<f64>() {
            Ok(v) => TemperatureSource::Uniform(v),
            Err(_) => TemperatureSource::Column(text.trim().to_string()),
        }
    }
}

impl TemperatureOptions {
    /// The corrections asked for: the machine scale first, then the artefact.
    pub fn corrections(&self) -> Vec<TableCorrection> {
        [
            (ExpandingBody::MachineScale, &self.scale_temperature, self.scale_expansion),
            (ExpandingBody::Reference, &self.artefact_temperature, self.artefact_expansion),
        ]
        .into_iter()
        .filter_map(|(body, t, alpha)| {
            Some(TableCorrection { body, alpha_um_per_m_k: alpha?, temperature: t.clone()?, datum_mm: self.datum_mm })
        })
        .collect()
    }

    /// The corrections asked for, or else the one the file's environment records (material
    /// temperature, mean of its sensors, and expansion coefficient: the machine scale expands,
    /// `instruments::scale`); the temperature checked for plausibility (`io::plausibility`).
    /// `file` names the file in notes and messages. An implausible file temperature is refused.
    pub fn resolve(&self, metadata: &Metadata, file: &str) -> Result<AppliedCorrection, ScaleError> {
        let options = self.corrections();
        if !options.is_empty() {
            let json = json!({"source": "options", "corrections": options.iter().map(|c| json!({
                "body": match c.body { ExpandingBody::MachineScale => "machine scale", ExpandingBody::Reference => "reference artefact" },
                "expansion_coefficient_um_per_m_k": c.alpha_um_per_m_k,
                "temperature": match &c.temperature { TemperatureSource::Uniform(t) => json!(t), TemperatureSource::Column(n) => json!(n) },
            })).collect::<Vec<_>>()});
            return Ok(AppliedCorrection { corrections: options, json, notes: Vec::new() });
        }
        let env = &metadata.environment;
        let none = AppliedCorrection { corrections: Vec::new(), json: Value::Null, notes: Vec::new() };
        match (env.material_temperature_degc(), env.expansion_coefficient_um_per_m_k) {
            (Some(t), Some(alpha)) if !self.no_file_temperature => {
                let place = Place { file, column: "material temperature" };
                let mut notes = Vec::new();
                if let Some(f) = temperature_degc(t, "material temperature", place) {
                    match f.severity {
                        Severity::Refuse => return Err(ScaleError::ImplausibleFileTemperature { message: f.message }),
                        Severity::Warn => notes.push(format!("warning: {}", f.message)),
                    }
                }
                let json = json!({"source": "file", "material_temperature_degc": t, "expansion_coefficient_um_per_m_k": alpha});
                notes.push(format!(
                    "{file}: readings corrected to 20 degC with the file's material temperature {t:.3} degC and expansion coefficient \
                     {alpha} um/m/K (--no-file-temperature keeps them as they are)"
                ));
                let c = TableCorrection {
                    body: ExpandingBody::MachineScale,
                    alpha_um_per_m_k: alpha,
                    temperature: TemperatureSource::Uniform(t),
                    datum_mm: self.datum_mm,
                };
                Ok(AppliedCorrection { corrections: vec![c], json, notes })
            }
            (Some(t), None) if !self.no_file_temperature => Ok(AppliedCorrection {
                notes: vec![format!(
                    "{file}: the file records a material temperature of {t:.3} degC but no expansion coefficient: no correction to 20 degC \
                     (give --scale-temperature and --scale-expansion)"
                )],
                ..none
            }),
            _ => Ok(none),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recorded(t: f64, alpha: Option<f64>) -> Metadata {
        let mut m = Metadata::default();
        m.environment.material_temperatures_degc = vec![t - 0.5, t + 0.5];
        m.environment.expansion_coefficient_um_per_m_k = alpha;
        m
    }

    #[test]
    fn options_come_before_the_file() {
        let o = TemperatureOptions {
            scale_temperature: Some(TemperatureSource::parse("21.5")),
            scale_expansion: Some(11.5),
            artefact_temperature: Some(TemperatureSource::parse(" T:gauge ")),
            artefact_expansion: Some(8.0),
            datum_mm: -10.0,
            no_file_temperature: false,
        };
        let a = o.resolve(&recorded(23.0, Some(11.0)), "f.rtl").unwrap();
        assert_eq!(a.corrections.len(), 2);
        assert_eq!(a.corrections[0].temperature, TemperatureSource::Uniform(21.5));
        assert_eq!(a.corrections[1].temperature, TemperatureSource::Column("T:gauge".into()));
        assert_eq!((a.corrections[0].datum_mm, a.corrections[1].body), (-10.0, ExpandingBody::Reference));
        assert_eq!(a.json["source"], "options");
        assert_eq!(a.json["corrections"][1]["temperature"], "T:gauge");
        assert!(a.notes.is_empty());
    }

    #[test]
    fn the_file_environment_corrects_the_scale_unless_refused() {
        let a = TemperatureOptions::default().resolve(&recorded(23.0, Some(11.0)), "f.rtl").unwrap();
        assert_eq!(a.corrections[0].temperature, TemperatureSource::Uniform(23.0));
        assert_eq!((a.corrections[0].alpha_um_per_m_k, a.corrections[0].body), (11.0, ExpandingBody::MachineScale));
        assert_eq!(a.json["material_temperature_degc"], 23.0);
        assert!(a.notes[0].starts_with("f.rtl: readings corrected to 20 degC"), "{:?}", a.notes);
        let kept = TemperatureOptions { no_file_temperature: true, ..Default::default() };
        assert_eq!(kept.resolve(&recorded(23.0, Some(11.0)), "f.rtl").unwrap().corrections, vec![]);
        // no coefficient: a note, no correction
        let a = TemperatureOptions::default().resolve(&recorded(23.0, None), "f.rtl").unwrap();
        assert!(a.corrections.is_empty() && a.json.is_null() && a.notes[0].contains("no expansion coefficient"));
        // kelvin is refused, naming the way out
        let e = TemperatureOptions::default().resolve(&recorded(296.0, Some(11.0)), "f.rtl").unwrap_err();
        assert!(e.to_string().ends_with("(or give --no-file-temperature)"), "{e}");
        assert!(e.to_string().starts_with("f.rtl: column `material temperature`"), "{e}");
    }
}
