//! The text of `thermal place --score`: every placement method with the same number of sensors,
//! scored by the error of the elongation model it leads to (um; computed by
//! `trueaxis::thermal::placement_comparison`), one line per method.

use std::fmt::Write;
use trueaxis::thermal::placement_comparison::PlacementComparison;

/// The table of the scores: training RMS and the RMS of each validation cycle (um).
pub fn scores_text(scores: &PlacementComparison) -> String {
    let mut text = format!(
        "placements scored by the elongation model (alpha {} um/m/K): trained on a 20-min on/off cycle, validated on 10 and 40 min\n  {:<38} {:<16} {:>10} {:>10} {:>10}\n",
        scores.alpha, "method", "nodes", "train RMS", "10 min", "40 min"
    );
    for (m, s) in &scores.rows {
        let v: Vec<String> = s.validation.iter().map(|(_, r, _)| format!("{r:>10.4}")).collect();
        let _ = writeln!(text, "  {m:<38} {:<16} {:>10.4} {} um", format!("{:?}", s.sensors), s.training_rms, v.join(" "));
    }
    text
}
