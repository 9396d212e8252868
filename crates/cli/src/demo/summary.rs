//! What the demo found, as the command prints it: the identified parameters beside their true
//! values with U (k = 2) and the Monte Carlo 95 % interval, the ballbar circular deviations G (um),
//! and the volumetric error (um) before and after compensation; as text or one JSON document.

use std::path::PathBuf;
use trueaxis::machine::Machine;
use trueaxis_report::calibration::{CirclePart, IdentificationPart, ParameterRow, UncertaintyPart, VolumePart};

/// What the demo found, for the command line summary.
#[derive(Clone, Debug)]
pub struct DemoSummary {
    pub machine: String,
    /// Poses of the volumetric map.
    pub poses: usize,
    /// Largest `|d|` over the map (um) before compensation, and where (axis letter, mm or deg).
    pub max_um: f64,
    pub max_pose: Vec<(char, f64)>,
    pub rms_um: f64,
    /// The same after compensation: the true machine at the set-points corrected for the identified
    /// errors on the exact chain.
    pub max_after_um: f64,
    pub rms_after_um: f64,
    /// Identified parameters with their true values, least-squares standard uncertainties and
    /// Monte Carlo intervals.
    pub parameters: Vec<ParameterRow>,
    pub residual_rms_um: f64,
    pub monte_carlo_sequences: usize,
    /// Circular deviation G (um) of the CCW and CW ballbar runs.
    pub ballbar_g_um: Vec<f64>,
    pub files: Vec<PathBuf>,
}

impl DemoSummary {
    /// The summary of the parts, without the files.
    pub fn of(
        machine: &Machine,
        identification: &IdentificationPart,
        uncertainty: &UncertaintyPart,
        volume: &VolumePart,
        circle: &CirclePart,
    ) -> DemoSummary {
        DemoSummary {
            machine: machine.name.clone(),
            poses: volume.poses,
            max_um: volume.before_um.0,
            max_pose: volume.max_pose.clone(),
            rms_um: volume.before_um.1,
            max_after_um: volume.after_um.0,
            rms_after_um: volume.after_um.1,
            parameters: identification.parameter_rows(Some(uncertainty)),
            residual_rms_um: identification.result.residual_rms_um,
            monte_carlo_sequences: uncertainty.budget.total.sequences,
            ballbar_g_um: circle.result.runs.iter().map(|r| r.g_um).collect(),
            files: Vec::new(),
        }
    }

    fn max_at(&self) -> String {
        self.max_pose.iter().map(|(l, v)| format!("{l}={v}")).collect::<Vec<_>>().join(" ")
    }

    /// The `--json` document.
    pub fn json(&self) -> serde_json::Value {
        let files: Vec<String> = self.files.iter().map(|p| p.display().to_string()).collect();
        let parameters: serde_json::Map<String, serde_json::Value> = self.parameters.iter().map(|p| (p.name.clone(), p.json())).collect();
        serde_json::json!({
            "machine": self.machine, "poses": self.poses,
            "max_position_error_um": self.max_um, "max_at": self.max_at(),
            "rms_position_error_um": self.rms_um,
            "max_position_error_after_compensation_um": self.max_after_um,
            "rms_position_error_after_compensation_um": self.rms_after_um,
            "residual_rms_um": self.residual_rms_um,
            "monte_carlo_sequences": self.monte_carlo_sequences,
            "ballbar_G_um": self.ballbar_g_um,
            "parameters": parameters, "files": files,
        })
    }

    /// Prints the summary as text.
    pub fn print(&self) {
        println!("trueaxis demo: {}", self.machine);
        println!("  identification: {} parameters, residual RMS {:.3} um", self.parameters.len(), self.residual_rms_um);
        println!("  {:<6} {:>5} {:>10} {:>12} {:>10} {:>24}", "param", "unit", "true", "identified", "U (k = 2)", "95 % interval (MC)");
        for p in &self.parameters {
            println!(
                "  {:<6} {:>5} {:>10} {:>12.2} {:>10} {:>24}",
                p.name,
                p.unit,
                p.truth.map_or("-".to_string(), |t| format!("{t:.2}")),
                p.value,
                p.expanded.map_or("-".to_string(), |u| format!("{u:.2}")),
                p.interval.map_or("-".to_string(), |(lo, hi)| format!("[{lo:.2}, {hi:.2}]"))
            );
        }
        if let Some(p) = self.parameters.first() {
            println!("  U: {}, as in the report", p.method.describe());
        }
        println!("  Monte Carlo: {} sequences", self.monte_carlo_sequences);
        let g: Vec<String> = self.ballbar_g_um.iter().map(|g| format!("{g:.2}")).collect();
        println!("  ballbar XY circle: G = {} um (CCW, CW)", g.join(", "));
        println!(
            "  volumetric error over {} poses: largest |d| {:.2} um at {}, RMS {:.2} um",
            self.poses,
            self.max_um,
            self.max_at(),
            self.rms_um
        );
        println!("  after compensation with the identified errors: largest {:.2} um, RMS {:.2} um", self.max_after_um, self.rms_after_um);
        for f in &self.files {
            println!("  wrote {}", f.display());
        }
    }
}
