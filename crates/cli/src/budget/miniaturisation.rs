//! `trueaxis budget miniaturisation`: the three-axis miniaturisation case, run by the library
//! (`trueaxis::budget::miniaturisation_study`); the figures and the tables printed here.

use crate::Failure;
use std::fmt::Write;
use trueaxis::budget::miniaturisation::{ARCSEC_URAD, SIZES};
use trueaxis::budget::miniaturisation_study::{group_sensitivity, group_share, MiniaturisationOptions, MiniaturisationStudy};
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

pub fn run(args: MiniaturisationArgs) -> Result<(), Failure> {
    let options = MiniaturisationOptions {
        sizes: args.sizes.clone(),
        linear_um: args.linear_um,
        angular_urad: args.angular_urad,
        relative_accuracy: args.relative_accuracy,
        seed: args.seed,
    };
    let study = MiniaturisationStudy::run(&options).map_err(Failure::of)?;
    let cases = &study.cases;
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
                (
                    "SM by axis (mm)".into(),
                    ["X", "Y", "Z"].iter().map(|a| series(&|c| group_sensitivity(&c.analysis.by_axis, a), a)).collect(),
                ),
                (
                    "share by kind (%)".into(),
                    ["linear", "angular", "squareness"].iter().map(|k| series(&|c| group_share(&c.analysis.by_kind, k), k)).collect(),
                ),
                (
                    "allocation: share by kind (%)".into(),
                    ["linear", "angular", "squareness"].iter().map(|k| series(&|c| group_share(&c.allocated.by_kind, k), k)).collect(),
                ),
            ],
        )
        .map_err(Failure::computation)?;
        plots.file(dir.join("machine_measures.svg"), machine);
        plots.commit().map_err(Failure::input)?;
    }
    if args.json {
        println!("{}", study.to_json());
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
    for c in cases {
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
            group_sensitivity(&a.by_axis, "X"),
            group_sensitivity(&a.by_axis, "Y"),
            group_sensitivity(&a.by_axis, "Z"),
            group_share(&a.by_kind, "linear"),
            group_share(&a.by_kind, "angular"),
            group_share(&a.by_kind, "squareness")
        );
    }
    let _ = writeln!(
        out,
        "\nallocation at relative accuracy {} (root-sum-square per direction), shares of the allocated errors",
        args.relative_accuracy
    );
    let _ = writeln!(out, "size (mm)  target (um)  X / Y / Z (%)              linear/angular/squareness (%)   KKT residual");
    for c in cases {
        let a = &c.allocated;
        let _ = writeln!(
            out,
            "{:>9}  {:>11.3}  {:>5.1} / {:>5.1} / {:>5.1}      {:>5.1} / {:>5.1} / {:>5.1}          {:.1e}",
            c.size,
            study.target_um(c.size),
            group_share(&a.by_axis, "X"),
            group_share(&a.by_axis, "Y"),
            group_share(&a.by_axis, "Z"),
            group_share(&a.by_kind, "linear"),
            group_share(&a.by_kind, "angular"),
            group_share(&a.by_kind, "squareness"),
            c.allocation.kkt_residual
        );
    }
    print!("{out}");
    Ok(())
}
