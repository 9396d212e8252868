//! `trueaxis budget allocate`: cost-optimal tolerances for a target volumetric error.

use super::inputs::BudgetInputs;
use crate::Failure;
use std::fmt::Write;
use trueaxis::budget::allocate::{AllocationOptions, Stack, Target};
use trueaxis::budget::documents::{direction_name, stack_name, target_text};
use trueaxis::budget::global::GeneticOptions;
use trueaxis::budget::problem::BudgetProblem;
use trueaxis::data::write_atomically;

#[derive(Clone, Copy, clap::ValueEnum)]
enum StackArg {
    Rss,
    WorstCase,
}

/// Allocation: the tolerance of every component that meets a target volumetric error at every pose
/// at the least cost (cost A / e^k of the homogenised tolerance, lower limits); a seeded genetic
/// global stage, then an interior-point local stage on the convex form of the problem, checked by
/// its KKT conditions.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis budget allocate --machine examples/machines/vmc3.toml --part 300x200x150 --target-um 10 --out vmc3-allocated.toml\n  \
     trueaxis budget allocate --machine examples/machines/c600u.toml --grid 3 --stack worst-case --target-xyz 15,15,10 --json\n\n\
     The written budget file feeds `trueaxis budget analyse --budget`. Guide: docs/budget.md"
)]
pub struct AllocateArgs {
    #[command(flatten)]
    inputs: BudgetInputs,
    /// Target of the 3D volumetric error at every pose (um).
    #[arg(long, conflicts_with = "target_xyz", required_unless_present = "target_xyz", allow_hyphen_values = true)]
    target_um: Option<f64>,
    /// Targets along x, y and z at every pose (um), e.g. 10,10,6.
    #[arg(long)]
    target_xyz: Option<String>,
    /// Stack-up the target applies to: root-sum-square (tolerances as standard deviations) or worst
    /// case (tolerances as limits).
    #[arg(long, value_enum, default_value = "rss")]
    stack: StackArg,
    /// Seed of the genetic global stage.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Generations of the genetic global stage (population 10, crossover 0.9, mutation 0.1).
    #[arg(long, default_value_t = 500, value_parser = crate::bounds::count::<0, { crate::bounds::MAX_ITERATIONS }>)]
    generations: usize,
    /// Write the allocated tolerances as a budget file (TOML) to this file.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// Print one JSON document instead of tables.
    #[arg(long)]
    json: bool,
}

fn parse_xyz(text: &str) -> Result<[f64; 3], String> {
    let v: Result<Vec<f64>, _> = text.split(',').map(|p| p.trim().parse::<f64>()).collect();
    match v {
        Ok(v) if v.len() == 3 && v.iter().all(|x| x.is_finite() && *x > 0.0) => Ok([v[0], v[1], v[2]]),
        _ => Err(format!("`{text}` is not three positive targets x,y,z in um")),
    }
}

pub fn run(args: AllocateArgs) -> Result<(), Failure> {
    let problem = args.inputs.load()?;
    let target = match (args.target_um, args.target_xyz) {
        (Some(v), _) if v.is_finite() && v > 0.0 => Target::Total(v),
        (Some(v), _) => return Err(Failure::input(anyhow::anyhow!("--target-um {v}: the target must be a positive number of um"))),
        (None, Some(v)) => Target::PerDirection(parse_xyz(&v).map_err(|m| Failure::input(anyhow::anyhow!("--target-xyz: {m}")))?),
        (None, None) => unreachable!("clap requires one target"),
    };
    let stack = match args.stack {
        StackArg::Rss => Stack::Rss,
        StackArg::WorstCase => Stack::WorstCase,
    };
    let options = AllocationOptions {
        stack,
        target,
        genetic: GeneticOptions { generations: args.generations, seed: args.seed, ..GeneticOptions::default() },
    };
    let (a, s) = problem.allocate(&options).map_err(Failure::of)?;
    if let Some(path) = &args.out {
        write_atomically(path, problem.allocation_toml(&a, &options, s.poses()).as_bytes()).map_err(Failure::input)?;
    }
    if args.json {
        println!("{}", problem.allocation_json(&a, &options, s.poses()));
        return Ok(());
    }
    let BudgetProblem { machine, spec, sets, .. } = &problem;
    let (stack_name, target_text) = (stack_name(stack), target_text(target).0);
    let set = &sets[0];
    let direction = direction_name;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Cost-optimal tolerances of {}: {stack_name} target {target_text} at {} poses ({})",
        machine.name,
        s.poses(),
        set.label
    );
    let _ = writeln!(
        out,
        "cost {:.6e} (global stage {:.6e}); KKT residual {:.1e}; duality gap {:.1e}; {} Newton steps, {} cutting-plane rounds",
        a.cost, a.global_cost, a.kkt_residual, a.duality_gap, a.newton_steps, a.cutting_rounds
    );
    for c in &a.active {
        let _ = writeln!(
            out,
            "binding: pose {} ({}), multiplier {:.4e}, cost change {:.4e} per um of target",
            c.pose + 1,
            direction(c.direction),
            c.multiplier,
            c.marginal_cost_per_um
        );
    }
    let _ = writeln!(out, "\ncomponent  kind        tolerance         homogenised     lower");
    for (j, c) in spec.components.iter().enumerate() {
        let note = if !a.allocated[j] {
            "  no effect at these poses: not allocated"
        } else if a.at_lower.contains(&j) {
            "  at its lower limit"
        } else {
            ""
        };
        let hunit = if c.kind.unit() == "um" { "um/m" } else { "urad" };
        let _ = writeln!(
            out,
            "  {:<9}{:<12}{:>10.4} {:<5}{:>10.4} {:<5}{:>8} {}{note}",
            c.id.to_string(),
            c.kind.name(),
            a.tolerances[j],
            c.kind.unit(),
            a.tolerances[j] / c.scale(),
            hunit,
            spec.cost.terms[j].lower,
            c.kind.unit()
        );
    }
    print!("{out}");
    Ok(())
}
