//! Options to correct positioning readings to 20 degC, shared by `fit` and `iso230-2`.

use trueaxis::instruments::{ExpandingBody, TableCorrection, TemperatureSource};

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
}

impl TemperatureArgs {
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
