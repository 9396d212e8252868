//! Page layout of the PDF: blocks flowed top to bottom onto A4 pages, words wrapped at the text
//! width (a word longer than its box, such as a SHA-256, broken between characters), table columns
//! sized from their contents, rows and figures moved whole to the next page when they do not fit,
//! the header row repeated on a new page.

use super::font::Fonts;
use super::svg;
use crate::html::{Block, Cell, HtmlReport, Mark};
use crate::ReportError;
use krilla::annotation::{Annotation, LinkAnnotation, Target};
use krilla::color::rgb;
use krilla::destination::{Destination, XyzDestination};
use krilla::geom::{PathBuilder, Point, Rect};
use krilla::num::NormalizedF32;
use krilla::outline::{Outline, OutlineNode};
use krilla::page::PageSettings;
use krilla::paint::{Fill, Stroke};
use krilla::surface::Surface;
use krilla::Document;
use std::collections::HashMap;

/// A4 in pt (210 x 297 mm).
pub const PAGE_WIDTH_PT: f32 = 595.276;
pub const PAGE_HEIGHT_PT: f32 = 841.89;
/// Left, right and top margin (18 mm); the footer sits in the bottom margin, its last line's
/// baseline `FOOTER_BASE_PT` above the page's edge, the text at least `FOOTER_GAP_PT` above its first.
pub const MARGIN_PT: f32 = 51.0;
const FOOTER_BASE_PT: f32 = 30.0;
const FOOTER_GAP_PT: f32 = 20.0;
pub const TEXT_WIDTH_PT: f32 = PAGE_WIDTH_PT - 2.0 * MARGIN_PT;
/// Body text, table cells, captions, commands and the footer: 10 pt; headings larger.
pub const BODY_PT: f32 = 10.0;
const LEADING: f32 = 1.3;
const TITLE_PT: f32 = 17.0;
const HEADING_PT: f32 = 13.0;
const CELL_PAD: f32 = 3.0;

const INK: (u8, u8, u8) = (34, 34, 34);
const GREY: (u8, u8, u8) = (90, 90, 90);
const RULE: (u8, u8, u8) = (185, 185, 185);
const HEADER_BG: (u8, u8, u8) = (238, 238, 238);
const CODE_BG: (u8, u8, u8) = (244, 244, 244);
const NOTE_BAR: (u8, u8, u8) = (213, 94, 0);
const NOTE_BG: (u8, u8, u8) = (253, 241, 232);
const LINK: (u8, u8, u8) = (0, 90, 160);

/// What is drawn on a page, in pt from its top-left corner.
pub enum Op {
    Text { x: f32, y: f32, size: f32, bold: bool, colour: (u8, u8, u8), text: String },
    Fill { rect: (f32, f32, f32, f32), colour: (u8, u8, u8) },
    Line { from: (f32, f32), to: (f32, f32), width: f32, colour: (u8, u8, u8) },
    Figure { x: f32, y: f32, scale: f32, svg: usize },
    Link { rect: (f32, f32, f32, f32), section: String },
}

pub struct Pages {
    pub pages: Vec<Vec<Op>>,
    /// The running identification, wrapped beside "page i of n" (`HtmlReport::running_lines`).
    pub footer: Vec<String>,
    /// Section id -> (page, y) of its heading; in order.
    pub anchors: Vec<(String, String, usize, f32)>,
    pub figures: Vec<String>,
}

struct Flow<'a> {
    fonts: &'a Fonts,
    pages: Vec<Vec<Op>>,
    y: f32,
    /// Where the text of a page ends (pt from the top): above the footer.
    bottom: f32,
    anchors: Vec<(String, String, usize, f32)>,
    figures: Vec<String>,
}

impl Flow<'_> {
    fn page(&mut self) -> &mut Vec<Op> {
        self.pages.last_mut().expect("a page")
    }

    fn new_page(&mut self) {
        self.pages.push(Vec::new());
        self.y = MARGIN_PT;
    }

    /// A new page unless `height` fits below the current position.
    fn need(&mut self, height: f32) {
        if self.y + height > self.bottom && self.y > MARGIN_PT + 1.0 {
            self.new_page();
        }
    }

    fn line_height(size: f32) -> f32 {
        size * LEADING
    }

    /// Lines of `text` wrapped at `width` (pt).
    fn wrap(&self, text: &str, size: f32, bold: bool, width: f32) -> Vec<String> {
        let face = self.fonts.face(bold);
        let mut lines = Vec::new();
        for paragraph in text.split('\n') {
            let mut line = String::new();
            for word in paragraph.split_whitespace() {
                let candidate = if line.is_empty() { word.to_string() } else { format!("{line} {word}") };
                if face.width(&candidate, size) <= width {
                    line = candidate;
                    continue;
                }
                if !line.is_empty() {
                    lines.push(std::mem::take(&mut line));
                }
                // a word wider than the box is broken between characters
                let mut piece = String::new();
                for c in word.chars() {
                    piece.push(c);
                    if face.width(&piece, size) > width && piece.chars().count() > 1 {
                        piece.pop();
                        lines.push(std::mem::take(&mut piece));
                        piece.push(c);
                    }
                }
                line = piece;
            }
            lines.push(line);
        }
        lines
    }

    /// A wrapped paragraph at `x` within `width`.
    fn paragraph(&mut self, text: &str, size: f32, bold: bool, colour: (u8, u8, u8), x: f32, width: f32) {
        let h = Self::line_height(size);
        for line in self.wrap(text, size, bold, width) {
            self.need(h);
            let y = self.y + size;
            self.page().push(Op::Text { x, y, size, bold, colour, text: line });
            self.y += h;
        }
    }

    fn heading(&mut self, id: &str, title: &str) {
        // a heading is kept with at least a few lines of what follows
        self.need(HEADING_PT * 2.0 + 60.0);
        if self.y > MARGIN_PT + 1.0 {
            self.y += 12.0;
        }
        let page = self.pages.len() - 1;
        self.anchors.push((id.to_string(), title.to_string(), page, self.y));
        self.paragraph(title, HEADING_PT, true, INK, MARGIN_PT, TEXT_WIDTH_PT);
        let y = self.y + 1.0;
        self.page().push(Op::Line { from: (MARGIN_PT, y), to: (MARGIN_PT + TEXT_WIDTH_PT, y), width: 0.6, colour: RULE });
        self.y += 7.0;
    }

    fn note(&mut self, text: &str) {
        let lines = self.wrap(text, BODY_PT, false, TEXT_WIDTH_PT - 14.0);
        let h = Self::line_height(BODY_PT);
        for (i, line) in lines.iter().enumerate() {
            self.need(h + 4.0);
            let top = self.y - if i == 0 { 3.0 } else { 0.0 };
            let bottom = self.y + h + if i + 1 == lines.len() { 3.0 } else { 0.0 };
            self.page().push(Op::Fill { rect: (MARGIN_PT, top, TEXT_WIDTH_PT, bottom - top), colour: NOTE_BG });
            self.page().push(Op::Fill { rect: (MARGIN_PT, top, 3.0, bottom - top), colour: NOTE_BAR });
            let y = self.y + BODY_PT;
            self.page().push(Op::Text { x: MARGIN_PT + 10.0, y, size: BODY_PT, bold: false, colour: INK, text: line.clone() });
            self.y += h;
        }
        self.y += 8.0;
    }

    fn code(&mut self, text: &str) {
        let h = Self::line_height(BODY_PT);
        for command in text.lines() {
            // continuation lines start 18 pt in; every line keeps 6 pt clear of the box's right edge
            let lines = self.wrap(command, BODY_PT, false, TEXT_WIDTH_PT - 24.0);
            for (i, line) in lines.iter().enumerate() {
                self.need(h);
                let top = self.y;
                self.page().push(Op::Fill { rect: (MARGIN_PT, top, TEXT_WIDTH_PT, h), colour: CODE_BG });
                let indent = if i == 0 { 6.0 } else { 18.0 };
                let y = self.y + BODY_PT;
                self.page().push(Op::Text { x: MARGIN_PT + indent, y, size: BODY_PT, bold: false, colour: INK, text: line.clone() });
                self.y += h;
            }
        }
        self.y += 8.0;
    }

    fn figure(&mut self, caption: &str, svg: &str) -> Result<(), ReportError> {
        let (w, h) = svg::size(svg)?;
        let mut scale = TEXT_WIDTH_PT / w;
        let room = self.bottom - MARGIN_PT - 3.0 * Self::line_height(BODY_PT);
        if h * scale > room {
            scale = room / h;
        }
        self.need(h * scale + 2.0 * Self::line_height(BODY_PT));
        let x = MARGIN_PT + 0.5 * (TEXT_WIDTH_PT - w * scale);
        let y = self.y;
        self.figures.push(svg.to_string());
        let index = self.figures.len() - 1;
        self.page().push(Op::Figure { x, y, scale, svg: index });
        self.y += h * scale + 4.0;
        self.paragraph(caption, BODY_PT, false, GREY, MARGIN_PT, TEXT_WIDTH_PT);
        self.y += 8.0;
        Ok(())
    }

    /// Column widths: each column gets its widest word, and a number with its U and unit whole (a
    /// value never wraps away from its unit); what is left goes to the columns whose text would
    /// wrap, in proportion to what they lack.
    fn columns(&self, header: &[String], rows: &[Vec<Cell>], width: f32) -> Vec<f32> {
        let n = header.len().max(rows.iter().map(Vec::len).max().unwrap_or(0));
        let mut least = vec![0f32; n];
        let mut full = vec![0f32; n];
        let mut measure = |k: usize, text: &str, bold: bool, whole: bool| {
            let face = self.fonts.face(bold);
            let widest = match whole {
                true => face.width(text, BODY_PT),
                false => text.split_whitespace().map(|w| face.width(w, BODY_PT)).fold(0.0, f32::max),
            };
            let cap = if whole { 0.45 * width } else { width / n as f32 };
            least[k] = least[k].max(widest.min(cap) + 2.0 * CELL_PAD);
            full[k] = full[k].max(face.width(text, BODY_PT) + 2.0 * CELL_PAD);
        };
        for (k, h) in header.iter().enumerate() {
            measure(k, h, true, false);
        }
        for row in rows {
            for (k, c) in row.iter().enumerate() {
                measure(k, &c.text, false, c.is_numeric());
            }
        }
        let total: f32 = full.iter().sum();
        if total <= width {
            return full;
        }
        let base: f32 = least.iter().sum();
        let lack: f32 = full.iter().zip(&least).map(|(f, l)| f - l).sum();
        let spare = (width - base).max(0.0);
        let widths: Vec<f32> = least.iter().zip(&full).map(|(l, f)| l + if lack > 0.0 { spare * (f - l) / lack } else { 0.0 }).collect();
        let sum: f32 = widths.iter().sum();
        widths.iter().map(|w| w * width / sum.max(width)).collect()
    }

    /// One row of cells; the row moves to the next page whole (with the header) when it does not fit.
    fn row(&mut self, cells: &[Cell], widths: &[f32], bold: bool, background: Option<(u8, u8, u8)>) -> f32 {
        let h = Self::line_height(BODY_PT);
        let wrapped: Vec<Vec<String>> = widths
            .iter()
            .enumerate()
            .map(|(k, w)| cells.get(k).map_or(Vec::new(), |c| self.wrap(&c.text, BODY_PT, bold, w - 2.0 * CELL_PAD)))
            .collect();
        let height = wrapped.iter().map(Vec::len).max().unwrap_or(1).max(1) as f32 * h + 2.0 * CELL_PAD;
        let top = self.y;
        let mut x = MARGIN_PT;
        for (k, lines) in wrapped.iter().enumerate() {
            let w = widths[k];
            let cell = cells.get(k);
            let fill = cell.and_then(|c| c.mark).map(mark_colour).or(background);
            if let Some(colour) = fill {
                self.page().push(Op::Fill { rect: (x, top, w, height), colour });
            }
            let numeric = !bold && cell.is_some_and(Cell::is_numeric);
            let cell_bold = bold || matches!(cell.and_then(|c| c.mark), Some(Mark::Fail | Mark::Beyond));
            let colour = if cell.is_some_and(|c| c.link.is_some()) { LINK } else { INK };
            for (i, line) in lines.iter().enumerate() {
                let lw = self.fonts.face(cell_bold).width(line, BODY_PT);
                let tx = if numeric { x + w - CELL_PAD - lw } else { x + CELL_PAD };
                let ty = top + CELL_PAD + i as f32 * h + BODY_PT;
                self.page().push(Op::Text { x: tx, y: ty, size: BODY_PT, bold: cell_bold, colour, text: line.clone() });
            }
            if let Some(id) = cell.and_then(|c| c.link.clone()) {
                self.page().push(Op::Link { rect: (x, top, w, height), section: id });
            }
            x += w;
        }
        // grid: the row's bottom line and the cell separators
        let right = MARGIN_PT + widths.iter().sum::<f32>();
        self.page().push(Op::Line { from: (MARGIN_PT, top), to: (right, top), width: 0.5, colour: RULE });
        self.page().push(Op::Line { from: (MARGIN_PT, top + height), to: (right, top + height), width: 0.5, colour: RULE });
        let mut x = MARGIN_PT;
        for w in std::iter::once(0.0).chain(widths.iter().copied()) {
            x += w;
            self.page().push(Op::Line { from: (x, top), to: (x, top + height), width: 0.5, colour: RULE });
        }
        self.y += height;
        height
    }

    fn row_height(&self, cells: &[Cell], widths: &[f32], bold: bool) -> f32 {
        let lines = widths
            .iter()
            .enumerate()
            .map(|(k, w)| cells.get(k).map_or(1, |c| self.wrap(&c.text, BODY_PT, bold, w - 2.0 * CELL_PAD).len()))
            .max()
            .unwrap_or(1);
        lines.max(1) as f32 * Self::line_height(BODY_PT) + 2.0 * CELL_PAD
    }

    fn table(&mut self, caption: &str, header: &[String], rows: &[Vec<Cell>]) {
        let widths = self.columns(header, rows, TEXT_WIDTH_PT);
        let head: Vec<Cell> = header.iter().map(|h| Cell::from(h.as_str())).collect();
        let head_h = if header.is_empty() { 0.0 } else { self.row_height(&head, &widths, true) };
        let first = rows.first().map_or(0.0, |r| self.row_height(r, &widths, false));
        let caption_h = self.wrap(caption, BODY_PT, true, TEXT_WIDTH_PT).len() as f32 * Self::line_height(BODY_PT);
        self.need(caption_h + head_h + first + 4.0);
        if !caption.is_empty() {
            self.paragraph(caption, BODY_PT, true, INK, MARGIN_PT, TEXT_WIDTH_PT);
            self.y += 2.0;
        }
        if !header.is_empty() {
            self.row(&head, &widths, true, Some(HEADER_BG));
        }
        for r in rows {
            let h = self.row_height(r, &widths, false);
            if self.y + h > self.bottom {
                self.new_page();
                if !header.is_empty() {
                    self.row(&head, &widths, true, Some(HEADER_BG));
                }
            }
            self.row(r, &widths, false, None);
        }
        self.y += 10.0;
    }

    fn fields(&mut self, fields: &[(String, String)]) {
        let rows: Vec<Vec<Cell>> = fields.iter().map(|(k, v)| vec![Cell::from(k.as_str()), Cell::from(v.as_str())]).collect();
        let name_w =
            fields.iter().map(|(k, _)| self.fonts.bold.width(k, BODY_PT)).fold(0.0, f32::max).min(0.35 * TEXT_WIDTH_PT) + 2.0 * CELL_PAD;
        let widths = [name_w, TEXT_WIDTH_PT - name_w];
        for r in &rows {
            let h = self.row_height(r, &widths, false);
            self.need(h);
            let top = self.y;
            self.page().push(Op::Fill { rect: (MARGIN_PT, top, name_w, h), colour: HEADER_BG });
            // the name in bold, the value in regular
            let name_lines = self.wrap(&r[0].text, BODY_PT, true, name_w - 2.0 * CELL_PAD);
            let value_lines = self.wrap(&r[1].text, BODY_PT, false, widths[1] - 2.0 * CELL_PAD);
            for (i, l) in name_lines.into_iter().enumerate() {
                let y = top + CELL_PAD + i as f32 * Self::line_height(BODY_PT) + BODY_PT;
                self.page().push(Op::Text { x: MARGIN_PT + CELL_PAD, y, size: BODY_PT, bold: true, colour: INK, text: l });
            }
            for (i, l) in value_lines.into_iter().enumerate() {
                let y = top + CELL_PAD + i as f32 * Self::line_height(BODY_PT) + BODY_PT;
                self.page().push(Op::Text { x: MARGIN_PT + name_w + CELL_PAD, y, size: BODY_PT, bold: false, colour: INK, text: l });
            }
            for y in [top, top + h] {
                self.page().push(Op::Line { from: (MARGIN_PT, y), to: (MARGIN_PT + TEXT_WIDTH_PT, y), width: 0.5, colour: RULE });
            }
            self.y += h;
        }
        self.y += 10.0;
    }
}

fn mark_colour(mark: Mark) -> (u8, u8, u8) {
    // light tints of the Okabe-Ito bluish green, vermillion and yellow: the words carry the meaning
    match mark {
        Mark::Pass => (214, 238, 226),
        Mark::Fail | Mark::Beyond => (249, 214, 200),
        Mark::Undecided => (252, 240, 196),
    }
}

/// The widest page label a report has ("page 999 of 999"), pt.
fn page_label_width(fonts: &Fonts) -> f32 {
    fonts.regular.width("page 999 of 999", BODY_PT)
}

/// The report laid out on pages.
pub fn lay_out(report: &HtmlReport, fonts: &Fonts) -> Result<Pages, ReportError> {
    let mut flow = Flow { fonts, pages: vec![Vec::new()], y: MARGIN_PT, bottom: PAGE_HEIGHT_PT, anchors: Vec::new(), figures: Vec::new() };
    // the running lines wrap beside the page label; the text ends above them
    let room = TEXT_WIDTH_PT - page_label_width(fonts) - 12.0;
    let footer: Vec<String> = report.running_lines().iter().flat_map(|l| flow.wrap(l, BODY_PT, false, room)).collect();
    flow.bottom = footer_top(footer.len()) - FOOTER_GAP_PT;
    flow.paragraph(&report.title, TITLE_PT, true, INK, MARGIN_PT, TEXT_WIDTH_PT);
    flow.y += 2.0;
    flow.paragraph(&report.subtitle, BODY_PT, false, GREY, MARGIN_PT, TEXT_WIDTH_PT);
    flow.y += 6.0;
    for s in &report.sections {
        flow.heading(&s.id, &s.title);
        for b in &s.blocks {
            match b {
                Block::Paragraph(t) => {
                    flow.paragraph(t, BODY_PT, false, INK, MARGIN_PT, TEXT_WIDTH_PT);
                    flow.y += 5.0;
                }
                Block::Note(t) => flow.note(t),
                Block::Code(t) => flow.code(t),
                Block::Table { caption, header, rows } => flow.table(caption, header, rows),
                Block::Fields(f) => flow.fields(f),
                Block::Figure { caption, svg } => flow.figure(caption, svg)?,
            }
        }
    }
    Ok(Pages { pages: flow.pages, footer, anchors: flow.anchors, figures: flow.figures })
}

/// The baseline of the first of `lines` footer lines, pt from the top of the page.
fn footer_top(lines: usize) -> f32 {
    PAGE_HEIGHT_PT - FOOTER_BASE_PT - lines.saturating_sub(1) as f32 * Flow::line_height(BODY_PT)
}

/// The footer of page `index` of `count`: a rule, the running lines at the left, the page label at
/// the right of the first line.
fn footer(surface: &mut Surface, fonts: &Fonts, lines: &[String], index: usize, count: usize) {
    let top = footer_top(lines.len());
    let rule = top - BODY_PT - 4.0;
    let mut b = PathBuilder::new();
    b.move_to(MARGIN_PT, rule);
    b.line_to(MARGIN_PT + TEXT_WIDTH_PT, rule);
    if let Some(path) = b.finish() {
        surface.set_fill(None);
        surface.set_stroke(Some(Stroke { paint: colour(RULE).into(), width: 0.5, ..Stroke::default() }));
        surface.draw_path(&path);
        surface.set_stroke(None);
    }
    for (i, line) in lines.iter().enumerate() {
        text(surface, fonts, MARGIN_PT, top + i as f32 * Flow::line_height(BODY_PT), BODY_PT, false, GREY, line);
    }
    let label = format!("page {} of {count}", index + 1);
    let w = fonts.regular.width(&label, BODY_PT);
    text(surface, fonts, MARGIN_PT + TEXT_WIDTH_PT - w, top, BODY_PT, false, GREY, &label);
}

fn colour(c: (u8, u8, u8)) -> rgb::Color {
    rgb::Color::new(c.0, c.1, c.2)
}

fn fill(c: (u8, u8, u8)) -> Fill {
    Fill { paint: colour(c).into(), opacity: NormalizedF32::ONE, rule: Default::default() }
}

#[allow(clippy::too_many_arguments)] // a position, a size, a face, a colour and the text: one call per drawn line
fn text(surface: &mut Surface, fonts: &Fonts, x: f32, y: f32, size: f32, bold: bool, c: (u8, u8, u8), t: &str) {
    let face = fonts.face(bold);
    surface.set_stroke(None);
    surface.set_fill(Some(fill(c)));
    surface.draw_glyphs(Point::from_xy(x, y), &face.glyphs(t), face.font.clone(), t, size, false);
}

/// The PDF of laid-out pages: page contents, the footer (the running identification and "page i of
/// n"), outline and links.
pub fn render(report: &HtmlReport, fonts: &Fonts, pages: &Pages) -> Result<Vec<u8>, ReportError> {
    let mut document = Document::new();
    let size = PageSettings::from_wh(PAGE_WIDTH_PT, PAGE_HEIGHT_PT).ok_or_else(|| ReportError::Draw("A4 page size".into()))?;
    let anchor: HashMap<&str, (usize, f32)> = pages.anchors.iter().map(|(id, _, p, y)| (id.as_str(), (*p, *y))).collect();
    let count = pages.pages.len();
    for (index, ops) in pages.pages.iter().enumerate() {
        let mut page = document.start_page_with(size.clone());
        let mut links = Vec::new();
        {
            let mut surface = page.surface();
            for op in ops {
                match op {
                    Op::Text { x, y, size, bold, colour, text: t } => text(&mut surface, fonts, *x, *y, *size, *bold, *colour, t),
                    Op::Fill { rect: (x, y, w, h), colour } => {
                        if let Some(path) = Rect::from_xywh(*x, *y, *w, *h).and_then(|r| {
                            let mut b = PathBuilder::new();
                            b.push_rect(r);
                            b.finish()
                        }) {
                            surface.set_stroke(None);
                            surface.set_fill(Some(fill(*colour)));
                            surface.draw_path(&path);
                        }
                    }
                    Op::Line { from, to, width, colour: c } => {
                        let mut b = PathBuilder::new();
                        b.move_to(from.0, from.1);
                        b.line_to(to.0, to.1);
                        if let Some(path) = b.finish() {
                            surface.set_fill(None);
                            surface.set_stroke(Some(Stroke { paint: colour(*c).into(), width: *width, ..Stroke::default() }));
                            surface.draw_path(&path);
                            surface.set_stroke(None);
                        }
                    }
                    Op::Figure { x, y, scale, svg: k } => svg::draw(&mut surface, fonts, &pages.figures[*k], *x, *y, *scale)?,
                    Op::Link { rect, section } => links.push((*rect, section.clone())),
                }
            }
            footer(&mut surface, fonts, &pages.footer, index, count);
            surface.finish();
        }
        for ((x, y, w, h), section) in links {
            if let (Some(&(p, ty)), Some(r)) = (anchor.get(section.as_str()), Rect::from_xywh(x, y, w, h)) {
                let target = Target::Destination(Destination::Xyz(XyzDestination::new(p, Point::from_xy(MARGIN_PT, ty))));
                page.add_annotation(Annotation::new_link(LinkAnnotation::new(r, target), Some(format!("go to {section}"))));
            }
        }
        page.finish();
    }
    let mut outline = Outline::new();
    for (_, title, p, y) in &pages.anchors {
        outline.push_child(OutlineNode::new(title.clone(), XyzDestination::new(*p, Point::from_xy(MARGIN_PT, *y))));
    }
    document.set_outline(outline);
    document.set_metadata(
        krilla::metadata::Metadata::new().title(report.title.clone()).creator(format!("trueaxis {}", env!("CARGO_PKG_VERSION"))),
    );
    document.finish().map_err(|e| ReportError::Draw(format!("cannot write the PDF: {e:?}")))
}
