//! Options to correct positioning readings to 20 degC, shared by `fit` and `iso230-2`; the file's
//! recorded environment (material temperature, expansion coefficient) when no option is given
//! (`trueaxis::instruments::scale_options` resolves them).

use trueaxis::instruments::{TemperatureOptions, TemperatureSource};

/// Correction of positioning readings to 20 degC (ISO 1).
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

impl TemperatureArgs {
    /// The options as the library takes them.
    pub fn options(&self) -> TemperatureOptions {
        TemperatureOptions {
            scale_temperature: self.scale_temperature.as_deref().map(TemperatureSource::parse),
            scale_expansion: self.scale_expansion,
            artefact_temperature: self.artefact_temperature.as_deref().map(TemperatureSource::parse),
            artefact_expansion: self.artefact_expansion,
            datum_mm: self.temperature_datum,
            no_file_temperature: self.no_file_temperature,
        }
    }
}
