//! The demo's CapBall campaign: the 807 poses of Andolfatto et al. 2011 simulated on the exact chain with sensor
//! noise and a cyclic drift of the measuring chain, and the true values in the campaign's parameter
//! set.

use super::{DemoError, Output, CAMPAIGN_POSES_CSV, CAMPAIGN_TOML, SOURCES_TOML};
use crate::calibration::IdentificationPart;
use std::path::PathBuf;
use trueaxis::error_model::ErrorModel;
use trueaxis::identify::{self, measurement_csv, simulate_campaign, Campaign, IndirectOptions};
use trueaxis::machine::Machine;
use trueaxis::uncertainty::{SourceKind, Sources};

/// Seed of the simulated noise (ChaCha8) and start phase of the simulated drift.
const SEED: u64 = 2011;
/// Time per CapBall point (s): the 807 points take 10 minutes.
pub const POINT_TIME_S: f64 = 0.75;
/// Phase of the simulated drift cycle at the first point (deg).
const DRIFT_PHASE_DEG: f64 = 40.0;

pub struct Simulated {
    pub campaign_path: PathBuf,
    /// Peak-to-valley of the simulated drift per channel (um) and its period (s).
    pub drift: Vec<(String, f64)>,
    pub drift_period_s: f64,
    pub noise_um: Vec<f64>,
    pub records: usize,
}

pub fn sources() -> Result<Sources, DemoError> {
    Ok(Sources::from_toml_str(SOURCES_TOML, "built-in kx8five_cyclic.toml")?)
}

/// Writes the campaign and its 807 poses, simulates the readings on the exact chain with the true
/// errors, the Table 3 sensor noise and the cyclic drift of the sources file (drift added at
/// `t = k POINT_TIME_S` for point `k`), and writes them as the campaign data.
pub fn simulate(machine: &Machine, truth: &ErrorModel, out: &mut Output) -> Result<Simulated, DemoError> {
    let campaign_path = out.write("campaign/campaign.toml", CAMPAIGN_TOML.as_bytes())?;
    out.write("campaign/capball.csv", CAMPAIGN_POSES_CSV.as_bytes())?;
    let campaign = Campaign::load(&campaign_path, machine)?;
    let mut readings = simulate_campaign(&campaign, machine, truth, Some(SEED))?;
    let sources = sources()?;
    let mut drift = Vec::new();
    let mut drift_period_s = 0.0;
    for s in &sources.sources {
        if let SourceKind::CyclicDrift(cyclic) = &s.kind {
            drift_period_s = cyclic.period();
            let phase_s = DRIFT_PHASE_DEG / 360.0 * drift_period_s;
            for (channel, function) in &cyclic.channels {
                let c = ["x", "y", "z"].iter().position(|n| n == channel).unwrap_or(0);
                for (k, record) in readings[0].chunks_mut(3).enumerate() {
                    record[c] += function.value(phase_s + k as f64 * POINT_TIME_S);
                }
                drift.push((channel.clone(), function.peak_to_valley()));
            }
        }
    }
    let m = &campaign.measurements[0];
    let csv = measurement_csv(machine, m, &readings[0]);
    out.write("campaign/capball.csv", csv.as_bytes())?;
    Ok(Simulated { campaign_path, drift, drift_period_s, noise_um: m.sigma_um.clone(), records: m.records() })
}

/// The values the identification gives on the same poses without noise and drift: the true errors
/// expressed in the campaign's parameter set (where the set cannot separate two true errors, their
/// combination; see the identifiability report).
pub fn equivalent_truth(machine: &Machine, truth: &ErrorModel, identified: &IdentificationPart) -> Result<Vec<f64>, DemoError> {
    let campaign = &identified.campaign;
    let nominal = campaign.nominal_errors(machine)?;
    let start = campaign.nominal_values(&nominal)?;
    let mut exact = campaign.clone();
    for (m, readings) in exact.measurements.iter_mut().zip(simulate_campaign(campaign, machine, truth, None)?) {
        m.readings = Some(readings);
    }
    Ok(identify::solve(&exact.design_matrix(machine, &nominal)?, &start, &IndirectOptions::default())?.values)
}
