//! Plot of a fitted error function: the measured points, the fit and its prediction band
//! (Soons 1993 Fig. 3.2), as SVG.

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

/// Draws the data, the fitted curve and the band `value +- half_width`.
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
    let pad = 0.05 * (y1 - y0).max(1e-6);
    let mut svg = String::new();
    {
        let text = |e: &dyn std::fmt::Display| e.to_string();
        let root = SVGBackend::with_string(&mut svg, (900, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| ReportError::Draw(text(&e)))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(plot.title, ("sans-serif", 18))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(65)
            .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))
            .map_err(|e| ReportError::Draw(text(&e)))?;
        chart
            .configure_mesh()
            .x_desc(plot.x_label)
            .y_desc(plot.y_label)
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(|e| ReportError::Draw(text(&e)))?;
        let band = RGBColor(120, 160, 220);
        for sign in [-1.0, 1.0] {
            chart
                .draw_series(LineSeries::new(plot.curve.iter().map(|c| (c.0, c.1 + sign * c.2)), band.stroke_width(1)))
                .map_err(|e| ReportError::Draw(text(&e)))?
                .label(if sign > 0.0 { plot.band_label } else { "" })
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], band));
        }
        chart
            .draw_series(plot.points.iter().map(|p| Circle::new(*p, 2, RGBColor(90, 90, 90).filled())))
            .map_err(|e| ReportError::Draw(text(&e)))?
            .label("measured")
            .legend(|(x, y)| Circle::new((x + 9, y), 3, RGBColor(90, 90, 90).filled()));
        chart
            .draw_series(LineSeries::new(plot.curve.iter().map(|c| (c.0, c.1)), RED.stroke_width(2)))
            .map_err(|e| ReportError::Draw(text(&e)))?
            .label("fit")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED.stroke_width(2)));
        chart
            .configure_series_labels()
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(|e| ReportError::Draw(text(&e)))?;
        root.present().map_err(|e| ReportError::Draw(text(&e)))?;
    }
    Ok(svg)
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
