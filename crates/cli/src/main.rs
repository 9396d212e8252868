//! The `trueaxis` command line: parse, call the library, print (DESIGN.md section 4).
//! Exit status: 0 success, 1 failed computation, 2 bad input.

mod ballbar;
mod bounds;
mod budget;
mod compensate;
mod convert;
mod demo;
mod design;
mod fit;
mod identify;
mod inputs;
mod inspect;
mod iso230_2;
mod live;
mod nc;
mod predict;
mod progress;
mod report;
mod reversal;
mod temperature;
mod thermal;
mod uncertainty;
mod verify;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "trueaxis",
    version,
    about = "Find, explain and remove the quasi-static errors of multi-axis machine tools",
    after_help = "Units: positions in mm (linear) and deg (rotary); errors in um and urad.\n\
                  Examples:\n  trueaxis demo --out demo\n  \
                  trueaxis predict --machine examples/machines/kx8five.toml --errors examples/errors/kx8five.toml --poses examples/poses/kx8five.csv\n  \
                  trueaxis report --machine examples/machines/kx8five.toml --campaign examples/campaigns/kx8five/campaign.toml --out report.html"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Ballbar(ballbar::BallbarArgs),
    Budget(budget::BudgetArgs),
    Demo(demo::DemoArgs),
    Design(design::DesignArgs),
    Fit(Box<fit::FitArgs>),
    Identify(identify::IdentifyArgs),
    Inspect(inspect::InspectArgs),
    Convert(convert::ConvertArgs),
    #[command(name = "iso230-2")]
    Iso2302(iso230_2::Iso2302Args),
    Live(Box<live::LiveArgs>),
    Predict(predict::PredictArgs),
    Reversal(reversal::ReversalArgs),
    Report(Box<report::ReportArgs>),
    Uncertainty(Box<uncertainty::UncertaintyArgs>),
    Compensate(Box<compensate::CompensateArgs>),
    Nc(Box<nc::NcArgs>),
    Thermal(thermal::ThermalArgs),
    Verify(Box<verify::VerifyArgs>),
}

/// Why a command failed: bad input (exit 2), a failed computation (exit 1) or the environment (a
/// server that cannot be reached, a program that is missing; exit 3).
pub enum Failure {
    Input(anyhow::Error),
    Computation(anyhow::Error),
    Environment(anyhow::Error),
}

impl Failure {
    pub fn input(e: impl Into<anyhow::Error>) -> Failure {
        Failure::Input(e.into())
    }
    pub fn computation(e: impl Into<anyhow::Error>) -> Failure {
        Failure::Computation(e.into())
    }
}

/// Restores the default action of SIGPIPE (end the process quietly), which the Rust runtime sets to
/// "ignore" before `main`: with it ignored, a write to a closed pipe (`trueaxis predict ... | head`)
/// returns an error and `println!` panics. With the default, the process ends like other Unix tools
/// when the reader goes away; every output file is written to a temporary file and renamed
/// (`data::write_atomically`), so an early end leaves no half-written file.
#[cfg(unix)]
fn restore_default_sigpipe() {
    extern "C" {
        fn signal(signum: std::ffi::c_int, handler: usize) -> usize;
    }
    const SIGPIPE: std::ffi::c_int = 13; // the same number on Linux, macOS and the BSDs
    const SIG_DFL: usize = 0;
    // SAFETY: `signal` from the C library with a valid signal number and the default handler; called
    // first thing in `main`, before any other thread exists.
    unsafe {
        signal(SIGPIPE, SIG_DFL);
    }
}

/// The one-line message of an error: its own text followed by each cause in its chain that the text
/// does not already contain. Error types that print their cause in their message (`{path}: cannot
/// read: {source}`) and also return it as `source()` would otherwise show it twice, as `{:#}` does.
fn message(error: &anyhow::Error) -> String {
    let mut text = error.to_string();
    for cause in error.chain().skip(1) {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            text.push_str(": ");
            text.push_str(&cause);
        }
    }
    text
}

fn main() -> ExitCode {
    #[cfg(unix)]
    restore_default_sigpipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Ballbar(args) => ballbar::run(args),
        Command::Budget(args) => budget::run(args),
        Command::Demo(args) => demo::run(args),
        Command::Design(args) => design::run(args),
        Command::Fit(args) => fit::run(*args),
        Command::Identify(args) => identify::run(args),
        Command::Inspect(args) => inspect::run(args),
        Command::Convert(args) => convert::run(args),
        Command::Iso2302(args) => iso230_2::run(args),
        Command::Live(args) => live::run(*args),
        Command::Predict(args) => predict::run(args),
        Command::Reversal(args) => reversal::run(args),
        Command::Report(args) => report::run(*args),
        Command::Uncertainty(args) => uncertainty::run(*args),
        Command::Compensate(args) => compensate::run(*args),
        Command::Nc(args) => nc::run(*args),
        Command::Thermal(args) => thermal::run(args),
        Command::Verify(args) => verify::run(*args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Input(e)) => {
            eprintln!("trueaxis: error: {}", message(&e));
            ExitCode::from(2)
        }
        Err(Failure::Computation(e)) => {
            eprintln!("trueaxis: error: {}", message(&e));
            ExitCode::from(1)
        }
        Err(Failure::Environment(e)) => {
            eprintln!("trueaxis: error: {}", message(&e));
            ExitCode::from(3)
        }
    }
}
