//! Profiles as SVG: one line per series against a position (e.g. the machine straightness and the
//! arbor form of a reversal, seed 003 §3.4) or against the observation index (residuals).

use super::ReportError;
use plotters::prelude::*;

const COLOURS: [RGBColor; 4] = [RGBColor(31, 97, 181), RGBColor(204, 60, 40), RGBColor(40, 150, 70), RGBColor(140, 80, 170)];

/// What to draw: `(name, points)` per series.
pub struct Profiles<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub series: &'a [(String, Vec<(f64, f64)>)],
    /// A y range symmetric about zero (residuals).
    pub symmetric: bool,
    /// A dot at every point.
    pub markers: bool,
}

/// Draws each series as a line through its points (sorted by x here).
pub fn profiles_svg(plot: &Profiles) -> Result<String, ReportError> {
    let series = plot.series;
    let points = || series.iter().flat_map(|(_, p)| p.iter().copied());
    if series.is_empty() || series.iter().any(|(_, p)| p.is_empty()) || points().any(|(x, y)| !(x.is_finite() && y.is_finite())) {
        return Err(ReportError::Input("a profile plot needs finite points in every series".into()));
    }
    let (x0, x1) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (x, _)| (a.min(x), b.max(x)));
    let (mut y0, mut y1) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (_, y)| (a.min(y), b.max(y)));
    if plot.symmetric {
        y1 = y0.abs().max(y1.abs()).max(1e-3) * 1.1;
        y0 = -y1;
    }
    let ypad = if plot.symmetric { 0.0 } else { 0.08 * (y1 - y0).max(1e-3) };
    let xpad = 0.02 * (x1 - x0).max(1e-6);
    let text = |e: &dyn std::fmt::Display| ReportError::Draw(e.to_string());
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 440)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| text(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(plot.title, ("sans-serif", 18))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(65)
            .build_cartesian_2d((x0 - xpad)..(x1 + xpad), (y0 - ypad)..(y1 + ypad))
            .map_err(|e| text(&e))?;
        chart.configure_mesh().x_desc(plot.x_label).y_desc(plot.y_label).label_style(("sans-serif", 12)).draw().map_err(|e| text(&e))?;
        for (k, (name, p)) in series.iter().enumerate() {
            let colour = COLOURS[k % COLOURS.len()];
            let mut sorted = p.clone();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart
                .draw_series(LineSeries::new(sorted.iter().copied(), colour.stroke_width(if plot.markers { 2 } else { 1 })))
                .map_err(|e| text(&e))?
                .label(name.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
            if plot.markers {
                chart.draw_series(sorted.iter().map(|p| Circle::new(*p, 2, colour.filled()))).map_err(|e| text(&e))?;
            }
        }
        chart.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw().map_err(|e| text(&e))?;
        root.present().map_err(|e| text(&e))?;
    }
    Ok(svg)
}
