//! `trueaxis thermal predict`: a fitted thermal error model evaluated on a campaign.

use super::{failure, write_plot};
use crate::iso230_2::print;
use crate::Failure;
use serde_json::{json, Value};
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::report::{drift_plot, drift_svg, CampaignPart, RunRole};
use trueaxis::thermal::campaign::Campaign;
use trueaxis::thermal::regression::RegressionModel;
use trueaxis::thermal::validation::{evaluate_rows, residual_stats};

/// Evaluates a fitted thermal error model on a campaign CSV; with the measured error column
/// present, also the residual band, RMS, max and range.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  trueaxis thermal predict --model dz_model.toml --data examples/thermal/campaign.csv --json\n  \
trueaxis thermal predict --model dz_model.toml --data examples/thermal/campaign.csv --out dz.csv --plot dz.svg")]
pub struct PredictArgs {
    /// Fitted model (TOML, kind = "regression", as written by `thermal fit --out`).
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
    let model = RegressionModel::from_toml_str(&text, &args.model.display().to_string()).map_err(failure)?;
    let campaign = Campaign::read(&args.data).map_err(failure)?;
    let rows: Vec<usize> = (0..campaign.len()).collect();
    let (measured, predicted) = evaluate_rows(&campaign, &model, &rows).map_err(failure)?;
    let times = campaign.column("t").ok();
    let mut per_run = Vec::new();
    if let Some(m) = &measured {
        for run in campaign.run_names() {
            let idx: Vec<usize> = rows.iter().copied().filter(|&i| campaign.runs[i] == run).collect();
            let (a, b): (Vec<f64>, Vec<f64>) = idx.iter().map(|&i| (m[i], predicted[i])).unzip();
            per_run.push((run, residual_stats(&a, &b)));
        }
    }
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
        format!("{}\n", json!({"error": model.error, "unit": "um", "samples": samples, "residuals": stats}))
    } else {
        let mut out = format!(
            "run,t,{}_predicted{}\n",
            model.error,
            if measured.is_some() { format!(",{0},{0}_residual", model.error) } else { String::new() }
        );
        for &i in &rows {
            let t = times.map_or(String::new(), |t| t[i].to_string());
            out += &format!("{},{t},{:.4}", campaign.runs[i], predicted[i]);
            if let Some(m) = &measured {
                out += &format!(",{},{:.4}", m[i], m[i] - predicted[i]);
            }
            out.push('\n');
        }
        for (run, s) in &per_run {
            if let Some(s) = s {
                out += &format!(
                    "# {run}: residual RMS {:.3} max {:.3} range {:.3} band [{:.3}, {:.3}] um\n",
                    s.rms, s.max_abs, s.range, s.min, s.max
                );
            }
        }
        out
    };
    if let Some(path) = &args.plot {
        let parts: Vec<CampaignPart> = campaign
            .run_names()
            .into_iter()
            .map(|run| {
                let rows = rows.iter().copied().filter(|&i| campaign.runs[i] == run).collect();
                CampaignPart { name: if run.is_empty() { "all rows".into() } else { run }, role: RunRole::Prediction, rows }
            })
            .collect();
        write_plot(path, drift_svg(&drift_plot(&campaign, &model, &parts).map_err(failure)?))?;
    }
    match &args.out {
        Some(p) => write_atomically(p, text.as_bytes()).map_err(Failure::input),
        None => print(&text),
    }
}
