//! `trueaxis uncertainty`.

use crate::output::print;
use crate::parse;
use crate::Failure;
use std::path::PathBuf;
use trueaxis::data::OutputSet;
use trueaxis::geometry::Vec3;
use trueaxis::identify::{solve, Campaign, Identification, IndirectOptions};
use trueaxis::machine::Machine;
use trueaxis::model::{Frame, Setup};
use trueaxis::poses::read_poses;
use trueaxis::uncertainty::{
    budget_json, run_budget, Budget, DesignMatrix, Evaluation, IdentificationMap, IntervalKind, PoseUncertainty, Sources,
};
use trueaxis_report::{interval_of, uncertainty_figures};

/// Uncertainty of identified parameters: GUM propagation and adaptive Monte Carlo (JCGM 101
/// §7.9, several outputs per JCGM 102) with the sources of a sources file (sensor noise, frame
/// transformation, drift by the statistical or the cyclic method), and the budget per source
/// (as Andolfatto et al. (2011) tabulate it).
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  trueaxis uncertainty --design examples/uncertainty/kx8five_design.csv \\\n      \
--sources examples/uncertainty/kx8five_cyclic.toml --plots kx8five-uncertainty\n  \
trueaxis uncertainty --machine examples/machines/kx8five.toml --campaign examples/campaigns/kx8five/campaign.toml \\\n      \
--sources examples/uncertainty/kx8five_cyclic.toml\n\n\
With --machine and --campaign the design is the campaign's identification (as `trueaxis identify`),\n\
record k measured at k * --point-time s, channels named x, y, z (one measurement) or measurement:x.\n\
The design CSV has one row per observation: channel (text), t (s), optional y (um, measured value)\n\
and weight (1/sigma^2), and one column per parameter with the sensitivities (um per um or urad).\n\
The sources TOML lists the sources and the Monte Carlo settings; see docs/uncertainty.md.\n\
Estimates, uncertainties and intervals are in the parameter units (um, urad).")]
pub struct UncertaintyArgs {
    /// Design matrix (CSV): channel, t, [y], [weight], one column per parameter.
    #[arg(long, required_unless_present = "campaign", conflicts_with_all = ["campaign", "machine"])]
    design: Option<PathBuf>,
    /// Machine description, with --campaign: the design of the campaign's identification.
    #[arg(long, requires = "campaign")]
    machine: Option<PathBuf>,
    /// Measurement campaign (TOML), with --machine.
    #[arg(long, requires = "machine")]
    campaign: Option<PathBuf>,
    /// Poses (CSV, one column per axis) at which to give the uncertainty of the predicted
    /// volumetric error dx dy dz (GUM and Monte Carlo); needs --machine and --campaign.
    #[arg(long, requires = "campaign")]
    poses: Option<PathBuf>,
    /// With --poses: tool-side point x,y,z in mm, in M at home (default: the machine's tool point).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true, requires = "poses")]
    tool_point: Option<Vec3>,
    /// With --poses: workpiece-side point x,y,z in mm, in M at home (default: 0,0,0).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true, requires = "poses")]
    work_point: Option<Vec3>,
    /// With --poses: frame of dx dy dz.
    #[arg(long, value_enum, default_value = "workpiece")]
    frame: FrameArg,
    /// Time per measured point of a campaign (s), for the drift sources.
    #[arg(long, default_value_t = 0.75)]
    point_time: f64,
    /// Uncertainty sources and Monte Carlo settings (TOML).
    #[arg(long)]
    sources: PathBuf,
    /// Seed of the random numbers (overrides the sources file).
    #[arg(long)]
    seed: Option<u64>,
    /// Only the run with all sources together (no per-source budget).
    #[arg(long)]
    no_budget: bool,
    /// Write histograms.svg and convergence.svg into this directory.
    #[arg(long, value_parser = crate::output::figures)]
    plots: Option<crate::output::OutputPath>,
    /// Print one JSON document instead of the tables.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum FrameArg {
    Workpiece,
    Machine,
}

/// A campaign and its identification (the same as `trueaxis identify` solves).
struct CampaignContext {
    machine: Machine,
    campaign: Campaign,
    identification: Identification,
    design: DesignMatrix,
}

fn campaign_context(machine: &std::path::Path, campaign: &std::path::Path, point_time: f64) -> Result<CampaignContext, Failure> {
    let machine = Machine::load(machine).map_err(Failure::input)?;
    let campaign = Campaign::load(campaign, &machine).map_err(Failure::of)?;
    let nominal = campaign.nominal_errors(&machine).map_err(Failure::of)?;
    let design = campaign.design_matrix(&machine, &nominal).map_err(Failure::of)?;
    let start = campaign.nominal_values(&nominal).map_err(Failure::of)?;
    let identification = solve(&design, &start, &IndirectOptions::default()).map_err(Failure::of)?;
    let design = trueaxis::uncertainty::from_identification(&design, point_time).map_err(Failure::of)?;
    Ok(CampaignContext { machine, campaign, identification, design })
}

/// The uncertainty of the predicted volumetric error at every pose of `path`
/// (`uncertainty::pose_uncertainties`).
fn pose_uncertainties(
    args: &UncertaintyArgs,
    path: &std::path::Path,
    ctx: &CampaignContext,
    budget: &Budget,
    level: f64,
) -> Result<Vec<PoseUncertainty>, Failure> {
    let m = &ctx.machine;
    let poses = read_poses(path, m).map_err(Failure::input)?;
    let setup = Setup { tool_point: args.tool_point.unwrap_or(m.tool_point), work_point: args.work_point.unwrap_or_else(Vec3::zeros) };
    let frame = match args.frame {
        FrameArg::Workpiece => Frame::Workpiece,
        FrameArg::Machine => Frame::Machine,
    };
    trueaxis::uncertainty::pose_uncertainties(m, &ctx.campaign, &ctx.identification, budget, &poses.user, &setup, frame, level)
        .map_err(Failure::of)
}

/// Where the design came from, for the outputs.
fn design_origin(args: &UncertaintyArgs) -> String {
    match (&args.design, &args.campaign) {
        (Some(d), _) => d.display().to_string(),
        (None, Some(c)) => c.display().to_string(),
        _ => String::new(),
    }
}

pub fn run(args: UncertaintyArgs) -> Result<(), Failure> {
    let context = match (&args.machine, &args.campaign) {
        (Some(machine), Some(campaign)) if args.design.is_none() => Some(campaign_context(machine, campaign, args.point_time)?),
        _ => None,
    };
    if args.poses.is_some() && context.is_none() {
        return Err(Failure::input(anyhow::anyhow!("--poses needs --machine and --campaign (the parameters' effect on dx dy dz)")));
    }
    let design = match (&args.design, &context) {
        (Some(path), _) => DesignMatrix::read_csv(path).map_err(Failure::of)?,
        (None, Some(ctx)) => ctx.design.clone(),
        _ => return Err(Failure::input(anyhow::anyhow!("give --design, or --machine and --campaign"))),
    };
    let mut sources = Sources::load(&args.sources).map_err(Failure::of)?;
    if let Some(seed) = args.seed {
        sources.settings.seed = seed;
    }
    sources.check_channels(&design).map_err(|e| Failure::of(trueaxis::Error::input(format!("{}: {e}", args.sources.display()))))?;
    let map = IdentificationMap::new(design).map_err(Failure::of)?;
    let bar = crate::progress::spinner(args.json);
    let settings = &sources.settings;
    let mut report = |stage: Option<&str>, h: usize, c: Option<&trueaxis::uncertainty::ControlVariables>| {
        let what = stage.map_or("all sources".to_string(), |s| format!("source `{s}` alone"));
        let control = c.map_or(String::new(), |c| {
            format!(", largest 2s = {:.4} (tolerance {})", 2.0 * c.max.iter().fold(0.0f64, |a, b| a.max(*b)), settings.tolerance)
        });
        bar.set_message(format!("{what}: sequence {h}{control}"));
        bar.tick();
    };
    let budget = run_budget(&map, &sources.sources, settings, Evaluation::Reduced, !args.no_budget, &mut report);
    bar.finish_and_clear();
    let budget = budget.map_err(Failure::of)?;
    let poses = match (&args.poses, &context) {
        (Some(path), Some(ctx)) => pose_uncertainties(&args, path, ctx, &budget, settings.coverage)?,
        _ => Vec::new(),
    };
    if let Some(dir) = &args.plots {
        write_plots(dir, &budget, &sources).map_err(Failure::input)?;
    }
    if !budget.total.converged {
        eprintln!(
            "trueaxis: warning: the adaptive Monte Carlo did not reach the tolerance {} within {} sequences",
            settings.tolerance, settings.max_sequences
        );
    }
    let text = if args.json {
        format!("{}\n", budget_json(&design_origin(&args), &map, &budget, &sources.settings, &poses))
    } else {
        table(&args, &map, &budget, &sources) + &poses_table(&args, &poses, &sources)
    };
    print(&text)
}

fn poses_table(args: &UncertaintyArgs, poses: &[PoseUncertainty], sources: &Sources) -> String {
    use std::fmt::Write;
    let Some(path) = &args.poses else { return String::new() };
    let mut out = String::new();
    let pct = 100.0 * sources.settings.coverage;
    let frame = match args.frame {
        FrameArg::Workpiece => "workpiece",
        FrameArg::Machine => "machine",
    };
    let _ = writeln!(
        out,
        "\nuncertainty of the predicted volumetric error dx dy dz ({}, {frame} frame): standard uncertainties (um) and the {pct} % \
         confidence ellipsoid (semi-axes sqrt(chi2_3 lambda_i), um, along unit directions), GUM (F Cov F^T) and Monte Carlo (F Cov_MC F^T)",
        path.display()
    );
    for (k, p) in poses.iter().enumerate() {
        let pose: Vec<String> = p.user.iter().map(|(a, v)| format!("{a}={v}")).collect();
        let _ = writeln!(out, "pose {} ({}):", k + 1, pose.join(" "));
        for (name, v) in [("GUM", &p.gum), ("MC ", &p.monte_carlo)] {
            let axes: Vec<String> = v
                .ellipsoid
                .semi_axes
                .iter()
                .enumerate()
                .map(|(i, a)| {
                    let d = v.ellipsoid.axes.directions.column(i);
                    format!("{a:.3} along ({:+.3} {:+.3} {:+.3})", d[0], d[1], d[2])
                })
                .collect();
            let u = v.std_uncertainty;
            let _ = writeln!(out, "  {name} u(dx dy dz) = {:.3} {:.3} {:.3} um; ellipsoid {}", u[0], u[1], u[2], axes.join(", "));
        }
    }
    out
}

fn table(args: &UncertaintyArgs, map: &IdentificationMap, budget: &Budget, sources: &Sources) -> String {
    use std::fmt::Write;
    let s = &sources.settings;
    let mut out = String::new();
    let pct = 100.0 * s.coverage;
    let _ = writeln!(
        out,
        "Uncertainty of {} parameters identified from {} observations ({}); condition number {:.1}",
        map.design.parameter_count(),
        map.design.observations(),
        design_origin(args),
        map.condition_number
    );
    let _ = writeln!(out, "sources: {}", budget.source_names.join(", "));
    let _ = writeln!(
        out,
        "adaptive Monte Carlo (JCGM 101 7.9): M = {} trials x h = {} sequences, tolerance {}, seed {}: {}",
        s.trials_per_sequence,
        budget.total.sequences,
        s.tolerance,
        s.seed,
        if budget.total.converged { "converged" } else { "NOT converged" }
    );
    let kind = match s.interval {
        IntervalKind::Symmetric => "symmetric",
        IntervalKind::Shortest => "shortest",
    };
    let _ = writeln!(
        out,
        "\n{:<8} {:>5} {:>10} {:>9} {:>9}   {:<24} {:<24}",
        "param",
        "unit",
        "estimate",
        "u (MC)",
        "u (GUM)",
        format!("{pct} % {kind}"),
        "GUM interval"
    );
    let k = budget.gum_coverage_factor;
    for (j, row) in budget.rows.iter().enumerate() {
        let o = &budget.total.outputs[j];
        let (lo, hi) = interval_of(s.interval, o);
        let g = budget.gum_estimate[j];
        let _ = writeln!(
            out,
            "{:<8} {:>5} {:>10.3} {:>9.3} {:>9.3}   [{:>9.3}, {:>9.3}]   [{:>9.3}, {:>9.3}]",
            row.parameter,
            row.unit,
            o.mean,
            o.std_uncertainty,
            row.gum_total_u,
            lo,
            hi,
            g - k * row.gum_total_u,
            g + k * row.gum_total_u
        );
    }
    if budget.per_source.len() > 1 {
        let _ = writeln!(out, "\nbudget: width of the {pct} % interval with each source alone (as Andolfatto et al. (2011) tabulate it)");
        let mut header = format!("{:<8} {:>5}", "param", "unit");
        for name in &budget.source_names {
            let _ = write!(header, " {:>14}", name);
        }
        let _ = writeln!(out, "{header} {:>10} {:>10}", "rss", "total");
        for row in &budget.rows {
            let mut line = format!("{:<8} {:>5}", row.parameter, row.unit);
            for w in &row.widths {
                let _ = write!(line, " {:>14.3}", w);
            }
            let _ = writeln!(out, "{line} {:>10.3} {:>10.3}", row.rss, row.total);
        }
    }
    if let Some(dir) = &args.plots {
        let _ = writeln!(out, "\nwrote {}/histograms.svg and {}/convergence.svg", dir.display(), dir.display());
    }
    out
}

fn write_plots(dir: &std::path::Path, budget: &Budget, sources: &Sources) -> anyhow::Result<()> {
    let (histograms, convergence) = uncertainty_figures(budget, &sources.settings)?;
    let mut plots = OutputSet::new();
    plots.create_directory(dir).file(dir.join("histograms.svg"), histograms);
    if let Some(svg) = convergence {
        plots.file(dir.join("convergence.svg"), svg);
    }
    Ok(plots.commit()?)
}
