//! Screening of a ballbar circular test (ISO 230-4).
//!
//! - Geometry: the plane's two axis columns, when present, must describe the circle. A file in
//!   which they stand still while a rotary axis column sweeps is a rotary-axis test (Jiang 2014):
//!   evaluated as a circle in the plane it would turn the rotary axis's errors into squareness and
//!   scale mismatch of the linear axes; it is refused.
//! - Spikes: each reading (um) against the median of its 4 neighbours on each side; beyond
//!   `SPIKE_LIMIT` robust sigmas of those differences and 1 um, away (more than
//!   `REVERSAL_ZONE_DEG`) from the angles where an axis of the plane reverses (0, 90, 180, 270 deg:
//!   reversal spikes there are the machine's behaviour and belong to the result), a reading is a
//!   transient of the test (a feed-rate overshoot, a knock on the bar). Each finding states G of
//!   its run without the spike.

use crate::data::CsvTable;
use crate::evaluate::ballbar_diagnostics::CircularRun;
use crate::evaluate::iso230_4::circular_values;
use crate::screen::finding::{Finding, Kind};
use crate::screen::series::neighbour_outliers;

/// A reading this many robust sigmas from its neighbours' median is a spike.
pub const SPIKE_LIMIT: f64 = 8.0;
/// The smallest spike flagged (um).
pub const SPIKE_FLOOR_UM: f64 = 1.0;
/// Half-width (deg) of the zones about the axis reversals where spikes are the machine's.
pub const REVERSAL_ZONE_DEG: f64 = 5.0;
/// A rotary column sweeping more than this (deg) is a rotary-axis test.
pub const ROTARY_SWEEP_DEG: f64 = 1.0;

fn span(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max) - v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Refuses a file whose plane axes (`a`, `b`) stand still while a rotary axis column sweeps.
pub fn circle_axes(table: &CsvTable, origin: &str, a: char, b: char) -> Option<Finding> {
    let column = |c: char| table.numbers(&c.to_string()).ok().filter(|v| v.iter().all(|x| x.is_finite()));
    let (xa, xb) = (column(a)?, column(b)?);
    if span(&xa) > 1e-6 || span(&xb) > 1e-6 {
        return None;
    }
    let (rotary, sweep) = ['A', 'B', 'C'].iter().filter_map(|&r| column(r).map(|v| (r, span(&v)))).max_by(|x, y| x.1.total_cmp(&y.1))?;
    (sweep > ROTARY_SWEEP_DEG).then(|| {
        Finding::flag(
            Kind::Geometry,
            origin,
            format!("columns {a}, {b}, {rotary}"),
            format!(
                "{a} and {b} stand still at {:.3}, {:.3} mm while {rotary} sweeps {sweep:.1} deg: this is a rotary-axis ballbar test, not a circle in \
                 the {a}{b} plane; evaluated as one it would report the rotary axis's errors as squareness and scale of {a} and {b}. Evaluate it \
                 with `trueaxis ballbar identify` (Jiang 2014)",
                xa[0], xb[0]
            ),
        )
        .refusing()
    })
}

/// Spikes of each run, with G of the run without them.
pub fn spikes(origin: &str, runs: &[CircularRun], radius_mm: f64) -> Vec<Finding> {
    let mut out = Vec::new();
    for run in runs {
        let dl_um: Vec<f64> = run.dl.iter().map(|v| v * 1e3).collect();
        let angles = &run.test.angles;
        let near_reversal = |i: usize| {
            let deg = angles[i].to_degrees().rem_euclid(90.0);
            deg.min(90.0 - deg) <= REVERSAL_ZONE_DEG
        };
        let found: Vec<(usize, f64)> =
            neighbour_outliers(&dl_um, SPIKE_LIMIT, SPIKE_FLOOR_UM).into_iter().filter(|(i, _)| !near_reversal(*i)).collect();
        if found.is_empty() {
            continue;
        }
        let keep: Vec<usize> = (0..dl_um.len()).filter(|i| !found.iter().any(|f| f.0 == *i)).collect();
        let g = |idx: &[usize]| {
            let a: Vec<f64> = idx.iter().map(|&i| angles[i]).collect();
            let d: Vec<f64> = idx.iter().map(|&i| run.dl[i]).collect();
            circular_values(run.rotation, &a, &d, radius_mm).ok().map(|v| v.g_um)
        };
        let all: Vec<usize> = (0..dl_um.len()).collect();
        let consequence = match (g(&all), g(&keep)) {
            (Some(with), Some(without)) => format!("G of this run would be {without:.2} um without them (with them: {with:.2} um)"),
            _ => String::new(),
        };
        let worst = found.iter().copied().max_by(|x, y| x.1.abs().total_cmp(&y.1.abs())).unwrap_or(found[0]);
        let samples: Vec<String> = found.iter().map(|(i, _)| format!("{}", i + 1)).collect();
        out.push(
            Finding::flag(
                Kind::Outlier,
                origin,
                format!("{} run, sample(s) {}", run.rotation.name(), samples.join(", ")),
                format!(
                    "{} reading(s) off their neighbours by up to {:+.2} um at {:.1} deg, away from the axis reversals: a transient of the test \
                     (feed-rate overshoot, a knock on the bar), not a machine error",
                    found.len(),
                    worst.1,
                    angles[worst.0].to_degrees()
                ),
            )
            .with_consequence(consequence),
        );
    }
    out
}
