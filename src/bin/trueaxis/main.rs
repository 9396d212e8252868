//! The `trueaxis` command line: parse, call the library, print (DESIGN.md section 4).
//! Exit status: 0 success, 1 failed computation, 2 bad input.

mod ballbar;
mod compensate;
mod demo;
mod design;
mod fit;
mod identify;
mod iso230_2;
mod nc;
mod predict;
mod reversal;
mod temperature;
mod thermal;
mod uncertainty;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "trueaxis",
    version,
    about = "Find, explain and remove the quasi-static errors of multi-axis machine tools",
    after_help = "Units: positions in mm (linear) and deg (rotary); errors in um and urad.\n\
                  Examples:\n  trueaxis demo --out demo\n  \
                  trueaxis predict --machine examples/machines/kx8five.toml --errors examples/errors/kx8five.toml --poses examples/poses/kx8five.csv"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Ballbar(ballbar::BallbarArgs),
    Demo(demo::DemoArgs),
    Design(design::DesignArgs),
    Fit(Box<fit::FitArgs>),
    Identify(identify::IdentifyArgs),
    #[command(name = "iso230-2")]
    Iso2302(iso230_2::Iso2302Args),
    Predict(predict::PredictArgs),
    Reversal(reversal::ReversalArgs),
    Uncertainty(Box<uncertainty::UncertaintyArgs>),
    Compensate(Box<compensate::CompensateArgs>),
    Nc(Box<nc::NcArgs>),
    Thermal(thermal::ThermalArgs),
}

/// Why a command failed: bad input (exit 2) or a failed computation (exit 1).
pub enum Failure {
    Input(anyhow::Error),
    Computation(anyhow::Error),
}

impl Failure {
    pub fn input(e: impl Into<anyhow::Error>) -> Failure {
        Failure::Input(e.into())
    }
    pub fn computation(e: impl Into<anyhow::Error>) -> Failure {
        Failure::Computation(e.into())
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Ballbar(args) => ballbar::run(args),
        Command::Demo(args) => demo::run(args),
        Command::Design(args) => design::run(args),
        Command::Fit(args) => fit::run(*args),
        Command::Identify(args) => identify::run(args),
        Command::Iso2302(args) => iso230_2::run(args),
        Command::Predict(args) => predict::run(args),
        Command::Reversal(args) => reversal::run(args),
        Command::Uncertainty(args) => uncertainty::run(*args),
        Command::Compensate(args) => compensate::run(*args),
        Command::Nc(args) => nc::run(*args),
        Command::Thermal(args) => thermal::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Input(e)) => {
            eprintln!("trueaxis: error: {e:#}");
            ExitCode::from(2)
        }
        Err(Failure::Computation(e)) => {
            eprintln!("trueaxis: error: {e:#}");
            ExitCode::from(1)
        }
    }
}
