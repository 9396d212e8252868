//! `trueaxis thermal modes|place|fit|predict`: thermal modal analysis and sensor placement
//! (`thermal/modal.rs`), thermal error model fits (`thermal/fit.rs`) and their evaluation
//! (`thermal/predict.rs`).

mod beam;
mod fit;
mod links;
mod modal;
mod predict;
mod score;
mod temperatures;
mod tune;

use crate::Failure;
use std::path::Path;
use trueaxis::data::write_atomically;
use trueaxis_report::ReportError;

/// Thermal modal analysis, sensor placement and thermal error models (Zhu (2008)).
#[derive(clap::Args)]
#[command(after_help = "Examples (see `trueaxis thermal <command> --help`):\n  \
trueaxis thermal modes --model examples/thermal/fin.toml --count 6\n  \
trueaxis thermal place --model examples/thermal/elongation.toml --count 3 --share 1\n  \
trueaxis thermal fit --data examples/thermal/campaign.csv --error dz --train-runs warmup --out dz_model.toml\n  \
trueaxis thermal predict --model dz_model.toml --data examples/thermal/campaign.csv\n  \
trueaxis thermal links --machine examples/machines/vmc3.toml --links examples/thermal/links_vmc3.toml")]
pub struct ThermalArgs {
    #[command(subcommand)]
    command: ThermalCommand,
}

#[derive(clap::Subcommand)]
enum ThermalCommand {
    Modes(modal::ModesArgs),
    Place(modal::PlaceArgs),
    Fit(Box<fit::FitArgs>),
    Predict(predict::PredictArgs),
    Links(links::LinksArgs),
    Temperatures(temperatures::TemperaturesArgs),
    Tune(tune::TuneArgs),
    Beam(beam::BeamArgs),
}

pub fn run(args: ThermalArgs) -> Result<(), Failure> {
    match args.command {
        ThermalCommand::Modes(a) => modal::modes(a),
        ThermalCommand::Place(a) => modal::place(a),
        ThermalCommand::Fit(a) => fit::fit(*a),
        ThermalCommand::Predict(a) => predict::predict(a),
        ThermalCommand::Links(a) => links::links(a),
        ThermalCommand::Temperatures(a) => temperatures::temperatures(a),
        ThermalCommand::Tune(a) => tune::tune(a),
        ThermalCommand::Beam(a) => beam::beam(a),
    }
}

/// Writes an SVG figure (atomically); a figure that cannot be drawn is a failed computation.
fn write_plot(path: &Path, svg: Result<String, ReportError>) -> Result<(), Failure> {
    write_atomically(path, plot_text(path, svg)?.as_bytes()).map_err(Failure::input)
}

/// The text of an SVG figure for `path`; a figure that cannot be drawn is a failed computation.
fn plot_text(path: &Path, svg: Result<String, ReportError>) -> Result<String, Failure> {
    svg.map_err(|e| Failure::computation(anyhow::anyhow!("{}: {e}", path.display())))
}
