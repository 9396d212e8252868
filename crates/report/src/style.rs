//! The style of every figure, for print: each figure is drawn on a canvas [`WIDTH`] units wide
//! that the PDF and the printed HTML scale to the text width of an A4 page (about 493 pt, 174 mm),
//! so a font of [`TICK`] units prints at 10 pt or more; legends sit in a strip above the plot, off
//! the data; colours are the Okabe-Ito palette, told apart with the common colour-vision
//! deficiencies (B. Wong, "Points of view: Color blindness", Nature Methods 8, 441 (2011)); maps
//! use viridis.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::ReportError;

/// Canvas width of a full-width figure (SVG units).
pub const WIDTH: u32 = 960;
/// Font sizes in SVG units: at the text width of A4 (493 pt / 960 units) 20 units print at 10.3 pt.
pub const TITLE: f64 = 24.0;
pub const LABEL: f64 = 22.0;
pub const TICK: f64 = 20.0;
/// The smallest font any figure uses.
pub const SMALLEST: f64 = TICK;
/// Height of the legend strip.
pub const LEGEND_HEIGHT: u32 = 40;

pub const FAMILY: &str = "Liberation Sans, Arial, Helvetica, sans-serif";

/// Okabe-Ito: blue, vermillion, bluish green, reddish purple, orange, sky blue, black.
pub const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];
pub const GREY: RGBColor = RGBColor(110, 110, 110);
pub const LIGHT: RGBColor = RGBColor(215, 215, 215);

/// The `k`-th series colour.
pub fn colour(k: usize) -> RGBColor {
    PALETTE[k % (PALETTE.len() - 1)]
}

/// A font of `px` SVG units (plotters writes its size divided by 1.24, hence the factor).
pub fn font(px: f64) -> FontDesc<'static> {
    (FAMILY, px * 1.24).into_font()
}

pub fn bold(px: f64) -> FontDesc<'static> {
    (FAMILY, px * 1.24, FontStyle::Bold).into_font()
}

/// The error of a drawing call: plotters' errors are generic over the backend, so their message is
/// kept (a figure that cannot be drawn is a failed computation, [`ReportError::Draw`]).
pub fn not_drawn(e: impl std::fmt::Display) -> ReportError {
    ReportError::Draw(e.to_string())
}

/// How a legend entry shows its series.
#[derive(Clone, Copy, Debug)]
pub enum Swatch {
    Line(RGBColor, u32),
    Dot(RGBColor),
    Band(RGBColor),
}

/// Draws legend entries in a row, centred in `area` (a strip above the plot).
pub fn legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[(String, Swatch)]) -> Result<(), ReportError> {
    let (w, h) = area.dim_in_pixel();
    let y = h as i32 / 2;
    // width estimate: 0.55 em per character (Liberation Sans averages about 0.5 em)
    let widths: Vec<i32> = entries.iter().map(|(t, _)| 44 + (0.55 * TICK * t.chars().count() as f64) as i32 + 28).collect();
    let mut x = (w as i32 - widths.iter().sum::<i32>()).max(0) / 2;
    for ((text, swatch), width) in entries.iter().zip(widths) {
        match *swatch {
            Swatch::Line(c, s) => area.draw(&PathElement::new(vec![(x, y), (x + 36, y)], c.stroke_width(s))),
            Swatch::Dot(c) => area.draw(&Circle::new((x + 18, y), 6, c.filled())),
            Swatch::Band(c) => area.draw(&Rectangle::new([(x, y - 8), (x + 36, y + 8)], c.mix(0.35).filled())),
        }
        .map_err(not_drawn)?;
        area.draw(&Text::new(text.clone(), (x + 44, y), TextStyle::from(font(TICK)).pos(Pos::new(HPos::Left, VPos::Center))))
            .map_err(not_drawn)?;
        x += width;
    }
    Ok(())
}

/// A title centred at the top of `area`.
pub fn title<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, text: &str, y: i32) -> Result<(), ReportError> {
    let (w, _) = area.dim_in_pixel();
    area.draw(&Text::new(text.to_string(), (w as i32 / 2, y), TextStyle::from(bold(TITLE)).pos(Pos::new(HPos::Center, VPos::Top))))
        .map_err(not_drawn)
}

/// A line of text centred at `y` in `area`.
pub fn centred<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, text: &str, y: i32, px: f64) -> Result<(), ReportError> {
    let (w, _) = area.dim_in_pixel();
    area.draw(&Text::new(text.to_string(), (w as i32 / 2, y), TextStyle::from(font(px)).pos(Pos::new(HPos::Center, VPos::Top))))
        .map_err(not_drawn)
}
