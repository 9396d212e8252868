//! The five-axis configuration study of Zhu (2008) appendix C as `trueaxis budget configurations`
//! runs it: the counts of the enumeration (720 / 360 / 432 / 288), the travel (mm) a part (mm)
//! needs and the space utility per category and order of the rotary axes (Table C.2), and the
//! budget of every five-degree-of-freedom configuration with the same tolerances (um, urad),
//! ranked by the root mean square of its root-sum-square volumetric error (um); its JSON document;
//! and the trend of the space utility of a cubic part with its size (Zhu 2008 Fig. C.1).

use super::configurations::{all_sequences, five_axis_configurations, practical_configurations, three_linear_sequences, Pattern};
use super::ranking::{study_with_progress, ConfigurationBudget, StudyOptions};
use super::travel::{required_travel, space_utility};
use crate::error::Error;
use serde_json::{json, Value};
use std::collections::BTreeMap;

/// The whole study.
#[derive(Clone, Debug)]
pub struct ConfigurationStudy {
    pub options: StudyOptions,
    /// Orders of five of the six axes, with the three linear axes, of the three categories, with
    /// five degrees of freedom.
    pub counts: [usize; 4],
    /// Per category and order of the rotary axes: the representative sequence (linear axes X Y Z)
    /// and its travel (largest |position| per linear axis, mm).
    pub travel: BTreeMap<(Pattern, String), ([char; 5], [f64; 3])>,
    /// The budgets, smallest RMS first.
    pub ranked: Vec<ConfigurationBudget>,
}

/// Checks the options as the command line does (names of its options in the messages).
fn check(options: &StudyOptions) -> Result<(), Error> {
    let t = options.tolerances.0;
    let lengths = [("--tool-length", options.tool_length), ("--linear-um", t[0]), ("--angular-urad", t[1]), ("--squareness-urad", t[2])];
    for (name, v) in lengths {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::input(format!("{name} {v}: must be a positive number")));
        }
    }
    if options.nodes < 2 || !(options.tilt_deg.is_finite() && options.tilt_deg.abs() < 90.0) {
        return Err(Error::input("--nodes must be at least 2 and --tilt-deg within (-90, 90) deg"));
    }
    Ok(())
}

/// The configuration of a category with the rotary axes `rotary` (in chain order) and the linear
/// axes in the order X Y Z (the rows of the appendix's tables).
pub fn representative(pattern: Pattern, rotary: &str) -> [char; 5] {
    let r: Vec<char> = rotary.chars().collect();
    match pattern {
        Pattern::RotaryAtWorkpiece => [r[0], r[1], 'X', 'Y', 'Z'],
        Pattern::Split => [r[0], 'X', 'Y', 'Z', r[1]],
        _ => ['X', 'Y', 'Z', r[0], r[1]],
    }
}

/// Edge-to-tool-length ratios of the cubic parts of [`space_utility_trend`].
pub const TREND_RATIOS: [f64; 7] = [0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0];

/// One curve of [`space_utility_trend`]: a category, its configuration with the rotary axes A, B,
/// and the points `(r, space utility)`.
#[derive(Clone, Debug, PartialEq)]
pub struct TrendCurve {
    pub pattern: Pattern,
    pub sequence: [char; 5],
    pub points: Vec<(f64, f64)>,
}

/// The space utility of a cubic part of edge `r p` (mm) against `r` ([`TREND_RATIOS`]) with a tool
/// of length `p` (mm), for the configuration of each category with the rotary axes A, B (ABXYZ,
/// AXYZB, XYZAB; Zhu 2008 Fig. C.1), one curve per category.
pub fn space_utility_trend(tool_length: f64) -> Result<Vec<TrendCurve>, crate::Error> {
    let trend = |pattern: Pattern| {
        let sequence = representative(pattern, "AB");
        let point = |r: f64| {
            let part = [r * tool_length; 3];
            Ok((r, space_utility(part, required_travel(&sequence, part, tool_length)?)))
        };
        Ok(TrendCurve { pattern, sequence, points: TREND_RATIOS.into_iter().map(point).collect::<Result<Vec<_>, crate::Error>>()? })
    };
    Pattern::PRACTICAL.into_iter().map(trend).collect()
}

impl ConfigurationStudy {
    /// Runs the study; `progress(done, total)` after each configuration's budget.
    pub fn run(options: &StudyOptions, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<ConfigurationStudy, Error> {
        check(options)?;
        let five = five_axis_configurations();
        let counts = [all_sequences().len(), three_linear_sequences().len(), practical_configurations().len(), five.len()];
        let mut travel = BTreeMap::new();
        for c in &five {
            let rotary: String = c.sequence.iter().filter(|a| "ABC".contains(**a)).collect();
            if let std::collections::btree_map::Entry::Vacant(e) = travel.entry((c.pattern(), rotary)) {
                let sequence = representative(c.pattern(), &e.key().1);
                let t = required_travel(&sequence, options.part, options.tool_length)?;
                e.insert((sequence, t));
            }
        }
        let ranked = study_with_progress(&five, options, progress)?;
        if ranked.iter().any(|r| !(r.rss_rms.is_finite() && r.worst_max.is_finite())) {
            return Err(Error::computation("a configuration's stack-up is not finite"));
        }
        Ok(ConfigurationStudy { options: *options, counts, travel, ranked })
    }

    /// The document of `trueaxis budget configurations --json`.
    pub fn to_json(&self) -> Value {
        let o = &self.options;
        let travel: Vec<Value> = self
            .travel
            .iter()
            .map(|((pattern, rotary), (seq, t))| {
                json!({"category": pattern.notation(), "rotary": rotary, "axes": seq.iter().collect::<String>(), "travel_mm": t,
                       "space_utility": space_utility(o.part, *t)})
            })
            .collect();
        let rows: Vec<Value> = self.ranked.iter().enumerate().map(|(i, r)| ranking_row(i + 1, r)).collect();
        let [linear, angular, squareness] = o.tolerances.0;
        json!({
            "part_mm": o.part, "tool_length_mm": o.tool_length,
            "tolerances": {"linear_um": linear, "angular_urad": angular, "squareness_urad": squareness},
            "counts": {"five_of_six_axes": self.counts[0], "three_linear_axes": self.counts[1], "three_categories": self.counts[2],
                       "five_degrees_of_freedom": self.counts[3]},
            "travel": travel, "ranking": rows,
        })
    }
}

fn ranking_row(rank: usize, r: &ConfigurationBudget) -> Value {
    let f = &r.form_shaping;
    json!({
        "rank": rank, "axes": r.configuration.axes(), "chain": r.configuration.chain(), "structure": r.configuration.structure(),
        "category": r.configuration.pattern().notation(), "travel_mm": r.travel, "space_utility": super::documents::number(r.space_utility),
        "rss_rms_um": r.rss_rms, "rss_max_um": r.rss_max, "worst_case_max_um": r.worst_max, "poses": r.poses,
        "share_percent": {"linear": r.kind_shares[0], "angular": r.kind_shares[1], "squareness": r.kind_shares[2]},
        "form_shaping": {"l": f.position[0].to_string(), "m": f.position[1].to_string(), "n": f.position[2].to_string(),
                         "u": f.orientation[0].to_string(), "v": f.orientation[1].to_string(), "w": f.orientation[2].to_string()},
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With both rotary axes at the tool (XYZAB) the tool axis sweeps the whole sphere, so a cube of
    /// edge `r p` with a corner on the pivot needs `(r + 1) p` of each linear axis: utility
    /// `r^3 / (r + 1)^3`. The categories come in the order of the appendix.
    #[test]
    fn the_trend_of_rotary_axes_at_the_tool_is_the_closed_form() {
        let trend = space_utility_trend(150.0).unwrap();
        let codes: Vec<String> = trend.iter().map(|c| c.sequence.iter().collect()).collect();
        assert_eq!(codes, ["ABXYZ", "AXYZB", "XYZAB"]);
        assert_eq!(trend[2].pattern, Pattern::RotaryAtTool);
        for ((r, utility), ratio) in trend[2].points.iter().zip(TREND_RATIOS) {
            assert_eq!(*r, ratio);
            let expected = (r / (r + 1.0)).powi(3);
            assert!((utility - expected).abs() < 1e-9 * expected, "r = {r}: {utility} vs {expected}");
        }
    }
}
