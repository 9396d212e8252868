//! `trueaxis demo`.

use crate::Failure;
use std::path::PathBuf;
use trueaxis::data::DataError;
use trueaxis::demo::{self, DemoError};

/// Run the main job on the built-in 5-axis machine (seed 004 KX8-Five) with known errors: a
/// volumetric error map over the work volume, written as CSV and SVG.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis demo --out demo\n  then: trueaxis predict --machine demo/machine.toml --errors demo/errors.toml --poses demo/volumetric_map.csv --frame machine"
)]
pub struct DemoArgs {
    /// Output directory (created if missing).
    #[arg(long, default_value = "trueaxis-demo")]
    out: PathBuf,
    /// Print a JSON summary on stdout instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: DemoArgs) -> Result<(), Failure> {
    let summary = demo::run(&args.out).map_err(|e| match e {
        // an output directory or file that cannot be written is a bad --out
        DemoError::CreateDir { .. } | DemoError::Data(DataError::Write { .. }) => Failure::input(e),
        other => Failure::computation(other),
    })?;
    let pose: Vec<String> = summary.max_pose.iter().map(|(l, v)| format!("{l}={v}")).collect();
    if args.json {
        let files: Vec<String> = summary.files.iter().map(|p| p.display().to_string()).collect();
        let doc = serde_json::json!({
            "machine": summary.machine, "poses": summary.poses,
            "max_position_error_um": summary.max_um, "max_at": pose.join(" "),
            "rms_position_error_um": summary.rms_um, "files": files,
        });
        println!("{doc}");
        return Ok(());
    }
    println!("trueaxis demo: {}", summary.machine);
    println!("  volumetric error map over the XY, XZ and YZ mid-planes: {} poses (machine frame)", summary.poses);
    println!("  largest position error |d| = {:.2} um at {}", summary.max_um, pose.join(" "));
    println!("  RMS of |d| over the map   = {:.2} um", summary.rms_um);
    for f in &summary.files {
        println!("  wrote {}", f.display());
    }
    Ok(())
}
