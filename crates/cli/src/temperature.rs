//! Options to correct positioning readings to 20 degC, shared by `fit` and `iso230-2`; the file's
//! recorded environment (material temperature, expansion coefficient) when no option is given.

use crate::Failure;
use trueaxis::instruments::{ExpandingBody, TableCorrection, TemperatureSource};
use trueaxis::io::plausibility::{temperature_degc, Place};
use trueaxis::io::{Metadata, Severity};

/// Correction of positioning readings to 20 degC (ISO 1; seed 000 §3.2.4).
#[derive(clap::Args, Clone, Debug)]
pub struct TemperatureArgs {
    /// Temperature of the machine scale (what laser software calls the material temperature of the
    /// machine) during the test: degC, or a data column with one temperature per reading (e.g.
    /// `T:scale`). The warm scale reads short: dev_20 = dev - alpha (T - 20) (x - datum) / 1000.
    #[arg(long, requires = "scale_expansion", allow_hyphen_values = true, value_name = "DEGC|COLUMN")]
    scale_temperature: Option<String>,
    /// Expansion coefficient of the machine scale, um/m/K (e.g. 11.5 for steel).
    #[arg(long, requires = "scale_temperature", value_name = "UM_PER_M_K", allow_hyphen_values = true)]
    scale_expansion: Option<f64>,
    /// Temperature of a reference artefact (step gauge, hole plate, workpiece) measured by the machine:
    /// degC, or a data column. The warm artefact is longer: dev_20 = dev + alpha (T - 20) (x - datum) / 1000.
    #[arg(long, requires = "artefact_expansion", allow_hyphen_values = true, value_name = "DEGC|COLUMN")]
    artefact_temperature: Option<String>,
    /// Expansion coefficient of the reference artefact, um/m/K.
    #[arg(long, requires = "artefact_temperature", value_name = "UM_PER_M_K", allow_hyphen_values = true)]
    artefact_expansion: Option<f64>,
    /// Position (mm) of the fixed point the scale and the artefact expand from.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_name = "MM")]
    temperature_datum: f64,
    /// Keep the readings as they are although the file records a material temperature and an
    /// expansion coefficient (by default they correct the readings to 20 degC, as
    /// --scale-temperature and --scale-expansion would).
    #[arg(long)]
    no_file_temperature: bool,
}

/// Where the correction to 20 degC came from, for the outputs.
pub struct Applied {
    pub corrections: Vec<TableCorrection>,
    /// `{"source": "file", "material_temperature_degc": .., "expansion_coefficient_um_per_m_k": ..}`
    /// when the file's environment was used, `{"source": "options", ...}` for the options, null for none.
    pub json: serde_json::Value,
    /// Notes for stderr (what the file's environment did).
    pub notes: Vec<String>,
}

impl TemperatureArgs {
    /// The corrections asked for, or else the one the file's environment records (material
    /// temperature, mean of its sensors, and expansion coefficient: the machine scale expands,
    /// `instruments::scale`); the temperature checked for plausibility (`io::plausibility`).
    pub fn applied(&self, metadata: &Metadata, file: &str) -> Result<Applied, Failure> {
        let options = self.corrections();
        if !options.is_empty() {
            let json = serde_json::json!({"source": "options", "corrections": options.iter().map(|c| serde_json::json!({
                "body": match c.body { ExpandingBody::MachineScale => "machine scale", ExpandingBody::Reference => "reference artefact" },
                "expansion_coefficient_um_per_m_k": c.alpha_um_per_m_k,
                "temperature": match &c.temperature { TemperatureSource::Uniform(t) => serde_json::json!(t), TemperatureSource::Column(n) => serde_json::json!(n) },
            })).collect::<Vec<_>>()});
            return Ok(Applied { corrections: options, json, notes: Vec::new() });
        }
        let env = &metadata.environment;
        let none = Applied { corrections: Vec::new(), json: serde_json::Value::Null, notes: Vec::new() };
        match (env.material_temperature_degc(), env.expansion_coefficient_um_per_m_k) {
            (Some(t), Some(alpha)) if !self.no_file_temperature => {
                let place = Place { file, column: "material temperature" };
                let mut notes = Vec::new();
                if let Some(f) = temperature_degc(t, "material temperature", place) {
                    match f.severity {
                        Severity::Refuse => return Err(Failure::input(anyhow::anyhow!("{} (or give --no-file-temperature)", f.message))),
                        Severity::Warn => notes.push(format!("warning: {}", f.message)),
                    }
                }
                let json = serde_json::json!({"source": "file", "material_temperature_degc": t, "expansion_coefficient_um_per_m_k": alpha});
                notes.push(format!(
                    "{file}: readings corrected to 20 degC with the file's material temperature {t:.3} degC and expansion coefficient \
                     {alpha} um/m/K (--no-file-temperature keeps them as they are)"
                ));
                let c = TableCorrection {
                    body: ExpandingBody::MachineScale,
                    alpha_um_per_m_k: alpha,
                    temperature: TemperatureSource::Uniform(t),
                    datum_mm: self.temperature_datum,
                };
                Ok(Applied { corrections: vec![c], json, notes })
            }
            (Some(t), None) if !self.no_file_temperature => Ok(Applied {
                notes: vec![format!(
                    "{file}: the file records a material temperature of {t:.3} degC but no expansion coefficient: no correction to 20 degC \
                     (give --scale-temperature and --scale-expansion)"
                )],
                ..none
            }),
            _ => Ok(none),
        }
    }

    /// The corrections asked for: the machine scale first, then the artefact.
    pub fn corrections(&self) -> Vec<TableCorrection> {
        let source = |t: &str| match t.trim().parse::<f64>() {
            Ok(v) => TemperatureSource::Uniform(v),
            Err(_) => TemperatureSource::Column(t.trim().to_string()),
        };
        [
            (ExpandingBody::MachineScale, &self.scale_temperature, self.scale_expansion),
            (ExpandingBody::Reference, &self.artefact_temperature, self.artefact_expansion),
        ]
        .into_iter()
        .filter_map(|(body, t, alpha)| {
            Some(TableCorrection { body, alpha_um_per_m_k: alpha?, temperature: source(t.as_deref()?), datum_mm: self.temperature_datum })
        })
        .collect()
    }
}
