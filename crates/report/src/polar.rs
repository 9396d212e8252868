//! Ballbar polar plots (SVG): the nominal circle, the bar readings magnified about it with a stated
//! scale per division, any number of traces (CW / CCW, raw / compensated, partial arcs), and lines of
//! text (results, diagnostics) beside the plot.

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
    /// Text printed beside the plot.
    pub lines: &'a [String],
}

const WIDTH: u32 = 1100;
const HEIGHT: u32 = 720;
/// Radius of the nominal circle, in divisions.
const NOMINAL: f64 = 5.0;
const COLOURS: [RGBColor; 4] = [RGBColor(31, 97, 181), RGBColor(204, 60, 40), RGBColor(40, 150, 70), RGBColor(140, 80, 170)];

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
    draw(&mut svg, plot, scale).map_err(ReportError::Draw)?;
    Ok(svg)
}

fn text(e: impl std::fmt::Display) -> String {
    e.to_string()
}

fn circle(radius: f64) -> Vec<(f64, f64)> {
    (0..=360).map(|i| f64::from(i).to_radians()).map(|t| (radius * t.cos(), radius * t.sin())).collect()
}

fn draw(svg: &mut String, plot: &PolarPlot, scale: f64) -> Result<(), String> {
    let root = SVGBackend::with_string(svg, (WIDTH, HEIGHT)).into_drawing_area();
    root.fill(&WHITE).map_err(text)?;
    let (head, body) = root.split_vertically(40);
    head.draw(&Text::new(
        plot.title,
        (WIDTH as i32 / 2, 10),
        TextStyle::from(("sans-serif", 18).into_font()).pos(Pos::new(HPos::Center, VPos::Top)),
    ))
    .map_err(text)?;
    let (left, right) = body.split_horizontally(HEIGHT - 40);
    let extent = NOMINAL + 3.6;
    let mut chart = ChartBuilder::on(&left).margin(20).build_cartesian_2d(-extent..extent, -extent..extent).map_err(text)?;
    // rings every division within +-3 of the nominal circle, spokes every 30 deg
    for k in -3i32..=3 {
        let style = if k == 0 { BLACK.stroke_width(2) } else { RGBColor(200, 200, 200).stroke_width(1) };
        chart.draw_series(std::iter::once(PathElement::new(circle(NOMINAL + f64::from(k)), style))).map_err(text)?;
    }
    for i in 0..12 {
        let t = f64::from(i * 30).to_radians();
        let (c, s) = (t.cos(), t.sin());
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(2.0 * c, 2.0 * s), ((NOMINAL + 3.0) * c, (NOMINAL + 3.0) * s)],
                RGBColor(220, 220, 220),
            )))
            .map_err(text)?;
    }
    let label = |s: &str, x: f64, y: f64| {
        Text::new(s.to_string(), (x, y), TextStyle::from(("sans-serif", 14).into_font()).pos(Pos::new(HPos::Center, VPos::Center)))
    };
    chart.draw_series([label(plot.axes.0, NOMINAL + 3.4, 0.0), label(plot.axes.1, 0.0, NOMINAL + 3.4)]).map_err(text)?;
    for (k, series) in plot.series.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let points: Vec<(f64, f64)> = series
            .angles
            .iter()
            .zip(series.dl_um)
            .map(|(t, d)| ((NOMINAL + d / scale) * t.cos(), (NOMINAL + d / scale) * t.sin()))
            .collect();
        chart
            .draw_series(std::iter::once(PathElement::new(points, colour.stroke_width(2))))
            .map_err(text)?
            .label(series.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .border_style(BLACK)
        .background_style(WHITE.mix(0.85))
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(text)?;
    let mut lines = vec![format!("scale: {} um / division", trim(scale)), "black: nominal circle".to_string(), String::new()];
    lines.extend(plot.lines.iter().cloned());
    for (i, line) in lines.iter().enumerate() {
        right.draw(&Text::new(line.clone(), (10, 30 + 20 * i as i32), ("sans-serif", 13).into_font())).map_err(text)?;
    }
    root.present().map_err(text)?;
    Ok(())
}

fn trim(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The polar plot of the runs of an ISO 230-4 circular test (one trace per run, labelled CCW / CW),
/// with `lines` (the evaluation's summary) beside it; `um_per_division` as in [`PolarPlot`].
pub fn circular_runs_svg(
    title: &str,
    axes: (&str, &str),
    runs: &[trueaxis::evaluate::ballbar_diagnostics::CircularRun],
    um_per_division: Option<f64>,
    lines: &[String],
) -> Result<String, ReportError> {
    let dl_um: Vec<Vec<f64>> = runs.iter().map(|r| r.dl.iter().map(|v| v * 1e3).collect()).collect();
    let series = runs
        .iter()
        .zip(&dl_um)
        .map(|(r, d)| PolarSeries { label: r.rotation.name().to_uppercase(), angles: &r.test.angles, dl_um: d })
        .collect();
    polar_svg(&PolarPlot { title, axes, series, um_per_division, lines })
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
        });
        assert!(err.is_err());
    }
}
