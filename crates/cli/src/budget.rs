//! `trueaxis budget`: the error budget for machine design (Zhu 2008 appendices B and C): forward
//! analysis, cost-optimal allocation, five-axis configuration study, miniaturisation case.

mod allocate;
mod analyse;
mod configurations;
mod inputs;
mod miniaturisation;

use crate::Failure;

/// Error budget for design: sensitivity, stack-up, tolerance allocation, five-axis configurations.
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis budget analyse --machine examples/machines/vmc3.toml --part 200x150x100\n\n\
     Units: tolerances in um (linear errors) and urad (angular and squareness errors); volumetric errors in um.\n\
     Guide: docs/budget.md")]
pub struct BudgetArgs {
    #[command(subcommand)]
    command: BudgetCommand,
}

#[derive(clap::Subcommand)]
enum BudgetCommand {
    Analyse(Box<analyse::AnalyseArgs>),
    Allocate(Box<allocate::AllocateArgs>),
    Configurations(configurations::ConfigurationsArgs),
    Miniaturisation(miniaturisation::MiniaturisationArgs),
}

pub fn run(args: BudgetArgs) -> Result<(), Failure> {
    match args.command {
        BudgetCommand::Analyse(a) => analyse::run(*a),
        BudgetCommand::Allocate(a) => allocate::run(*a),
        BudgetCommand::Configurations(a) => configurations::run(a),
        BudgetCommand::Miniaturisation(a) => miniaturisation::run(a),
    }
}
