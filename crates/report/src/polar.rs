//! Ballbar polar plots (SVG): the nominal circle, the bar readings magnified about it with a stated
//! scale per division, any number of traces (CW / CCW, raw / compensated, partial arcs), and lines of
//! text (results, diagnostics) beside the plot.

use super::style::{self, Swatch};
use super::ReportError;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One trace: angles (rad, in the plane of the test) and bar readings (um).
pub struct PolarSeries<'a> {
    pub label: String,
    pub angles: &'a [f64],
    pub dl_um: &'a [f64],
}

pub struct PolarPlot<'a> {
    pub title: &'a str,
    /// Names of the plane's axes for the 0 and 90 deg labels, e.g. `("+X", "+Y")`.
    pub axes: (&'a str, &'a str),
    pub series: Vec<PolarSeries<'a>>,
    /// um per division; `None` chooses 1-2-5 steps so that the largest reading spans <= 3 divisions.
    pub um_per_division: Option<f64>,
    /// Text printed under the plot (results, diagnostics).
    pub lines: &'a [String],
    /// The test's conditions under the title: radius, feed, direction, plane.
    pub conditions: &'a [String],
}

/// Side of the square plot, and the strips above and below it (SVG units).
const PLOT: u32 = 640;
const LINE: u32 = 28;
/// Radius of the nominal circle, in divisions.
const NOMINAL: f64 = 5.0;

/// A 1-2-5 scale (um per division) that puts `max_abs` within 3 divisions.
pub fn auto_scale(max_abs: f64) -> f64 {
    let target = (max_abs / 3.0).max(1e-3);
    let decade = 10f64.powf(target.log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * decade).find(|s| *s >= target).unwrap_or(10.0 * decade)
}

/// Draws the plot; refuses non-finite values and empty traces.
pub fn polar_svg(plot: &PolarPlot) -> Result<String, ReportError> {
    if plot.series.is_empty() || plot.series.iter().any(|s| s.angles.len() != s.dl_um.len() || s.angles.is_empty()) {
        return Err(ReportError::Input("a polar plot needs at least one trace with one reading per angle".into()));
    }
    if plot.series.iter().any(|s| s.angles.iter().chain(s.dl_um).any(|v| !v.is_finite())) {
        return Err(ReportError::Input("a polar plot value is not a finite number".into()));
    }
    let max_abs = plot.series.iter().flat_map(|s| s.dl_um.iter()).fold(0.0f64, |a, v| a.max(v.abs()));
    let scale = match plot.um_per_division {
        Some(s) if s > 0.0 && s.is_finite() => s,
        Some(_) => return Err(ReportError::Input("the scale per division must be a positive number of um".into())),
        None => auto_scale(max_abs),
    };
    let mut svg = String::new();
    draw(&mut svg, plot, scale)?;
    Ok(svg)
}

fn circle(radius: f64) -> Vec<(f64, f64)> {
    (0..=360).map(|i| f64::from(i).to_radians()).map(|t| (radius * t.cos(), radius * t.sin())).collect()
}

/// Title, conditions, legend, the square plot centred, the scale and the lines of text below.
fn draw(svg: &mut String, plot: &PolarPlot, scale: f64) -> Result<(), ReportError> {
    let head = 10 + 34 + LINE * plot.conditions.len() as u32 + style::LEGEND_HEIGHT;
    let mut below = vec![format!("scale: {} um / division; rings every division, the nominal circle in black", trim(scale))];
    below.extend(plot.lines.iter().cloned());
    let height = head + PLOT + 12 + LINE * below.len() as u32 + 8;
    let root = SVGBackend::with_string(svg, (style::WIDTH, height)).into_drawing_area();
    root.fill(&WHITE).map_err(style::not_drawn)?;
    style::title(&root, plot.title, 10)?;
    for (i, c) in plot.conditions.iter().enumerate() {
        style::centred(&root, c, 44 + (LINE * i as u32) as i32, style::TICK)?;
    }
    let (top, rest) = root.split_vertically(head);
    let (_, legend_strip) = top.split_vertically(head - style::LEGEND_HEIGHT);
    let mut entries: Vec<(String, Swatch)> =
        plot.series.iter().enumerate().map(|(k, s)| (s.label.clone(), Swatch::Line(style::colour(k), 3))).collect();
    entries.push(("nominal circle".into(), Swatch::Line(BLACK, 2)));
    style::legend(&legend_strip, &entries)?;
    let (plot_row, text_area) = rest.split_vertically(PLOT);
    let side = (style::WIDTH - PLOT) / 2;
    let (_, right) = plot_row.split_horizontally(side);
    let (square, _) = right.split_horizontally(PLOT);
    let extent = NOMINAL + 3.9;
    let mut chart = ChartBuilder::on(&square).build_cartesian_2d(-extent..extent, -extent..extent).map_err(style::not_drawn)?;
    // rings every division within +-3 of the nominal circle, spokes every 30 deg
    for k in -3i32..=3 {
        let line = if k == 0 { BLACK.stroke_width(2) } else { style::LIGHT.stroke_width(1) };
        chart.draw_series(std::iter::once(PathElement::new(circle(NOMINAL + f64::from(k)), line))).map_err(style::not_drawn)?;
    }
    for i in 0..12 {
        let a = f64::from(i * 30).to_radians();
        let (c, s) = (a.cos(), a.sin());
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(2.0 * c, 2.0 * s), ((NOMINAL + 3.0) * c, (NOMINAL + 3.0) * s)],
                style::LIGHT,
            )))
            .map_err(style::not_drawn)?;
    }
    let (pa, pb) = plot.axes;
    let minus = |name: &str| name.replacen('+', "-", 1);
    let label = |s: String, x: f64, y: f64| {
        Text::new(s, (x, y), TextStyle::from(style::bold(style::LABEL)).pos(Pos::new(HPos::Center, VPos::Center)))
    };
    let r = NOMINAL + 3.5;
    chart
        .draw_series([label(pa.to_string(), r, 0.0), label(pb.to_string(), 0.0, r), label(minus(pa), -r, 0.0), label(minus(pb), 0.0, -r)])
        .map_err(style::not_drawn)?;
    for (k, series) in plot.series.iter().enumerate() {
        let points: Vec<(f64, f64)> = series
            .angles
            .iter()
            .zip(series.dl_um)
            .map(|(a, d)| ((NOMINAL + d / scale) * a.cos(), (NOMINAL + d / scale) * a.sin()))
            .collect();
        chart.draw_series(std::iter::once(PathElement::new(points, style::colour(k).stroke_width(2)))).map_err(style::not_drawn)?;
    }
    for (i, line) in below.iter().enumerate() {
        style::centred(&text_area, line, 12 + (LINE * i as u32) as i32, style::TICK)?;
    }
    root.present().map_err(style::not_drawn)?;
    Ok(())
}

fn trim(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The polar plot of the runs of an ISO 230-4 circular test (one trace per run, labelled CCW / CW),
/// with `lines` (the evaluation's summary) under it; `um_per_division` as in [`PolarPlot`].
pub fn circular_runs_svg(
    title: &str,
    axes: (&str, &str),
    runs: &[trueaxis::evaluate::ballbar_diagnostics::CircularRun],
    um_per_division: Option<f64>,
    lines: &[String],
) -> Result<String, ReportError> {
    circle_svg(title, axes, runs, um_per_division, lines, &[])
}

/// As [`circular_runs_svg`] with the test's conditions (radius, feed, direction) under the title.
pub fn circle_svg(
    title: &str,
    axes: (&str, &str),
    runs: &[trueaxis::evaluate::ballbar_diagnostics::CircularRun],
    um_per_division: Option<f64>,
    lines: &[String],
    conditions: &[String],
) -> Result<String, ReportError> {
    let dl_um: Vec<Vec<f64>> = runs.iter().map(|r| r.dl.iter().map(|v| v * 1e3).collect()).collect();
    let series = runs
        .iter()
        .zip(&dl_um)
        .map(|(r, d)| PolarSeries { label: r.rotation.name().to_uppercase(), angles: &r.test.angles, dl_um: d })
        .collect();
    polar_svg(&PolarPlot { title, axes, series, um_per_division, lines, conditions })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_is_1_2_5() {
        assert_eq!(auto_scale(8.7), 5.0);
        assert_eq!(auto_scale(15.0), 5.0);
        assert_eq!(auto_scale(16.0), 10.0);
        assert_eq!(auto_scale(0.5), 0.2);
    }

    #[test]
    fn svg_has_traces_scale_and_text() {
        let angles: Vec<f64> = (0..90).map(|i| f64::from(i).to_radians()).collect();
        let dl: Vec<f64> = angles.iter().map(|t| 8.7 * (2.0 * t).sin()).collect();
        let lines = vec!["squareness: +174.5 urad".to_string()];
        let svg = polar_svg(&PolarPlot {
            title: "arc",
            axes: ("+X", "+Y"),
            series: vec![PolarSeries { label: "CCW".into(), angles: &angles, dl_um: &dl }],
            um_per_division: None,
            lines: &lines,
            conditions: &[],
        })
        .unwrap();
        assert!(svg.contains("scale: 5 um / division") && svg.contains("squareness") && svg.contains("CCW"));
        assert!(!svg.contains("NaN"));
        let bad = [f64::NAN];
        let err = polar_svg(&PolarPlot {
            title: "",
            axes: ("", ""),
            series: vec![PolarSeries { label: String::new(), angles: &bad, dl_um: &bad }],
            um_per_division: None,
            lines: &[],
            conditions: &[],
        });
        assert!(err.is_err());
    }
}
