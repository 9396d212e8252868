//! `trueaxis uncertainty`.

use crate::Failure;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::{json, Map, Value};
use std::io::IsTerminal;
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::report::{interval_of, uncertainty_figures};
use trueaxis::uncertainty::{run_budget, Budget, DesignMatrix, Evaluation, IdentificationMap, IntervalKind, Sources, UncertaintyError};

/// Uncertainty of identified parameters: GUM propagation and adaptive Monte Carlo (JCGM 101
/// §7.9, several outputs per JCGM 102) with the sources of a sources file (sensor noise, frame
/// transformation, drift by the statistical or the cyclic method), and the budget per source
/// (seed 004 Table 5).
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
    #[arg(long)]
    plots: Option<PathBuf>,
    /// Print one JSON document instead of the tables.
    #[arg(long)]
    json: bool,
}

/// The design of a campaign's identification (the same as `trueaxis identify` solves).
fn campaign_design(machine: &std::path::Path, campaign: &std::path::Path, point_time: f64) -> Result<DesignMatrix, Failure> {
    let identify_failure = |e: trueaxis::identify::IdentifyError| match e {
        trueaxis::identify::IdentifyError::RankDeficient { .. } => Failure::computation(e),
        other => Failure::input(other),
    };
    let machine = trueaxis::machine::Machine::load(machine).map_err(Failure::input)?;
    let campaign = trueaxis::identify::Campaign::load(campaign, &machine).map_err(identify_failure)?;
    let nominal = campaign.nominal_errors(&machine).map_err(identify_failure)?;
    let design = campaign.design_matrix(&machine, &nominal).map_err(identify_failure)?;
    trueaxis::uncertainty::from_identification(&design, point_time).map_err(failure)
}

/// Where the design came from, for the outputs.
fn design_origin(args: &UncertaintyArgs) -> String {
    match (&args.design, &args.campaign) {
        (Some(d), _) => d.display().to_string(),
        (None, Some(c)) => c.display().to_string(),
        _ => String::new(),
    }
}

fn failure(e: UncertaintyError) -> Failure {
    if e.is_input() {
        Failure::input(e)
    } else {
        Failure::computation(e)
    }
}

pub fn run(args: UncertaintyArgs) -> Result<(), Failure> {
    let design = match (&args.design, &args.machine, &args.campaign) {
        (Some(path), _, _) => DesignMatrix::read_csv(path).map_err(failure)?,
        (None, Some(machine), Some(campaign)) => campaign_design(machine, campaign, args.point_time)?,
        _ => return Err(Failure::input(anyhow::anyhow!("give --design, or --machine and --campaign"))),
    };
    let mut sources = Sources::load(&args.sources).map_err(failure)?;
    if let Some(seed) = args.seed {
        sources.settings.seed = seed;
    }
    sources.check_channels(&design).map_err(|e| failure(UncertaintyError::Input(format!("{}: {e}", args.sources.display()))))?;
    let map = IdentificationMap::new(design).map_err(failure)?;
    let bar = progress_bar(args.json);
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
    let budget = budget.map_err(failure)?;
    if let Some(dir) = &args.plots {
        write_plots(dir, &budget, &sources).map_err(Failure::input)?;
    }
    if !budget.total.converged {
        eprintln!(
            "trueaxis: warning: the adaptive Monte Carlo did not reach the tolerance {} within {} sequences",
            settings.tolerance, settings.max_sequences
        );
    }
    let text = if args.json { format!("{}\n", to_json(&args, &map, &budget, &sources)) } else { table(&args, &map, &budget, &sources) };
    print(&text)
}

fn progress_bar(json: bool) -> ProgressBar {
    if json || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    bar.set_style(ProgressStyle::with_template("{spinner} {elapsed} {msg}").unwrap_or_else(|_| ProgressStyle::default_spinner()));
    bar
}

fn to_json(args: &UncertaintyArgs, map: &IdentificationMap, budget: &Budget, sources: &Sources) -> Value {
    let s = &sources.settings;
    let k = budget.gum_coverage_factor;
    let mut parameters = Map::new();
    for (j, row) in budget.rows.iter().enumerate() {
        let o = &budget.total.outputs[j];
        let (gum_mean, gum_u) = (budget.gum_estimate[j], row.gum_total_u);
        let mut per_source = Map::new();
        for (name, w) in budget.source_names.iter().zip(&row.widths) {
            per_source.insert(name.clone(), json!(w));
        }
        if !row.widths.is_empty() {
            per_source.insert("rss".into(), json!(row.rss));
        }
        per_source.insert("total".into(), json!(row.total));
        parameters.insert(
            row.parameter.clone(),
            json!({
                "unit": row.unit,
                "estimate": o.mean,
                "std_uncertainty": o.std_uncertainty,
                "interval": [o.symmetric.low, o.symmetric.high],
                "shortest_interval": [o.shortest.low, o.shortest.high],
                "skewness": o.skewness,
                "excess_kurtosis": o.excess_kurtosis,
                "gum": {"estimate": gum_mean, "std_uncertainty": gum_u, "interval": [gum_mean - k * gum_u, gum_mean + k * gum_u]},
                "budget_interval_widths": per_source,
                "gum_std_uncertainty_per_source": budget.source_names.iter().zip(&row.gum_u).map(|(n, u)| (n.clone(), json!(u))).collect::<Map<_, _>>(),
            }),
        );
    }
    let history: Vec<Value> = budget
        .total
        .history
        .iter()
        .map(|c| json!({"sequence": c.sequence, "s_estimate": c.max[0], "s_std_uncertainty": c.max[1], "s_low": c.max[2], "s_high": c.max[3]}))
        .collect();
    json!({
        "design": design_origin(args),
        "observations": map.design.observations(),
        "parameter_order": map.design.parameters,
        "parameters": parameters,
        "sources": budget.source_names,
        "coverage": s.coverage,
        "interval": s.interval,
        "tolerance": s.tolerance,
        "seed": s.seed,
        "trials_per_sequence": s.trials_per_sequence,
        "sequences": budget.total.sequences,
        "trials": budget.total.trials,
        "converged": budget.total.converged,
        "budget_sequences": budget.per_source.iter().map(|r| r.sequences).collect::<Vec<_>>(),
        "condition_number": map.condition_number,
        "history": history,
    })
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
        let _ = writeln!(out, "\nbudget: width of the {pct} % interval with each source alone (seed 004 Table 5)");
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
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("{}: cannot create directory: {e}", dir.display()))?;
    let (histograms, convergence) = uncertainty_figures(budget, &sources.settings)?;
    write_atomically(&dir.join("histograms.svg"), histograms.as_bytes())?;
    if let Some(svg) = convergence {
        write_atomically(&dir.join("convergence.svg"), svg.as_bytes())?;
    }
    Ok(())
}

/// Writes to stdout; a closed pipe (`| head`) is not an error.
fn print(text: &str) -> Result<(), Failure> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Failure::computation(anyhow::anyhow!("cannot write to stdout: {e}"))),
        _ => Ok(()),
    }
}
