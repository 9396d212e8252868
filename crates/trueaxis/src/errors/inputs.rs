//! The inputs of an error model: what, besides the axis positions and directions of motion, its
//! terms depend on. Each input is named by a prefix that says what it is and in which unit:
//!
//! | name | quantity | unit | a term uses |
//! |---|---|---|---|
//! | `T:<sensor>` | temperature | degC | `T - 20 degC` (ISO 1) |
//! | `S:<spindle>` | spindle speed (seed 003 §3.5: "spindle speed and temperatures") | rpm | `S` |
//! | `F:<load>` | force, e.g. the weight of the workpiece (seed 000 §3.3.3) | N | `F` |
//! | `P:<name>` | a position that is not an axis, e.g. of the workpiece's centre of gravity | mm | `P` |
//! | `<T:sensor> lag <tau> s` | the rise of a sensor since the start of its run through a first-order lag of time constant tau (s), the state of a drift model (seed 000 §3.4.4) | degC | the lag |
//!
//! The first four come from columns of a pose or data file named exactly so, or from a value given
//! on the command line; a lag input is computed from its sensor's column and the time column `t`
//! (s), each run (column `run`) from its first row, the reference state (as [`crate::thermal`]'s
//! drift model: `z[k] = e^(-dt/tau) z[k-1] + (1 - e^(-dt/tau)) (T[k-1] - T[0])`, the input held
//! over each sample interval).

/// What an input is (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub enum InputKind {
    Temperature,
    SpindleSpeed,
    Force,
    Position,
    /// The lagged rise of a temperature sensor.
    Lag {
        sensor: String,
        tau_s: f64,
    },
}

impl InputKind {
    /// The kind of an input name; an error explains the names.
    pub fn parse(name: &str) -> Result<InputKind, String> {
        if let Some((sensor, rest)) = name.split_once(" lag ") {
            let tau = rest.strip_suffix(" s").and_then(|t| t.trim().parse::<f64>().ok()).filter(|t| t.is_finite() && *t > 0.0);
            return match (InputKind::parse(sensor), tau) {
                (Ok(InputKind::Temperature), Some(tau_s)) => Ok(InputKind::Lag { sensor: sensor.to_string(), tau_s }),
                _ => Err(format!("input `{name}`: a lagged input is `T:<sensor> lag <seconds> s`")),
            };
        }
        let kind = match name.split_once(':') {
            Some(("T", n)) if !n.is_empty() => InputKind::Temperature,
            Some(("S", n)) if !n.is_empty() => InputKind::SpindleSpeed,
            Some(("F", n)) if !n.is_empty() => InputKind::Force,
            Some(("P", n)) if !n.is_empty() => InputKind::Position,
            _ => {
                return Err(format!(
                    "input `{name}` is not a temperature `T:<sensor>` (degC), a spindle speed `S:<name>` (rpm), a force `F:<name>` (N) \
                     or a position `P:<name>` (mm)"
                ))
            }
        };
        Ok(kind)
    }

    /// The value at which a term of this input vanishes: 20 degC for a temperature, else 0.
    pub fn reference(&self) -> f64 {
        match self {
            InputKind::Temperature => super::REFERENCE_TEMPERATURE,
            _ => 0.0,
        }
    }

    /// The unit of the input's values.
    pub fn unit(&self) -> &'static str {
        match self {
            InputKind::Temperature | InputKind::Lag { .. } => "degC",
            InputKind::SpindleSpeed => "rpm",
            InputKind::Force => "N",
            InputKind::Position => "mm",
        }
    }
}

/// The name of the lagged rise of `sensor` with time constant `tau_s` (s).
pub fn lag_name(sensor: &str, tau_s: f64) -> String {
    format!("{sensor} lag {tau_s} s")
}

/// Where the values of inputs come from, for a table of rows (poses or samples).
pub struct InputSource<'a> {
    /// Number of rows.
    pub rows: usize,
    /// The column of an input name, when the table has one.
    pub column: &'a dyn Fn(&str) -> Option<Vec<f64>>,
    /// A value given for every row (command line), when there is one.
    pub given: &'a dyn Fn(&str) -> Option<f64>,
    /// Times of the rows (s), when the table has them.
    pub times: Option<&'a [f64]>,
    /// Run of each row, when the table has them (one run otherwise).
    pub runs: Option<&'a [String]>,
    /// Names the table in messages.
    pub origin: &'a str,
}

/// The values of `inputs` (names as in [`super::ErrorModel::sensors`]) for every row, `inputs.len()`
/// per row in that order; an error names an input that has neither a column nor a given value, or
/// a lag input without times.
pub fn input_values(inputs: &[String], source: &InputSource) -> Result<Vec<f64>, String> {
    let n = source.rows;
    let plain = |name: &str, kind: &InputKind| -> Result<Vec<f64>, String> {
        match ((source.column)(name), (source.given)(name)) {
            (Some(c), _) => Ok(c),
            (None, Some(v)) => Ok(vec![v; n]),
            (None, None) => Err(format!(
                "{}: missing column `{name}` ({unit}) needed by the error model; add it or give --{} {name}={unit}",
                source.origin,
                if *kind == InputKind::Temperature { "temperature" } else { "input" },
                unit = kind.unit()
            )),
        }
    };
    let mut columns = Vec::with_capacity(inputs.len());
    for name in inputs {
        let kind = InputKind::parse(name)?;
        let column = match &kind {
            InputKind::Lag { sensor, tau_s } => {
                let readings = plain(sensor, &InputKind::Temperature)?;
                let times = source.times.ok_or_else(|| {
                    format!("{}: the error model has a drift term (input `{name}`): the rows need the time column `t` (s)", source.origin)
                })?;
                lagged_rise(&readings, times, source.runs, *tau_s).map_err(|m| format!("{}: {m}", source.origin))?
            }
            kind => plain(name, kind)?,
        };
        columns.push(column);
    }
    Ok((0..n).flat_map(|i| columns.iter().map(move |c| c[i])).collect())
}

/// The rise of `readings` since the first row of each run through a first-order lag of time
/// constant `tau_s` (module documentation); rows of a run in time order.
pub fn lagged_rise(readings: &[f64], times: &[f64], runs: Option<&[String]>, tau_s: f64) -> Result<Vec<f64>, String> {
    let mut out = vec![0.0; readings.len()];
    // the previous row of each run: (row, lag value)
    let mut last: Vec<(&str, usize, usize, f64)> = Vec::new(); // (run, first row, previous row, z)
    for k in 0..readings.len() {
        let run = runs.map_or("", |r| r[k].as_str());
        match last.iter_mut().find(|(r, ..)| *r == run) {
            None => last.push((run, k, k, 0.0)),
            Some((_, first, previous, z)) => {
                let dt = times[k] - times[*previous];
                if dt.is_nan() || dt <= 0.0 {
                    return Err(format!(
                        "row {}: the time t = {} does not follow the previous time {} of its run; a drift model needs the rows of each run in time order",
                        k + 1,
                        times[k],
                        times[*previous]
                    ));
                }
                let decay = (-dt / tau_s).exp();
                *z = decay * *z + (1.0 - decay) * (readings[*previous] - readings[*first]);
                *previous = k;
                out[k] = *z;
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_kinds_and_references() {
        assert_eq!(InputKind::parse("T:spindle").unwrap().reference(), 20.0);
        assert_eq!(InputKind::parse("S:main").unwrap(), InputKind::SpindleSpeed);
        assert_eq!(InputKind::parse("F:workpiece").unwrap().reference(), 0.0);
        assert_eq!(InputKind::parse("P:workpiece_z").unwrap().unit(), "mm");
        assert_eq!(InputKind::parse(&lag_name("T:34", 1800.0)).unwrap(), InputKind::Lag { sensor: "T:34".into(), tau_s: 1800.0 });
        assert!(InputKind::parse("Q:x").unwrap_err().contains("spindle speed"));
        assert!(InputKind::parse("T:").is_err());
        assert!(InputKind::parse("S:x lag 10 s").unwrap_err().contains("lagged"));
    }

    #[test]
    fn lag_of_a_step_is_the_exponential() {
        // a step of 2 K at t = 0 (held from the first interval on): z(t) = 2 (1 - e^(-t/tau))
        let times: Vec<f64> = (0..50).map(|k| 60.0 * k as f64).collect();
        let readings: Vec<f64> = (0..50).map(|k| if k == 0 { 20.0 } else { 22.0 }).collect();
        let z = lagged_rise(&readings, &times, None, 600.0).unwrap();
        // the input is held at its value of the previous sample: zero over [0, 60), 2 K after
        for k in 1..50 {
            let want = 2.0 * (1.0 - (-(times[k] - 60.0) / 600.0).exp());
            assert!((z[k] - want).abs() < 1e-12, "{k}: {} vs {want}", z[k]);
        }
        // a second run starts from its own reference state
        let runs: Vec<String> = (0..50).map(|k| if k < 25 { "a" } else { "b" }.to_string()).collect();
        let z = lagged_rise(&readings, &times, Some(&runs), 600.0).unwrap();
        assert_eq!(z[25], 0.0);
        assert!(lagged_rise(&[20.0, 21.0], &[0.0, 0.0], None, 1.0).unwrap_err().contains("time order"));
    }
}

/// The values of the inputs of `errors` for every row of the pose or data file `path` (`rows`
/// rows, `errors.sensors().len()` values per row): columns named like the inputs, else `given`
/// (`(name, value)`, e.g. from `--temperature T:spindle=24.5` or `--input S:spindle=3000`); the
/// drift lags from the columns `t` (s) and `run`. Shared by `predict`, `compensate --poses` and
/// `verify`. An error names the file and the input that has neither a column nor a value.
pub fn pose_file_inputs(
    errors: &super::ErrorModel,
    path: &std::path::Path,
    rows: usize,
    given: &[(String, f64)],
) -> Result<Vec<f64>, String> {
    if errors.sensors().is_empty() {
        return Ok(Vec::new());
    }
    let table = crate::data::CsvTable::read(path).map_err(|e| e.to_string())?;
    let numbers = |name: &str| table.has_column(name).then(|| table.numbers(name)).transpose().map_err(|e| e.to_string());
    let mut columns = Vec::new();
    for name in errors.sensors().iter().map(String::as_str).chain(std::iter::once("t")) {
        // a lag input is computed from its sensor's column
        let source = name.split_once(" lag ").map_or(name, |(s, _)| s);
        columns.push((source.to_string(), numbers(source)?));
    }
    let times = columns.iter().find(|(n, _)| n == "t").and_then(|(_, c)| c.clone());
    let runs = if table.has_column("run") { Some(table.texts("run").map_err(|e| e.to_string())?) } else { None };
    let lookup = |name: &str| columns.iter().find(|(n, _)| n == name).and_then(|(_, c)| c.clone());
    let value = |name: &str| given.iter().find(|(n, _)| n == name).map(|(_, v)| *v);
    let origin = path.display().to_string();
    let source = InputSource { rows, column: &lookup, given: &value, times: times.as_deref(), runs: runs.as_deref(), origin: &origin };
    input_values(errors.sensors(), &source)
}
