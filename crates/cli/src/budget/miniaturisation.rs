//! `trueaxis budget miniaturisation`: the three-axis miniaturisation case.

use crate::Failure;
use serde_json::{json, Value};
use std::fmt::Write;
use trueaxis::budget::analysis::GroupShare;
use trueaxis::budget::documents::number;
use trueaxis::budget::global::GeneticOptions;
use trueaxis::budget::miniaturisation::{run as run_case, ARCSEC_URAD, SIZES};
use trueaxis::budget::spec::KindValues;
use trueaxis::data::OutputSet;
use trueaxis_report::budget::{trends_svg, Series};

/// The miniaturisation case of the error budget: a three-axis machine (part on the bed, X, Y on X, Z
/// on Y, tool) scaled to cubic parts of 10 to 300 mm with equal component errors: part and machine
/// sensitivities, robustness indices and shares by axis and kind, then the cost-optimal allocation
/// at a constant relative accuracy.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis budget miniaturisation --plots mini\n  trueaxis budget miniaturisation --sizes 10,300 --json\n\n\
     Assumptions (machine scaled with the part, 1 um and 1 arcsec errors, 1 m homogenisation length): docs/budget.md"
)]
pub struct MiniaturisationArgs {
    /// Part sizes (mm), comma separated.
    #[arg(long, value_delimiter = ',', default_values_t = SIZES.to_vec())]
    sizes: Vec<f64>,
    /// Every linear error (um).
    #[arg(long, default_value_t = 1.0)]
    linear_um: f64,
    /// Every angular and squareness error (urad); default 1 arcsec.
    #[arg(long, default_value_t = ARCSEC_URAD)]
    angular_urad: f64,
    /// Target of the allocation per direction over the part size.
    #[arg(long, default_value_t = 1e-4)]
    relative_accuracy: f64,
    /// Seed of the genetic global stage of the allocation.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Write the trend figures to this directory.
    #[arg(long, value_parser = crate::output::figures)]
    plots: Option<crate::output::OutputPath>,
    /// Print one JSON document instead of tables.
    #[arg(long)]
    json: bool,
}

fn share(groups: &[GroupShare], label: &str) -> f64 {
    groups.iter().find(|g| g.label == label).map_or(0.0, |g| g.share)
}

fn sm(groups: &[GroupShare], label: &str) -> f64 {
    groups.iter().find(|g| g.label == label).map_or(0.0, |g| g.sensitivity_mm)
}

pub fn run(args: MiniaturisationArgs) -> Result<(), Failure> {
    for (name, v) in
        [("--linear-um", args.linear_um), ("--angular-urad", args.angular_urad), ("--relative-accuracy", args.relative_accuracy)]
    {
        if !(v.is_finite() && v > 0.0) {
            return Err(Failure::input(anyhow::anyhow!("{name} {v}: must be a positive number")));
        }
    }
    if args.sizes.is_empty() {
        return Err(Failure::input(anyhow::anyhow!("--sizes: give at least one part size (mm)")));
    }
    let tolerances = KindValues([args.linear_um, args.angular_urad, args.angular_urad]);
    let cases = run_case(&args.sizes, tolerances, args.relative_accuracy, GeneticOptions { seed: args.seed, ..GeneticOptions::default() })
        .map_err(Failure::of)?;
    if let Some(dir) = &args.plots {
        // both figures or neither (docs/reliability.md)
        let mut plots = OutputSet::new();
        plots.create_directory(dir);
        let series = |f: &dyn Fn(&trueaxis::budget::miniaturisation::SizeCase) -> f64, name: &str| Series {
            name: name.into(),
            points: cases.iter().map(|c| (c.size, f(c))).collect(),
        };
        let part = trends_svg(
            "Part measures over part size",
            "part size (mm)",
            &[
                (
                    "part sensitivity SP (mm)".into(),
                    vec![
                        series(&|c| c.analysis.part_sensitivity[0], "SP x"),
                        series(&|c| c.analysis.part_sensitivity[1], "SP y"),
                        series(&|c| c.analysis.part_sensitivity[2], "SP z"),
                    ],
                ),
                (
                    "robustness indices".into(),
                    vec![
                        series(&|c| c.analysis.condition.unwrap_or(0.0), "RI_1 (condition)"),
                        series(&|c| c.analysis.singular_values[0] / 1000.0, "RI_2 (m)"),
                    ],
                ),
            ],
        )
        .map_err(Failure::computation)?;
        plots.file(dir.join("part_measures.svg"), part);
        let machine = trends_svg(
            "Machine measures over part size",
            "part size (mm)",
            &[
                ("SM by axis (mm)".into(), ["X", "Y", "Z"].iter().map(|a| series(&|c| sm(&c.analysis.by_axis, a), a)).collect()),
                (
                    "share by kind (%)".into(),
                    ["linear", "angular", "squareness"].iter().map(|k| series(&|c| share(&c.analysis.by_kind, k), k)).collect(),
                ),
                (
                    "allocation: share by kind (%)".into(),
                    ["linear", "angular", "squareness"].iter().map(|k| series(&|c| share(&c.allocated.by_kind, k), k)).collect(),
                ),
            ],
        )
        .map_err(Failure::computation)?;
        plots.file(dir.join("machine_measures.svg"), machine);
        plots.commit().map_err(Failure::input)?;
    }
    let groups = |g: &[GroupShare]| -> Value {
        Value::Array(g.iter().map(|g| json!({"group": g.label, "share_percent": g.share, "sm_mm": g.sensitivity_mm})).collect())
    };
    if args.json {
        let rows: Vec<Value> = cases
            .iter()
            .map(|c| {
                let a = &c.analysis;
                json!({
                    "size_mm": c.size, "rss_rms_um": a.rss_rms,
                    "part_sensitivity_mm": {"x": a.part_sensitivity[0], "y": a.part_sensitivity[1], "z": a.part_sensitivity[2]},
                    "ri1": a.condition.map_or(Value::Null, number), "ri2_mm": a.singular_values[0],
                    "by_axis": groups(&a.by_axis), "by_kind": groups(&a.by_kind),
                    "allocation": {
                        "target_um": args.relative_accuracy * c.size * 1000.0, "cost": c.allocation.cost, "kkt_residual": c.allocation.kkt_residual,
                        "by_axis": groups(&c.allocated.by_axis), "by_kind": groups(&c.allocated.by_kind),
                    },
                })
            })
            .collect();
        println!(
            "{}",
            json!({"linear_um": args.linear_um, "angular_urad": args.angular_urad, "relative_accuracy": args.relative_accuracy, "sizes": rows})
        );
        return Ok(());
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Miniaturisation case: machine wbXYZt scaled to the part, errors {} um and {:.3} urad, 125 poses per size\n",
        args.linear_um, args.angular_urad
    );
    let _ =
        writeln!(out, "size (mm)  SP x / y / z (mm)          RI_1    RI_2 (mm)  SM X / Y / Z (mm)         linear/angular/squareness (%)");
    for c in &cases {
        let a = &c.analysis;
        let _ = writeln!(
            out,
            "{:>9}  {:>7.1} {:>7.1} {:>7.1}   {:>7.3} {:>10.1}  {:>7.1} {:>7.1} {:>7.1}   {:>5.1} / {:>5.1} / {:>5.1}",
            c.size,
            a.part_sensitivity[0],
            a.part_sensitivity[1],
            a.part_sensitivity[2],
            a.condition.unwrap_or(f64::INFINITY),
            a.singular_values[0],
            sm(&a.by_axis, "X"),
            sm(&a.by_axis, "Y"),
            sm(&a.by_axis, "Z"),
            share(&a.by_kind, "linear"),
            share(&a.by_kind, "angular"),
            share(&a.by_kind, "squareness")
        );
    }
    let _ = writeln!(
        out,
        "\nallocation at relative accuracy {} (root-sum-square per direction), shares of the allocated errors",
        args.relative_accuracy
    );
    let _ = writeln!(out, "size (mm)  target (um)  X / Y / Z (%)              linear/angular/squareness (%)   KKT residual");
    for c in &cases {
        let a = &c.allocated;
        let _ = writeln!(
            out,
            "{:>9}  {:>11.3}  {:>5.1} / {:>5.1} / {:>5.1}      {:>5.1} / {:>5.1} / {:>5.1}          {:.1e}",
            c.size,
            args.relative_accuracy * c.size * 1000.0,
            share(&a.by_axis, "X"),
            share(&a.by_axis, "Y"),
            share(&a.by_axis, "Z"),
            share(&a.by_kind, "linear"),
            share(&a.by_kind, "angular"),
            share(&a.by_kind, "squareness"),
            c.allocation.kkt_residual
        );
    }
    print!("{out}");
    Ok(())
}
