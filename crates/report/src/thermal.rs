//! Thermal plots (SVG): mode shapes along the structure (Zhu 2008 Fig. 3.3), time constants with
//! their mode weights and the truncation share (Zhu 2008 §3.2.2, eq. 3.11), and a measured thermal
//! drift against the model prediction over time with its residual band (Zhu 2008 Fig. 3.10,
//! Table 4.3), training and validation runs told apart. Plain data in, SVG text out, so that the
//! CLI (`trueaxis thermal ... --plot`) and an HTML report draw the same figures.

use super::style;
use super::ReportError;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Colours of the series, in order (the palette of the other trueaxis plots).
const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 97, 181),
    RGBColor(204, 60, 40),
    RGBColor(40, 150, 70),
    RGBColor(140, 80, 170),
    RGBColor(230, 140, 20),
    RGBColor(90, 90, 90),
];
const TRUNCATED: RGBColor = RGBColor(170, 170, 170);
const BAND: RGBColor = RGBColor(120, 160, 220);
const MEASURED: RGBColor = RGBColor(70, 70, 70);
const WIDTH: u32 = 960;

/// One mode shape sampled along the structure.
#[derive(Clone, Debug)]
pub struct ModeShapeCurve {
    /// E.g. `mode 1, tau 140.98 min`.
    pub label: String,
    /// Values of the C-orthonormal mode at the sample points (any scale: drawn normalised to a
    /// largest magnitude of 1).
    pub values: Vec<f64>,
}

/// Mode shapes at sample points of the structure (nodes along a line, or node numbers).
#[derive(Clone, Debug)]
pub struct ModeShapesPlot {
    pub title: String,
    /// E.g. `x (m), line y = 0.125 m through the heat source`, or `node`.
    pub x_label: String,
    /// Abscissa of each sample point, increasing.
    pub positions: Vec<f64>,
    pub modes: Vec<ModeShapeCurve>,
    /// Vertical markers (position, label), e.g. placed sensors.
    pub markers: Vec<(f64, String)>,
}

/// One mode for the time-constant plot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeBar {
    /// Mode number (1 = longest time constant).
    pub mode: usize,
    pub tau_min: f64,
    /// Weight over the sum of the computed weights (0..1).
    pub share: f64,
    /// Kept by the truncation.
    pub dominant: bool,
}

/// Time constants and weight shares of the computed modes, with the truncation share.
#[derive(Clone, Debug)]
pub struct TimeConstantsPlot {
    pub title: String,
    pub modes: Vec<ModeBar>,
    /// Cumulative share kept by the truncation (e.g. 0.9).
    pub share: f64,
}

/// What a run of a drift plot was used for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunRole {
    Training,
    Validation,
    /// Evaluated with a given model (`thermal predict`).
    Prediction,
}

impl RunRole {
    fn name(self) -> &'static str {
        match self {
            RunRole::Training => "training",
            RunRole::Validation => "validation",
            RunRole::Prediction => "prediction",
        }
    }

    fn colour(self) -> RGBColor {
        match self {
            RunRole::Training => COLOURS[0],
            RunRole::Validation => COLOURS[1],
            RunRole::Prediction => COLOURS[3],
        }
    }
}

/// One run (test, duty cycle) of a drift plot: times (s) and the measured (optional) and
/// predicted values.
#[derive(Clone, Debug)]
pub struct DriftRun {
    pub name: String,
    pub role: RunRole,
    pub times_s: Vec<f64>,
    pub measured: Option<Vec<f64>>,
    pub predicted: Vec<f64>,
}

/// Measured drift against the model prediction, one row of panels per run.
#[derive(Clone, Debug)]
pub struct DriftPlot {
    pub title: String,
    /// Name and unit of the modelled quantity, e.g. `dz (um)`.
    pub quantity: String,
    /// Legend of the model curve, e.g. `predicted` or `eq. 3.17 fit`.
    pub model_label: String,
    pub runs: Vec<DriftRun>,
}

fn finite(values: impl IntoIterator<Item = f64>) -> bool {
    values.into_iter().all(f64::is_finite)
}

/// `(lo, hi)` of the values, widened by 5 % (and to a non-empty range).
fn span(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.into_iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    let pad = 0.05 * (hi - lo).max(1e-9 * (1.0 + hi.abs()));
    (lo - pad, hi + pad)
}

/// The mode shapes, each normalised to a largest magnitude of 1, with the markers.
pub fn mode_shapes_svg(plot: &ModeShapesPlot) -> Result<String, ReportError> {
    svg_document(WIDTH, 480, |root| mode_shapes_chart(root, plot))
}

/// Stems of the weight shares against the time constants (log scale; dominant modes in colour,
/// truncated in grey) and the cumulative share of the modes by decreasing weight with the
/// truncation share.
pub fn time_constants_svg(plot: &TimeConstantsPlot) -> Result<String, ReportError> {
    svg_document(WIDTH, 440, |root| time_constants_chart(root, plot))
}

/// Both modal figures in one document: mode shapes above, time constants and weights below.
pub fn modes_svg(shapes: &ModeShapesPlot, taus: &TimeConstantsPlot) -> Result<String, ReportError> {
    svg_document(WIDTH, 920, |root| {
        let (top, bottom) = root.split_vertically(480);
        mode_shapes_chart(&top, shapes)?;
        time_constants_chart(&bottom, taus)
    })
}

/// Per run: the measured values (points) and the prediction (line) against time, and the residual
/// `measured - predicted` with its band `[min, max]` shaded; panel titles name the run and its role.
pub fn drift_svg(plot: &DriftPlot) -> Result<String, ReportError> {
    if plot.runs.is_empty() {
        return Err(ReportError::Input("a drift plot needs at least one run".into()));
    }
    for run in &plot.runs {
        let measured_ok = run.measured.as_ref().is_none_or(|m| m.len() == run.times_s.len() && finite(m.iter().copied()));
        if run.times_s.is_empty()
            || run.predicted.len() != run.times_s.len()
            || !measured_ok
            || !finite(run.times_s.iter().chain(&run.predicted).copied())
        {
            return Err(ReportError::Input(format!("run `{}` needs finite times and values, one per time", run.name)));
        }
    }
    const ROW: u32 = 280;
    svg_document(WIDTH, 50 + ROW * plot.runs.len() as u32, |root| {
        let root = root.titled(&plot.title, ("sans-serif", 20)).map_err(style::not_drawn)?;
        for (row, run) in root.split_evenly((plot.runs.len(), 1)).iter().zip(&plot.runs) {
            match &run.measured {
                Some(measured) => {
                    let (left, right) = row.split_horizontally(WIDTH * 3 / 5);
                    drift_chart(&left, run, Some(measured), plot)?;
                    residual_chart(&right, run, measured, &plot.quantity)?;
                }
                None => drift_chart(row, run, None, plot)?,
            }
        }
        Ok(())
    })
}

fn svg_document(
    width: u32,
    height: u32,
    body: impl FnOnce(&DrawingArea<SVGBackend, Shift>) -> Result<(), ReportError>,
) -> Result<String, ReportError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(style::not_drawn)?;
        body(&root)?;
        root.present().map_err(style::not_drawn)?;
    }
    Ok(svg)
}

fn mode_shapes_chart(area: &DrawingArea<SVGBackend, Shift>, plot: &ModeShapesPlot) -> Result<(), ReportError> {
    let n = plot.positions.len();
    if n < 2 || plot.modes.is_empty() || plot.modes.iter().any(|m| m.values.len() != n) {
        return Err(ReportError::Input("a mode-shape plot needs at least two points and one value per point in every mode".into()));
    }
    if !finite(plot.positions.iter().chain(plot.modes.iter().flat_map(|m| &m.values)).chain(plot.markers.iter().map(|m| &m.0)).copied()) {
        return Err(ReportError::Input("mode shapes must be finite".into()));
    }
    let (x0, x1) = (plot.positions[0], plot.positions[n - 1]);
    if x1 <= x0 {
        return Err(ReportError::Input("the sample positions of a mode-shape plot must increase".into()));
    }
    let mut chart = ChartBuilder::on(area)
        .caption(&plot.title, ("sans-serif", 18))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, -1.1..1.1)
        .map_err(style::not_drawn)?;
    chart
        .configure_mesh()
        .x_desc(plot.x_label.as_str())
        .y_desc("mode shape / largest |value|")
        .y_label_formatter(&|v: &f64| format!("{:.1}", if v.abs() < 1e-9 { 0.0 } else { *v }))
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(style::not_drawn)?;
    chart.draw_series(LineSeries::new([(x0, 0.0), (x1, 0.0)], BLACK.stroke_width(1))).map_err(style::not_drawn)?;
    for (position, label) in &plot.markers {
        chart.draw_series(LineSeries::new([(*position, -1.1), (*position, 1.1)], MEASURED.stroke_width(1))).map_err(style::not_drawn)?;
        chart
            .draw_series([Text::new(label.clone(), (*position, 1.05), ("sans-serif", 12).into_font().color(&MEASURED))])
            .map_err(style::not_drawn)?;
    }
    // earlier modes drawn wider, so that curves that coincide on this line (modes varying across
    // it) stay visible
    for (k, mode) in plot.modes.iter().enumerate() {
        let largest = mode.values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let scale = if largest > 0.0 { 1.0 / largest } else { 0.0 };
        let colour = COLOURS[k % COLOURS.len()];
        let width = (1 + plot.modes.len() - k) as u32;
        chart
            .draw_series(LineSeries::new(plot.positions.iter().zip(&mode.values).map(|(x, v)| (*x, v * scale)), colour.stroke_width(width)))
            .map_err(style::not_drawn)?
            .label(mode.label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(width)));
    }
    chart.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw().map_err(style::not_drawn)
}

fn time_constants_chart(area: &DrawingArea<SVGBackend, Shift>, plot: &TimeConstantsPlot) -> Result<(), ReportError> {
    if plot.modes.is_empty()
        || !finite(plot.modes.iter().flat_map(|m| [m.tau_min, m.share]).chain([plot.share]))
        || plot.modes.iter().any(|m| m.tau_min <= 0.0 || m.share < 0.0)
    {
        return Err(ReportError::Input("a time-constant plot needs modes with positive finite time constants and shares".into()));
    }
    let area = area.titled(&plot.title, ("sans-serif", 18)).map_err(style::not_drawn)?;
    let (left, right) = area.split_horizontally(WIDTH * 3 / 5);
    // stems: share against tau
    let (lo, hi) = plot.modes.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), m| (a.min(m.tau_min), b.max(m.tau_min)));
    let top = plot.modes.iter().fold(0.0f64, |a, m| a.max(m.share)).max(1e-6) * 1.15;
    let mut chart = ChartBuilder::on(&left)
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d((lo / 1.5..hi * 1.5).log_scale(), 0.0..top)
        .map_err(style::not_drawn)?;
    chart
        .configure_mesh()
        .x_desc("time constant tau (min)")
        .x_labels(6)
        .x_label_formatter(&|v: &f64| format!("{}", (v * 100.0).round() / 100.0))
        .y_desc("weight |xi tau| / sum")
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(style::not_drawn)?;
    for (dominant, colour, label) in [
        (true, COLOURS[0], format!("dominant (first {:.0} % of the weight)", 100.0 * plot.share)),
        (false, TRUNCATED, "truncated".to_string()),
    ] {
        let modes: Vec<&ModeBar> = plot.modes.iter().filter(|m| m.dominant == dominant).collect();
        if modes.is_empty() {
            continue;
        }
        chart
            .draw_series(modes.iter().map(|m| PathElement::new(vec![(m.tau_min, 0.0), (m.tau_min, m.share)], colour.stroke_width(3))))
            .map_err(style::not_drawn)?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(3)));
        chart.draw_series(modes.iter().map(|m| Circle::new((m.tau_min, m.share), 3, colour.filled()))).map_err(style::not_drawn)?;
        chart
            .draw_series(
                modes
                    .iter()
                    .filter(|m| m.dominant)
                    .map(|m| Text::new(format!("{}", m.mode), (m.tau_min, m.share + 0.04 * top), ("sans-serif", 11).into_font())),
            )
            .map_err(style::not_drawn)?;
    }
    chart.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw().map_err(style::not_drawn)?;
    // cumulative share by decreasing weight, the truncation share and the number of modes kept
    let mut shares: Vec<f64> = plot.modes.iter().map(|m| m.share).collect();
    shares.sort_by(|a, b| b.total_cmp(a));
    let total: f64 = shares.iter().sum::<f64>().max(f64::MIN_POSITIVE);
    let cumulative: Vec<(f64, f64)> = shares
        .iter()
        .scan(0.0, |acc, s| {
            *acc += s / total;
            Some(*acc)
        })
        .enumerate()
        .map(|(i, c)| ((i + 1) as f64, c))
        .collect();
    let kept = plot.modes.iter().filter(|m| m.dominant).count() as f64;
    let count = plot.modes.len() as f64;
    let mut chart = ChartBuilder::on(&right)
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(50)
        .build_cartesian_2d(0.5..count + 0.5, 0.0..1.05)
        .map_err(style::not_drawn)?;
    chart
        .configure_mesh()
        .x_desc("modes kept (by decreasing weight)")
        .y_desc("cumulative share")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(style::not_drawn)?;
    chart
        .draw_series(LineSeries::new(cumulative.iter().copied(), COLOURS[0].stroke_width(2)))
        .map_err(style::not_drawn)?
        .label("cumulative share")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], COLOURS[0].stroke_width(2)));
    chart.draw_series(cumulative.iter().map(|p| Circle::new(*p, 3, COLOURS[0].filled()))).map_err(style::not_drawn)?;
    chart
        .draw_series(LineSeries::new([(0.5, plot.share), (count + 0.5, plot.share)], COLOURS[1].stroke_width(1)))
        .map_err(style::not_drawn)?
        .label(format!("truncation share {:.0} %: {} modes", 100.0 * plot.share, kept))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], COLOURS[1]));
    chart.draw_series(LineSeries::new([(kept, 0.0), (kept, 1.05)], COLOURS[1].stroke_width(1))).map_err(style::not_drawn)?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(style::not_drawn)
}

fn drift_chart(
    area: &DrawingArea<SVGBackend, Shift>,
    run: &DriftRun,
    measured: Option<&Vec<f64>>,
    plot: &DriftPlot,
) -> Result<(), ReportError> {
    let minutes: Vec<f64> = run.times_s.iter().map(|t| t / 60.0).collect();
    let (x0, x1) = span(minutes.iter().copied());
    let (y0, y1) = span(run.predicted.iter().chain(measured.into_iter().flatten()).copied());
    let colour = run.role.colour();
    let mut chart = ChartBuilder::on(area)
        .caption(format!("{}: {}", run.name, run.role.name()), ("sans-serif", 15))
        .margin(10)
        .x_label_area_size(38)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(style::not_drawn)?;
    chart
        .configure_mesh()
        .x_desc("t (min)")
        .y_desc(plot.quantity.as_str())
        .x_label_formatter(&|v: &f64| format!("{v:.0}"))
        .label_style(("sans-serif", 11))
        .draw()
        .map_err(style::not_drawn)?;
    if let Some(m) = measured {
        chart
            .draw_series(minutes.iter().zip(m).map(|(t, v)| Circle::new((*t, *v), 2, MEASURED.filled())))
            .map_err(style::not_drawn)?
            .label("measured")
            .legend(|(x, y)| Circle::new((x + 9, y), 3, MEASURED.filled()));
    }
    chart
        .draw_series(LineSeries::new(minutes.iter().copied().zip(run.predicted.iter().copied()), colour.stroke_width(2)))
        .map_err(style::not_drawn)?
        .label(match run.role {
            RunRole::Prediction => plot.model_label.clone(),
            role => format!("{} ({})", plot.model_label, role.name()),
        })
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
    chart.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw().map_err(style::not_drawn)
}

fn residual_chart(area: &DrawingArea<SVGBackend, Shift>, run: &DriftRun, measured: &[f64], quantity: &str) -> Result<(), ReportError> {
    let minutes: Vec<f64> = run.times_s.iter().map(|t| t / 60.0).collect();
    let residual: Vec<f64> = measured.iter().zip(&run.predicted).map(|(m, p)| m - p).collect();
    let (lo, hi) = residual.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
    let (x0, x1) = span(minutes.iter().copied());
    let (y0, y1) = span([lo, hi, 0.0]);
    let mut chart = ChartBuilder::on(area)
        .caption(format!("{}: residual band [{lo:.3}, {hi:.3}]", run.name), ("sans-serif", 15))
        .margin(10)
        .x_label_area_size(38)
        .y_label_area_size(55)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(style::not_drawn)?;
    chart
        .configure_mesh()
        .x_desc("t (min)")
        .y_desc(format!("measured - predicted {quantity}"))
        .x_label_formatter(&|v: &f64| format!("{v:.0}"))
        .y_label_formatter(&|v: &f64| format!("{}", if v.abs() < 1e-9 { 0.0 } else { (v * 1e6).round() / 1e6 }))
        .label_style(("sans-serif", 11))
        .draw()
        .map_err(style::not_drawn)?;
    chart.draw_series([Rectangle::new([(x0, lo), (x1, hi)], BAND.mix(0.25).filled())]).map_err(style::not_drawn)?;
    chart.draw_series(LineSeries::new([(x0, 0.0), (x1, 0.0)], BLACK.stroke_width(1))).map_err(style::not_drawn)?;
    let colour = run.role.colour();
    chart
        .draw_series(LineSeries::new(minutes.iter().copied().zip(residual.iter().copied()), colour.stroke_width(1)))
        .map_err(style::not_drawn)?;
    Ok(())
}
