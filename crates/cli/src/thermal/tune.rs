//! `trueaxis thermal tune`: the convection coefficients of a heat-conduction model tuned so that its
//! time constants equal measured ones (`thermal::tuning`).

use crate::output::{self, print};
use crate::Failure;
use serde_json::json;
use std::fmt::Write;
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::thermal::tuning::tune_boundaries;

/// Tunes the boundary conditions (convection coefficients) of a thermal model file so that its
/// largest time constants equal measured ones, e.g. those fitted to warm-up records by `thermal fit
/// --time-constants` (model updating before modal analysis and sensor placement).
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
trueaxis thermal tune --model examples/thermal/fin.toml --tau-min 363.6 --tune convection_w_m2k\n  \
trueaxis thermal tune --model examples/thermal/elongation.toml --tau-min 100,30 --tune convection_w_m2k,right_end \\\n      \
--out tuned.toml --json\n\n\
Keys: convection_w_m2k (lateral surface), left_end / right_end (bar1d), boundary.xmin .. boundary.zmax\n\
(grid2d, grid3d); each must hold a positive coefficient (W/m^2/K) to start from. The n largest time\n\
constants of the model are matched to the n measured ones in relative terms (least squares of ln tau).")]
pub struct TuneArgs {
    /// Thermal model file (TOML).
    #[arg(long)]
    model: PathBuf,
    /// Measured time constants in minutes, comma separated (at least one per tuned coefficient).
    #[arg(long, value_delimiter = ',', required = true, allow_hyphen_values = true)]
    tau_min: Vec<f64>,
    /// Convection coefficients to tune, by their keys in the model file, comma separated.
    #[arg(long, value_delimiter = ',', required = true)]
    tune: Vec<String>,
    /// Write the tuned model file here (comments kept).
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// Print one JSON document.
    #[arg(long)]
    json: bool,
}

pub fn tune(args: TuneArgs) -> Result<(), Failure> {
    let text = trueaxis::files::inputs::read_to_string(&args.model)
        .map_err(|e| Failure::input(anyhow::anyhow!("{}: cannot read: {e}", args.model.display())))?;
    let dir = args.model.parent().map(PathBuf::from).unwrap_or_default();
    let measured: Vec<f64> = args.tau_min.iter().map(|t| t * 60.0).collect();
    let tuning = tune_boundaries(&text, &args.model.display().to_string(), &dir, &args.tune, &measured).map_err(Failure::of)?;
    if let Some(out) = &args.out {
        write_atomically(out, tuning.text.as_bytes()).map_err(Failure::input)?;
    }
    if args.json {
        let doc = json!({
            "coefficients": tuning.values.iter().zip(&tuning.start).map(|((k, v), (_, s))| json!({"key": k, "start_w_m2k": s, "tuned_w_m2k": v})).collect::<Vec<_>>(),
            "tau_min": tuning.measured_tau_s.iter().zip(&tuning.model_tau_s).map(|(m, t)| json!({"measured": m / 60.0, "model": t / 60.0})).collect::<Vec<_>>(),
            "iterations": tuning.iterations,
            "out": args.out.as_ref().map(|p| p.display().to_string()),
        });
        return output::json(&doc);
    }
    let mut s = format!("boundary conditions of {} tuned to {} measured time constants:\n", args.model.display(), measured.len());
    for ((k, v), (_, start)) in tuning.values.iter().zip(&tuning.start) {
        let _ = writeln!(s, "  {k:<20} {start:>10.4} -> {v:>12.6} W/m^2/K");
    }
    s += "  time constant      measured      model (min)\n";
    for (i, (m, t)) in tuning.measured_tau_s.iter().zip(&tuning.model_tau_s).enumerate() {
        let _ = writeln!(s, "  {:<14} {:>12.3} {:>12.3}  ({:+.3} %)", i + 1, m / 60.0, t / 60.0, 100.0 * (t / m - 1.0));
    }
    print(&s)
}
