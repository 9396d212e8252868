//! The report's document model (sections of paragraphs, notes, tables, figures) and its
//! self-contained HTML form: inline SVG figures, tables and text, no script and no network access,
//! with print styles for A4. The PDF (`crate::pdf`) is made from the same model.

use std::fmt::Write;

/// A conformity decision shown in a table cell (ISO 14253-1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    Pass,
    Fail,
    /// The measured value is beyond the limit, but by less than its expanded uncertainty (or its
    /// uncertainty is unknown): out of tolerance as measured, non-conformity not proven under a
    /// guard band.
    Beyond,
    /// Neither conformity nor non-conformity proven: the value is within the limit but within the
    /// expanded uncertainty of it (or its uncertainty is unknown).
    Undecided,
}

impl Mark {
    /// The word printed in the cell.
    pub fn word(self) -> &'static str {
        match self {
            Mark::Pass => "pass",
            Mark::Fail => "FAIL",
            Mark::Beyond => "fails (within U)",
            Mark::Undecided => "not proven",
        }
    }

    fn class(self) -> &'static str {
        match self {
            Mark::Pass => "pass",
            Mark::Fail | Mark::Beyond => "fail",
            Mark::Undecided => "undecided",
        }
    }
}

/// One table cell: text, an optional link to a section of the report (its id) and an optional
/// conformity mark.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    pub text: String,
    pub link: Option<String>,
    pub mark: Option<Mark>,
}

impl Cell {
    /// A cell that links to the section `id`.
    pub fn link(text: impl Into<String>, id: &str) -> Cell {
        Cell { text: text.into(), link: Some(id.into()), mark: None }
    }

    /// A cell with a conformity decision (its word is the text).
    pub fn mark(mark: Mark) -> Cell {
        Cell { text: mark.word().into(), link: None, mark: Some(mark) }
    }

    /// Right-aligned in tables: a number with or without its unit.
    pub fn is_numeric(&self) -> bool {
        looks_numeric(&self.text)
    }
}

impl From<String> for Cell {
    fn from(text: String) -> Cell {
        Cell { text, link: None, mark: None }
    }
}

impl From<&str> for Cell {
    fn from(text: &str) -> Cell {
        Cell::from(text.to_string())
    }
}

/// One block of a section.
#[derive(Clone, Debug)]
pub enum Block {
    /// A paragraph of plain text (escaped).
    Paragraph(String),
    /// A highlighted remark (e.g. an identifiability warning), plain text.
    Note(String),
    /// A table with a caption, a header row and body rows (plain text cells, escaped).
    Table { caption: String, header: Vec<String>, rows: Vec<Vec<Cell>> },
    /// Named values (a certificate's particulars): name, value.
    Fields(Vec<(String, String)>),
    /// An SVG document (as written by the `report` plots) shown inline, with a caption.
    Figure { caption: String, svg: String },
    /// A preformatted block (e.g. a command line), escaped.
    Code(String),
}

/// A titled section with an anchor for the table of contents.
#[derive(Clone, Debug)]
pub struct Section {
    pub id: String,
    pub title: String,
    pub blocks: Vec<Block>,
}

impl Section {
    pub fn new(id: &str, title: &str) -> Section {
        Section { id: id.into(), title: title.into(), blocks: Vec::new() }
    }

    pub fn paragraph(mut self, text: impl Into<String>) -> Section {
        self.blocks.push(Block::Paragraph(text.into()));
        self
    }

    pub fn note(mut self, text: impl Into<String>) -> Section {
        self.blocks.push(Block::Note(text.into()));
        self
    }

    pub fn table(self, caption: impl Into<String>, header: &[&str], rows: Vec<Vec<String>>) -> Section {
        self.cells(caption, header, rows.into_iter().map(|r| r.into_iter().map(Cell::from).collect()).collect())
    }

    /// A table of cells with links or conformity marks.
    pub fn cells(mut self, caption: impl Into<String>, header: &[&str], rows: Vec<Vec<Cell>>) -> Section {
        self.blocks.push(Block::Table { caption: caption.into(), header: header.iter().map(|h| h.to_string()).collect(), rows });
        self
    }

    pub fn fields(mut self, fields: Vec<(String, String)>) -> Section {
        self.blocks.push(Block::Fields(fields));
        self
    }

    pub fn figure(mut self, caption: impl Into<String>, svg: impl Into<String>) -> Section {
        self.blocks.push(Block::Figure { caption: caption.into(), svg: svg.into() });
        self
    }

    pub fn code(mut self, text: impl Into<String>) -> Section {
        self.blocks.push(Block::Code(text.into()));
        self
    }
}

/// The whole report.
#[derive(Clone, Debug)]
pub struct HtmlReport {
    pub title: String,
    /// One line under the title: machine, date, software version.
    pub subtitle: String,
    pub sections: Vec<Section>,
    /// What every printed page repeats at its foot, above or beside "page i of n": the report's
    /// unique identification (ISO/IEC 17025:2017 7.8.2.1 b: certificate number, customer, item
    /// calibrated), one line each; a specimen says so here. Empty: the title alone.
    pub running: Vec<String>,
}

/// Screen and print (A4) styles. Long words (file names, SHA-256) and command lines wrap instead of
/// overflowing their boxes; figures scale to the text width (their fonts are sized for that width,
/// `crate::style`).
const STYLE: &str =
    "body{font-family:'Liberation Sans',Arial,Helvetica,sans-serif;font-size:16px;max-width:60em;margin:2em auto;padding:0 1em;color:#222;line-height:1.4}\
h1{font-size:1.6em;margin-bottom:0.2em}h2{font-size:1.25em;border-bottom:1px solid #bbb;padding-bottom:0.2em;margin-top:2em}\
.subtitle{color:#555}nav ol{columns:2}table{border-collapse:collapse;margin:0.8em 0;font-size:0.9em;max-width:100%}\
caption{text-align:left;font-weight:bold;padding-bottom:0.3em}th,td{border:1px solid #ccc;padding:0.2em 0.6em;overflow-wrap:break-word;vertical-align:top}td.long{word-break:break-all}\
th{background:#f0f0f0}td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}\
td.pass{background:#d9f0e3}td.fail{background:#f9d6c8;font-weight:bold}td.undecided{background:#fdf0c4}\
table.fields th{text-align:left;width:14em}\
figure{margin:1em 0;page-break-inside:avoid;break-inside:avoid}figure svg{display:block;width:100%;height:auto}\
figcaption{font-size:0.9em;color:#444}.note{border-left:4px solid #d55e00;background:#fdf1e8;padding:0.5em 0.8em}\
pre{background:#f6f6f6;padding:0.6em;white-space:pre-wrap;overflow-wrap:anywhere}\
@media print{body{max-width:none;margin:0;padding:0;font-size:10pt}nav{display:none}\
h2{page-break-after:avoid;break-after:avoid}tr{page-break-inside:avoid;break-inside:avoid}}\
.running{color:#555;font-size:0.9em;border:1px solid #bbb;padding:0.3em 0.6em}.running p{margin:0.1em 0}@media print{.running{display:none}}";

impl HtmlReport {
    /// The complete HTML document.
    pub fn to_html(&self) -> String {
        let mut out = String::with_capacity(1 << 16);
        let _ = write!(
            out,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}{}</style>\n</head>\n<body>\n",
            escape(&self.title),
            self.page_style()
        );
        let _ = writeln!(out, "<h1>{}</h1>\n<p class=\"subtitle\">{}</p>", escape(&self.title), escape(&self.subtitle));
        if !self.running.is_empty() {
            out.push_str("<div class=\"running\">");
            for line in &self.running {
                let _ = write!(out, "<p>{}</p>", escape(line));
            }
            out.push_str("</div>\n");
        }
        out.push_str("<nav><ol>\n");
        for s in &self.sections {
            let _ = writeln!(out, "<li><a href=\"#{}\">{}</a></li>", escape(&s.id), escape(&s.title));
        }
        out.push_str("</ol></nav>\n");
        for s in &self.sections {
            let _ = writeln!(out, "<section id=\"{}\">\n<h2>{}</h2>", escape(&s.id), escape(&s.title));
            for b in &s.blocks {
                write_block(&mut out, b);
            }
            out.push_str("</section>\n");
        }
        out.push_str("</body>\n</html>\n");
        out
    }
}

impl HtmlReport {
    /// The lines every page repeats: the running identification, else the title.
    pub fn running_lines(&self) -> Vec<String> {
        if self.running.is_empty() {
            vec![self.title.clone()]
        } else {
            self.running.clone()
        }
    }

    /// The A4 page with the running identification at its foot and "page i of n" beside it (CSS
    /// Paged Media margin boxes, which Chromium prints), so that a printed page carries them all.
    fn page_style(&self) -> String {
        let running = self.running_lines();
        let lines: Vec<String> = running.iter().map(|l| css_string(l)).collect();
        // the margin box holds about 70 characters of 10 pt a line over 80 % of the text width;
        // 4.6 mm a line, and room above and below
        let wrapped: usize = running.iter().map(|l| l.chars().count().div_ceil(70).max(1)).sum();
        let bottom_mm = 12 + (46 * wrapped).div_ceil(10);
        format!(
            "@page{{size:A4;margin:18mm 16mm {bottom_mm}mm 16mm;\
@bottom-left{{content:{};white-space:pre-wrap;font-family:'Liberation Sans',Arial,sans-serif;font-size:10pt;color:#555;vertical-align:top;padding-top:3mm;width:80%}}\
@bottom-right{{content:\"page \" counter(page) \" of \" counter(pages);font-family:'Liberation Sans',Arial,sans-serif;font-size:10pt;color:#555;vertical-align:top;padding-top:3mm}}}}",
            lines.join(" \"\\A \" ")
        )
    }
}

/// A CSS string literal of `text`: quotes and backslashes escaped, line breaks as `\A`, and `<` as
/// `\3C` so that no `</style>` can end the style sheet early.
fn css_string(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\A "),
            '<' => out.push_str("\\3C "),
            _ => out.push(c),
        }
    }
    out.push('"');
    out
}

fn write_block(out: &mut String, block: &Block) {
    match block {
        Block::Paragraph(t) => {
            let _ = writeln!(out, "<p>{}</p>", escape(t));
        }
        Block::Note(t) => {
            let _ = writeln!(out, "<p class=\"note\">{}</p>", escape(t));
        }
        Block::Code(t) => {
            let _ = writeln!(out, "<pre>{}</pre>", escape(t));
        }
        Block::Table { caption, header, rows } => {
            let _ = write!(out, "<table>\n<caption>{}</caption>\n<thead><tr>", escape(caption));
            for h in header {
                let _ = write!(out, "<th>{}</th>", escape(h));
            }
            out.push_str("</tr></thead>\n<tbody>\n");
            for row in rows {
                out.push_str("<tr>");
                for cell in row {
                    // a token too long for a column (a SHA-256, a path) breaks between any characters
                    let long = cell.text.split_whitespace().any(|w| w.chars().count() > 28);
                    let class = match (cell.mark, cell.is_numeric(), long) {
                        (Some(m), _, _) => format!(" class=\"{}\"", m.class()),
                        (None, true, _) => " class=\"num\"".into(),
                        (None, false, true) => " class=\"long\"".into(),
                        (None, false, false) => String::new(),
                    };
                    match &cell.link {
                        Some(id) => {
                            let _ = write!(out, "<td{class}><a href=\"#{}\">{}</a></td>", escape(id), escape(&cell.text));
                        }
                        None => {
                            let _ = write!(out, "<td{class}>{}</td>", escape(&cell.text));
                        }
                    }
                }
                out.push_str("</tr>\n");
            }
            out.push_str("</tbody>\n</table>\n");
        }
        Block::Fields(fields) => {
            out.push_str("<table class=\"fields\">\n<tbody>\n");
            for (name, value) in fields {
                let _ = writeln!(out, "<tr><th>{}</th><td>{}</td></tr>", escape(name), escape(value));
            }
            out.push_str("</tbody>\n</table>\n");
        }
        Block::Figure { caption, svg } => {
            let _ = writeln!(out, "<figure>\n{}\n<figcaption>{}</figcaption>\n</figure>", inline_svg(svg), escape(caption));
        }
    }
}

/// An SVG document made fit for inline use: the XML declaration and doctype removed, and a
/// `viewBox` added from `width`/`height` when missing so that the figure scales with the page.
pub fn inline_svg(svg: &str) -> String {
    let start = svg.find("<svg").unwrap_or(0);
    let body = svg[start..].trim_end();
    let Some(tag_end) = body.find('>') else { return body.to_string() };
    let tag = &body[..tag_end];
    if tag.contains("viewBox") {
        return body.to_string();
    }
    let attribute = |name: &str| -> Option<f64> {
        let key = format!(" {name}=\"");
        let i = tag.find(&key)? + key.len();
        let j = tag[i..].find('"')? + i;
        tag[i..j].trim_end_matches("px").parse().ok()
    };
    match (attribute("width"), attribute("height")) {
        (Some(w), Some(h)) => format!("{tag} viewBox=\"0 0 {w} {h}\"{}", &body[tag_end..]),
        _ => body.to_string(),
    }
}

/// HTML text escaping of `& < > "`.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

/// A number, possibly with `± U` and a unit after it (`-7.4 ± 2.4 urad`, `12 um`).
fn looks_numeric(cell: &str) -> bool {
    let first = cell.split_whitespace().next().unwrap_or("");
    let t = first.trim_start_matches(['+', '-', '\u{2212}', '\u{2264}']);
    !t.is_empty() && t.chars().next().is_some_and(|c| c.is_ascii_digit()) && t.parse::<f64>().is_ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_is_escaped_and_svg_inlined_with_a_view_box() {
        let svg = "<?xml version=\"1.0\"?>\n<svg width=\"400\" height=\"300\" xmlns=\"http://www.w3.org/2000/svg\"><rect/></svg>\n";
        let r = HtmlReport {
            title: "A <b> & C".into(),
            subtitle: "s".into(),
            sections: vec![Section::new("one", "One")
                .paragraph("x < y")
                .table("t", &["a", "b"], vec![vec!["1.5".into(), "EX0C".into()]])
                .figure("f", svg)],
            running: vec!["Certificate \"X-1\" <b>".into(), "Customer: C".into()],
        };
        let html = r.to_html();
        assert!(html.contains("<title>A &lt;b&gt; &amp; C</title>"));
        assert!(html.contains("<p>x &lt; y</p>"));
        assert!(html.contains("<td class=\"num\">1.5</td><td>EX0C</td>"));
        assert!(
            html.contains("<svg width=\"400\" height=\"300\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 400 300\"><rect/></svg>")
        );
        assert!(!html.contains("<?xml"));
        assert!(html.contains("<a href=\"#one\">One</a>"));
        // every printed page repeats the identification and its number, quoted for CSS
        assert!(html.contains("@bottom-left{content:\"Certificate \\\"X-1\\\" \\3C b>\" \"\\A \" \"Customer: C\""), "{html}");
        assert!(html.contains("counter(page) \" of \" counter(pages)"));
        assert!(html.contains("<div class=\"running\"><p>Certificate &quot;X-1&quot; &lt;b&gt;</p><p>Customer: C</p></div>"));
    }
}
