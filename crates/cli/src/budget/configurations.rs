//! `trueaxis budget configurations`: the five-axis configuration study.

use super::{failure, number};
use crate::Failure;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::fmt::Write;
use trueaxis::budget::configurations::{
    all_sequences, five_axis_configurations, practical_configurations, three_linear_sequences, Pattern,
};
use trueaxis::budget::form_shaping::form_shaping;
use trueaxis::budget::ranking::{study, StudyOptions};
use trueaxis::budget::spec::KindValues;
use trueaxis::budget::travel::{required_travel, space_utility};
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
    #[arg(long, value_parser = crate::outputs::figures)]
    plots: Option<crate::outputs::OutputPath>,
    /// Print one JSON document instead of tables.
    #[arg(long)]
    json: bool,
}

pub fn run(args: ConfigurationsArgs) -> Result<(), Failure> {
    let part = super::inputs::parse_part(&args.part).map_err(|m| Failure::input(anyhow::anyhow!("--part: {m}")))?;
    for (name, v) in [
        ("--tool-length", args.tool_length),
        ("--linear-um", args.linear_um),
        ("--angular-urad", args.angular_urad),
        ("--squareness-urad", args.squareness_urad),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Failure::input(anyhow::anyhow!("{name} {v}: must be a positive number")));
        }
    }
    if args.nodes < 2 || !(args.tilt_deg.is_finite() && args.tilt_deg.abs() < 90.0) {
        return Err(Failure::input(anyhow::anyhow!("--nodes must be at least 2 and --tilt-deg within (-90, 90) deg")));
    }
    let progress = crate::progress::spinner(args.json);
    progress.set_message("enumerating the configurations");
    let counts = [all_sequences().len(), three_linear_sequences().len(), practical_configurations().len()];
    let five = five_axis_configurations();
    // travel by category and order of the rotary axes (the order of the linear axes does not matter)
    let mut travel_rows: BTreeMap<(Pattern, String), ([char; 5], [f64; 3])> = BTreeMap::new();
    for c in &five {
        let rotary: String = c.sequence.iter().filter(|a| "ABC".contains(**a)).collect();
        let key = (c.pattern(), rotary);
        if let std::collections::btree_map::Entry::Vacant(e) = travel_rows.entry(key) {
            let representative = representative(c.pattern(), &e.key().1);
            let travel = required_travel(&representative, part, args.tool_length).map_err(failure)?;
            e.insert((representative, travel));
        }
    }
    progress.set_message(format!("budgets of {} configurations", five.len()));
    let options = StudyOptions {
        part,
        tool_length: args.tool_length,
        tolerances: KindValues([args.linear_um, args.angular_urad, args.squareness_urad]),
        nodes: args.nodes,
        tilt_deg: args.tilt_deg,
    };
    let ranked = study(&five, &options).map_err(failure)?;
    progress.finish_and_clear();
    if ranked.iter().any(|r| !(r.rss_rms.is_finite() && r.worst_max.is_finite())) {
        return Err(Failure::computation(anyhow::anyhow!("a configuration's stack-up is not finite")));
    }
    if let Some(dir) = &args.plots {
        // both figures or neither (docs/reliability.md)
        let mut plots = OutputSet::new();
        plots.create_directory(dir);
        let ratios = [0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0];
        let mut series = Vec::new();
        for (pattern, code) in [(Pattern::RotaryAtWorkpiece, "ABXYZ"), (Pattern::Split, "AXYZB"), (Pattern::RotaryAtTool, "XYZAB")] {
            let s: Vec<char> = code.chars().collect();
            let sequence = [s[0], s[1], s[2], s[3], s[4]];
            let mut points = Vec::new();
            for r in ratios {
                let part = [r * args.tool_length; 3];
                let travel = required_travel(&sequence, part, args.tool_length).map_err(failure)?;
                points.push((r, space_utility(part, travel)));
            }
            series.push(Series { name: format!("{} ({code})", pattern.notation()), points });
        }
        let svg = trends_svg("Space utility of a cubic part", "part edge / tool length", &[("part volume / travel volume".into(), series)])
            .map_err(Failure::computation)?;
        plots.file(dir.join("space_utility.svg"), svg);
        let bars: Vec<(String, f64)> =
            ranked.iter().take(args.top.clamp(1, 30)).map(|r| (r.configuration.structure(), r.rss_rms)).collect();
        let svg =
            bars_svg("Configurations ranked", &[BarPanel { title: "RMS of the root-sum-square 3D error".into(), unit: "um".into(), bars }])
                .map_err(Failure::computation)?;
        plots.file(dir.join("ranking.svg"), svg);
        plots.commit().map_err(Failure::input)?;
    }
    if args.json {
        let travel: Vec<Value> = travel_rows
            .iter()
            .map(|((pattern, rotary), (seq, t))| {
                json!({"category": pattern.notation(), "rotary": rotary, "axes": seq.iter().collect::<String>(), "travel_mm": t,
                       "space_utility": space_utility(part, *t)})
            })
            .collect();
        let rows: Vec<Value> = ranked
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let f = &r.form_shaping;
                json!({
                    "rank": i + 1, "axes": r.configuration.axes(), "chain": r.configuration.chain(), "structure": r.configuration.structure(),
                    "category": r.configuration.pattern().notation(), "travel_mm": r.travel, "space_utility": number(r.space_utility),
                    "rss_rms_um": r.rss_rms, "rss_max_um": r.rss_max, "worst_case_max_um": r.worst_max, "poses": r.poses,
                    "share_percent": {"linear": r.kind_shares[0], "angular": r.kind_shares[1], "squareness": r.kind_shares[2]},
                    "form_shaping": {"l": f.position[0].to_string(), "m": f.position[1].to_string(), "n": f.position[2].to_string(),
                                     "u": f.orientation[0].to_string(), "v": f.orientation[1].to_string(), "w": f.orientation[2].to_string()},
                })
            })
            .collect();
        let doc = json!({
            "part_mm": part, "tool_length_mm": args.tool_length,
            "tolerances": {"linear_um": args.linear_um, "angular_urad": args.angular_urad, "squareness_urad": args.squareness_urad},
            "counts": {"five_of_six_axes": counts[0], "three_linear_axes": counts[1], "three_categories": counts[2], "five_degrees_of_freedom": five.len()},
            "travel": travel, "ranking": rows,
        });
        println!("{doc}");
        return Ok(());
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Five-axis configurations: {} orders of five of the axes X Y Z A B C, {} with the three linear axes,\n\
         {} with both rotary axes next to the workpiece, one at each end, or both next to the tool and the bed between two axes,\n\
         {} of them with five degrees of freedom ({} per category)",
        counts[0],
        counts[1],
        counts[2],
        five.len(),
        five.len() / 3
    );
    let _ = writeln!(
        out,
        "\ntravel for a {} x {} x {} mm part, tool length {} mm (largest |position|, mm)",
        part[0], part[1], part[2], args.tool_length
    );
    let _ = writeln!(out, "  category     axes      X          Y          Z          space utility");
    for ((pattern, _), (seq, t)) in &travel_rows {
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
    print!("{out}");
    Ok(())
}

/// The configuration of a category with the rotary axes `rotary` (in chain order) and the linear
/// axes in the order X Y Z (the rows of the appendix's tables).
fn representative(pattern: Pattern, rotary: &str) -> [char; 5] {
    let r: Vec<char> = rotary.chars().collect();
    match pattern {
        Pattern::RotaryAtWorkpiece => [r[0], r[1], 'X', 'Y', 'Z'],
        Pattern::Split => [r[0], 'X', 'Y', 'Z', r[1]],
        _ => ['X', 'Y', 'Z', r[0], r[1]],
    }
}
