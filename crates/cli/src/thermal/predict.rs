//! `trueaxis thermal predict`: a fitted thermal error model evaluated on a campaign.

use super::{failure, write_plot};
use crate::iso230_2::print;
use crate::Failure;
use serde_json::{json, Value};
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::thermal::campaign::Campaign;
use trueaxis::thermal::error_model::ThermalErrorModel;
use trueaxis::thermal::validation::{evaluate_segments, prediction_segments, ResidualStats};
use trueaxis_report::{drift_plot, drift_svg};

/// Evaluates a fitted thermal error model on a campaign CSV; with the measured error column
/// present, also the residual band, RMS, max and range.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  trueaxis thermal predict --model dz_model.toml --data examples/thermal/campaign.csv --json\n  \
trueaxis thermal predict --model dz_model.toml --data examples/thermal/campaign.csv --out dz.csv --plot dz.svg")]
pub struct PredictArgs {
    /// Fitted model (TOML, kind = "regression" or "state_space", as written by `thermal fit --out`).
    #[arg(long)]
    model: PathBuf,
    /// Campaign (CSV): columns t (s), run (optional), the model's T:<sensor> columns (degC), its
    /// position column (PDTE) and, for residuals, the modelled error column (um).
    #[arg(long)]
    data: PathBuf,
    /// Print one JSON document (every sample and the residual statistics per run) instead of CSV.
    #[arg(long)]
    json: bool,
    /// Write the result here (atomically) instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Write a figure (SVG): per run the prediction over time against the measured values and the
    /// residual band.
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
}

pub fn predict(args: PredictArgs) -> Result<(), Failure> {
    let text =
        std::fs::read_to_string(&args.model).map_err(|e| Failure::input(anyhow::anyhow!("{}: cannot read: {e}", args.model.display())))?;
    let model = ThermalErrorModel::from_toml_str(&text, &args.model.display().to_string()).map_err(failure)?;
    let campaign = Campaign::read(&args.data).map_err(failure)?;
    let evaluated = evaluate_segments(&campaign, &model, &prediction_segments(&campaign)).map_err(failure)?;
    // back in file order
    let rows: Vec<usize> = (0..campaign.len()).collect();
    let mut predicted = vec![0.0; campaign.len()];
    let mut measured = evaluated.iter().all(|e| e.measured.is_some()).then(|| vec![0.0; campaign.len()]);
    for e in &evaluated {
        for (k, &r) in e.segment.rows.iter().enumerate() {
            predicted[r] = e.predicted[k];
            if let (Some(m), Some(em)) = (measured.as_mut(), &e.measured) {
                m[r] = em[k];
            }
        }
    }
    let error = model.error().to_string();
    let times = campaign.column("t").ok();
    let per_run: Vec<(String, ResidualStats)> = evaluated.iter().filter_map(|e| e.stats().map(|s| (e.segment.name.clone(), s))).collect();
    let text = if args.json {
        let samples: Vec<Value> = rows
            .iter()
            .map(|&i| {
                let mut s = json!({"run": campaign.runs[i], "predicted": predicted[i]});
                if let Some(t) = times {
                    s["t"] = json!(t[i]);
                }
                if let Some(m) = &measured {
                    s["measured"] = json!(m[i]);
                    s["residual"] = json!(m[i] - predicted[i]);
                }
                s
            })
            .collect();
        let stats: serde_json::Map<String, Value> = per_run.iter().map(|(r, s)| (r.clone(), json!(s))).collect();
        format!("{}\n", json!({"error": error, "unit": "um", "samples": samples, "residuals": stats}))
    } else {
        let mut out =
            format!("run,t,{}_predicted{}\n", error, if measured.is_some() { format!(",{0},{0}_residual", error) } else { String::new() });
        for &i in &rows {
            let t = times.map_or(String::new(), |t| t[i].to_string());
            out += &format!("{},{t},{:.4}", campaign.runs[i], predicted[i]);
            if let Some(m) = &measured {
                out += &format!(",{},{:.4}", m[i], m[i] - predicted[i]);
            }
            out.push('\n');
        }
        for (run, s) in &per_run {
            out += &format!(
                "# {run}: residual RMS {:.3} max {:.3} range {:.3} band [{:.3}, {:.3}] um\n",
                s.rms, s.max_abs, s.range, s.min, s.max
            );
        }
        out
    };
    if let Some(path) = &args.plot {
        write_plot(path, drift_svg(&drift_plot(&error, &evaluated)))?;
    }
    match &args.out {
        Some(p) => write_atomically(p, text.as_bytes()).map_err(Failure::input),
        None => print(&text),
    }
}
