//! Monte Carlo plots as SVG: histograms of output distributions with their coverage interval and
//! the Gaussian of the GUM (Andolfatto et al. 2011 Fig. 10), and the convergence history of the control
//! variables of the adaptive procedure against the tolerance (Andolfatto et al. 2011 Fig. 13).

use super::style::{self, Swatch};
use super::ReportError;
use plotters::prelude::*;

/// One output's histogram panel.
#[derive(Clone, Debug)]
pub struct HistogramPanel {
    /// E.g. `EC0Y (urad)`.
    pub title: String,
    /// The Monte Carlo values (any order).
    pub values: Vec<f64>,
    /// The coverage interval drawn as two vertical lines.
    pub interval: (f64, f64),
    /// `(mean, u)` of a Gaussian drawn over the histogram (the GUM result), if any.
    pub gaussian: Option<(f64, f64)>,
}

const PANEL_H: u32 = 230;
const COLUMNS: usize = 3;
const BAR: RGBColor = RGBColor(86, 180, 233);
const INTERVAL: RGBColor = RGBColor(213, 94, 0);

/// Histograms (probability density, `bins` classes) in a grid of up to 4 columns.
pub fn histograms_svg(title: &str, panels: &[HistogramPanel], bins: usize) -> Result<String, ReportError> {
    if panels.is_empty() || bins < 2 {
        return Err(ReportError::Input("histograms need at least one panel and two bins".into()));
    }
    for p in panels {
        if p.values.len() < 2 || p.values.iter().any(|v| !v.is_finite()) || !p.interval.0.is_finite() || !p.interval.1.is_finite() {
            return Err(ReportError::Input(format!("panel `{}` needs at least two finite values", p.title)));
        }
    }
    let columns = panels.len().min(COLUMNS);
    let rows = panels.len().div_ceil(columns);
    let mut svg = String::new();
    {
        let head = 44 + style::LEGEND_HEIGHT;
        let root = SVGBackend::with_string(&mut svg, (style::WIDTH, PANEL_H * rows as u32 + head)).into_drawing_area();
        root.fill(&WHITE).map_err(style::not_drawn)?;
        style::title(&root, title, 8)?;
        let (top, root) = root.split_vertically(head);
        let (_, strip) = top.split_vertically(44);
        let mut entries =
            vec![("Monte Carlo".to_string(), Swatch::Band(BAR)), ("coverage interval".to_string(), Swatch::Line(INTERVAL, 3))];
        if panels.iter().any(|p| p.gaussian.is_some()) {
            entries.push(("GUM (Gaussian)".to_string(), Swatch::Line(BLACK, 2)));
        }
        style::legend(&strip, &entries)?;
        let _ = columns;
        for (area, panel) in root.split_evenly((rows, COLUMNS)).iter().zip(panels) {
            panel_chart(area, panel, bins)?;
        }
        root.present().map_err(style::not_drawn)?;
    }
    Ok(svg)
}

fn panel_chart<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &HistogramPanel,
    bins: usize,
) -> Result<(), ReportError>
where
    DB::ErrorType: 'static,
{
    let (lo, hi) = panel.values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
    let (lo, hi) = if hi - lo > 1e-12 * (1.0 + hi.abs()) { (lo, hi) } else { (lo - 0.5, hi + 0.5) };
    let width = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for v in &panel.values {
        counts[(((v - lo) / width) as usize).min(bins - 1)] += 1;
    }
    let n = panel.values.len() as f64;
    let density: Vec<f64> = counts.iter().map(|c| *c as f64 / (n * width)).collect();
    let gauss = |x: f64, (m, u): (f64, f64)| (-0.5 * ((x - m) / u).powi(2)).exp() / (u * (2.0 * std::f64::consts::PI).sqrt());
    let top = density.iter().copied().chain(panel.gaussian.filter(|g| g.1 > 0.0).map(|g| gauss(g.0, g))).fold(0.0, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, style::font(style::LABEL))
        .margin(6)
        .margin_left(12)
        .margin_right(22)
        .x_label_area_size(34)
        .y_label_area_size(6)
        .build_cartesian_2d(lo..hi, 0.0..top.max(1e-12))
        .map_err(style::not_drawn)?;
    // the density scale carries no information of its own: no y labels
    let span = hi - lo;
    let decimals = if span >= 20.0 {
        0
    } else if span >= 2.0 {
        1
    } else if span >= 0.2 {
        2
    } else {
        3
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(3)
        .y_labels(0)
        .x_label_formatter(&|v| format!("{v:.decimals$}"))
        .label_style(style::font(style::TICK))
        .draw()
        .map_err(style::not_drawn)?;
    chart
        .draw_series(density.iter().enumerate().map(|(i, d)| {
            let a = lo + width * i as f64;
            Rectangle::new([(a, 0.0), (a + width, *d)], BAR.filled())
        }))
        .map_err(style::not_drawn)?;
    for x in [panel.interval.0, panel.interval.1] {
        chart.draw_series(LineSeries::new([(x, 0.0), (x, top)], INTERVAL.stroke_width(2))).map_err(style::not_drawn)?;
    }
    if let Some(g) = panel.gaussian.filter(|g| g.1 > 0.0) {
        let curve = (0..=200).map(|i| {
            let x = lo + (hi - lo) * i as f64 / 200.0;
            (x, gauss(x, g))
        });
        chart.draw_series(LineSeries::new(curve, BLACK.stroke_width(1))).map_err(style::not_drawn)?;
    }
    Ok(())
}

/// Named series of control variables per sequence number `h` (e.g. `s_y`, `s_u`, `s_low`, `s_high`).
#[derive(Clone, Debug)]
pub struct ConvergenceSeries {
    pub sequences: Vec<usize>,
    pub series: Vec<(String, Vec<f64>)>,
    /// The curves are compared with `tolerance`: the adaptive loop stops when `2 s <= delta`,
    /// so the curves drawn are `2 s` and the line is `delta`.
    pub tolerance: f64,
    pub unit: String,
}

/// The convergence history with the tolerance line.
pub fn convergence_svg(title: &str, history: &ConvergenceSeries) -> Result<String, ReportError> {
    let all = history.series.iter().flat_map(|(_, v)| v.iter().map(|s| 2.0 * s)).chain([history.tolerance]);
    if history.sequences.is_empty() || history.series.iter().any(|(_, v)| v.len() != history.sequences.len()) {
        return Err(ReportError::Input("a convergence plot needs one value per sequence in every series".into()));
    }
    let values: Vec<f64> = all.collect();
    if values.iter().any(|v| !v.is_finite() || *v <= 0.0) {
        return Err(ReportError::Input("control variables must be positive finite numbers".into()));
    }
    let (lo, hi) = values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
    let h0 = *history.sequences.first().unwrap_or(&1) as f64;
    let h1 = (*history.sequences.last().unwrap_or(&2) as f64).max(h0 + 1.0);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (style::WIDTH, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(style::not_drawn)?;
        style::title(&root, title, 8)?;
        let (top, root) = root.split_vertically(44 + style::LEGEND_HEIGHT);
        let (_, strip) = top.split_vertically(44);
        let mut entries: Vec<(String, Swatch)> =
            history.series.iter().enumerate().map(|(k, (name, _))| (format!("2 {name}"), Swatch::Line(style::colour(k), 3))).collect();
        entries.push(("tolerance".into(), Swatch::Line(BLACK, 2)));
        style::legend(&strip, &entries)?;
        // a linear axis from zero: the few sequences of an adaptive run span less than a decade
        let _ = lo;
        let mut chart = ChartBuilder::on(&root)
            .margin(12)
            .margin_right(24)
            .x_label_area_size(64)
            .y_label_area_size(100)
            .build_cartesian_2d(h0..h1, 0.0..hi * 1.1)
            .map_err(style::not_drawn)?;
        chart
            .configure_mesh()
            .x_desc("sequence h")
            .x_labels(((h1 - h0) as usize + 1).min(8))
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_labels(5)
            .y_label_formatter(&|v| short(*v))
            .y_desc(format!("2 s ({})", history.unit))
            .label_style(style::font(style::TICK))
            .axis_desc_style(style::font(style::TICK))
            .draw()
            .map_err(style::not_drawn)?;
        for (k, (_, v)) in history.series.iter().enumerate() {
            let colour = style::colour(k);
            chart
                .draw_series(LineSeries::new(history.sequences.iter().zip(v).map(|(h, s)| (*h as f64, 2.0 * s)), colour.stroke_width(3)))
                .map_err(style::not_drawn)?;
        }
        chart
            .draw_series(LineSeries::new([(h0, history.tolerance), (h1, history.tolerance)], BLACK.stroke_width(2)))
            .map_err(style::not_drawn)?;
        root.present().map_err(style::not_drawn)?;
    }
    Ok(svg)
}

/// A tick value with two significant digits (`0.05`, `0.002`, `1.5`, `20`).
fn short(v: f64) -> String {
    if v.abs() < 1e-12 {
        return "0".into();
    }
    if !(v.is_finite() && v > 0.0) {
        return String::new();
    }
    let decimals = (1 - v.log10().floor() as i32).max(0) as usize;
    let text = format!("{v:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_has_one_bar_per_bin_and_refuses_nan() {
        let values: Vec<f64> = (0..1000).map(|i| (i as f64 / 1000.0 * 6.0).sin()).collect();
        let panel = HistogramPanel { title: "EC0Y (urad)".into(), values, interval: (-0.9, 0.9), gaussian: Some((0.0, 0.7)) };
        let svg = histograms_svg("outputs", &[panel.clone(), panel.clone()], 30).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("EC0Y (urad)"));
        assert!(svg.matches("<rect").count() >= 60);
        let mut bad = panel;
        bad.values[3] = f64::NAN;
        assert!(histograms_svg("x", &[bad], 30).is_err());
    }

    #[test]
    fn convergence_plot_draws_each_series() {
        let h = ConvergenceSeries {
            sequences: vec![2, 3, 4],
            series: vec![("s_y".into(), vec![0.1, 0.05, 0.02]), ("s_low".into(), vec![0.2, 0.1, 0.02])],
            tolerance: 0.05,
            unit: "um or urad".into(),
        };
        let svg = convergence_svg("convergence", &h).unwrap();
        assert!(svg.contains("2 s_y") && svg.contains("tolerance"));
    }
}
