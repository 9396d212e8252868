//! The uncertainty-sources file (TOML): Monte Carlo settings and a list of sources, each acting on
//! the observations of named channels (see docs/uncertainty.md for the full format):
//!
//! ```toml
//! coverage = 0.95          # coverage probability p
//! tolerance = 0.05         # numerical tolerance delta (um, urad)
//! seed = 4
//! [[source]]
//! name = "sensors"
//! kind = "noise"           # independent per observation (Andolfatto et al. 2011 §4.2, §4.3)
//! channels.x = { distribution = "normal", u = 0.28 }
//! [[source]]
//! name = "drift"
//! kind = "drift_cyclic"    # or "drift_statistical" with e_ve = { x = 6.95 }
//! period_s = 1000
//! channels.x = { peak_to_valley = 6.95 }
//! [[source]]
//! name = "frame"
//! kind = "correlated"      # x, y, z of one point drawn jointly (JCGM 101 §6.4.8)
//! channels = ["x", "y", "z"]
//! u = [0.56, 0.27, 0.69]
//! correlation = [[1, 0.5, 0], [0.5, 1, 0], [0, 0, 1]]
//! ```

use super::chain_drift::{PeriodicDrift, StartPhase};
use super::distributions::Distribution;
use super::monte_carlo::{IntervalKind, McSettings};
use super::DesignMatrix;
use crate::error::Error;
use serde::Deserialize;
use std::collections::BTreeMap;

/// One source of uncertainty.
#[derive(Clone, Debug, PartialEq)]
pub struct Source {
    pub name: String,
    pub kind: SourceKind,
}

#[derive(Clone, Debug, PartialEq)]
pub enum SourceKind {
    /// An error drawn independently for every observation of a channel from the channel's
    /// distribution (um): sensor output noise (Andolfatto et al. 2011 Table 3), or the sensor-to-machine frame
    /// transformation modelled per point as in Andolfatto et al. 2011 §4.3.
    Noise { channels: Vec<(String, Distribution)> },
    /// Gaussian errors correlated across channels (JCGM 101 §6.4.8, JCGM 102 §6.3): the
    /// observations of `channels` taken at the same time `t` (one point of a 3D-ball head: its x, y
    /// and z) get one joint draw from N(0, `covariance`) (um^2, in the order of `channels`);
    /// points are independent of each other.
    Correlated { channels: Vec<String>, covariance: nalgebra::DMatrix<f64> },
    /// Drift by the statistical method of ISO/TR 230-9 (Andolfatto et al. 2011 §4.4.1): a Gaussian error with
    /// `u = E_VE / (2 sqrt 3)`, independent per observation; `E_VE` in um per channel.
    StatisticalDrift { channels: Vec<(String, f64)> },
    /// Drift by the cyclic method (Andolfatto et al. 2011 §4.4.2).
    CyclicDrift(CyclicDrift),
}

/// The cyclic drift: a periodic function of time per channel, subtracted from the simulated
/// measurement at `t0 + (n - 1) t_m + t_k` (Andolfatto et al. 2011 eq. 12) with `t0` uniform over one period.
#[derive(Clone, Debug, PartialEq)]
pub struct CyclicDrift {
    /// Drift function of each channel; all share the period and the random start time.
    pub channels: Vec<(String, PeriodicDrift)>,
    /// Duration of one run `t_m` (s); `None`: the largest observation time of the design
    /// (`t_m = 807 t_i` when point `k` is measured at `k t_i`, eq. 13).
    pub run_duration: Option<f64>,
    pub start_phase: StartPhase,
}

impl CyclicDrift {
    /// The common period of the channels' drift functions (s).
    pub fn period(&self) -> f64 {
        self.channels.first().map_or(1.0, |(_, d)| d.period())
    }
}

impl Source {
    /// The channel names this source refers to.
    pub fn channel_names(&self) -> Vec<&str> {
        match &self.kind {
            SourceKind::Noise { channels } => channels.iter().map(|(c, _)| c.as_str()).collect(),
            SourceKind::StatisticalDrift { channels } => channels.iter().map(|(c, _)| c.as_str()).collect(),
            SourceKind::CyclicDrift(c) => c.channels.iter().map(|(c, _)| c.as_str()).collect(),
            SourceKind::Correlated { channels, .. } => channels.iter().map(String::as_str).collect(),
        }
    }
}

/// The sources file: Monte Carlo settings and the sources.
#[derive(Clone, Debug, PartialEq)]
pub struct Sources {
    pub settings: McSettings,
    pub sources: Vec<Source>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    coverage: Option<f64>,
    tolerance: Option<f64>,
    trials_per_sequence: Option<usize>,
    max_sequences: Option<usize>,
    seed: Option<u64>,
    interval: Option<RawInterval>,
    #[serde(default)]
    source: Vec<RawSource>,
}

#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
enum RawInterval {
    Symmetric,
    Shortest,
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum RawSource {
    Noise {
        name: String,
        channels: BTreeMap<String, RawDistribution>,
    },
    DriftStatistical {
        name: String,
        e_ve: BTreeMap<String, f64>,
    },
    Correlated {
        name: String,
        channels: Vec<String>,
        u: Option<Vec<f64>>,
        correlation: Option<Vec<Vec<f64>>>,
        covariance: Option<Vec<Vec<f64>>>,
    },
    DriftCyclic {
        name: String,
        period_s: f64,
        run_duration_s: Option<f64>,
        start_phase: Option<StartPhase>,
        channels: BTreeMap<String, RawCycle>,
    },
}

#[derive(Deserialize)]
#[serde(tag = "distribution", rename_all = "snake_case", deny_unknown_fields)]
enum RawDistribution {
    Normal {
        u: f64,
        #[serde(default)]
        mean: f64,
    },
    Rectangular {
        half_width: f64,
        #[serde(default)]
        mean: f64,
    },
    Triangular {
        half_width: f64,
        #[serde(default)]
        mean: f64,
    },
    Arcsine {
        half_width: f64,
        #[serde(default)]
        mean: f64,
    },
    StudentT {
        scale: f64,
        dof: f64,
        #[serde(default)]
        mean: f64,
    },
}

impl RawDistribution {
    fn build(self) -> Result<Distribution, Error> {
        let half = |h: f64| if h >= 0.0 { Ok(h) } else { Err(Error::input(format!("half_width {h} must not be negative"))) };
        match self {
            RawDistribution::Normal { u, mean } => Distribution::Normal { mean, u },
            RawDistribution::Rectangular { half_width, mean } => {
                Distribution::Rectangular { low: mean - half(half_width)?, high: mean + half_width }
            }
            RawDistribution::Triangular { half_width, mean } => {
                Distribution::Triangular { low: mean - half(half_width)?, mode: mean, high: mean + half_width }
            }
            RawDistribution::Arcsine { half_width, mean } => {
                Distribution::Arcsine { low: mean - half(half_width)?, high: mean + half_width }
            }
            RawDistribution::StudentT { scale, dof, mean } => Distribution::StudentT { mean, scale, dof },
        }
        .validated()
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCycle {
    peak_to_valley: Option<f64>,
    phase_deg: Option<f64>,
    harmonics: Option<Vec<[f64; 2]>>,
    samples: Option<Vec<f64>>,
}

impl RawCycle {
    fn build(self, period: f64) -> Result<PeriodicDrift, Error> {
        match (self.peak_to_valley, self.harmonics, self.samples) {
            (Some(pv), None, None) => PeriodicDrift::sine(period, pv, self.phase_deg.unwrap_or(0.0)),
            (None, Some(h), None) if self.phase_deg.is_none() && !h.is_empty() => {
                PeriodicDrift::harmonics(period, &h.iter().map(|[a, p]| (*a, *p)).collect::<Vec<_>>())
            }
            (None, None, Some(s)) if self.phase_deg.is_none() => PeriodicDrift::from_samples(period, &s),
            _ => Err(Error::input(
                "give exactly one of peak_to_valley (with optional phase_deg), harmonics = [[amplitude, phase_deg], ...] or samples = [...]",
            )),
        }
    }
}

impl Sources {
    /// Reads a sources file.
    pub fn load(path: impl AsRef<std::path::Path>) -> Result<Sources, Error> {
        let path = path.as_ref();
        let text = crate::files::inputs::read_to_string(path)
            .map_err(|source| crate::data::DataError::Read { path: path.display().to_string(), source })?;
        Self::from_toml_str(&text, &path.display().to_string())
    }

    /// Parses the TOML text; `origin` names it in messages.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Sources, Error> {
        let fail = |m: String| Error::input(format!("{origin}: {m}"));
        crate::io::toml_numbers::refuse_underflow(text).map_err(|e| e.in_file(origin))?;
        let raw: RawFile = toml::from_str(text).map_err(|e| fail(e.to_string().trim().replace('\n', " ")))?;
        let coverage = raw.coverage.unwrap_or(0.95);
        let mut settings = McSettings::new(coverage, raw.tolerance.unwrap_or(0.05));
        if let Some(m) = raw.trials_per_sequence {
            settings.trials_per_sequence = m;
        }
        if let Some(h) = raw.max_sequences {
            settings.max_sequences = h;
        }
        if let Some(seed) = raw.seed {
            settings.seed = seed;
        }
        settings.interval = match raw.interval {
            Some(RawInterval::Shortest) => IntervalKind::Shortest,
            _ => IntervalKind::Symmetric,
        };
        settings.validate().map_err(|e| fail(e.to_string()))?;
        let mut sources = Vec::new();
        for raw_source in raw.source {
            let source = build_source(raw_source).map_err(|(name, e)| fail(format!("source `{name}`: {e}")))?;
            if sources.iter().any(|s: &Source| s.name == source.name) {
                return Err(fail(format!("two sources are named `{}`", source.name)));
            }
            sources.push(source);
        }
        if sources.is_empty() {
            return Err(fail("no [[source]] given".into()));
        }
        Ok(Sources { settings, sources })
    }

    /// Checks that every channel a source names exists in the design (channels a source does not
    /// name receive nothing from it).
    pub fn check_channels(&self, design: &DesignMatrix) -> Result<(), Error> {
        for source in &self.sources {
            for name in source.channel_names() {
                if design.channel_index(name).is_none() {
                    return Err(Error::input(format!(
                        "source `{}`: channel `{name}` is not in the design (channels: {})",
                        source.name,
                        design.channels.join(", ")
                    )));
                }
            }
        }
        Ok(())
    }
}

fn build_source(raw: RawSource) -> Result<Source, (String, Error)> {
    let input = |m: String| Error::input(m);
    match raw {
        RawSource::Noise { name, channels } => {
            let mut built = Vec::new();
            for (channel, d) in channels {
                let d = d.build().map_err(|e| (name.clone(), input(format!("channel `{channel}`: {e}"))))?;
                built.push((channel, d));
            }
            Ok(Source { name, kind: SourceKind::Noise { channels: built } })
        }
        RawSource::DriftStatistical { name, e_ve } => {
            if let Some((c, v)) = e_ve.iter().find(|(_, v)| !(**v >= 0.0 && v.is_finite())) {
                return Err((name, input(format!("channel `{c}`: E_VE {v} must be a non-negative number (um)"))));
            }
            Ok(Source { name, kind: SourceKind::StatisticalDrift { channels: e_ve.into_iter().collect() } })
        }
        RawSource::Correlated { name, channels, u, correlation, covariance } => {
            let covariance = correlated_covariance(&channels, u, correlation, covariance).map_err(|e| (name.clone(), e))?;
            Ok(Source { name, kind: SourceKind::Correlated { channels, covariance } })
        }
        RawSource::DriftCyclic { name, period_s, run_duration_s, start_phase, channels } => {
            if let Some(t) = run_duration_s.filter(|t| !(*t > 0.0 && t.is_finite())) {
                return Err((name, input(format!("run_duration_s {t} must be a positive number"))));
            }
            let mut built = Vec::new();
            for (channel, c) in channels {
                let d = c.build(period_s).map_err(|e| (name.clone(), input(format!("channel `{channel}`: {e}"))))?;
                built.push((channel, d));
            }
            if built.is_empty() {
                return Err((name, input("no channels given".into())));
            }
            let kind = SourceKind::CyclicDrift(CyclicDrift {
                channels: built,
                run_duration: run_duration_s,
                start_phase: start_phase.unwrap_or_default(),
            });
            Ok(Source { name, kind })
        }
    }
}

/// The covariance (um^2) of a `correlated` source: `covariance` directly, or `V_ij = r_ij u_i u_j`
/// from the standard uncertainties `u` (um) and the correlation matrix `correlation`; symmetric,
/// positive semidefinite, one row per channel, distinct channels.
fn correlated_covariance(
    channels: &[String],
    u: Option<Vec<f64>>,
    correlation: Option<Vec<Vec<f64>>>,
    covariance: Option<Vec<Vec<f64>>>,
) -> Result<nalgebra::DMatrix<f64>, Error> {
    let n = channels.len();
    if n == 0 {
        crate::bail!(input, "no channels given");
    }
    if let Some(c) = channels.iter().enumerate().find(|(i, c)| channels[..*i].contains(c)).map(|(_, c)| c) {
        crate::bail!(input, "channel `{c}` appears twice");
    }
    let square = |what: &str, m: &[Vec<f64>]| -> Result<nalgebra::DMatrix<f64>, Error> {
        if m.len() != n || m.iter().any(|row| row.len() != n) {
            crate::bail!(input, "{what} must be {n} x {n} (one row and column per channel: {})", channels.join(", "));
        }
        if m.iter().flatten().any(|v| !v.is_finite()) {
            crate::bail!(input, "{what} holds a number that is not finite");
        }
        Ok(nalgebra::DMatrix::from_fn(n, n, |i, j| m[i][j]))
    };
    let v = match (u, correlation, covariance) {
        (None, None, Some(c)) => square("covariance", &c)?,
        (Some(u), Some(r), None) => {
            if u.len() != n || u.iter().any(|v| !(*v >= 0.0 && v.is_finite())) {
                crate::bail!(input, "u must hold {n} non-negative standard uncertainties (um), one per channel");
            }
            let r = square("correlation", &r)?;
            if (0..n).any(|i| (r[(i, i)] - 1.0).abs() > 1e-12) || r.iter().any(|v| v.abs() > 1.0 + 1e-12) {
                crate::bail!(input, "a correlation matrix has 1 on its diagonal and coefficients within [-1, 1]");
            }
            nalgebra::DMatrix::from_fn(n, n, |i, j| r[(i, j)] * u[i] * u[j])
        }
        _ => crate::bail!(input, "give either covariance = [[...]] (um^2) or u = [...] (um) with correlation = [[...]]"),
    };
    if (&v - v.transpose()).abs().max() > 1e-12 * v.abs().max().max(1e-300) {
        crate::bail!(input, "the matrix must be symmetric");
    }
    let eigen = v.clone().symmetric_eigen();
    let largest = eigen.eigenvalues.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    if eigen.eigenvalues.iter().any(|&l| l < -1e-10 * largest) {
        crate::bail!(input, "the covariance is not positive semidefinite (no such joint distribution exists)");
    }
    Ok(v)
}
