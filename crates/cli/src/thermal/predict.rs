//! `trueaxis thermal predict`: a fitted thermal error model evaluated on a campaign
//! (`trueaxis::thermal::campaign_predict`).

use super::write_plot;
use crate::output::text_or_file;
use crate::Failure;
use std::path::PathBuf;
use trueaxis::thermal::campaign_predict::{predict_campaign, read_model_file};
use trueaxis::thermal::thermal_campaign::Campaign;
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
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// Write a figure (SVG): per run the prediction over time against the measured values and the
    /// residual band.
    #[arg(long, value_name = "FILE.svg", value_parser = crate::output::file)]
    plot: Option<crate::output::OutputPath>,
}

pub fn predict(args: PredictArgs) -> Result<(), Failure> {
    let model = read_model_file(&args.model).map_err(Failure::of)?;
    let campaign = Campaign::read(&args.data).map_err(Failure::of)?;
    let prediction = predict_campaign(&model, &campaign).map_err(Failure::of)?;
    let text = if args.json { format!("{}\n", prediction.to_json()) } else { prediction.to_csv() };
    if let Some(path) = &args.plot {
        write_plot(path, drift_svg(&drift_plot(&prediction.error, &prediction.evaluated)))?;
    }
    text_or_file(args.out.as_deref(), &text)
}
