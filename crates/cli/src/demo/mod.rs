//! `trueaxis demo`: the main job end to end on the built-in machine, the Huron KX8-Five of Andolfatto et al. 2011
//! (structure `WCAYFXZT`, A tilted 45 deg) with the link and setup errors of Andolfatto et al. 2011 Table 1
//! (`trueaxis::simulation::kx8five`):
//!
//! 1. a CapBall campaign of 807 poses (Andolfatto et al. 2011 §3.2) simulated on the exact chain with the sensor
//!    noise of Table 3 and a cyclic drift of the measuring chain (§4.4.2, peak-to-valley of Table 4);
//! 2. ISO 230-4 ballbar circles (CW and CCW) in the XY plane, with noise, and their diagnostics;
//! 3. identification of the separable link and setup errors with the identifiability report;
//! 4. adaptive Monte Carlo uncertainty (JCGM 101) with the statistical sources and the cyclic drift,
//!    and the per-source budget (Andolfatto et al. 2011 Table 5);
//! 5. compensation tables from the identified errors, and the volumetric error over the work volume
//!    before compensation and after (the true machine driven to the set-points the tables correct);
//! 6. a self-contained HTML report, built by `trueaxis_report::calibration` like `trueaxis report`.
//!
//! The simulation is the library's (`trueaxis::simulation`), the parts of the report the report
//! crate's; here: which step runs when ([`job`]), where each file goes ([`folder`]) and what the
//! command prints ([`summary`]). Everything it writes goes to the output directory, with the
//! inputs, so that each step can be repeated with the individual `trueaxis` commands. The directory
//! is built in a temporary beside it and swapped in whole at the end: a run that fails (a full
//! disk) or is stopped leaves the directory as it was.

mod error;
mod folder;
mod job;
mod notes;
mod specimen;
mod summary;

use crate::Failure;

/// Run the main job on the built-in 5-axis machine (the KX8-Five of Andolfatto et al. (2011)) with known errors: simulate
/// a 3D-ball campaign with noise and cyclic drift and ballbar circles, identify, Monte Carlo
/// uncertainty, volumetric error before and after compensation, compensation tables, HTML report.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis demo --out demo\n  then open demo/report.html; every step can be repeated with the commands in its last section."
)]
pub struct DemoArgs {
    /// Output directory (created if missing).
    #[arg(long, default_value = "trueaxis-demo", value_parser = crate::output::directory)]
    out: crate::output::OutputPath,
    /// Print a JSON summary on stdout instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: DemoArgs) -> Result<(), Failure> {
    let bar = crate::progress::steps(job::STEPS, args.json);
    let mut progress = |step: usize, _total: usize, message: &str| {
        bar.set_position(step as u64 - 1);
        bar.set_message(message.to_string());
    };
    let result = job::run(&args.out, &mut progress);
    bar.finish_and_clear();
    let summary = result.map_err(Failure::of)?;
    if args.json {
        println!("{}", summary.json());
    } else {
        summary.print();
    }
    Ok(())
}
