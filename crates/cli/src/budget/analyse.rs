//! `trueaxis budget analyse`: the forward analysis of a budget.

use super::inputs::{frame_name, BudgetInputs, Loaded, PoseSet};
use super::{failure, number};
use crate::Failure;
use serde_json::{json, Value};
use std::fmt::Write;
use std::path::Path;
use trueaxis::budget::analysis::{Analysis, GroupShare};
use trueaxis::budget::{analyse, BudgetSpec};
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
    #[arg(long, value_parser = crate::outputs::file)]
    out: Option<crate::outputs::OutputPath>,
    /// Write the sensitivity matrix (CSV: one row per pose and direction, one column per component,
    /// um per um or um per urad) to this file.
    #[arg(long, value_parser = crate::outputs::file)]
    sensitivity: Option<crate::outputs::OutputPath>,
    /// Write the figures (contribution chart, map of the root-sum-square error over the mid-planes of
    /// the work volume) to this directory.
    #[arg(long, value_parser = crate::outputs::figures)]
    plots: Option<crate::outputs::OutputPath>,
    /// Write an HTML report of the analysis to this file.
    #[arg(long, value_parser = crate::outputs::file)]
    report: Option<crate::outputs::OutputPath>,
    /// Print one JSON document instead of tables.
    #[arg(long)]
    json: bool,
}

pub fn run(args: AnalyseArgs) -> Result<(), Failure> {
    let loaded = args.inputs.load()?;
    let Loaded { machine, spec, setup, frame, sets } = &loaded;
    let mut analyses = Vec::new();
    for set in sets {
        analyses.push(analyse(machine, spec, &set.internal, setup, *frame).map_err(failure)?);
    }
    for (set, a) in sets.iter().zip(&analyses) {
        check_finite(a).map_err(|m| Failure::computation(anyhow::anyhow!("{}: {m}", set.label)))?;
    }
    let suffix = |set: &PoseSet| if sets.len() > 1 { format!("_{}", set.label.replace('.', "p")) } else { String::new() };
    // tables, plots and report together, or none of them (docs/reliability.md)
    let mut outputs = OutputSet::new();
    if let Some(path) = &args.out {
        let mut text = String::new();
        for (k, (set, a)) in sets.iter().zip(&analyses).enumerate() {
            text += &poses_csv(machine, set, a, sets.len() > 1, k == 0);
        }
        outputs.file(path, text);
    }
    if let Some(path) = &args.sensitivity {
        let mut text = String::new();
        for (k, (set, a)) in sets.iter().zip(&analyses).enumerate() {
            text += &sensitivity_csv(machine, spec, set, a, k == 0);
        }
        outputs.file(path, text);
    }
    let mut figures = Vec::new();
    if args.plots.is_some() || args.report.is_some() {
        for (set, a) in sets.iter().zip(&analyses) {
            let svg = contribution_svg(spec, a, 12).map_err(Failure::computation)?;
            figures.push((format!("contributions{}.svg", suffix(set)), format!("Shares in the root-sum-square error, {}", set.label), svg));
        }
        if let Some(svg) = volume_map(machine, spec, &loaded)? {
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
        let sets_json: Vec<Value> = sets.iter().zip(&analyses).map(|(set, a)| analysis_json(machine, spec, set, a)).collect();
        let doc = json!({
            "machine": machine.name,
            "frame": frame_name(*frame),
            "units": {"tolerance": "um (linear) / urad (angular, squareness)", "volumetric_error": "um", "homogenised_sensitivity": "mm"},
            "sets": sets_json,
        });
        println!("{doc}");
    } else {
        let mut text = String::new();
        for (set, a) in sets.iter().zip(&analyses) {
            text += &analysis_text(machine, spec, set, a, &args.inputs);
        }
        print!("{text}");
    }
    Ok(())
}

fn check_finite(a: &Analysis) -> Result<(), String> {
    let ok = a.poses.iter().all(|p| p.stack.rss_total.is_finite() && p.stack.worst_total.is_finite()) && a.rss_rms.is_finite();
    ok.then_some(()).ok_or_else(|| "the stack-up is not finite (check the machine and tolerances)".into())
}

/// The map of the root-sum-square 3D error over the mid-planes of the travel, with the rotary axes
/// where the pose options put them; `None` for a machine with fewer than two linear axes.
fn volume_map(machine: &Machine, spec: &BudgetSpec, loaded: &Loaded) -> Result<Option<String>, Failure> {
    let Some(mut map) = VolumeMap::new(machine) else { return Ok(None) };
    let n = machine.axis_count();
    let base = &loaded.sets[0].user[..n];
    for (k, axis) in machine.axes().iter().enumerate() {
        if axis.kind == trueaxis::machine::AxisKind::Rotary {
            for pose in map.poses_user.chunks_mut(n) {
                pose[k] = base[k];
            }
        }
    }
    map.poses_internal = super::inputs::internal(machine, &map.poses_user);
    let a = analyse(machine, spec, &map.poses_internal, &loaded.setup, loaded.frame).map_err(failure)?;
    let values: Vec<f64> = a.poses.iter().map(|p| p.stack.rss_total).collect();
    Ok(Some(map.heatmap("Root-sum-square volumetric error (um)", &values, None).map_err(|e| Failure::computation(anyhow::anyhow!("{e}")))?))
}

fn pose_columns(machine: &Machine) -> Vec<String> {
    machine.axes().iter().map(|a| a.letter.to_string()).collect()
}

fn poses_csv(machine: &Machine, set: &PoseSet, a: &Analysis, with_part: bool, first: bool) -> String {
    let mut out = String::new();
    let header = pose_columns(machine).join(",");
    let part = if with_part { "part," } else { "" };
    if first {
        let _ = writeln!(out, "{part}pose,{header},rss_x,rss_y,rss_z,rss_total,worst_x,worst_y,worst_z,worst_total,sigma_max_mm,condition");
    }
    for (i, (pose, r)) in set.user.chunks(machine.axis_count()).zip(&a.poses).enumerate() {
        let s = &r.stack;
        let positions: Vec<String> = pose.iter().map(|v| format!("{v}")).collect();
        let label = if with_part { format!("{},", set.label) } else { String::new() };
        let _ = writeln!(
            out,
            "{label}{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.4},{}",
            i + 1,
            positions.join(","),
            s.rss[0],
            s.rss[1],
            s.rss[2],
            s.rss_total,
            s.worst[0],
            s.worst[1],
            s.worst[2],
            s.worst_total,
            r.singular_values[0],
            r.condition.map_or(String::new(), |c| format!("{c:.4}"))
        );
    }
    out
}

fn sensitivity_csv(machine: &Machine, spec: &BudgetSpec, set: &PoseSet, a: &Analysis, header: bool) -> String {
    let mut out = String::new();
    if header {
        let names: Vec<String> = spec.components.iter().map(|c| c.id.to_string()).collect();
        let _ = writeln!(out, "set,pose,{},direction,{}", pose_columns(machine).join(","), names.join(","));
    }
    for (p, pose) in set.user.chunks(machine.axis_count()).enumerate() {
        let positions: Vec<String> = pose.iter().map(|v| format!("{v}")).collect();
        for (d, name) in ["x", "y", "z"].iter().enumerate() {
            let values: Vec<String> = a.sensitivity.row(p, d).iter().map(|v| format!("{v:.9e}")).collect();
            let _ = writeln!(out, "{},{},{},{name},{}", set.label, p + 1, positions.join(","), values.join(","));
        }
    }
    out
}

fn group_json(groups: &[GroupShare]) -> Value {
    Value::Array(
        groups.iter().map(|g| json!({"group": g.label, "share_percent": g.share, "rss_um": g.rss_um, "sm_mm": g.sensitivity_mm})).collect(),
    )
}

fn analysis_json(machine: &Machine, spec: &BudgetSpec, set: &PoseSet, a: &Analysis) -> Value {
    let (rss_pose, rss) = a.rss_max();
    let (worst_pose, worst) = a.worst_max();
    let components: Vec<Value> = spec
        .components
        .iter()
        .zip(&spec.tolerances)
        .zip(&a.components)
        .map(|((c, t), s)| {
            let rotation = c.id.component().is_rotation();
            json!({
                "name": c.id.to_string(), "kind": c.kind.name(), "axis": c.axis.to_string(), "tolerance": t, "unit": c.kind.unit(),
                "homogenisation_length_mm": c.length_mm, "gain": s.gain, "gain_unit": if rotation { "um/urad" } else { "um/um" },
                "lever_mm": if rotation { number(s.gain * 1000.0) } else { Value::Null },
                "rss_um": s.rss_um, "share_percent": s.share,
            })
        })
        .collect();
    let per_pose: Vec<Value> = set
        .user
        .chunks(machine.axis_count())
        .zip(&a.poses)
        .enumerate()
        .map(|(i, (pose, r))| {
            let positions: serde_json::Map<String, Value> =
                machine.axes().iter().zip(pose).map(|(ax, v)| (ax.letter.to_string(), json!(v))).collect();
            json!({
                "pose": i + 1, "position": positions,
                "rss_um": {"x": r.stack.rss[0], "y": r.stack.rss[1], "z": r.stack.rss[2], "total": r.stack.rss_total},
                "worst_case_um": {"x": r.stack.worst[0], "y": r.stack.worst[1], "z": r.stack.worst[2], "total": r.stack.worst_total},
                "singular_values_mm": r.singular_values, "condition_number": r.condition.map_or(Value::Null, number),
            })
        })
        .collect();
    let dmax = |d: usize, worst: bool| a.direction_max(d, worst).1;
    json!({
        "label": set.label,
        "part_mm": set.part,
        "poses": a.poses.len(),
        "rss_um": {"max": rss, "max_pose": rss_pose + 1, "rms": a.rss_rms, "x_max": dmax(0, false), "y_max": dmax(1, false), "z_max": dmax(2, false)},
        "worst_case_um": {"max": worst, "max_pose": worst_pose + 1, "x_max": dmax(0, true), "y_max": dmax(1, true), "z_max": dmax(2, true)},
        "exact_check": {"pose": a.exact_check.pose + 1, "linear_um": a.exact_check.linear_um, "exact_um": a.exact_check.exact_um},
        "singular_values_mm": a.singular_values,
        "condition_number": a.condition.map_or(Value::Null, number),
        "part_sensitivity_mm": {"x": a.part_sensitivity[0], "y": a.part_sensitivity[1], "z": a.part_sensitivity[2]},
        "by_axis": group_json(&a.by_axis),
        "by_kind": group_json(&a.by_kind),
        "components": components,
        "no_effect": a.no_effect.iter().map(|&j| spec.components[j].id.to_string()).collect::<Vec<_>>(),
        "per_pose": per_pose,
    })
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
