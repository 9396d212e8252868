//! The design matrix of a linear identification (Andolfatto et al. 2011 eqs. 3-4, `d_chi = J_id d_p`) with what
//! the uncertainty sources need per observation: its channel, its measurement time and its weight.
//!
//! File form (CSV, `#` comments): one row per observation; columns `channel` (text, e.g. `x`, `y`,
//! `z` of a 3D-ball head, or `s1.x`), `t` (s, measurement time within the run), optional `y`
//! (um, the measured value; default 0), optional `weight` (`1/sigma^2`; default 1), and one column per
//! parameter with the sensitivities in um per parameter unit (um or urad for ISO 230 names).

use crate::data::DataError;
use crate::error::Error;
use crate::machine::ParameterId;
use nalgebra::DMatrix;

/// Columns of the design file that are not parameters.
pub const RESERVED_COLUMNS: [&str; 4] = ["channel", "t", "y", "weight"];

/// An immutable linear measurement model `y = X p + e`.
#[derive(Clone, Debug)]
pub struct DesignMatrix {
    /// Parameter names, in column order.
    pub parameters: Vec<String>,
    /// Unit of each parameter: `um`/`urad` for ISO 230 names, `unit` otherwise.
    pub units: Vec<String>,
    /// Distinct channel names, in order of first appearance.
    pub channels: Vec<String>,
    /// Channel of each observation (index into `channels`).
    pub channel: Vec<usize>,
    /// Measurement time of each observation within one run (s).
    pub time: Vec<f64>,
    /// Weight of each observation, `1/sigma^2` (relative weights suffice).
    pub weight: Vec<f64>,
    /// Measured value of each observation (um); zeros when unknown.
    pub measured: Vec<f64>,
    /// `n_obs x n_par`, um per parameter unit.
    pub x: DMatrix<f64>,
}

impl DesignMatrix {
    /// Builds and checks a design: one channel name, time, weight and measured value per row;
    /// finite numbers; positive weights; distinct parameter names; more rows than parameters.
    pub fn new(
        parameters: Vec<String>,
        channel_names: &[String],
        time: Vec<f64>,
        weight: Option<Vec<f64>>,
        measured: Option<Vec<f64>>,
        x: DMatrix<f64>,
    ) -> Result<DesignMatrix, Error> {
        let (n, p) = x.shape();
        let bad = |m: String| Err(Error::input(m));
        if parameters.len() != p || channel_names.len() != n || time.len() != n {
            return bad(format!(
                "design matrix {n}x{p} with {} parameter names, {} channels and {} times",
                parameters.len(),
                channel_names.len(),
                time.len()
            ));
        }
        if n <= p {
            return bad(format!("{n} observations cannot determine {p} parameters"));
        }
        for (i, name) in parameters.iter().enumerate() {
            if parameters[..i].contains(name) {
                return bad(format!("parameter `{name}` appears twice"));
            }
        }
        let weight = weight.unwrap_or_else(|| vec![1.0; n]);
        let measured = measured.unwrap_or_else(|| vec![0.0; n]);
        if weight.len() != n || measured.len() != n {
            return bad("one weight and one measured value per observation are needed".into());
        }
        if let Some(i) = weight.iter().position(|w| !(*w > 0.0 && w.is_finite())) {
            return bad(format!("observation {}: weight {} must be a positive number", i + 1, weight[i]));
        }
        if x.iter().chain(&time).chain(&measured).any(|v| !v.is_finite()) {
            return bad("the design contains numbers that are not finite".into());
        }
        let mut channels: Vec<String> = Vec::new();
        let channel = channel_names
            .iter()
            .map(|c| match channels.iter().position(|k| k == c) {
                Some(i) => i,
                None => {
                    channels.push(c.clone());
                    channels.len() - 1
                }
            })
            .collect();
        let units = parameters.iter().map(|name| ParameterId::parse(name).map_or("unit", |id| id.unit()).to_string()).collect();
        Ok(DesignMatrix { parameters, units, channels, channel, time, weight, measured, x })
    }

    pub fn observations(&self) -> usize {
        self.x.nrows()
    }

    pub fn parameter_count(&self) -> usize {
        self.x.ncols()
    }

    /// Index of a channel by name.
    pub fn channel_index(&self, name: &str) -> Option<usize> {
        self.channels.iter().position(|c| c == name)
    }

    /// Reads the CSV form described in the module documentation.
    pub fn read_csv(path: impl AsRef<std::path::Path>) -> Result<DesignMatrix, Error> {
        let path = path.as_ref();
        let file = crate::files::inputs::open(path).map_err(|source| DataError::Read { path: path.display().to_string(), source })?;
        Self::from_csv_reader(file, &path.display().to_string())
    }

    /// Reads CSV text (forgivingly: `crate::data::CsvTable`); `origin` names it in messages.
    pub fn from_csv_reader(reader: impl std::io::Read, origin: &str) -> Result<DesignMatrix, Error> {
        let fail = |m: String| Error::input(format!("{origin}: {m}"));
        let table = crate::data::CsvTable::from_reader(reader, origin).map_err(|e| Error::input(e.to_string()))?;
        let data = |e: DataError| Error::input(e.to_string());
        let headers = table.headers();
        let reserved = |name: &str| RESERVED_COLUMNS.iter().any(|r| r.eq_ignore_ascii_case(name.trim()));
        if !(table.has_column("channel") && table.has_column("t")) {
            let list: Vec<&str> = headers.iter().map(|h| h.text.as_str()).collect();
            return Err(fail(format!("the header needs the columns `channel` and `t`; it has: {}", list.join(","))));
        }
        let parameter_columns: Vec<&str> =
            headers.iter().filter(|h| !reserved(&h.name) && !h.name.eq_ignore_ascii_case("time")).map(|h| h.name.as_str()).collect();
        if parameter_columns.is_empty() {
            return Err(fail("no parameter columns: add one column of sensitivities per parameter".into()));
        }
        let channels = table.texts("channel").map_err(data)?;
        if let Some(r) = channels.iter().position(|c| c.is_empty()) {
            return Err(fail(format!("line {}: empty channel name", table.lines()[r])));
        }
        let time = table.numbers("t").map_err(data)?;
        let weight = if table.has_column("weight") { table.numbers("weight").map_err(data)? } else { Vec::new() };
        let measured = if table.has_column("y") { table.numbers("y").map_err(data)? } else { Vec::new() };
        let i_w = table.has_column("weight").then_some(());
        let i_y = table.has_column("y").then_some(());
        let columns: Vec<Vec<f64>> = parameter_columns.iter().map(|c| table.numbers(c)).collect::<Result<_, _>>().map_err(data)?;
        let values: Vec<f64> = (0..table.len()).flat_map(|r| columns.iter().map(move |c| c[r])).collect();
        let names: Vec<String> = parameter_columns.iter().map(|s| s.to_string()).collect();
        let n = channels.len();
        let x = DMatrix::from_row_slice(n, names.len(), &values);
        Self::new(names, &channels, time, i_w.map(|_| weight), i_y.map(|_| measured), x).map_err(|e| fail(e.to_string()))
    }

    /// The CSV form (the inverse of [`DesignMatrix::from_csv_reader`]).
    pub fn to_csv(&self) -> String {
        use std::fmt::Write;
        let mut out = format!("channel,t,y,weight,{}\n", self.parameters.join(","));
        for i in 0..self.observations() {
            let _ = write!(out, "{},{},{},{}", self.channels[self.channel[i]], self.time[i], self.measured[i], self.weight[i]);
            for j in 0..self.parameter_count() {
                let _ = write!(out, ",{}", self.x[(i, j)]);
            }
            out.push('\n');
        }
        out
    }
}

/// The design of a campaign identification (`trueaxis identify`'s stacked Jacobian, observations
/// and weights) as the linear model of the uncertainty sources (Andolfatto et al. 2011 eqs. 3-4): record `k` of a
/// measurement is taken at `k point_time_s` (Andolfatto et al. 2011 eq. 12 with `t_i = point_time_s`). Channels
/// are named by the reading without its `d` (`x`, `y`, `z`, `L`) when the campaign has one
/// measurement, else `<measurement>:<x>` — the names the sources file uses.
pub fn from_identification(design: &crate::identify::DesignMatrix, point_time_s: f64) -> Result<DesignMatrix, Error> {
    if !(point_time_s.is_finite() && point_time_s >= 0.0) {
        return Err(Error::input(format!("the time per point must be a non-negative number of seconds, got {point_time_s}")));
    }
    let single = design.records.iter().all(|(m, _)| *m == design.records.first().map_or(0, |r| r.0));
    let short = |name: &str| -> String {
        let (measurement, channel) = name.rsplit_once(':').unwrap_or(("", name));
        let channel = channel.strip_prefix('d').unwrap_or(channel);
        if single || measurement.is_empty() {
            channel.to_string()
        } else {
            format!("{measurement}:{channel}")
        }
    };
    let channels: Vec<String> = design.channels.iter().map(|&c| short(&design.channel_names[c])).collect();
    let time = design.records.iter().map(|(_, r)| *r as f64 * point_time_s).collect();
    DesignMatrix::new(
        design.names.clone(),
        &channels,
        time,
        Some(design.weights.clone()),
        Some(design.observations.clone()),
        design.matrix.clone(),
    )
}
