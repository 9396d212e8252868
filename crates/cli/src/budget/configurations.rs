//! `trueaxis budget configurations`: the five-axis configuration study.

use crate::{output, Failure};
use std::fmt::Write;
use std::path::Path;
use trueaxis::budget::configuration_study::{space_utility_trend, ConfigurationStudy};
use trueaxis::budget::form_shaping::form_shaping;
use trueaxis::budget::ranking::StudyOptions;
use trueaxis::budget::spec::KindValues;
use trueaxis::budget::travel::space_utility;
use trueaxis::data::OutputSet;
use trueaxis_report::budget::{bars_svg, trends_svg, BarPanel, Series};

/// Five-axis configurations: enumeration (720 / 360 / 432 / 288), ideal form-shaping functions, travel
/// and space utility for a part, and the budget of every five-degree-of-freedom configuration with
/// the same component tolerances, ranked by its root-sum-square volumetric error.
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis budget configurations --part 200x150x100 --tool-length 150 --top 10\n\n\
     The part stands with a corner on the pivot of the rotary axes; the poses put the tool on a grid over it,\n\
     upright and tilted by --tilt-deg towards +-x and +-y. Guide: docs/budget.md")]
pub struct ConfigurationsArgs {
    /// Part size LxMxN (mm) or L for a cube.
    #[arg(long, default_value = "100")]
    part: String,
    /// Tool length p (mm) from the pivot of the rotary axes next to the tool.
    #[arg(long, default_value_t = 100.0)]
    tool_length: f64,
    /// Tolerance of every linear error (um).
    #[arg(long, default_value_t = 5.0)]
    linear_um: f64,
    /// Tolerance of every angular error (urad).
    #[arg(long, default_value_t = 10.0)]
    angular_urad: f64,
    /// Tolerance of every squareness or parallelism error (urad).
    #[arg(long, default_value_t = 10.0)]
    squareness_urad: f64,
    /// Grid points per edge of the part.
    #[arg(long, default_value_t = 3)]
    nodes: usize,
    /// Tilt of the tool in the tilted poses (deg).
    #[arg(long, default_value_t = 30.0)]
    tilt_deg: f64,
    /// Rows of the ranking to print (all with --json).
    #[arg(long, default_value_t = 20)]
    top: usize,
    /// Print the form-shaping function of each order of rotary axes (linear axes X Y Z).
    #[arg(long)]
    formulas: bool,
    /// Write the figures (space utility over part size, ranking) to this directory.
    #[arg(long, value_parser = crate::output::figures)]
    plots: Option<crate::output::OutputPath>,
    /// Print one JSON document instead of tables.
    #[arg(long)]
    json: bool,
}

pub fn run(args: ConfigurationsArgs) -> Result<(), Failure> {
    let part = super::inputs::parse_part(&args.part).map_err(|m| Failure::input(anyhow::anyhow!("--part: {m}")))?;
    let options = StudyOptions {
        part,
        tool_length: args.tool_length,
        tolerances: KindValues([args.linear_um, args.angular_urad, args.squareness_urad]),
        nodes: args.nodes,
        tilt_deg: args.tilt_deg,
    };
    let progress = crate::progress::spinner(args.json);
    progress.set_message("budgets of the five-axis configurations");
    let report = |done: usize, total: usize| progress.set_message(format!("budgets of the configurations: {done} of {total}"));
    let study = ConfigurationStudy::run(&options, &report).map_err(Failure::of)?;
    progress.finish_and_clear();
    if let Some(dir) = &args.plots {
        write_figures(dir, &args, &study)?;
    }
    if args.json {
        return output::json(&study.to_json());
    }
    output::print(&(counts_text(&study.counts) + &travel_text(&args, &study) + &ranking_text(&args, &study)))
}

/// The figures: the space utility of a cubic part over its size, and the ranking; both or neither
/// (docs/reliability.md).
fn write_figures(dir: &Path, args: &ConfigurationsArgs, study: &ConfigurationStudy) -> Result<(), Failure> {
    let mut plots = OutputSet::new();
    plots.create_directory(dir);
    let series: Vec<Series> = space_utility_trend(args.tool_length)
        .map_err(Failure::of)?
        .into_iter()
        .map(|c| Series { name: format!("{} ({})", c.pattern.notation(), c.sequence.iter().collect::<String>()), points: c.points })
        .collect();
    let svg = trends_svg("Space utility of a cubic part", "part edge / tool length", &[("part volume / travel volume".into(), series)])
        .map_err(Failure::computation)?;
    plots.file(dir.join("space_utility.svg"), svg);
    let bars: Vec<(String, f64)> =
        study.ranked.iter().take(args.top.clamp(1, 30)).map(|r| (r.configuration.structure(), r.rss_rms)).collect();
    let svg =
        bars_svg("Configurations ranked", &[BarPanel { title: "RMS of the root-sum-square 3D error".into(), unit: "um".into(), bars }])
            .map_err(Failure::computation)?;
    plots.file(dir.join("ranking.svg"), svg);
    plots.commit().map_err(Failure::input)
}

/// The counts of the enumeration.
fn counts_text(counts: &[usize; 4]) -> String {
    format!(
        "Five-axis configurations: {} orders of five of the axes X Y Z A B C, {} with the three linear axes,\n\
         {} with both rotary axes next to the workpiece, one at each end, or both next to the tool and the bed between two axes,\n\
         {} of them with five degrees of freedom ({} per category)\n",
        counts[0],
        counts[1],
        counts[2],
        counts[3],
        counts[3] / 3
    )
}

/// The travel and space utility per category and order of the rotary axes (with `--formulas`, the
/// form-shaping functions).
fn travel_text(args: &ConfigurationsArgs, study: &ConfigurationStudy) -> String {
    let part = study.options.part;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\ntravel for a {} x {} x {} mm part, tool length {} mm (largest |position|, mm)",
        part[0], part[1], part[2], args.tool_length
    );
    let _ = writeln!(out, "  category     axes      X          Y          Z          space utility");
    for ((pattern, _), (seq, t)) in &study.travel {
        let _ = writeln!(
            out,
            "  {:<12} {:<9}{:>9.2}  {:>9.2}  {:>9.2}  {:>10.4}",
            pattern.notation(),
            seq.iter().collect::<String>(),
            t[0],
            t[1],
            t[2],
            space_utility(part, *t)
        );
        if args.formulas {
            let f = form_shaping(seq);
            for (name, e) in ["l", "m", "n"].iter().zip(&f.position).chain(["u", "v", "w"].iter().zip(&f.orientation)) {
                let _ = writeln!(out, "      {name} = {e}");
            }
        }
    }
    out
}

/// The first `--top` rows of the ranking.
fn ranking_text(args: &ConfigurationsArgs, study: &ConfigurationStudy) -> String {
    let ranked = &study.ranked;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\nranking by the root mean square of the root-sum-square 3D error (linear {} um, angular {} urad, squareness {} urad; {} poses each)",
        args.linear_um,
        args.angular_urad,
        args.squareness_urad,
        ranked.first().map_or(0, |r| r.poses)
    );
    let _ =
        writeln!(out, "  rank  chain                          structure    RMS (um)  max (um)  worst (um)  linear/angular/squareness (%)");
    for (i, r) in ranked.iter().take(args.top).enumerate() {
        let _ = writeln!(
            out,
            "  {:>4}  {:<30} {:<11}{:>9.3}{:>10.3}{:>12.3}  {:.0} / {:.0} / {:.0}",
            i + 1,
            r.configuration.chain(),
            r.configuration.structure(),
            r.rss_rms,
            r.rss_max,
            r.worst_max,
            r.kind_shares[0],
            r.kind_shares[1],
            r.kind_shares[2]
        );
    }
    out
}
