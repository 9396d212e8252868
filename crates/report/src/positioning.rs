//! Plot of a bidirectional positioning test (ISO 230-2): every reading against its target, the
//! mean lines of both directions and their bands `mean ± 2s`, as SVG.

use super::style::{self, Swatch, WIDTH};
use super::ReportError;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use trueaxis::evaluate::iso230_2::{Direction, Iso2302Result, PositioningData};

/// Statistics of one target position for the plot (target in mm, the rest in the deviation unit).
#[derive(Clone, Copy, Debug)]
pub struct PositionBand {
    pub target: f64,
    pub mean_plus: f64,
    pub mean_minus: f64,
    pub s_plus: f64,
    pub s_minus: f64,
}

/// What to draw: readings `(target, deviation)` of the `+` and `-` runs and the per-target statistics.
pub struct PositioningPlot<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub plus: &'a [(f64, f64)],
    pub minus: &'a [(f64, f64)],
    pub positions: &'a [PositionBand],
    /// A line under the title, e.g. the axis results (may be empty).
    pub subtitle: &'a str,
}

const HEIGHT: u32 = 640;

/// Draws the readings (`+` runs as blue circles, `-` runs as vermillion triangles; Okabe-Ito
/// colours, fonts and legend strip of [`super::style`], printable at 10 pt), the mean lines
/// `x̄↑` and `x̄↓` and the bands `x̄ ± 2s` of each direction (shaded, with edge lines).
/// Refuses non-finite values rather than writing NaN.
pub fn positioning_svg(plot: &PositioningPlot) -> Result<String, ReportError> {
    let finite_points = plot.plus.iter().chain(plot.minus).all(|(x, y)| x.is_finite() && y.is_finite());
    let finite_bands =
        plot.positions.iter().all(|p| [p.target, p.mean_plus, p.mean_minus, p.s_plus, p.s_minus].iter().all(|v| v.is_finite()));
    if !finite_points || !finite_bands || plot.positions.is_empty() {
        return Err(ReportError::Input("a positioning plot needs at least one target position and finite values".into()));
    }
    let mut positions = plot.positions.to_vec();
    positions.sort_by(|a, b| a.target.total_cmp(&b.target));

    let xs = plot.plus.iter().chain(plot.minus).map(|p| p.0).chain(positions.iter().map(|p| p.target));
    let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    let ys = plot.plus.iter().chain(plot.minus).map(|p| p.1).chain(positions.iter().flat_map(|p| {
        [p.mean_plus - 2.0 * p.s_plus, p.mean_plus + 2.0 * p.s_plus, p.mean_minus - 2.0 * p.s_minus, p.mean_minus + 2.0 * p.s_minus]
    }));
    let (y0, y1) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| (a.min(y), b.max(y)));
    let xpad = 0.03 * (x1 - x0).max(1.0);
    let ypad = 0.08 * (y1 - y0).max(1e-3);
    // the legend sits in a strip above the plot, off the data
    let (x0, x1, y0, y1) = (x0 - xpad, x1 + xpad, y0 - ypad, y1 + ypad);

    let mut svg = String::new();
    draw(&mut svg, plot, &positions, (x0, x1, y0, y1))?;
    Ok(svg)
}

fn draw(
    svg: &mut String,
    plot: &PositioningPlot,
    positions: &[PositionBand],
    (x0, x1, y0, y1): (f64, f64, f64, f64),
) -> Result<(), ReportError> {
    let root = SVGBackend::with_string(svg, (WIDTH, HEIGHT)).into_drawing_area();
    root.fill(&WHITE).map_err(style::not_drawn)?;
    let head_height = if plot.subtitle.is_empty() { 44 } else { 74 };
    let (head, rest) = root.split_vertically(head_height);
    let (strip, body) = rest.split_vertically(style::LEGEND_HEIGHT);
    let mid = WIDTH as i32 / 2;
    head.draw(&Text::new(plot.title, (mid, 8), TextStyle::from(style::bold(style::TITLE)).pos(Pos::new(HPos::Center, VPos::Top))))
        .map_err(style::not_drawn)?;
    if !plot.subtitle.is_empty() {
        head.draw(&Text::new(plot.subtitle, (mid, 42), TextStyle::from(style::font(style::TICK)).pos(Pos::new(HPos::Center, VPos::Top))))
            .map_err(style::not_drawn)?;
    }
    let (plus_colour, minus_colour) = (style::colour(0), style::colour(1));
    style::legend(
        &strip,
        &[
            ("+ readings".to_string(), Swatch::Dot(plus_colour)),
            ("- readings".to_string(), Swatch::Dot(minus_colour)),
            ("+ mean ± 2s".to_string(), Swatch::Band(plus_colour)),
            ("- mean ± 2s".to_string(), Swatch::Band(minus_colour)),
        ],
    )?;
    let mut chart = ChartBuilder::on(&body)
        .margin(16)
        .margin_top(6)
        .x_label_area_size(70)
        .y_label_area_size(100)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(style::not_drawn)?;
    chart
        .configure_mesh()
        .x_desc(plot.x_label)
        .y_desc(plot.y_label)
        .x_labels(8)
        .y_labels(8)
        .label_style(style::font(style::TICK))
        .axis_desc_style(style::font(style::LABEL))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(style::LIGHT)
        .draw()
        .map_err(style::not_drawn)?;

    type Pick = fn(&PositionBand) -> (f64, f64);
    let directions: [(RGBColor, Pick); 2] = [(plus_colour, |p| (p.mean_plus, p.s_plus)), (minus_colour, |p| (p.mean_minus, p.s_minus))];
    for (colour, pick) in directions {
        let upper: Vec<(f64, f64)> = positions.iter().map(|p| (p.target, pick(p).0 + 2.0 * pick(p).1)).collect();
        let lower: Vec<(f64, f64)> = positions.iter().map(|p| (p.target, pick(p).0 - 2.0 * pick(p).1)).collect();
        let outline: Vec<(f64, f64)> = upper.iter().copied().chain(lower.iter().rev().copied()).collect();
        chart.draw_series(std::iter::once(Polygon::new(outline, colour.mix(0.15).filled()))).map_err(style::not_drawn)?;
        for edge in [upper, lower] {
            chart.draw_series(DashedLineSeries::new(edge, 6, 4, colour.mix(0.8).stroke_width(2))).map_err(style::not_drawn)?;
        }
        chart
            .draw_series(LineSeries::new(positions.iter().map(|p| (p.target, pick(p).0)), colour.stroke_width(3)))
            .map_err(style::not_drawn)?;
    }
    chart.draw_series(plot.plus.iter().map(|p| Circle::new(*p, 4, plus_colour.filled()))).map_err(style::not_drawn)?;
    chart.draw_series(plot.minus.iter().map(|p| TriangleMarker::new(*p, 5, minus_colour.filled()))).map_err(style::not_drawn)?;
    root.present().map_err(style::not_drawn)?;
    Ok(())
}

/// A plot of the test (SVG): every reading against its target (`+` and `-` runs with their own
/// markers and colours), the mean lines `x̄_i↑`, `x̄_i↓` and the bands `x̄ ± 2s` of each direction.
/// `title` heads the plot; positions in mm, deviations in um.
pub fn iso230_2_svg(result: &Iso2302Result, data: &PositioningData, title: &str) -> Result<String, ReportError> {
    let points = |d: Direction| data.readings.iter().filter(|r| r.direction == d).map(|r| (r.target, r.dev)).collect::<Vec<_>>();
    let bands: Vec<PositionBand> = result
        .positions
        .iter()
        .map(|q| PositionBand { target: q.target, mean_plus: q.mean_plus, mean_minus: q.mean_minus, s_plus: q.s_plus, s_minus: q.s_minus })
        .collect();
    let (x_label, y_label) =
        (format!("target position ({})", data.position_unit()), format!("positional deviation, actual minus target ({})", data.unit()));
    let u = data.unit();
    positioning_svg(&PositioningPlot {
        title,
        x_label: &x_label,
        y_label: &y_label,
        plus: &points(Direction::Plus),
        minus: &points(Direction::Minus),
        positions: &bands,
        subtitle: &format!(
            "A = {:.3} {u}, R = {:.3} {u}, E = {:.3} {u}, M = {:.3} {u}, B = {:.3} {u}",
            result.a, result.r, result.e, result.m, result.b
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band(target: f64) -> PositionBand {
        PositionBand { target, mean_plus: 1.0, mean_minus: -1.0, s_plus: 0.2, s_minus: 0.3 }
    }

    #[test]
    fn svg_has_labels_and_markers() {
        let positions = [band(0.0), band(100.0)];
        let svg = positioning_svg(&PositioningPlot {
            title: "X axis",
            x_label: "target position (mm)",
            y_label: "deviation (um)",
            plus: &[(0.0, 1.1), (100.0, 0.9)],
            minus: &[(0.0, -1.1), (100.0, -0.8)],
            positions: &positions,
            subtitle: "A = 1 um",
        })
        .unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(svg.contains("target position (mm)") && svg.contains("deviation (um)") && svg.contains("A = 1 um"));
        assert!(svg.matches("<circle").count() >= 2);
        assert!(!svg.contains("NaN"));
    }

    #[test]
    fn non_finite_values_are_refused() {
        let positions = [band(0.0)];
        let plot = PositioningPlot {
            title: "",
            x_label: "",
            y_label: "",
            plus: &[(0.0, f64::NAN)],
            minus: &[],
            positions: &positions,
            subtitle: "",
        };
        assert!(positioning_svg(&plot).is_err());
    }
}
