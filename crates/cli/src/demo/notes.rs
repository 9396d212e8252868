//! What the demo's report says beyond the parts every report has: how the data were simulated, the
//! identifiability of the KX8-Five parameter set, and the commands that repeat each step from the
//! output folder (each reproduces the report's numbers; `tests/demo.rs` runs them).

use super::job::{CIRCLE_FILE, CONTROLLER};
use trueaxis::simulation::capball::{SimulatedCampaign, POINT_TIME_S};
use trueaxis::simulation::circle::{NOISE_UM, RADIUS_MM};
use trueaxis_report::calibration::{CircleInput, CompensationPart};
use trueaxis_report::html::Section;

pub const MACHINE_NOTE: &str = "Frame M at the nominal intersection of the A and C axes at home. The machine is simulated with the link and setup errors published for this machine by Andolfatto, Mayer and Lavernhe (International Journal of Machine Tools and Manufacture 51, 2011) (errors_true.toml): the true errors that the calibration has to find.";

/// How the campaign was simulated.
pub fn campaign_description(s: &SimulatedCampaign) -> String {
    let drift: Vec<String> = s.drift.iter().map(|(c, p)| format!("{c} {p:.2} um")).collect();
    format!(
        "Simulated CapBall test (a 3D probe on a master ball, as Andolfatto et al. measured this machine): {} poses; the A axis sweeps 0..120 deg while C turns four times, the linear axes following so that the sensing head stays on the master ball at [150, 0, 100] mm on the table. Readings dx, dy, dz in the machine frame, computed on the exact kinematic chain with the true errors, Gaussian sensor noise of {} um and a cyclic drift of the measuring chain (period {} s, peak-to-valley {}), both as published for this test, one point every {} s. The slow wave in the residuals is the drift cycle, which the link errors cannot absorb.",
        s.records,
        s.noise_um.iter().map(|v| format!("{v}")).collect::<Vec<_>>().join(" / "),
        s.drift_period_s,
        drift.join(", "),
        POINT_TIME_S
    )
}

pub const IDENTIFIABILITY_NOTE: &str = "Identifiability: in this ISO parameterisation with the A axis tilted 45 deg, the paper's 14 link errors contain two combinations that no 3D-ball reading sees: EB0A + EC0A - EB0C - 0.15 WY (a tilt of A about its own axis is a zero offset of C, absorbed by the ball setup) and EY0C + TY + TZ + WZ (the part of a C offset along the tilted A axis is a pure translation). The campaign therefore identifies 12 parameters with EC0A = EY0C = 0; the true values are the published errors expressed in that set (the identification of noise-free readings).";

pub fn circle_description() -> String {
    format!("Simulated on the exact chain with the true errors and {NOISE_UM} um of noise, CCW then CW, R {RADIUS_MM} mm around the middle of the travel; the simulation is quasi-static, so the feed stated in the file adds no servo error.")
}

pub const VOLUME_NOTE: &str = "The machine has the true errors; the corrections and tables are computed from the identified errors. What remains after compensation is the error of the identification (noise and drift) and the combinations the campaign cannot see. The compensation page judges the Heidenhain files on another pose set (the whole travel, rotary axes moving) and against the identified errors they were made from: its error left is what the files cannot carry, not the identification's error shown here.";

/// The commands that repeat each step, from the output folder.
pub fn reproduce_section(circle: &CircleInput, compensation: &CompensationPart) -> Section {
    let [gx, gy, gz] = compensation.grid_nodes;
    Section::new("reproduce", "Repeat each step")
        .paragraph("Each command below, run in the output folder of the demo, prints the numbers of the section it repeats: the identified parameters, the uncertainty budget, the ballbar results, the volumetric error before compensation (the map's poses and values, volumetric_map.csv) and the compensation summary. `trueaxis report` builds a report like this one from your own files (see the user guide).")
        .code(format!(
            "trueaxis identify --machine machine.toml --campaign campaign/campaign.toml --out identified.toml\n\
trueaxis uncertainty --machine machine.toml --campaign campaign/campaign.toml --point-time {POINT_TIME_S} --sources uncertainty/sources.toml\n\
{}\n\
trueaxis predict --machine machine.toml --errors errors_true_machine.toml --poses volumetric_map.csv --frame machine\n\
trueaxis compensate --machine machine.toml --errors identified.toml --format csv --points {} --grid {gx},{gy},{gz} --out compensation\n\
trueaxis compensate --machine machine.toml --errors identified.toml --format {controller} --points {} --out compensation-{controller}",
            circle.command(CIRCLE_FILE, "machine.toml"),
            compensation.points,
            compensation.points,
            controller = CONTROLLER,
        ))
}
