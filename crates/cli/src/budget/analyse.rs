//! `trueaxis budget analyse`: the forward analysis of a budget.

use super::inputs::BudgetInputs;
use crate::Failure;
use std::fmt::Write;
use std::path::Path;
use trueaxis::budget::analysis::Analysis;
use trueaxis::budget::problem::{BudgetProblem, PoseSet};
use trueaxis::budget::BudgetSpec;
use trueaxis::data::OutputSet;
use trueaxis::machine::Machine;
use trueaxis_report::budget::{budget_section, contribution_svg};
use trueaxis_report::calibration::VolumeMap;
use trueaxis_report::html::HtmlReport;

/// Forward analysis: sensitivity of the tool point to every component error, root-sum-square and
/// worst-case stack-up per direction and in 3D, singular values, part and machine sensitivities,
/// and the share of every axis, kind and component (angular errors with their lever arm).
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis budget analyse --machine examples/machines/vmc3.toml --part 200x150x100 --part 50\n  \
     trueaxis budget analyse --machine examples/machines/c600u.toml --grid 3 --rotary A=45 --plots c600u-budget --json\n\n\
     Tolerances: --budget FILE, else --linear-um / --angular-urad / --squareness-urad for every component.\n\
     Guide: docs/budget.md")]
pub struct AnalyseArgs {
    #[command(flatten)]
    inputs: BudgetInputs,
    /// Write the per-pose stack-up (CSV: axis positions, rss_x ... worst_total in um) to this file.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// Write the sensitivity matrix (CSV: one row per pose and direction, one column per component,
    /// um per um or um per urad) to this file.
    #[arg(long, value_parser = crate::output::file)]
    sensitivity: Option<crate::output::OutputPath>,
    /// Write the figures (contribution chart, map of the root-sum-square error over the mid-planes of
    /// the work volume) to this directory.
    #[arg(long, value_parser = crate::output::figures)]
    plots: Option<crate::output::OutputPath>,
    /// Write an HTML report of the analysis to this file.
    #[arg(long, value_parser = crate::output::file)]
    report: Option<crate::output::OutputPath>,
    /// Print one JSON document instead of tables.
    #[arg(long)]
    json: bool,
}

pub fn run(args: AnalyseArgs) -> Result<(), Failure> {
    let problem = args.inputs.load()?;
    let analyses = problem.analyse().map_err(Failure::of)?;
    let BudgetProblem { machine, spec, sets, .. } = &problem;
    let suffix = |set: &PoseSet| if sets.len() > 1 { format!("_{}", set.label.replace('.', "p")) } else { String::new() };
    // tables, plots and report together, or none of them (docs/reliability.md)
    let mut outputs = OutputSet::new();
    if let Some(path) = &args.out {
        outputs.file(path, problem.poses_csv(&analyses));
    }
    if let Some(path) = &args.sensitivity {
        outputs.file(path, problem.sensitivity_csv(&analyses));
    }
    let mut figures = Vec::new();
    if args.plots.is_some() || args.report.is_some() {
        for (set, a) in sets.iter().zip(&analyses) {
            let svg = contribution_svg(spec, a, 12).map_err(Failure::computation)?;
            figures.push((format!("contributions{}.svg", suffix(set)), format!("Shares in the root-sum-square error, {}", set.label), svg));
        }
        if let Some(svg) = volume_map(&problem)? {
            figures.push(("volume_map.svg".into(), "Root-sum-square 3D error over the mid-planes of the travel".into(), svg));
        }
    }
    if let Some(dir) = &args.plots {
        outputs.create_directory(dir);
        for (name, _, svg) in &figures {
            outputs.file(dir.join(name), svg.as_bytes());
        }
    }
    if let Some(path) = &args.report {
        let mut report = HtmlReport {
            title: format!("Error budget: {}", machine.name),
            subtitle: format!("trueaxis {} budget analyse", env!("CARGO_PKG_VERSION")),
            sections: Vec::new(),
            running: Vec::new(),
        };
        for (set, a) in sets.iter().zip(&analyses) {
            let mine: Vec<(String, String)> = figures
                .iter()
                .filter(|(name, _, _)| name.contains(&suffix(set)) || name == "volume_map.svg")
                .map(|(_, c, s)| (c.clone(), s.clone()))
                .collect();
            let mut section = budget_section(machine, spec, a, &mine);
            section.id = format!("budget{}", suffix(set));
            section.title = format!("Error budget, {}", set.label);
            report.sections.push(section);
        }
        outputs.file(path, report.to_html());
    }
    outputs.commit().map_err(Failure::input)?;
    if args.json {
        println!("{}", problem.analysis_json(&analyses));
    } else {
        let mut text = String::new();
        for (set, a) in sets.iter().zip(&analyses) {
            text += &analysis_text(machine, spec, set, a, &args.inputs);
        }
        print!("{text}");
    }
    Ok(())
}

/// The map of the root-sum-square 3D error over the mid-planes of the travel, with the rotary axes
/// where the pose options put them (`BudgetProblem::rss_at`); `None` for a machine with fewer than
/// two linear axes.
fn volume_map(problem: &BudgetProblem) -> Result<Option<String>, Failure> {
    let Some(map) = VolumeMap::new(&problem.machine) else { return Ok(None) };
    let values = problem.rss_at(&map.poses_user).map_err(Failure::of)?;
    Ok(Some(map.heatmap("Root-sum-square volumetric error (um)", &values, None).map_err(|e| Failure::computation(anyhow::anyhow!("{e}")))?))
}

fn analysis_text(machine: &Machine, spec: &BudgetSpec, set: &PoseSet, a: &Analysis, inputs: &BudgetInputs) -> String {
    let mut out = String::new();
    let source = match &inputs.budget {
        Some(p) => format!("budget file {}", Path::new(p).display()),
        None => format!("linear {} um, angular {} urad, squareness {} urad", inputs.linear_um, inputs.angular_urad, inputs.squareness_urad),
    };
    let _ = writeln!(
        out,
        "Error budget of {}: {} components ({source}), {} poses ({})",
        machine.name,
        spec.components.len(),
        a.poses.len(),
        set.label
    );
    let d = |k: usize, w: bool| a.direction_max(k, w).1;
    let _ = writeln!(out, "\nvolumetric error (um)              x         y         z        3D");
    let _ = writeln!(
        out,
        "  root-sum-square, largest  {:>9.3} {:>9.3} {:>9.3} {:>9.3}  (3D at pose {})",
        d(0, false),
        d(1, false),
        d(2, false),
        a.rss_max().1,
        a.rss_max().0 + 1
    );
    let _ = writeln!(
        out,
        "  worst case, largest       {:>9.3} {:>9.3} {:>9.3} {:>9.3}  (3D at pose {})",
        d(0, true),
        d(1, true),
        d(2, true),
        a.worst_max().1,
        a.worst_max().0 + 1
    );
    let _ = writeln!(out, "  root-sum-square 3D, root mean square over the poses: {:.3}", a.rss_rms);
    let _ = writeln!(
        out,
        "  exact chain, worst-case signs at pose {}: {:.3} um (linear stack-up {:.3} um)",
        a.exact_check.pose + 1,
        a.exact_check.exact_um,
        a.exact_check.linear_um
    );
    let sv = a.singular_values;
    let _ = writeln!(
        out,
        "\nhomogenised sensitivity (mm): singular values {:.1} / {:.1} / {:.1}, condition number RI_1 {}, RI_2 {:.1}",
        sv[0],
        sv[1],
        sv[2],
        a.condition.map_or("infinite".to_string(), |c| format!("{c:.2}")),
        sv[0]
    );
    let sp = a.part_sensitivity;
    let _ = writeln!(out, "part sensitivity SP x / y / z (mm): {:.1} / {:.1} / {:.1}", sp[0], sp[1], sp[2]);
    let _ = writeln!(out, "\ngroup        share (%)   RSS (um)    SM (mm)");
    for g in a.by_axis.iter().chain(&a.by_kind) {
        let _ = writeln!(out, "  {:<11}{:>8.1}{:>11.3}{:>11.1}", g.label, g.share, g.rss_um, g.sensitivity_mm);
    }
    let _ = writeln!(out, "\ncomponent  kind        tolerance      gain           RSS (um)  share (%)");
    let mut order: Vec<usize> = (0..spec.components.len()).collect();
    order.sort_by(|x, y| a.components[*y].share.total_cmp(&a.components[*x].share));
    for &j in &order {
        let c = &spec.components[j];
        let s = &a.components[j];
        let gain = if c.id.component().is_rotation() { format!("{:.1} mm lever", s.gain * 1000.0) } else { format!("{:.3} um/um", s.gain) };
        let _ = writeln!(
            out,
            "  {:<9}{:<12}{:>8} {:<5}{:<15}{:>9.3}{:>10.2}",
            c.id.to_string(),
            c.kind.name(),
            spec.tolerances[j],
            c.kind.unit(),
            gain,
            s.rss_um,
            s.share
        );
    }
    if !a.no_effect.is_empty() {
        let names: Vec<String> = a.no_effect.iter().map(|&j| spec.components[j].id.to_string()).collect();
        let _ = writeln!(out, "no effect at the tool point at these poses: {}", names.join(" "));
    }
    out.push('\n');
    out
}
