//! The report as a PDF (A4), from the same document model as the HTML ([`HtmlReport`]): the same
//! sections, paragraphs, notes, tables, figures and commands, laid out on pages with the page
//! number and the report's title in the footer, an outline (bookmarks) of the sections, and links
//! from table cells to the sections they name. Made in Rust with krilla (no browser); text is real
//! text in the embedded Liberation Sans (searchable, copyable); figures stay vector graphics.
//! Every text is at least 10 pt: figures are drawn at the text width, for which their fonts are
//! sized (`crate::style`).

mod font;
mod layout;
mod svg;

pub use layout::{BODY_PT, MARGIN_PT, PAGE_HEIGHT_PT, PAGE_WIDTH_PT, TEXT_WIDTH_PT};

use crate::html::HtmlReport;
use crate::ReportError;

/// The PDF document of `report`.
pub fn report_pdf(report: &HtmlReport) -> Result<Vec<u8>, ReportError> {
    let fonts = font::Fonts::load().ok_or_else(|| ReportError::Draw("the embedded font cannot be read".into()))?;
    let pages = layout::lay_out(report, &fonts)?;
    layout::render(report, &fonts, &pages)
}
