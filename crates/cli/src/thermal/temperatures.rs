//! `trueaxis thermal temperatures`: the state-space model of the temperature distribution (the
//! temperatures of output sensors from a few input sensors, `thermal::temperature_model`): fitted
//! and validated on other runs, or a fitted model evaluated on a campaign.

use crate::output::{self, print};
use crate::Failure;
use serde_json::json;
use std::fmt::Write;
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::thermal::temperature_model::{fit_temperature_model, predict_run, TemperatureModel};
use trueaxis::thermal::thermal_campaign::Campaign;
use trueaxis::thermal::validation::ResidualStats;

/// Fits the temperatures of output sensors as first-order lags (time constants shared) of the rises
/// of input sensors near the heat sources since the start of each run, and validates the model on
/// the runs not trained on; or, with --model, evaluates a fitted model.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
trueaxis thermal temperatures --data examples/thermal/campaign.csv --inputs T:p1 --outputs T:p5 --rates 2 \\\n      \
--train-runs warmup --out temperatures.toml\n  \
trueaxis thermal temperatures --model temperatures.toml --data examples/thermal/campaign.csv --json\n\n\
Columns: t (s), run (optional), the T:<sensor> columns (degC). Each run starts from its reference state:\n\
the inputs' rises are counted from a run's first row, the outputs start at their measured values.")]
pub struct TemperaturesArgs {
    /// Campaign (CSV).
    #[arg(long)]
    data: PathBuf,
    /// Input sensors (comma separated), the temperatures near the heat sources.
    #[arg(long, value_delimiter = ',', required_unless_present = "model")]
    inputs: Option<Vec<String>>,
    /// Output sensors (comma separated) whose temperatures the model predicts.
    #[arg(long, value_delimiter = ',', required_unless_present = "model")]
    outputs: Option<Vec<String>>,
    /// Number of time constants shared by inputs and outputs (1 to 4).
    #[arg(long, default_value_t = 2)]
    rates: usize,
    /// Runs to train on, comma separated (default: every run); the others validate.
    #[arg(long, value_delimiter = ',')]
    train_runs: Option<Vec<String>>,
    /// A fitted model (TOML, kind = "temperature_state_space") to evaluate instead of fitting.
    #[arg(long, conflicts_with_all = ["inputs", "outputs", "train_runs"])]
    model: Option<PathBuf>,
    /// Fitting: write the model (TOML). Evaluating: write the predicted temperatures (CSV).
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// Print one JSON document.
    #[arg(long)]
    json: bool,
}

pub fn temperatures(args: TemperaturesArgs) -> Result<(), Failure> {
    let campaign = Campaign::read(&args.data).map_err(Failure::of)?;
    let runs = campaign.run_names();
    let rows_of = |run: &String| campaign.rows_of(std::slice::from_ref(run)).map_err(Failure::of);
    let (model, training) = match &args.model {
        Some(path) => {
            let text = trueaxis::files::inputs::read_to_string(path)
                .map_err(|e| Failure::input(anyhow::anyhow!("{}: cannot read: {e}", path.display())))?;
            (TemperatureModel::from_toml_str(&text, &path.display().to_string()).map_err(Failure::of)?, Vec::new())
        }
        None => {
            let training: Vec<String> = match &args.train_runs {
                Some(r) => {
                    campaign.rows_of(r).map_err(Failure::of)?;
                    r.clone()
                }
                None => runs.clone(),
            };
            let records = training.iter().map(rows_of).collect::<Result<Vec<_>, _>>()?;
            let inputs = args.inputs.clone().expect("clap requires --inputs");
            let outputs = args.outputs.clone().expect("clap requires --outputs");
            let (model, _) = fit_temperature_model(&campaign, &records, &inputs, &outputs, args.rates).map_err(Failure::of)?;
            if let Some(out) = &args.out {
                write_atomically(out, model.to_toml().as_bytes()).map_err(Failure::input)?;
            }
            (model, training)
        }
    };
    let mut per_run: Vec<(String, bool, Vec<Option<ResidualStats>>)> = Vec::new();
    let mut csv = format!("run,t,{}\n", model.outputs.iter().map(|o| format!("{o}_predicted")).collect::<Vec<_>>().join(","));
    let t = campaign.column("t").map_err(Failure::of)?;
    for run in &runs {
        let rows = rows_of(run)?;
        let (predicted, stats) = predict_run(&campaign, &model, &rows).map_err(Failure::of)?;
        for (k, &r) in rows.iter().enumerate() {
            let _ = writeln!(csv, "{run},{},{}", t[r], predicted[k].iter().map(|v| format!("{v:.4}")).collect::<Vec<_>>().join(","));
        }
        per_run.push((run.clone(), training.contains(run), stats));
    }
    if args.model.is_some() {
        if let Some(out) = &args.out {
            write_atomically(out, csv.as_bytes()).map_err(Failure::input)?;
        }
    }
    if args.json {
        let residuals: serde_json::Map<String, serde_json::Value> = per_run
            .iter()
            .map(|(run, trained, stats)| {
                let by_output: serde_json::Map<String, serde_json::Value> =
                    model.outputs.iter().zip(stats).map(|(o, s)| (o.clone(), json!(s))).collect();
                (run.clone(), json!({"training": trained, "outputs": by_output}))
            })
            .collect();
        return output::json(&json!({"model": model, "unit": "degC", "residuals": residuals}));
    }
    if args.model.is_some() && args.out.is_none() {
        return print(&csv);
    }
    let mut text = format!(
        "temperature model: outputs {} from inputs {}, time constants {} min\n",
        model.outputs.join(", "),
        model.inputs.join(", "),
        model.time_constants_s.iter().map(|t| format!("{:.2}", t / 60.0)).collect::<Vec<_>>().join(", ")
    );
    for (o, g) in model.outputs.iter().zip(&model.gains) {
        let _ = writeln!(
            text,
            "  {o:<10} gains (degC/degC, input x time constant) {}",
            g.iter().map(|v| format!("{v:+.4}")).collect::<Vec<_>>().join(" ")
        );
    }
    text += "residuals (measured - predicted, degC):\n";
    for (run, trained, stats) in &per_run {
        for (o, s) in model.outputs.iter().zip(stats) {
            if let Some(s) = s {
                let _ = writeln!(
                    text,
                    "  {:<10} {o:<10} {:<10} RMS {:.4}  max {:.4}  band [{:.4}, {:.4}]",
                    run,
                    if *trained { "training" } else { "validation" },
                    s.rms,
                    s.max_abs,
                    s.min,
                    s.max
                );
            }
        }
    }
    print(&text)
}
