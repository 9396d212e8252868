//! What an instrument file says about the test besides its readings: machine, serial number, date,
//! operator, axis, location, title, and the environment (air and material temperatures, the
//! expansion coefficient of the material). Read from the `USER-TEXT::` and `ENVIRONMENT::` sections
//! of a Renishaw file, the `Key: value` header of a ballbar export and the `# Key: value` comments of
//! a CSV. A report (certificate contents) and the `--json` outputs consume it; the material
//! temperature and the expansion coefficient feed the correction to 20 degC
//! (`instruments::scale`).

use super::header::normalised;
use super::units::{leading_number, Dimension, Unit};
use serde_json::{json, Map, Value};

/// The environment recorded with a test.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Environment {
    /// Air temperature, degC.
    pub air_temperature_degc: Option<f64>,
    /// Material (machine scale or workpiece) temperatures, degC, in the order written (a laser
    /// system has up to three material sensors).
    pub material_temperatures_degc: Vec<f64>,
    /// Expansion coefficient of the material, um/m/K (= ppm/K).
    pub expansion_coefficient_um_per_m_k: Option<f64>,
}

impl Environment {
    /// The mean material temperature, degC, when any was recorded.
    pub fn material_temperature_degc(&self) -> Option<f64> {
        let t = &self.material_temperatures_degc;
        (!t.is_empty()).then(|| t.iter().sum::<f64>() / t.len() as f64)
    }

    pub fn is_empty(&self) -> bool {
        self.air_temperature_degc.is_none() && self.material_temperatures_degc.is_empty() && self.expansion_coefficient_um_per_m_k.is_none()
    }
}

/// Metadata of a test file. Free text is kept as written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Metadata {
    pub machine: Option<String>,
    pub serial: Option<String>,
    pub date: Option<String>,
    pub operator: Option<String>,
    pub axis: Option<String>,
    pub location: Option<String>,
    pub title: Option<String>,
    pub environment: Environment,
    /// The other `Key: value` pairs of the file's header, as written (test parameters, instrument
    /// settings).
    pub other: Vec<(String, String)>,
}

/// What a recognised key sets.
enum Field {
    Machine,
    Serial,
    Date,
    Operator,
    Axis,
    Location,
    Title,
    AirTemperature,
    MaterialTemperature,
    Expansion,
}

fn field_of(key: &str) -> Option<Field> {
    let k = normalised(key);
    // units written into the key (`Air temp (°C)`) do not matter here
    let k = k.split(['(', '[']).next().unwrap_or("").to_string();
    Some(match k.as_str() {
        "machine" | "machinename" | "maschine" | "machinetool" => Field::Machine,
        "serialno" | "serialnumber" | "serial" | "sn" | "s/n" | "machineserial" | "seriennummer" => Field::Serial,
        "date" | "datetime" | "testdate" | "datum" => Field::Date,
        "by" | "operator" | "user" | "tester" | "testedby" | "bediener" | "prüfer" => Field::Operator,
        "axis" | "achse" | "axisname" => Field::Axis,
        "location" | "site" | "ort" | "place" => Field::Location,
        "title" | "testtitle" | "testname" | "titel" => Field::Title,
        "airtemp" | "airtemperature" | "lufttemperatur" | "airt" => Field::AirTemperature,
        "mattemp"
        | "materialtemp"
        | "materialtemperature"
        | "mattemp1"
        | "mattemp2"
        | "mattemp3"
        | "materialtemp1"
        | "materialtemp2"
        | "materialtemp3"
        | "materialtemperature1"
        | "materialtemperature2"
        | "materialtemperature3"
        | "materialtemperatur"
        | "scaletemperature" => Field::MaterialTemperature,
        "expcoeff" | "expcoef" | "expansioncoefficient" | "expansioncoeff" | "materialexpansion" | "cte" | "ausdehnungskoeffizient" => {
            Field::Expansion
        }
        _ => return None,
    })
}

/// A temperature value: a number with an optional temperature unit (`21.3`, `21,3 °C`, `294.45 K`);
/// text after the number that is not a unit (`21.3 C (scale)`) is ignored.
fn temperature(value: &str) -> Option<f64> {
    let (v, rest) = leading_number(value)?;
    let degc = match Unit::parse(rest) {
        Some(u) if u.dimension == Dimension::Temperature => u.convert(v, Unit::DEGC),
        Some(_) => return None,
        None => v,
    };
    degc.is_finite().then_some(degc)
}

/// An expansion coefficient in um/m/K: the leading number; a value below 1e-3 is taken as written
/// in 1/K (e.g. `11.5e-6`) and scaled by 1e6.
fn expansion(value: &str) -> Option<f64> {
    let (v, _) = leading_number(value)?;
    let v = if v != 0.0 && v.abs() < 1e-3 { v * 1e6 } else { v };
    v.is_finite().then_some(v)
}

/// True for keys that [`Metadata::from_pairs`] recognises or that describe a ballbar test
/// (`io::ballbar`): the keys taken from `# Key: value` comments of a table (other comments are
/// prose).
pub fn is_known_key(key: &str) -> bool {
    field_of(key).is_some() || super::ballbar::is_test_key(key)
}

impl Metadata {
    /// Builds metadata from `Key: value` pairs: recognised keys (in English or German, any case,
    /// units in the key ignored: `Machine`, `Serial No`, `Date`, `By`/`Operator`, `Axis`,
    /// `Location`, `Title`, `Air temp`, `Mat temp 1..3`, `Exp coeff`) fill the fields, the others are
    /// kept in [`Metadata::other`]. Empty values are skipped; a number that cannot be read keeps the
    /// pair in `other`.
    pub fn from_pairs<'a>(pairs: impl IntoIterator<Item = (&'a str, &'a str)>) -> Metadata {
        let mut m = Metadata::default();
        for (key, value) in pairs {
            let value = value.trim();
            if value.is_empty() {
                continue;
            }
            let keep = |m: &mut Metadata| m.other.push((key.trim().to_string(), value.to_string()));
            let text = |slot: &mut Option<String>| {
                if slot.is_none() {
                    *slot = Some(value.to_string());
                }
            };
            match field_of(key) {
                Some(Field::Machine) => text(&mut m.machine),
                Some(Field::Serial) => text(&mut m.serial),
                Some(Field::Date) => text(&mut m.date),
                Some(Field::Operator) => text(&mut m.operator),
                Some(Field::Axis) => text(&mut m.axis),
                Some(Field::Location) => text(&mut m.location),
                Some(Field::Title) => text(&mut m.title),
                Some(Field::AirTemperature) => match temperature(value) {
                    Some(t) if m.environment.air_temperature_degc.is_none() => m.environment.air_temperature_degc = Some(t),
                    Some(_) => {}
                    None => keep(&mut m),
                },
                Some(Field::MaterialTemperature) => match temperature(value) {
                    Some(t) => m.environment.material_temperatures_degc.push(t),
                    None => keep(&mut m),
                },
                Some(Field::Expansion) => match expansion(value) {
                    Some(a) if m.environment.expansion_coefficient_um_per_m_k.is_none() => {
                        m.environment.expansion_coefficient_um_per_m_k = Some(a)
                    }
                    Some(_) => {}
                    None => keep(&mut m),
                },
                None => keep(&mut m),
            }
        }
        m
    }

    /// The value of an `other` pair by key (compared as [`normalised`] names).
    pub fn other_value(&self, key: &str) -> Option<&str> {
        let k = normalised(key);
        self.other.iter().find(|(name, _)| normalised(name) == k).map(|(_, v)| v.as_str())
    }

    /// True when nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.named().is_empty() && self.environment.is_empty() && self.other.is_empty()
    }

    /// The named text fields that are present, as (key, value).
    pub fn named(&self) -> Vec<(&'static str, &str)> {
        [
            ("machine", &self.machine),
            ("serial", &self.serial),
            ("date", &self.date),
            ("operator", &self.operator),
            ("axis", &self.axis),
            ("location", &self.location),
            ("title", &self.title),
        ]
        .into_iter()
        .filter_map(|(k, v)| v.as_deref().map(|v| (k, v)))
        .collect()
    }

    /// The `metadata` object of the `--json` outputs: the named fields present, `environment`
    /// (`air_temperature_degc`, `material_temperatures_degc`, `material_temperature_degc` (mean),
    /// `expansion_coefficient_um_per_m_k`) when any was recorded, and `other` as an object.
    pub fn to_json(&self) -> Value {
        let mut o = Map::new();
        for (k, v) in self.named() {
            o.insert(k.into(), v.into());
        }
        let e = &self.environment;
        if !e.is_empty() {
            let mut env = Map::new();
            if let Some(t) = e.air_temperature_degc {
                env.insert("air_temperature_degc".into(), t.into());
            }
            if !e.material_temperatures_degc.is_empty() {
                env.insert("material_temperatures_degc".into(), json!(e.material_temperatures_degc));
                env.insert("material_temperature_degc".into(), json!(e.material_temperature_degc()));
            }
            if let Some(a) = e.expansion_coefficient_um_per_m_k {
                env.insert("expansion_coefficient_um_per_m_k".into(), a.into());
            }
            o.insert("environment".into(), Value::Object(env));
        }
        if !self.other.is_empty() {
            let other: Map<String, Value> = self.other.iter().map(|(k, v)| (k.clone(), Value::from(v.as_str()))).collect();
            o.insert("other".into(), Value::Object(other));
        }
        Value::Object(o)
    }

    /// One line per recorded item (`machine: DMU 50`, `material temperature: 20.6 degC (mean of 3)`),
    /// for text outputs and reports.
    pub fn lines(&self) -> Vec<String> {
        let mut out: Vec<String> = self.named().iter().map(|(k, v)| format!("{k}: {v}")).collect();
        let e = &self.environment;
        if let Some(t) = e.air_temperature_degc {
            out.push(format!("air temperature: {t} degC"));
        }
        if let Some(t) = e.material_temperature_degc() {
            let n = e.material_temperatures_degc.len();
            let of = if n > 1 { format!(" (mean of {n} sensors)") } else { String::new() };
            out.push(format!("material temperature: {t:.3} degC{of}"));
        }
        if let Some(a) = e.expansion_coefficient_um_per_m_k {
            out.push(format!("expansion coefficient: {a} um/m/K"));
        }
        out
    }

    /// The pairs to write back as `# Key: value` comments of a canonical CSV, so that reading it
    /// again gives the same metadata.
    pub fn comment_pairs(&self) -> Vec<(String, String)> {
        let mut out: Vec<(String, String)> = self
            .named()
            .iter()
            .map(|(k, v)| {
                let key = match *k {
                    "serial" => "Serial No",
                    "operator" => "Operator",
                    other => other,
                };
                let mut key = key.to_string();
                if let Some(first) = key.get_mut(0..1) {
                    first.make_ascii_uppercase();
                }
                (key, v.to_string())
            })
            .collect();
        let e = &self.environment;
        if let Some(t) = e.air_temperature_degc {
            out.push(("Air temperature (degC)".into(), format!("{t}")));
        }
        for (i, t) in e.material_temperatures_degc.iter().enumerate() {
            out.push((format!("Mat temp {} (degC)", i + 1), format!("{t}")));
        }
        if let Some(a) = e.expansion_coefficient_um_per_m_k {
            out.push(("Exp coeff (um/m/K)".into(), format!("{a}")));
        }
        out.extend(self.other.iter().cloned());
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recognised_keys_and_values() {
        let m = Metadata::from_pairs([
            ("Machine", "DMU 50"),
            ("Serial No", "12345"),
            ("By", "J. Smith"),
            ("Mat temp 1", "20,4"),
            ("Mat temp 2", "20.6 °C"),
            ("Air temp", "293.15 K"),
            ("Exp coeff", "11.5e-6"),
            ("Feed rate", "1000 mm/min"),
            ("Axis", ""),
        ]);
        assert_eq!(m.machine.as_deref(), Some("DMU 50"));
        assert_eq!(m.serial.as_deref(), Some("12345"));
        assert_eq!(m.operator.as_deref(), Some("J. Smith"));
        assert_eq!(m.axis, None);
        assert_eq!(m.environment.material_temperatures_degc, vec![20.4, 20.6]);
        assert!((m.environment.material_temperature_degc().unwrap() - 20.5).abs() < 1e-12);
        assert!((m.environment.air_temperature_degc.unwrap() - 20.0).abs() < 1e-9);
        assert!((m.environment.expansion_coefficient_um_per_m_k.unwrap() - 11.5).abs() < 1e-9);
        assert_eq!(m.other_value("feed rate"), Some("1000 mm/min"));
        let again = Metadata::from_pairs(m.comment_pairs().iter().map(|(k, v)| (k.as_str(), v.as_str())));
        assert_eq!(again, m);
    }
}
