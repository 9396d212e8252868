//! Plot of a fitted error function: the measured points, the fit and its prediction band
//! (Soons 1993 Fig. 3.2), as SVG.

use super::framed::{framed_svg, Frame};
use super::style::{self, Swatch};
use super::ReportError;
use plotters::prelude::*;
use trueaxis::identify::DirectFitReport;

/// One curve with its band: `(x, value, half_width)` sorted by `x`.
pub struct FitPlot<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub points: &'a [(f64, f64)],
    pub curve: &'a [(f64, f64, f64)],
    pub band_label: &'a str,
}

/// Draws the data (grey dots), the fitted curve (a vermillion line) and the band `value +-
/// half_width` (shaded, blue), in the print style of [`super::style`] (printable at 10 pt, the
/// legend in a strip above the plot).
pub fn fit_plot_svg(plot: &FitPlot) -> Result<String, ReportError> {
    let finite = plot.points.iter().all(|(x, y)| x.is_finite() && y.is_finite())
        && plot.curve.iter().all(|(x, y, h)| x.is_finite() && y.is_finite() && h.is_finite());
    if !finite || plot.points.is_empty() || plot.curve.len() < 2 {
        return Err(ReportError::Input("a fit plot needs finite points and a curve of at least two nodes".into()));
    }
    let xs = plot.points.iter().map(|p| p.0).chain(plot.curve.iter().map(|c| c.0));
    let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    let ys = plot.points.iter().map(|p| p.1).chain(plot.curve.iter().flat_map(|c| [c.1 - c.2, c.1 + c.2]));
    let (y0, y1) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| (a.min(y), b.max(y)));
    let pad = 0.08 * (y1 - y0).max(1e-6);
    let xpad = 0.02 * (x1 - x0).max(1e-6);
    let (band, fit, dots) = (style::PALETTE[0], style::PALETTE[1], style::GREY);
    let legend = [
        ("measured".to_string(), Swatch::Dot(dots)),
        ("fit".to_string(), Swatch::Line(fit, 3)),
        (plot.band_label.to_string(), Swatch::Band(band)),
    ];
    let frame = Frame {
        height: 560,
        title: plot.title,
        legend: &legend,
        x: (x0 - xpad)..(x1 + xpad),
        y: (y0 - pad)..(y1 + pad),
        x_label: plot.x_label,
        y_label: plot.y_label,
    };
    framed_svg(&frame, |chart| {
        let outline: Vec<(f64, f64)> =
            plot.curve.iter().map(|c| (c.0, c.1 + c.2)).chain(plot.curve.iter().rev().map(|c| (c.0, c.1 - c.2))).collect();
        chart.draw_series(std::iter::once(Polygon::new(outline, band.mix(0.3).filled()))).map_err(style::not_drawn)?;
        chart.draw_series(plot.points.iter().map(|p| Circle::new(*p, 3, dots.filled()))).map_err(style::not_drawn)?;
        chart.draw_series(LineSeries::new(plot.curve.iter().map(|c| (c.0, c.1)), fit.stroke_width(3))).map_err(style::not_drawn)?;
        Ok(())
    })
}

/// The plot of the data, the fit and its 95 % prediction band.
pub fn direct_fit_svg(fit: &DirectFitReport, position_unit: &str) -> Result<String, ReportError> {
    let (lo, hi) = fit.positions.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
    let nodes = 400;
    let curve: Vec<(f64, f64, f64)> = (0..=nodes)
        .map(|k| {
            let x = lo + (hi - lo) * k as f64 / nodes as f64;
            let (v, h) = fit.fitted.predict(x, 0.95);
            (x, v, h)
        })
        .collect();
    let points: Vec<(f64, f64)> = fit.positions.iter().copied().zip(fit.values.iter().copied()).collect();
    let title = format!("{} fitted by {} functions", fit.parameter, fit.fitted.names.len());
    let x_label = format!("position ({position_unit})");
    let y_label = format!("{} ({})", fit.parameter, fit.parameter.unit());
    fit_plot_svg(&FitPlot {
        title: &title,
        x_label: &x_label,
        y_label: &y_label,
        points: &points,
        curve: &curve,
        band_label: "95 % prediction interval",
    })
}
