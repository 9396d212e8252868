//! The miniaturisation case of Zhu 2008 appendix B.2 as `trueaxis budget miniaturisation` and
//! `trueaxis.budget_miniaturisation` run it ([`super::miniaturisation`] computes each size): the
//! options checked, every size's forward analysis and allocation, and the JSON document (part
//! sizes in mm, errors in um and urad, sensitivities in mm, shares in %, the allocation's target
//! in um: the relative accuracy times the part size).

use super::analysis::GroupShare;
use super::documents::number;
use super::global::GeneticOptions;
use super::miniaturisation::{run, SizeCase, ARCSEC_URAD, SIZES};
use super::spec::KindValues;
use crate::error::Error;
use serde_json::{json, Value};

/// The options of the case.
#[derive(Clone, Debug, PartialEq)]
pub struct MiniaturisationOptions {
    /// Part sizes (mm).
    pub sizes: Vec<f64>,
    /// Every linear error (um).
    pub linear_um: f64,
    /// Every angular and squareness error (urad).
    pub angular_urad: f64,
    /// Target of the allocation per direction over the part size.
    pub relative_accuracy: f64,
    /// Seed of the genetic global stage of the allocation.
    pub seed: u64,
}

impl Default for MiniaturisationOptions {
    /// The appendix's sizes, 1 um and 1 arcsec, a relative accuracy of 1e-4, seed 1.
    fn default() -> Self {
        MiniaturisationOptions { sizes: SIZES.to_vec(), linear_um: 1.0, angular_urad: ARCSEC_URAD, relative_accuracy: 1e-4, seed: 1 }
    }
}

/// The case computed for every size.
pub struct MiniaturisationStudy {
    pub options: MiniaturisationOptions,
    pub cases: Vec<SizeCase>,
}

/// The share (%) of the group `label` (an axis letter or a kind), 0 when there is none.
pub fn group_share(groups: &[GroupShare], label: &str) -> f64 {
    groups.iter().find(|g| g.label == label).map_or(0.0, |g| g.share)
}

/// The machine sensitivity SM (mm) of the group `label`, 0 when there is none.
pub fn group_sensitivity(groups: &[GroupShare], label: &str) -> f64 {
    groups.iter().find(|g| g.label == label).map_or(0.0, |g| g.sensitivity_mm)
}

impl MiniaturisationStudy {
    /// Checks the options (positive errors and accuracy, at least one size) and runs the case.
    pub fn run(options: &MiniaturisationOptions) -> Result<MiniaturisationStudy, Error> {
        let checked = [
            ("--linear-um", options.linear_um),
            ("--angular-urad", options.angular_urad),
            ("--relative-accuracy", options.relative_accuracy),
        ];
        for (name, v) in checked {
            crate::ensure!(v.is_finite() && v > 0.0, input, "{name} {v}: must be a positive number");
        }
        crate::ensure!(!options.sizes.is_empty(), input, "--sizes: give at least one part size (mm)");
        let tolerances = KindValues([options.linear_um, options.angular_urad, options.angular_urad]);
        let genetic = GeneticOptions { seed: options.seed, ..GeneticOptions::default() };
        let cases = run(&options.sizes, tolerances, options.relative_accuracy, genetic)?;
        Ok(MiniaturisationStudy { options: options.clone(), cases })
    }

    /// The allocation's target for a part of `size` mm (um per direction).
    pub fn target_um(&self, size: f64) -> f64 {
        self.options.relative_accuracy * size * 1000.0
    }

    /// The document of `trueaxis budget miniaturisation --json`.
    pub fn to_json(&self) -> Value {
        let groups = |g: &[GroupShare]| -> Value {
            Value::Array(g.iter().map(|g| json!({"group": g.label, "share_percent": g.share, "sm_mm": g.sensitivity_mm})).collect())
        };
        let rows: Vec<Value> = self
            .cases
            .iter()
            .map(|c| {
                let a = &c.analysis;
                json!({
                    "size_mm": c.size, "rss_rms_um": a.rss_rms,
                    "part_sensitivity_mm": {"x": a.part_sensitivity[0], "y": a.part_sensitivity[1], "z": a.part_sensitivity[2]},
                    "ri1": a.condition.map_or(Value::Null, number), "ri2_mm": a.singular_values[0],
                    "by_axis": groups(&a.by_axis), "by_kind": groups(&a.by_kind),
                    "allocation": {
                        "target_um": self.target_um(c.size), "cost": c.allocation.cost, "kkt_residual": c.allocation.kkt_residual,
                        "by_axis": groups(&c.allocated.by_axis), "by_kind": groups(&c.allocated.by_kind),
                    },
                })
            })
            .collect();
        let o = &self.options;
        json!({"linear_um": o.linear_um, "angular_urad": o.angular_urad, "relative_accuracy": o.relative_accuracy, "sizes": rows})
    }
}
