//! `trueaxis ballbar sensitivity`: how a rotary-axis method reacts to its setup and to bar noise.

use super::{BarArgs, MethodArgs};
use crate::output::{self, print};
use crate::Failure;
use std::path::PathBuf;
use trueaxis::identify::pige_report::{pige_user_value, sensitivity_report};
use trueaxis::machine::Machine;

/// Sensitivity of a rotary-axis ballbar method (the PIGEs of two rotary axes from four steps) to
/// its setup and to bar noise, before it is run: the change of every PIGE per um of setup error of
/// each step (either ball off its place along X, Y, Z; the bar off its calibration), the standard
/// uncertainty per um of bar noise, and the combined uncertainty for the given setup tolerances.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  trueaxis ballbar sensitivity --machine examples/machines/c600u.toml\n  \
trueaxis ballbar sensitivity --machine examples/machines/c600u.toml --method four-setup \\\n      \
--outer-positions -200,250 --inner-positions 0,78 --setup-u 2 --noise 0.5 --json\n\n\
Each step is simulated on the exact chain with one setup error alone and identified as if the setup\n\
were nominal. Units: um of PIGE per um of setup error, urad per um for orientations; the combined\n\
standard uncertainty treats every setup error, bar calibration and noise as independent.")]
pub struct SensitivityArgs {
    #[arg(long)]
    machine: PathBuf,
    #[command(flatten)]
    bars: BarArgs,
    #[command(flatten)]
    method: MethodArgs,
    /// Standard uncertainty of each ball's placement along X, Y and Z (um), for the combined value.
    #[arg(long, default_value_t = 1.0)]
    setup_u: f64,
    /// Standard uncertainty of each bar's calibrated length (um).
    #[arg(long, default_value_t = 1.0)]
    bar_u: f64,
    /// Standard deviation of the bar readings (um).
    #[arg(long, default_value_t = 1.0)]
    noise: f64,
    #[arg(long)]
    json: bool,
}

pub fn run(a: SensitivityArgs) -> Result<(), Failure> {
    let m = Machine::load(&a.machine).map_err(Failure::input)?;
    let method = a.method.method()?;
    let bars = a.bars.lengths()?;
    let report = sensitivity_report(&m, method, bars, a.setup_u, a.bar_u, a.noise).map_err(Failure::of)?;
    if a.json {
        return output::json(&report.to_json());
    }
    let (s, combined) = (&report.sensitivity, &report.combined);
    let per_um = |p: usize, v: f64| report.per_um(p, v);
    let user_value = pige_user_value;
    let mut out = format!(
        "Sensitivity of the {} method on {} (bars {} / {} mm)\n{:<6} {:>6} {:>10} {:>12}   largest setup effects (per um)\n",
        method.name(),
        m.name,
        bars.normal,
        bars.extended,
        "PIGE",
        "unit",
        "noise/um",
        format!("u ({}/{}/{})", a.setup_u, a.bar_u, a.noise),
    );
    for (p, id) in s.parameters.iter().enumerate() {
        let mut largest: Vec<_> = s.sources.iter().map(|x| (per_um(p, x.effect[p]), x)).collect();
        largest.sort_by(|x, y| y.0.abs().total_cmp(&x.0.abs()));
        let top: Vec<String> = largest.iter().take(3).map(|(v, x)| format!("{} {} {v:+.3}", x.step.name(), x.name)).collect();
        out.push_str(&format!(
            "{:<6} {:>6} {:>10.3} {:>12.3}   {}\n",
            id.to_string(),
            user_value(id, 0.0).1,
            per_um(p, s.noise[p]),
            user_value(id, combined[p]).0,
            top.join(", ")
        ));
    }
    out.push_str(
        "noise/um: standard uncertainty per um of bar noise; u: combined standard uncertainty for the given setup, bar and noise\n\
         uncertainties (um); a bar calibration error changes no circle centre, so it drops out of every method\n",
    );
    print(&out)
}
