//! The `trueaxis` command line: parse, call the library, print (docs/design.md, Command line).
//! Exit status: 0 success, 1 failed computation, 2 bad input, 3 the environment (`exit`).

mod ballbar;
mod bounds;
mod budget;
mod compensate;
mod convert;
mod demo;
mod design;
mod exit;
mod fit;
mod fit_options;
mod identify;
mod inputs;
mod inspect;
mod iso230_2;
mod live;
#[cfg(unix)]
mod memory;
mod nc;
mod output;
mod parse;
mod predict;
mod progress;
mod report;
mod reversal;
mod signals;
mod temperature;
mod thermal;
mod uncertainty;
mod verify;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
pub use exit::Failure;
use std::process::ExitCode;

#[cfg(unix)]
#[global_allocator]
static ALLOCATOR: memory::Watched = memory::Watched;

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

fn main() -> ExitCode {
    #[cfg(unix)]
    {
        memory::reserve();
        restore_default_sigpipe();
    }
    let command = Cli::command();
    let matches = command.clone().get_matches();
    // outputs that would destroy an input are refused before anything runs (`output`)
    let (outputs, inputs) = output::named(&matches, &command);
    if let Err(failure) = output::check(&outputs, &inputs) {
        return failure.report();
    }
    output::route_standard_output(&outputs);
    trueaxis::files::inputs::track();
    // a stop of the live service by its supervisor is its normal end
    signals::install(matches.subcommand_name() == Some("live"));
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
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
        Err(failure) => failure.report(),
    }
}
