//! Heat maps of a scalar over 2D slices of the work volume (e.g. the volumetric error magnitude on
//! the XY, XZ and YZ mid-planes), side by side with one shared colour scale, as SVG.

use super::style;
use super::ReportError;
use plotters::prelude::*;

/// A regular grid of values over a plane: `values[j * xs.len() + i]` at `(xs[i], ys[j])`.
#[derive(Clone, Debug)]
pub struct MapSlice {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    pub values: Vec<f64>,
}

const BAR_WIDTH: u32 = 120;
const HEIGHT: u32 = 420;

/// Draws the slices side by side with a colour bar labelled `value_label` (e.g. "|d| (um)"), the
/// colours spanning the values.
pub fn heatmap_svg(title: &str, slices: &[MapSlice], value_label: &str) -> Result<String, ReportError> {
    heatmap_svg_scaled(title, slices, value_label, None)
}

/// As [`heatmap_svg`] with the colour scale over `range` (e.g. the same scale before and after
/// compensation, so that a smaller error shows as darker colours, not as the same picture).
pub fn heatmap_svg_scaled(title: &str, slices: &[MapSlice], value_label: &str, range: Option<(f64, f64)>) -> Result<String, ReportError> {
    for s in slices {
        if s.xs.len() < 2 || s.ys.len() < 2 || s.values.len() != s.xs.len() * s.ys.len() {
            return Err(ReportError::Input(format!("slice `{}` needs at least a 2 x 2 grid with one value per node", s.title)));
        }
        if s.values.iter().any(|v| !v.is_finite()) {
            return Err(ReportError::Input(format!("slice `{}` has values that are not finite", s.title)));
        }
    }
    let lo = slices.iter().flat_map(|s| &s.values).copied().fold(f64::INFINITY, f64::min);
    let hi = slices.iter().flat_map(|s| &s.values).copied().fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = range.filter(|(a, b)| a.is_finite() && b.is_finite() && b > a).map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi)));
    let (lo, hi) = if hi - lo > 1e-12 { (lo, hi) } else { (lo - 0.5, hi + 0.5) };
    let mut svg = String::new();
    draw(&mut svg, title, slices, value_label, lo, hi)?;
    Ok(svg)
}

fn draw(svg: &mut String, title: &str, slices: &[MapSlice], value_label: &str, lo: f64, hi: f64) -> Result<(), ReportError> {
    let width = style::WIDTH;
    let root = SVGBackend::with_string(svg, (width, HEIGHT)).into_drawing_area();
    root.fill(&WHITE).map_err(style::not_drawn)?;
    style::title(&root, title, 8)?;
    let (_, root) = root.split_vertically(44);
    let (panels, bar) = root.split_horizontally(width - BAR_WIDTH);
    for (panel, slice) in panels.split_evenly((1, slices.len())).iter().zip(slices) {
        let (x0, x1) = bounds(&slice.xs);
        let (y0, y1) = bounds(&slice.ys);
        let mut chart = ChartBuilder::on(panel)
            .caption(&slice.title, style::font(style::LABEL))
            .margin(8)
            .margin_right(14)
            .x_label_area_size(62)
            .y_label_area_size(78)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(style::not_drawn)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(&slice.x_label)
            .y_desc(&slice.y_label)
            .x_labels(3)
            .y_labels(5)
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0}"))
            .label_style(style::font(style::TICK))
            .axis_desc_style(style::font(style::TICK))
            .draw()
            .map_err(style::not_drawn)?;
        let nx = slice.xs.len();
        chart
            .draw_series(slice.values.iter().enumerate().map(|(k, v)| {
                let (i, j) = (k % nx, k / nx);
                let (xa, xb) = cell(&slice.xs, i);
                let (ya, yb) = cell(&slice.ys, j);
                Rectangle::new([(xa, ya), (xb, yb)], ViridisRGB::get_color_normalized(*v, lo, hi).filled())
            }))
            .map_err(style::not_drawn)?;
    }
    let steps = 50;
    let mut chart = ChartBuilder::on(&bar)
        .caption(value_label, style::font(style::TICK))
        .margin_top(4)
        .margin_bottom(70)
        .margin_right(6)
        .y_label_area_size(66)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(style::not_drawn)?;
    let decimals = if hi - lo >= 20.0 {
        0
    } else if hi - lo >= 2.0 {
        1
    } else {
        2
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(6)
        .y_label_formatter(&|v| format!("{v:.decimals$}"))
        .label_style(style::font(style::TICK))
        .draw()
        .map_err(style::not_drawn)?;
    chart
        .draw_series((0..steps).map(|s| {
            let a = lo + (hi - lo) * s as f64 / steps as f64;
            let b = lo + (hi - lo) * (s + 1) as f64 / steps as f64;
            Rectangle::new([(0.0, a), (1.0, b)], ViridisRGB::get_color_normalized(0.5 * (a + b), lo, hi).filled())
        }))
        .map_err(style::not_drawn)?;
    root.present().map_err(style::not_drawn)?;
    Ok(())
}

fn bounds(v: &[f64]) -> (f64, f64) {
    let (a, b) = (cell(v, 0).0, cell(v, v.len() - 1).1);
    (a.min(b), a.max(b))
}

/// Extent of the cell around node `i`: half-way to each neighbour.
fn cell(v: &[f64], i: usize) -> (f64, f64) {
    let left = if i == 0 { v[0] - 0.5 * (v[1] - v[0]) } else { 0.5 * (v[i - 1] + v[i]) };
    let n = v.len();
    let right = if i + 1 == n { v[n - 1] + 0.5 * (v[n - 1] - v[n - 2]) } else { 0.5 * (v[i] + v[i + 1]) };
    (left, right)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svg_has_one_cell_per_node_and_labels() {
        let slice = MapSlice {
            title: "XY".into(),
            x_label: "X (mm)".into(),
            y_label: "Y (mm)".into(),
            xs: vec![0.0, 1.0, 2.0],
            ys: vec![0.0, 1.0],
            values: vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
        };
        let svg = heatmap_svg("map", &[slice], "|d| (um)").unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(svg.contains("X (mm)") && svg.contains("|d| (um)"));
        // 6 cells + 50 colour-bar steps (+ the background rectangles)
        assert!(svg.matches("<rect").count() >= 56);
    }

    #[test]
    fn non_finite_values_are_refused() {
        let slice = MapSlice {
            title: "t".into(),
            x_label: "".into(),
            y_label: "".into(),
            xs: vec![0.0, 1.0],
            ys: vec![0.0, 1.0],
            values: vec![0.0, f64::NAN, 1.0, 2.0],
        };
        assert!(heatmap_svg("m", &[slice], "v").is_err());
    }
}
