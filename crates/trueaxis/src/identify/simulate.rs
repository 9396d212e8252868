//! Simulated campaign data: the exact readings of every measurement of a campaign on a machine with
//! known errors, plus seeded Gaussian noise of each channel's stated standard deviation. For
//! planning measurements and for round-trip tests (simulate with known errors, identify, compare).

use super::campaign::{Campaign, Measurement};
use super::IdentifyError;
use crate::error_model::ErrorModel;
use crate::geometry::Vec3;
use crate::machine::Machine;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// Readings (um, `channels` per record) of every measurement, with the errors `truth`; with
/// `seed`, noise `N(0, sigma_um^2)` per channel is added (ChaCha8, reproducible). A measurement
/// with a sensor-frame calibration gets the raw sensor readings that its calibration maps to these
/// values (`sigma_um` is the noise of the calibrated readings), as its data file holds them.
pub fn simulate_campaign(
    campaign: &Campaign,
    machine: &Machine,
    truth: &ErrorModel,
    seed: Option<u64>,
) -> Result<Vec<Vec<f64>>, IdentifyError> {
    let zero = vec![0.0; campaign.unknowns.len()];
    let exact = campaign.predict(machine, truth, &zero)?;
    let mut rng = seed.map(ChaCha8Rng::seed_from_u64);
    let mut rows = exact.into_iter();
    let mut out = Vec::new();
    for m in &campaign.measurements {
        let nc = m.instrument.channels().len();
        let mut readings = Vec::with_capacity(m.records() * nc);
        for _ in 0..m.records() {
            for c in 0..nc {
                let mut v = rows.next().expect("one predicted value per row");
                if let Some(rng) = rng.as_mut() {
                    let z: f64 = StandardNormal.sample(rng);
                    v += z * m.sigma_um[c];
                }
                readings.push(v);
            }
            if let Some(calibration) = &m.calibration {
                let record = readings.len() - nc;
                let raw = calibration.reading_of(&Vec3::new(readings[record], readings[record + 1], readings[record + 2]));
                readings[record..].copy_from_slice(raw.as_slice());
            }
        }
        out.push(readings);
    }
    Ok(out)
}

/// CSV text of measurement `m` with `readings` (um): the axis columns (mm, deg; `X2, Y2, ...` for
/// the second end of a two-point length) and the reading columns, 4 decimals (0.1 nm).
pub fn measurement_csv(machine: &Machine, m: &Measurement, readings: &[f64]) -> String {
    use std::fmt::Write;
    let letters: Vec<String> = machine.axes().iter().map(|a| a.letter.to_string()).collect();
    let k = m.instrument.poses_per_record();
    let mut header = letters.clone();
    if k == 2 {
        header.extend(letters.iter().map(|l| format!("{l}2")));
    }
    header.extend(m.instrument.channels().iter().map(|c| c.to_string()));
    let mut text = format!(
        "# {} readings (um) of measurement `{}`, simulated by trueaxis on machine `{}`\n{}\n",
        m.instrument.kind(),
        m.name,
        machine.name,
        header.join(",")
    );
    let n = machine.axis_count();
    let nc = m.instrument.channels().len();
    for r in 0..m.records() {
        let poses = &m.poses[r * k * n..(r + 1) * k * n];
        let mut fields: Vec<String> = poses.iter().map(|v| format!("{}", round(*v, 9))).collect();
        fields.extend(readings[r * nc..(r + 1) * nc].iter().map(|v| format!("{:.4}", v)));
        let _ = writeln!(text, "{}", fields.join(","));
    }
    text
}

fn round(v: f64, decimals: i32) -> f64 {
    let f = 10f64.powi(decimals);
    let r = (v * f).round() / f;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}
