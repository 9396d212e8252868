//! `trueaxis demo`.

use crate::Failure;
use trueaxis_report::demo;

/// Run the main job on the built-in 5-axis machine (the KX8-Five of Andolfatto et al. (2011)) with known errors: simulate
/// a 3D-ball campaign with noise and cyclic drift and ballbar circles, identify, Monte Carlo
/// uncertainty, volumetric error before and after compensation, compensation tables, HTML report.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis demo --out demo\n  then open demo/report.html; every step can be repeated with the commands in its last section."
)]
pub struct DemoArgs {
    /// Output directory (created if missing).
    #[arg(long, default_value = "trueaxis-demo", value_parser = crate::outputs::directory)]
    out: crate::outputs::OutputPath,
    /// Print a JSON summary on stdout instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: DemoArgs) -> Result<(), Failure> {
    let bar = crate::progress::steps(demo::STEPS, args.json);
    let mut progress = |step: usize, _total: usize, message: &str| {
        bar.set_position(step as u64 - 1);
        bar.set_message(message.to_string());
    };
    let result = demo::run(&args.out, &mut progress);
    bar.finish_and_clear();
    let summary = result.map_err(Failure::of)?;
    let pose: Vec<String> = summary.max_pose.iter().map(|(l, v)| format!("{l}={v}")).collect();
    if args.json {
        let files: Vec<String> = summary.files.iter().map(|p| p.display().to_string()).collect();
        let parameters: serde_json::Map<String, serde_json::Value> =
            summary.parameters.iter().map(|p| (p.name.clone(), p.json())).collect();
        let doc = serde_json::json!({
            "machine": summary.machine, "poses": summary.poses,
            "max_position_error_um": summary.max_um, "max_at": pose.join(" "),
            "rms_position_error_um": summary.rms_um,
            "max_position_error_after_compensation_um": summary.max_after_um,
            "rms_position_error_after_compensation_um": summary.rms_after_um,
            "residual_rms_um": summary.residual_rms_um,
            "monte_carlo_sequences": summary.monte_carlo_sequences,
            "ballbar_G_um": summary.ballbar_g_um,
            "parameters": parameters, "files": files,
        });
        println!("{doc}");
        return Ok(());
    }
    println!("trueaxis demo: {}", summary.machine);
    println!("  identification: {} parameters, residual RMS {:.3} um", summary.parameters.len(), summary.residual_rms_um);
    println!("  {:<6} {:>5} {:>10} {:>12} {:>10} {:>24}", "param", "unit", "true", "identified", "U (k = 2)", "95 % interval (MC)");
    for p in &summary.parameters {
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
    if let Some(p) = summary.parameters.first() {
        println!("  U: {}, as in the report", p.method.describe());
    }
    println!("  Monte Carlo: {} sequences", summary.monte_carlo_sequences);
    let g: Vec<String> = summary.ballbar_g_um.iter().map(|g| format!("{g:.2}")).collect();
    println!("  ballbar XY circle: G = {} um (CCW, CW)", g.join(", "));
    println!(
        "  volumetric error over {} poses: largest |d| {:.2} um at {}, RMS {:.2} um",
        summary.poses,
        summary.max_um,
        pose.join(" "),
        summary.rms_um
    );
    println!("  after compensation with the identified errors: largest {:.2} um, RMS {:.2} um", summary.max_after_um, summary.rms_after_um);
    for f in &summary.files {
        println!("  wrote {}", f.display());
    }
    Ok(())
}
