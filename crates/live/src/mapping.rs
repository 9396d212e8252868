//! The mapping file of a live compensation (TOML): where each model input comes from, how far it
//! may go, and where each axis offset goes.
//!
//! ```toml
//! [input."T:p1"]                    # a model input (a T:<sensor> of the thermal model)
//! node = "ns=2;s=vmc3.T_p1"         # OPC UA node id (source opcua)
//! pin = "thermo.0.temperature"      # LinuxCNC HAL pin (source hal)
//! column = "T:p1"                   # CSV column (source csv; default: the input's name)
//! unit = "degC"                     # degC (default) or K
//! range = [5.0, 60.0]               # the sensor's physical range (degC); outside: refused
//! rate_limit = 0.05                 # degC/s: a faster change is refused (default 0.05)
//! noise = 0.5                       # degC: a change this small is never a jump (default 0.5)
//!
//! [run]                             # optional: a change of this value starts a new run
//! node = "ns=2;s=vmc3.Run"          # (the reference state of a drift model), as the
//! pin = "..."                       # `run` column of a campaign does
//!
//! [output.Z]                        # the offset of axis Z
//! node = "ns=2;s=vmc3.ThermalOffsetZ"
//! unit = "mm"                       # mm (default) or um
//! pin = "ta-vmc3.0.thermal-z"       # HAL pin (sink hal), in mm
//! ```
//!
//! A change between two accepted readings larger than `rate_limit * min(dt, 600 s) + noise` is a
//! jump (dt the time between them): no machine structure warms by 30 K in ten minutes, so a
//! reading that does is a broken sensor, a unit slip or a wire fault, whatever the gap before it.

use crate::input;
use crate::LiveError;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Default rate limit (degC/s): 3 K per minute.
pub const DEFAULT_RATE_LIMIT: f64 = 0.05;
/// Default change that is never a jump (degC).
pub const DEFAULT_NOISE: f64 = 0.5;
/// The longest interval the rate limit scales with (s).
pub const RATE_WINDOW_S: f64 = 600.0;

/// One input of the models.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputMap {
    pub node: Option<String>,
    pub pin: Option<String>,
    pub column: Option<String>,
    #[serde(default = "default_temperature_unit")]
    pub unit: String,
    pub range: Option<[f64; 2]>,
    pub rate_limit: Option<f64>,
    pub noise: Option<f64>,
}

/// The run signal (optional).
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunMap {
    pub node: Option<String>,
    pub pin: Option<String>,
    pub column: Option<String>,
}

/// One axis offset.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputMap {
    pub node: Option<String>,
    pub pin: Option<String>,
    #[serde(default = "default_length_unit")]
    pub unit: String,
}

fn default_temperature_unit() -> String {
    "degC".into()
}

fn default_length_unit() -> String {
    "mm".into()
}

/// The whole mapping file.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mapping {
    #[serde(default)]
    pub input: BTreeMap<String, InputMap>,
    pub run: Option<RunMap>,
    #[serde(default)]
    pub output: BTreeMap<String, OutputMap>,
    /// Where the file came from (for messages).
    #[serde(skip)]
    pub origin: String,
}

impl Mapping {
    /// Reads and checks a mapping file.
    pub fn read(path: &Path) -> Result<Mapping, LiveError> {
        let text = std::fs::read_to_string(path).map_err(|e| input(format!("{}: cannot read: {e}", path.display())))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses mapping text; `origin` names it in messages.
    pub fn parse(text: &str, origin: &str) -> Result<Mapping, LiveError> {
        let mut m: Mapping = toml::from_str(text)
            .map_err(|e| input(format!("{origin}: {}", e.to_string().split_whitespace().collect::<Vec<_>>().join(" "))))?;
        m.origin = origin.into();
        for (name, i) in &m.input {
            let at = format!("{origin}: [input.\"{name}\"]");
            if !["degC", "K"].contains(&i.unit.as_str()) {
                return Err(input(format!("{at} unit `{}`: a temperature is in degC or K", i.unit)));
            }
            if let Some([lo, hi]) = i.range {
                if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                    return Err(input(format!("{at} range [{lo}, {hi}] needs finite lo < hi (degC)")));
                }
            }
            for (key, v) in [("rate_limit", i.rate_limit), ("noise", i.noise)] {
                if v.is_some_and(|v| !(v.is_finite() && v >= 0.0)) {
                    return Err(input(format!("{at} {key} must be a non-negative number")));
                }
            }
        }
        for (axis, o) in &m.output {
            if !["mm", "um"].contains(&o.unit.as_str()) {
                return Err(input(format!("{origin}: [output.{axis}] unit `{}`: an offset is in mm or um", o.unit)));
            }
        }
        Ok(m)
    }

    /// The entry of input `name`, if the file has one.
    pub fn input_of(&self, name: &str) -> Option<&InputMap> {
        self.input.get(name)
    }

    /// The address of every model input for a source (`node`, `pin` or `column`), in order:
    /// refuses a missing one, naming it.
    pub fn addresses(&self, inputs: &[String], kind: AddressKind) -> Result<Vec<String>, LiveError> {
        inputs
            .iter()
            .map(|name| {
                let entry = self.input.get(name);
                let address = match kind {
                    AddressKind::Node => entry.and_then(|e| e.node.clone()),
                    AddressKind::Pin => entry.and_then(|e| e.pin.clone()),
                    AddressKind::Column => Some(entry.and_then(|e| e.column.clone()).unwrap_or_else(|| name.clone())),
                };
                address.ok_or_else(|| {
                    input(format!("{}: the model input `{name}` has no {} in [input.\"{name}\"]", self.origin_or_none(), kind.key()))
                })
            })
            .collect()
    }

    /// The address of the run signal, if mapped.
    pub fn run_address(&self, kind: AddressKind) -> Option<String> {
        let r = self.run.as_ref()?;
        match kind {
            AddressKind::Node => r.node.clone(),
            AddressKind::Pin => r.pin.clone(),
            AddressKind::Column => r.column.clone(),
        }
    }

    fn origin_or_none(&self) -> &str {
        if self.origin.is_empty() {
            "the mapping (no --map file)"
        } else {
            &self.origin
        }
    }
}

/// What addresses a source uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AddressKind {
    Node,
    Pin,
    Column,
}

impl AddressKind {
    fn key(self) -> &'static str {
        match self {
            AddressKind::Node => "node (OPC UA node id)",
            AddressKind::Pin => "pin (HAL pin)",
            AddressKind::Column => "column",
        }
    }
}

/// A reading in its unit to degC.
pub fn to_degc(value: f64, unit: &str) -> f64 {
    match unit {
        "K" => value - 273.15,
        _ => value,
    }
}
