//! Profiles as SVG: one line per series against a position (e.g. the machine straightness and the
//! arbor form of a reversal, NISTIR 5236 §3.4) or against the observation index (residuals).

use super::framed::{framed_svg, Frame};
use super::style::{self, Swatch};
use super::ReportError;
use plotters::prelude::*;

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
    let legend: Vec<(String, Swatch)> =
        series.iter().enumerate().map(|(k, (name, _))| (name.clone(), Swatch::Line(style::colour(k), 3))).collect();
    let frame = Frame {
        height: 520,
        title: plot.title,
        legend: &legend,
        x: (x0 - xpad)..(x1 + xpad),
        y: (y0 - ypad)..(y1 + ypad),
        x_label: plot.x_label,
        y_label: plot.y_label,
    };
    framed_svg(&frame, |chart| {
        for (k, (_, p)) in series.iter().enumerate() {
            let colour = style::colour(k);
            let mut sorted = p.clone();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart.draw_series(LineSeries::new(sorted.iter().copied(), colour.stroke_width(2))).map_err(style::not_drawn)?;
            if plot.markers {
                chart.draw_series(sorted.iter().map(|p| Circle::new(*p, 3, colour.filled()))).map_err(style::not_drawn)?;
            }
        }
        Ok(())
    })
}
