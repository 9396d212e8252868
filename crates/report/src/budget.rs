//! Figures and the report section of the error budget for design (`trueaxis budget`): the share of
//! each axis, kind of error and component in the root-sum-square volumetric error (bar charts), the
//! trends of the miniaturisation case over part sizes, and an HTML section with the tables.

use super::html::Section;
use super::style;
use super::ReportError;
use plotters::prelude::*;
use trueaxis::budget::analysis::{Analysis, GroupShare};
use trueaxis::budget::BudgetSpec;
use trueaxis::machine::Machine;

/// One panel of horizontal bars: `(label, value)`.
#[derive(Clone, Debug)]
pub struct BarPanel {
    pub title: String,
    pub unit: String,
    pub bars: Vec<(String, f64)>,
}

const BAR_COLOUR: RGBColor = RGBColor(70, 110, 170);
const PANEL_WIDTH: u32 = 420;

/// Panels of horizontal bars side by side (e.g. shares in % by axis, by kind, by component).
pub fn bars_svg(title: &str, panels: &[BarPanel]) -> Result<String, ReportError> {
    if panels.is_empty() || panels.iter().any(|p| p.bars.is_empty()) {
        return Err(ReportError::Input("a bar chart needs at least one panel with one bar".into()));
    }
    if panels.iter().flat_map(|p| &p.bars).any(|(_, v)| !v.is_finite()) {
        return Err(ReportError::Input("bar values must be finite".into()));
    }
    let rows = panels.iter().map(|p| p.bars.len()).max().unwrap_or(1);
    let height = 110 + 26 * rows as u32;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (PANEL_WIDTH * panels.len() as u32, height)).into_drawing_area();
        root.fill(&WHITE).map_err(style::not_drawn)?;
        let root = root.titled(title, ("sans-serif", 20)).map_err(style::not_drawn)?;
        for (area, panel) in root.split_evenly((1, panels.len())).iter().zip(panels) {
            let n = panel.bars.len();
            let top = panel.bars.iter().map(|b| b.1).fold(0.0, f64::max).max(1e-12) * 1.15;
            let labels: Vec<String> = panel.bars.iter().map(|b| b.0.clone()).collect();
            let label_width = labels.iter().map(|l| l.chars().count()).max().unwrap_or(1) as u32 * 7 + 12;
            let mut chart = ChartBuilder::on(area)
                .caption(&panel.title, ("sans-serif", 15))
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(label_width.clamp(60, 220))
                .build_cartesian_2d(0.0..top, -0.5..(n as f64 - 0.5))
                .map_err(style::not_drawn)?;
            chart
                .configure_mesh()
                .disable_y_mesh()
                .y_labels(n)
                .y_label_formatter(&|y| {
                    let i = y.round();
                    if (y - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < labels.len() {
                        labels[n - 1 - i as usize].clone()
                    } else {
                        String::new()
                    }
                })
                .x_desc(&panel.unit)
                .label_style(("sans-serif", 12))
                .draw()
                .map_err(style::not_drawn)?;
            chart
                .draw_series(panel.bars.iter().enumerate().map(|(i, (_, v))| {
                    let y = (n - 1 - i) as f64;
                    Rectangle::new([(0.0, y - 0.35), (*v, y + 0.35)], BAR_COLOUR.filled())
                }))
                .map_err(style::not_drawn)?;
        }
        root.present().map_err(style::not_drawn)?;
    }
    Ok(svg)
}

/// Named series of `(x, y)` points.
#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// Line panels side by side over a logarithmic x axis (the part size of the miniaturisation case).
pub fn trends_svg(title: &str, x_label: &str, panels: &[(String, Vec<Series>)]) -> Result<String, ReportError> {
    let points = || panels.iter().flat_map(|(_, s)| s).flat_map(|s| &s.points);
    if panels.is_empty() || points().count() < 2 || points().any(|(x, y)| !(x.is_finite() && *x > 0.0 && y.is_finite())) {
        return Err(ReportError::Input("a trend plot needs positive finite sizes and finite values".into()));
    }
    let colours = [RGBColor(200, 60, 40), RGBColor(40, 110, 190), RGBColor(60, 150, 60), RGBColor(150, 80, 170), RGBColor(120, 120, 120)];
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (420 * panels.len() as u32, 400)).into_drawing_area();
        root.fill(&WHITE).map_err(style::not_drawn)?;
        let root = root.titled(title, ("sans-serif", 20)).map_err(style::not_drawn)?;
        for (area, (panel_title, series)) in root.split_evenly((1, panels.len())).iter().zip(panels) {
            let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
            let (x0, x1) = xs.clone().fold((f64::INFINITY, 0.0_f64), |(a, b), x| (a.min(x), b.max(x)));
            let y1 = series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).fold(0.0, f64::max).max(1e-12) * 1.35;
            let mut chart = ChartBuilder::on(area)
                .caption(panel_title, ("sans-serif", 15))
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(55)
                .build_cartesian_2d((x0 * 0.8..x1 * 1.25).log_scale(), 0.0..y1)
                .map_err(style::not_drawn)?;
            chart
                .configure_mesh()
                .disable_x_mesh()
                .x_labels(6)
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&|v| format!("{v:.0}"))
                .x_desc(x_label)
                .label_style(("sans-serif", 12))
                .draw()
                .map_err(style::not_drawn)?;
            for (k, s) in series.iter().enumerate() {
                let colour = colours[k % colours.len()];
                chart
                    .draw_series(LineSeries::new(s.points.clone(), colour.stroke_width(2)))
                    .map_err(style::not_drawn)?
                    .label(&s.name)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
                chart.draw_series(s.points.iter().map(|p| Circle::new(*p, 3, colour.filled()))).map_err(style::not_drawn)?;
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(style::not_drawn)?;
        }
        root.present().map_err(style::not_drawn)?;
    }
    Ok(svg)
}

fn group_bars(groups: &[GroupShare]) -> Vec<(String, f64)> {
    groups.iter().map(|g| (g.label.clone(), g.share)).collect()
}

/// The contribution chart of an analysis: shares (%) by axis, by kind, and of the `top` largest
/// components (angular ones labelled with their lever arm, the Abbe effect).
pub fn contribution_svg(spec: &BudgetSpec, analysis: &Analysis, top: usize) -> Result<String, ReportError> {
    let mut order: Vec<usize> = (0..spec.components.len()).collect();
    order.sort_by(|a, b| analysis.components[*b].share.total_cmp(&analysis.components[*a].share));
    let components = order
        .iter()
        .take(top)
        .map(|&j| {
            let c = &spec.components[j];
            let label = if c.id.component().is_rotation() {
                format!("{} ({:.0} mm)", c.id, analysis.components[j].gain * 1000.0)
            } else {
                c.id.to_string()
            };
            (label, analysis.components[j].share)
        })
        .collect();
    bars_svg(
        "Share in the root-sum-square volumetric error",
        &[
            BarPanel { title: "by axis".into(), unit: "%".into(), bars: group_bars(&analysis.by_axis) },
            BarPanel { title: "by kind".into(), unit: "%".into(), bars: group_bars(&analysis.by_kind) },
            BarPanel { title: format!("largest {top} components (lever arm)"), unit: "%".into(), bars: components },
        ],
    )
}

/// The report section of a forward analysis: summary, measures, shares, components, figures.
pub fn budget_section(machine: &Machine, spec: &BudgetSpec, analysis: &Analysis, figures: &[(String, String)]) -> Section {
    let (rss_pose, rss) = analysis.rss_max();
    let (worst_pose, worst) = analysis.worst_max();
    let fmt = |v: f64| format!("{v:.3}");
    let condition = analysis.condition.map_or("infinite".to_string(), |c| format!("{c:.2}"));
    let mut section = Section::new("budget", "Error budget").paragraph(format!(
        "Machine {}: {} component errors at {} poses. Root-sum-square 3D error: largest {} um (pose {}), root mean square {} um; \
         worst case: largest {} um (pose {}). On the exact chain, the worst-case combination gives {} um at that pose.",
        machine.name,
        spec.components.len(),
        analysis.poses.len(),
        fmt(rss),
        rss_pose + 1,
        fmt(analysis.rss_rms),
        fmt(worst),
        worst_pose + 1,
        fmt(analysis.exact_check.exact_um)
    ));
    let sp = analysis.part_sensitivity;
    let sv = analysis.singular_values;
    section = section.table(
        "Sensitivity measures (homogenised: mm = um per urad or per um/m)",
        &["measure", "value"],
        vec![
            vec!["singular values (mm)".into(), format!("{:.1} / {:.1} / {:.1}", sv[0], sv[1], sv[2])],
            vec!["condition number RI_1".into(), condition],
            vec!["largest singular value RI_2 (mm)".into(), format!("{:.1}", sv[0])],
            vec!["part sensitivity SP x / y / z (mm)".into(), format!("{:.1} / {:.1} / {:.1}", sp[0], sp[1], sp[2])],
        ],
    );
    let group_rows = |groups: &[GroupShare]| -> Vec<Vec<String>> {
        groups.iter().map(|g| vec![g.label.clone(), format!("{:.1}", g.share), fmt(g.rss_um), format!("{:.1}", g.sensitivity_mm)]).collect()
    };
    let mut rows = group_rows(&analysis.by_axis);
    rows.extend(group_rows(&analysis.by_kind));
    section = section.table("Shares by axis and by kind", &["group", "share (%)", "RSS (um)", "SM (mm)"], rows);
    let mut order: Vec<usize> = (0..spec.components.len()).collect();
    order.sort_by(|a, b| analysis.components[*b].share.total_cmp(&analysis.components[*a].share));
    let rows = order
        .iter()
        .map(|&j| {
            let c = &spec.components[j];
            let share = &analysis.components[j];
            let gain = if c.id.component().is_rotation() { format!("{:.1} mm", share.gain * 1000.0) } else { format!("{:.3}", share.gain) };
            vec![
                c.id.to_string(),
                c.kind.name().into(),
                format!("{} {}", spec.tolerances[j], c.kind.unit()),
                gain,
                fmt(share.rss_um),
                format!("{:.2}", share.share),
            ]
        })
        .collect();
    section = section.table(
        "Components (gain: lever arm of angular errors, um per um of linear errors)",
        &["component", "kind", "tolerance", "gain", "RSS (um)", "share (%)"],
        rows,
    );
    for (caption, svg) in figures {
        section = section.figure(caption.clone(), svg.clone());
    }
    section
}
