//! The frame the report's line figures share, in the print style of [`super::style`]: a white
//! page of the report's width, the title, the legend in a strip under it, and a chart over the
//! given x and y ranges with labelled axes (6 ticks each at the tick size) and a light grey mesh;
//! the figure draws its series into that chart.

use super::style::{self, Swatch};
use super::ReportError;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::ops::Range;

/// The chart a figure draws into: x and y in the data's units.
pub type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// What frames a figure: its height in pixels, the title, the legend and the axes.
pub struct Frame<'a> {
    pub height: u32,
    pub title: &'a str,
    pub legend: &'a [(String, Swatch)],
    pub x: Range<f64>,
    pub y: Range<f64>,
    pub x_label: &'a str,
    pub y_label: &'a str,
}

/// The SVG of `frame` with what `draw` puts into its chart.
pub fn framed_svg(frame: &Frame, draw: impl FnOnce(&mut Chart) -> Result<(), ReportError>) -> Result<String, ReportError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (style::WIDTH, frame.height)).into_drawing_area();
        root.fill(&WHITE).map_err(style::not_drawn)?;
        style::title(&root, frame.title, 8)?;
        let (top, root) = root.split_vertically(44 + style::LEGEND_HEIGHT);
        let (_, strip) = top.split_vertically(44);
        style::legend(&strip, frame.legend)?;
        let mut chart = ChartBuilder::on(&root)
            .margin(12)
            .margin_right(30)
            .x_label_area_size(64)
            .y_label_area_size(90)
            .build_cartesian_2d(frame.x.clone(), frame.y.clone())
            .map_err(style::not_drawn)?;
        chart
            .configure_mesh()
            .x_desc(frame.x_label)
            .y_desc(frame.y_label)
            .x_labels(6)
            .y_labels(6)
            .label_style(style::font(style::TICK))
            .axis_desc_style(style::font(style::TICK))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(style::not_drawn)?;
        draw(&mut chart)?;
        root.present().map_err(style::not_drawn)?;
    }
    Ok(svg)
}
