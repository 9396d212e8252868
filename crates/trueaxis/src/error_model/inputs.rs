//! The inputs of an error model: what, besides the axis positions and directions of motion, its
//! terms depend on. Each input is named by a prefix that says what it is and in which unit:
//!
//! | name | quantity | unit | a term uses |
//! |---|---|---|---|
//! | `T:<sensor>` | temperature | degC | `T - 20 degC` (ISO 1) |
//! | `S:<spindle>` | spindle speed (NISTIR 5236 §3.5: "spindle speed and temperatures") | rpm | `S` |
//! | `F:<load>` | force, e.g. the weight of the workpiece (Soons 1993 §3.3.3) | N | `F` |
//! | `P:<name>` | a position that is not an axis, e.g. of the workpiece's centre of gravity | mm | `P` |
//! | `<T:sensor> lag <tau> s` | the rise of a sensor since the start of its run through a first-order lag of time constant tau (s), the state of a drift model (Soons 1993 §3.4.4) | degC | the lag |
//!
//! The first four come from columns of a pose or data file named exactly so, or from a value given
//! on the command line; a lag input is computed from its sensor's column and the time column `t`
//! (s), each run (column `run`) from its first row, the reference state (as [`crate::thermal`]'s
//! drift model: `z[k] = e^(-dt/tau) z[k-1] + (1 - e^(-dt/tau)) (T[k-1] - T[0])`, the input held
//! over each sample interval).

use crate::error::{Error, Result};

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
    pub fn parse(name: &str) -> Result<InputKind> {
        if let Some((sensor, rest)) = name.split_once(" lag ") {
            let tau = rest.strip_suffix(" s").and_then(|t| t.trim().parse::<f64>().ok()).filter(|t| t.is_finite() && *t > 0.0);
            return match (InputKind::parse(sensor), tau) {
                (Ok(InputKind::Temperature), Some(tau_s)) => Ok(InputKind::Lag { sensor: sensor.to_string(), tau_s }),
                _ => Err(Error::input(format!("input `{name}`: a lagged input is `T:<sensor> lag <seconds> s`"))),
            };
        }
        let kind = match name.split_once(':') {
            Some(("T", n)) if !n.is_empty() => InputKind::Temperature,
            Some(("S", n)) if !n.is_empty() => InputKind::SpindleSpeed,
            Some(("F", n)) if !n.is_empty() => InputKind::Force,
            Some(("P", n)) if !n.is_empty() => InputKind::Position,
            _ => {
                return Err(Error::input(format!(
                    "input `{name}` is not a temperature `T:<sensor>` (degC), a spindle speed `S:<name>` (rpm), a force `F:<name>` (N) \
                     or a position `P:<name>` (mm)"
                )))
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
pub fn input_values(inputs: &[String], source: &InputSource) -> Result<Vec<f64>> {
    let (mut rows, wanted) = InputRows::new(inputs, &|name| (source.column)(name).is_some(), source.given, source.times.is_some())
        .map_err(|m| Error::input(format!("{}: {m}", source.origin)))?;
    let columns: Vec<Vec<f64>> = wanted.iter().map(|name| (source.column)(name).expect("a column the source has")).collect();
    let mut out = Vec::with_capacity(source.rows * inputs.len());
    let mut values = vec![0.0; columns.len()];
    for k in 0..source.rows {
        for (v, c) in values.iter_mut().zip(&columns) {
            *v = c[k];
        }
        let (time, run) = (source.times.map(|t| t[k]), source.runs.map_or("", |r| r[k].as_str()));
        rows.push(&values, time, run, &mut out).map_err(|m| Error::input(format!("{}: row {}: {m}", source.origin, k + 1)))?;
    }
    Ok(out)
}

/// The rise of `readings` since the first row of each run through a first-order lag of time
/// constant `tau_s` (module documentation); rows of a run in time order.
pub fn lagged_rise(readings: &[f64], times: &[f64], runs: Option<&[String]>, tau_s: f64) -> Result<Vec<f64>> {
    let mut lag = Lag::new(tau_s);
    (0..readings.len())
        .map(|k| {
            lag.next(readings[k], times[k], runs.map_or("", |r| r[k].as_str())).map_err(|m| Error::input(format!("row {}: {m}", k + 1)))
        })
        .collect()
}

/// The lagged rise of one sensor, row after row (module documentation): per run its first
/// reading, the previous reading and time, and the lag's state.
#[derive(Clone, Debug)]
struct Lag {
    tau_s: f64,
    /// (run, first reading, previous reading, previous time, z)
    runs: Vec<(String, f64, f64, f64, f64)>,
}

impl Lag {
    fn new(tau_s: f64) -> Lag {
        Lag { tau_s, runs: Vec::new() }
    }

    /// The lag at a row with `reading` (degC) at `time` (s) of `run`.
    fn next(&mut self, reading: f64, time: f64, run: &str) -> Result<f64> {
        let Some((_, first, previous, previous_time, z)) = self.runs.iter_mut().find(|r| r.0 == run) else {
            self.runs.push((run.to_string(), reading, reading, time, 0.0));
            return Ok(0.0);
        };
        let dt = time - *previous_time;
        if dt.is_nan() || dt <= 0.0 {
            return Err(Error::input(format!(
                "the time t = {time} does not follow the previous time {previous_time} of its run; a drift model needs the rows of each \
                 run in time order"
            )));
        }
        let decay = (-dt / self.tau_s).exp();
        *z = decay * *z + (1.0 - decay) * (*previous - *first);
        (*previous, *previous_time) = (reading, time);
        Ok(*z)
    }
}

/// Where one input's value comes from, row by row.
#[derive(Clone, Debug)]
enum Source {
    /// The row's value of a column (index into the wanted columns).
    Column(usize),
    Given(f64),
    /// The lag of the sensor whose value is that column.
    Lag(usize, Lag),
}

/// The inputs of an error model row after row, for a table read as a stream (a pose file of any
/// length): each input from the row's column of that name, else a value given for every row, and
/// each lag from its sensor's column and the row's time and run (module documentation).
#[derive(Clone, Debug)]
pub struct InputRows {
    sources: Vec<Source>,
}

impl InputRows {
    /// The plan for `inputs` (the model's names) given which columns the table has (`has_column`)
    /// and the given values; returns it with the names of the columns [`InputRows::push`] wants
    /// per row, in order. An error names the input that has neither a column nor a value, or a
    /// lag without the time column (the message does not name the table: the caller does).
    pub fn new(
        inputs: &[String],
        has_column: &dyn Fn(&str) -> bool,
        given: &dyn Fn(&str) -> Option<f64>,
        has_times: bool,
    ) -> Result<(InputRows, Vec<String>)> {
        let mut wanted: Vec<String> = Vec::new();
        let mut column_of = |name: &str, kind: &InputKind| -> Result<Source> {
            if has_column(name) {
                let i = wanted.iter().position(|w| w == name).unwrap_or_else(|| {
                    wanted.push(name.to_string());
                    wanted.len() - 1
                });
                return Ok(Source::Column(i));
            }
            given(name).map(Source::Given).ok_or_else(|| {
                Error::input(format!(
                    "missing column `{name}` ({unit}) needed by the error model; add it or give --{} {name}={unit}",
                    if *kind == InputKind::Temperature { "temperature" } else { "input" },
                    unit = kind.unit()
                ))
            })
        };
        let mut sources = Vec::with_capacity(inputs.len());
        for name in inputs {
            let kind = InputKind::parse(name)?;
            sources.push(match &kind {
                InputKind::Lag { sensor, tau_s } => {
                    if !has_times {
                        return Err(Error::input(format!(
                            "the error model has a drift term (input `{name}`): the rows need the time column `t` (s)"
                        )));
                    }
                    match column_of(sensor, &InputKind::Temperature)? {
                        Source::Column(i) => Source::Lag(i, Lag::new(*tau_s)),
                        // a sensor held at one value does not rise
                        _ => Source::Given(0.0),
                    }
                }
                kind => column_of(name, kind)?,
            });
        }
        Ok((InputRows { sources }, wanted))
    }

    /// Appends the inputs of the next row to `out`: `columns` the row's values of the wanted
    /// columns, `time` its time (s; needed by lags), `run` its run. An error (a time out of order
    /// within a run) does not name the row: the caller does.
    pub fn push(&mut self, columns: &[f64], time: Option<f64>, run: &str, out: &mut Vec<f64>) -> Result<()> {
        for source in &mut self.sources {
            out.push(match source {
                Source::Column(i) => columns[*i],
                Source::Given(v) => *v,
                Source::Lag(i, lag) => lag.next(columns[*i], time.unwrap_or(f64::NAN), run)?,
            });
        }
        Ok(())
    }
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
        assert!(InputKind::parse("Q:x").unwrap_err().to_string().contains("spindle speed"));
        assert!(InputKind::parse("T:").is_err());
        assert!(InputKind::parse("S:x lag 10 s").unwrap_err().to_string().contains("lagged"));
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
        assert!(lagged_rise(&[20.0, 21.0], &[0.0, 0.0], None, 1.0).unwrap_err().to_string().contains("time order"));
    }
}
