//! The CapBall campaign of Andolfatto et al. 2011 (§3.2: a 3D probe on a master ball, readings
//! dx, dy, dz in um in the machine frame) simulated on the exact chain with the true errors, the
//! sensor noise of their Table 3 (seeded ChaCha8) and a cyclic drift of the measuring chain
//! (§4.4.2, peak-to-valley of Table 4) added at `t = phase + k POINT_TIME_S` for point `k`; and
//! the true values in the campaign's parameter set.

use crate::error_model::ErrorModel;
use crate::identify::{self, measurement_csv, simulate_campaign, Campaign, IdentifyError, IndirectOptions};
use crate::machine::Machine;
use crate::uncertainty::{SourceKind, Sources};

/// Seed of the simulated noise (ChaCha8) and start phase of the simulated drift.
const SEED: u64 = 2011;
/// Time per CapBall point (s): the 807 points take 10 minutes.
pub const POINT_TIME_S: f64 = 0.75;
/// Phase of the simulated drift cycle at the first point (deg).
const DRIFT_PHASE_DEG: f64 = 40.0;

/// The simulated data file of the campaign's measurement and how it was made.
pub struct SimulatedCampaign {
    /// The readings as the campaign's data file holds them.
    pub csv: String,
    /// Peak-to-valley of the simulated drift per channel (um) and its period (s).
    pub drift: Vec<(String, f64)>,
    pub drift_period_s: f64,
    pub noise_um: Vec<f64>,
    pub records: usize,
}

/// Simulates the readings of the campaign's first measurement on the exact chain with the true
/// errors, its stated sensor noise and the cyclic drift of `sources` (drift added at
/// `t = k POINT_TIME_S` for point `k`, from the phase `DRIFT_PHASE_DEG`).
pub fn simulate(campaign: &Campaign, machine: &Machine, truth: &ErrorModel, sources: &Sources) -> Result<SimulatedCampaign, IdentifyError> {
    let mut readings = simulate_campaign(campaign, machine, truth, Some(SEED))?;
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
    Ok(SimulatedCampaign { csv, drift, drift_period_s, noise_um: m.sigma_um.clone(), records: m.records() })
}

/// The values the identification gives on the same poses without noise and drift: the true errors
/// expressed in the campaign's parameter set (where the set cannot separate two true errors, their
/// combination; see the identifiability report).
pub fn equivalent_truth(machine: &Machine, truth: &ErrorModel, campaign: &Campaign) -> Result<Vec<f64>, IdentifyError> {
    let nominal = campaign.nominal_errors(machine)?;
    let start = campaign.nominal_values(&nominal)?;
    let mut exact = campaign.clone();
    for (m, readings) in exact.measurements.iter_mut().zip(simulate_campaign(campaign, machine, truth, None)?) {
        m.readings = Some(readings);
    }
    Ok(identify::solve(&exact.design_matrix(machine, &nominal)?, &start, &IndirectOptions::default())?.values)
}
