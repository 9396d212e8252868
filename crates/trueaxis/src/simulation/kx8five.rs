//! The built-in machine of `trueaxis demo`: the Huron KX8-Five of Andolfatto et al. 2011 (structure
//! `WCAYFXZT`, A tilted 45 deg; lengths in mm, angles in deg) with the link and setup errors of
//! their Table 1 (um, urad), the 807 CapBall poses of their §3.2 and the uncertainty sources of
//! their Tables 3 and 4 with a cyclic drift of the measuring chain (§4.4.2). The texts are the
//! example files of the repository, built in so that the demo needs no file.

use crate::error_model::{ErrorModel, ErrorModelError};
use crate::machine::{Machine, MachineError};
use crate::uncertainty::Sources;

/// The built-in machine (`examples/machines/kx8five.toml`).
pub const MACHINE_TOML: &str = include_str!("../../../../examples/machines/kx8five.toml");
/// The errors the machine is simulated with: Andolfatto et al. 2011 Table 1 (`examples/errors/kx8five_table1.toml`).
pub const ERRORS_TOML: &str = include_str!("../../../../examples/errors/kx8five_table1.toml");
/// The campaign: 807 CapBall poses (`examples/campaigns/kx8five/`).
pub const CAMPAIGN_TOML: &str = include_str!("../../../../examples/campaigns/kx8five/campaign.toml");
pub const CAMPAIGN_POSES_CSV: &str = include_str!("../../../../examples/campaigns/kx8five/capball.csv");
/// The uncertainty sources: Andolfatto et al. 2011 Tables 3 and 4 with a cyclic drift (`examples/uncertainty/`).
pub const SOURCES_TOML: &str = include_str!("../../../../examples/uncertainty/kx8five_cyclic.toml");

/// The set-up errors of the CapBall campaign (where the balls sat), not errors of the machine.
const SETUP_PARAMETERS: [&str; 6] = ["TX", "TY", "TZ", "WX", "WY", "WZ"];

/// The built-in machine.
pub fn machine() -> Result<Machine, MachineError> {
    Machine::from_toml_str(MACHINE_TOML, "built-in kx8five.toml")
}

/// The true errors of [`machine`]: Andolfatto et al. 2011 Table 1.
pub fn true_errors(machine: &Machine) -> Result<ErrorModel, ErrorModelError> {
    ErrorModel::from_toml_str(ERRORS_TOML, "built-in kx8five errors", machine)
}

/// The uncertainty sources, with the cyclic drift the campaign is simulated with.
pub fn sources() -> Result<Sources, crate::Error> {
    Sources::from_toml_str(SOURCES_TOML, "built-in kx8five_cyclic.toml")
}

/// The true errors of the machine alone: [`ERRORS_TOML`] without the set-up errors of the CapBall
/// campaign (`TX TY TZ WX WY WZ`: where the balls sat), which volumetric maps leave out.
pub fn machine_errors_toml() -> String {
    let setup = |line: &str| SETUP_PARAMETERS.iter().any(|p| line.split('=').next().map(str::trim) == Some(*p));
    let mut text = String::from("# errors_true.toml without the set-up errors of the campaign (TX TY TZ WX WY WZ)\n");
    for line in ERRORS_TOML.lines().filter(|l| !setup(l)) {
        text.push_str(line);
        text.push('\n');
    }
    text
}
