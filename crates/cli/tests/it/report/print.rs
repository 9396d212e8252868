//! The report as a customer sees it (issue 20): the demo report and a report from imported files
//! (a ballbar export with its header, a report.toml) rendered by headless Chromium and, as a PDF,
//! by poppler (`pdftoppm`, `pdftotext`). Checked: no text overflows its box in the browser (the
//! layout boxes read back through the DOM at the width of an A4 page); every word of the PDF inside
//! the page margins, no two words overlapping, none smaller than 10 pt; every `value ± U` rounded
//! by its uncertainty (two significant digits of U, the value to the same place) and equal to the
//! JSON output; conformity decisions on tolerances made to pass, to fail and to be undecided.
//! Chromium and poppler-utils are skipped with a message when missing, unless CI requires them
//! (TRUEAXIS_REQUIRE_BROWSER, TRUEAXIS_REQUIRE_POPPLER).

use crate::support::{arg, failed, json, root, trueaxis_in};
use std::path::Path;
use std::process::Command;

fn tool(name: &str, require: &str) -> Option<String> {
    if Command::new(name).arg("-v").output().is_ok() || Command::new(name).arg("--version").output().is_ok() {
        return Some(name.to_string());
    }
    assert!(std::env::var_os(require).is_none(), "{require} is set but `{name}` was not found");
    eprintln!("skipped: `{name}` is not installed");
    None
}

fn chromium() -> Option<String> {
    let found = ["chromium", "chromium-browser", "google-chrome"].into_iter().find(|b| Command::new(b).arg("--version").output().is_ok());
    if found.is_none() {
        assert!(std::env::var_os("TRUEAXIS_REQUIRE_BROWSER").is_none(), "TRUEAXIS_REQUIRE_BROWSER is set but no chromium was found");
        eprintln!("skipped the browser check: chromium is not installed");
    }
    found.map(String::from)
}

/// Chromium, when it is installed, once no box of `html` overflows in it.
fn browser_without_overflow(html: &Path, scratch: &Path) -> Option<String> {
    let browser = chromium()?;
    let bad = browser_overflow(&browser, html, scratch);
    assert!(bad.is_empty(), "overflowing boxes: {bad:#?}");
    Some(browser)
}

/// The text of `pdf` checked by [`check_pdf`] (its pages rendered below `dir`), when poppler is
/// installed.
fn checked_pdf_text(pdf: &Path, dir: &Path) -> Option<String> {
    tool("pdftotext", "TRUEAXIS_REQUIRE_POPPLER")?;
    let scratch = dir.join("pages");
    std::fs::create_dir(&scratch).unwrap();
    Some(check_pdf(pdf, &scratch))
}

/// The text of the HTML document at `path`.
fn html_text(path: &Path) -> String {
    text_of(&std::fs::read_to_string(path).unwrap())
}

/// Each conformity item of a report's JSON summary with its decision.
fn decisions(summary: &serde_json::Value) -> Vec<(String, String)> {
    summary["conformity"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| (i["item"].as_str().unwrap().to_string(), i["decision"].as_str().unwrap().to_string()))
        .collect()
}

/// `report --machine MACHINE --errors ERRORS INPUTS... [--certificate C] --out HTML [--pdf PDF] --json`
fn report_args<'a>(
    machine: &'a str,
    errors: &'a str,
    inputs: &[&'a str],
    certificate: Option<&'a Path>,
    html: &'a Path,
    pdf: Option<&'a Path>,
) -> Vec<&'a str> {
    let mut args = [&["report", "--machine", machine, "--errors", errors][..], inputs].concat();
    if let Some(c) = certificate {
        args.extend(["--certificate", arg(c)]);
    }
    args.extend(["--out", arg(html)]);
    if let Some(p) = pdf {
        args.extend(["--pdf", arg(p)]);
    }
    args.push("--json");
    args
}

/// The repository's file `p` as an argument.
fn path(p: &str) -> String {
    root().join(p).display().to_string()
}

/// The ballbar report from imported files: the export's header gives the radius, the feed, the
/// serial number, date and operator; report.toml the particulars and tolerances.
fn imported_report(dir: &Path, certificate: &Path, extra: &[&str]) -> serde_json::Value {
    let r = root();
    let html = dir.join("vmc3.html");
    let pdf = dir.join("vmc3.pdf");
    let (machine, errors, export) =
        (r.join("examples/machines/vmc3.toml"), r.join("examples/errors/vmc3.toml"), r.join("examples/ballbar/export_xy.txt"));
    let inputs = ["--ballbar", arg(&export), "--ballbar-radius", "100", "--ballbar-centre", "0,0,-200"];
    let args = report_args(arg(&machine), arg(&errors), &inputs, Some(certificate), &html, Some(&pdf));
    json(&trueaxis_in(dir, &[&args[..], extra].concat()))
}

/// The text of an HTML document without its tags, entities decoded.
fn text_of(html: &str) -> String {
    let mut out = String::new();
    let mut inside = false;
    for c in html.chars() {
        match c {
            '<' => {
                inside = true;
                out.push(' ');
            }
            '>' => inside = false,
            c if !inside => out.push(c),
            _ => {}
        }
    }
    out.replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"").replace("&amp;", "&")
}

/// Every `value ± U unit` in `text`: checked for rounding by U, returned as (value, U, unit).
fn measured_values(text: &str) -> Vec<(f64, f64, String)> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let mut out = Vec::new();
    for i in 1..words.len().saturating_sub(2) {
        if words[i] != "±" {
            continue;
        }
        let (value, u, unit) = (words[i - 1].trim_start_matches(['(', '=']), words[i + 1], words[i + 2]);
        if value.parse::<f64>().is_err() {
            continue; // a header: `value ± U (k = 2)`
        }
        let decimals = |t: &str| t.split_once('.').map_or(0, |(_, d)| d.len());
        let digits = u.chars().filter(char::is_ascii_digit).collect::<String>();
        let significant = digits.trim_start_matches('0');
        assert!(
            significant.len() == 2 || (significant.len() == 3 && significant.ends_with('0') && !u.contains('.')),
            "U `{u}` in `{value} ± {u} {unit}` has not two significant digits"
        );
        assert_eq!(decimals(value), decimals(u), "`{value} ± {u} {unit}`: the value is not rounded to the place of U");
        assert!(
            ["um", "urad", "um/m", "um/m^2", "um/m^3", "urad/m", "urad/m^2", "deg", "mm", "%"]
                .contains(&unit.trim_end_matches([',', '.', ';', ')'])),
            "`{value} ± {u} {unit}`: unit"
        );
        out.push((value.parse().unwrap(), u.parse().unwrap(), unit.trim_end_matches([',', '.', ';', ')']).to_string()));
    }
    out
}

/// No number in `text` needs more than 4 zeros after the point before its first digit, nor has
/// more than 10 significant digits (units chosen per quantity, every number rounded).
fn numbers_are_readable(text: &str, what: &str) {
    for word in text.split_whitespace() {
        let t = word.trim_matches(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-')).trim_start_matches(['-', '+']);
        if t.is_empty() || t.parse::<f64>().is_err() || !t.chars().all(|c| c.is_ascii_digit() || c == '.') {
            continue;
        }
        let digits: String = t.chars().filter(char::is_ascii_digit).collect();
        let significant = digits.trim_start_matches('0').len();
        let zeros = t
            .split_once('.')
            .filter(|(i, _)| i.trim_start_matches('0').is_empty())
            .map_or(0, |(_, f)| f.len() - f.trim_start_matches('0').len());
        assert!(zeros <= 4 || significant == 0, "{what}: `{word}` has {zeros} zeros after the point");
        assert!(significant <= 10, "{what}: `{word}` has {significant} significant digits");
    }
}

/// `value` rounded as the report shows it equals `shown` (within half its last place).
fn rounds_to(value: f64, shown: f64, u: f64) -> bool {
    let d = 1 - u.log10().floor() as i32;
    (value - shown).abs() <= 0.5 * 10f64.powi(-d) + 1e-9
}

/// Reads the layout boxes through the DOM: a copy of the page with a script that lists every text
/// box whose content is wider than the box, and every table, figure or command block that sticks
/// out of the page's text column, at the width of an A4 page (794 CSS px at 96 dpi).
fn browser_overflow(browser: &str, html: &Path, scratch: &Path) -> Vec<String> {
    let page = std::fs::read_to_string(html).unwrap();
    let script = "<script>const bad=[];const col=document.body.getBoundingClientRect();\
for(const el of document.querySelectorAll('td,th,p,pre,figcaption,caption,h1,h2,li')){if(el.scrollWidth>el.clientWidth+1)bad.push(el.tagName+': '+el.textContent.trim().slice(0,80));}\
for(const el of document.querySelectorAll('table,figure,svg,pre,p')){const r=el.getBoundingClientRect();if(r.right>col.right+1||r.left<col.left-1)bad.push('outside the column: '+el.tagName+' '+el.textContent.trim().slice(0,60));}\
document.body.setAttribute('data-overflow',JSON.stringify(bad));document.body.setAttribute('data-checked','yes');</script></body>";
    let checked = scratch.join("checked.html");
    std::fs::write(&checked, page.replace("</body>", script)).unwrap();
    let out = headless(browser, &scratch.join("profile"))
        .arg("--window-size=794,1123")
        .arg("--dump-dom")
        .arg(format!("file://{}", checked.display()))
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&out.stdout);
    assert!(dom.contains("data-checked=\"yes\""), "the check did not run: {}", String::from_utf8_lossy(&out.stderr));
    let start = dom.find("data-overflow=\"").unwrap() + "data-overflow=\"".len();
    let end = dom[start..].find('"').unwrap() + start;
    let list: Vec<String> = serde_json::from_str(&dom[start..end].replace("&quot;", "\"").replace("&amp;", "&")).unwrap();
    list
}

/// Words of a PDF with their boxes (pt), per page, from `pdftotext -bbox-layout`.
type Word = (f64, f64, f64, f64, String, bool);

fn pdf_words(pdf: &Path) -> (Vec<(f64, f64)>, Vec<Vec<Word>>) {
    let out = Command::new("pdftotext").arg("-bbox-layout").arg(pdf).arg("-").output().unwrap();
    assert!(out.status.success(), "pdftotext: {}", String::from_utf8_lossy(&out.stderr));
    let xml = String::from_utf8(out.stdout).unwrap();
    let attr = |tag: &str, name: &str| -> f64 {
        let key = format!("{name}=\"");
        let i = tag.find(&key).unwrap() + key.len();
        tag[i..i + tag[i..].find('"').unwrap()].parse().unwrap()
    };
    let mut sizes = Vec::new();
    let mut pages = Vec::new();
    for page in xml.split("<page ").skip(1) {
        sizes.push((attr(page, "width"), attr(page, "height")));
        let mut words = Vec::new();
        for line in page.split("<line ").skip(1) {
            let mut in_line = Vec::new();
            for w in line.split("<word ").skip(1) {
                let tag = &w[..w.find('>').unwrap()];
                let text = &w[w.find('>').unwrap() + 1..w.find("</word>").unwrap()];
                in_line.push((attr(tag, "xMin"), attr(tag, "yMin"), attr(tag, "xMax"), attr(tag, "yMax"), text.to_string(), false));
            }
            // a rotated line (an axis title): its words stack vertically; its font size is then
            // the width of the box
            let vertical = in_line.len() >= 2 && in_line.windows(2).all(|p| p[1].1 >= p[0].3 - 0.5 || p[0].1 >= p[1].3 - 0.5);
            words.extend(in_line.into_iter().map(|mut w| {
                w.5 = vertical;
                w
            }));
        }
        pages.push(words);
    }
    (sizes, pages)
}

/// Every word inside the margins (18 mm at the sides and top, the footer within the page), no two
/// words of a page overlapping, every word at least 10 pt (poppler's box is 0.94 of the font
/// size for Liberation Sans), and the pages rendered by pdftoppm with ink on each.
fn check_pdf(pdf: &Path, scratch: &Path) -> String {
    let (sizes, pages) = pdf_words(pdf);
    assert!(!pages.is_empty());
    let mut all = String::new();
    for (p, words) in pages.iter().enumerate() {
        let (w, h) = sizes[p];
        for (x0, y0, x1, y1, t, vertical) in words {
            assert!(
                *x0 >= 50.0 && *x1 <= w - 50.0 && *y0 >= 40.0 && *y1 <= h - 20.0,
                "page {}: `{t}` outside the margins at ({x0}, {y0})-({x1}, {y1})",
                p + 1
            );
            let size = if *vertical { x1 - x0 } else { y1 - y0 } / 0.938;
            assert!(size >= 9.9, "page {}: `{t}` is {size:.1} pt", p + 1);
        }
        for (i, a) in words.iter().enumerate() {
            for b in &words[i + 1..] {
                let overlap_x = a.2.min(b.2) - a.0.max(b.0);
                let overlap_y = a.3.min(b.3) - a.1.max(b.1);
                assert!(overlap_x < 0.5 || overlap_y < 0.5, "page {}: `{}` and `{}` overlap", p + 1, a.4, b.4);
            }
        }
        all.push_str(&words.iter().map(|w| w.4.as_str()).collect::<Vec<_>>().join(" "));
        all.push('\n');
    }
    let prefix = scratch.join("page");
    let out = Command::new("pdftoppm").args(["-r", "40", "-png"]).arg(pdf).arg(&prefix).output().unwrap();
    assert!(out.status.success(), "pdftoppm: {}", String::from_utf8_lossy(&out.stderr));
    let mut rendered = 0;
    for entry in std::fs::read_dir(scratch).unwrap() {
        let path = entry.unwrap().path();
        if !path.file_name().unwrap().to_string_lossy().starts_with("page") {
            continue;
        }
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        let step = info.line_size / info.width as usize;
        let ink = buf[..info.buffer_size()].chunks(step).filter(|p| p.iter().take(3).any(|&c| c < 200)).count();
        assert!(ink > 500, "{}: an empty page", path.display());
        rendered += 1;
    }
    assert_eq!(rendered, pages.len(), "one image per page");
    all
}

/// The text of each page of a PDF, its words in reading order.
fn page_texts(pdf: &Path) -> Vec<String> {
    pdf_words(pdf).1.iter().map(|words| words.iter().map(|w| w.4.as_str()).collect::<Vec<_>>().join(" ")).collect()
}

/// Every page carries the identification (ISO/IEC 17025:2017 7.8.2.1 b) and "page i of n" (ibid.:
/// the page's place in the whole and the end recognisable).
fn identification_on_every_page(pages: &[String], identification: &[&str], what: &str) {
    let n = pages.len();
    assert!(n >= 2, "{what}: {n} pages");
    for (i, page) in pages.iter().enumerate() {
        let label = format!("page {} of {n}", i + 1);
        assert!(page.contains(&label), "{what}, page {}: no `{label}` in `{}`", i + 1, &page[page.len().saturating_sub(300)..]);
        for id in identification {
            assert!(page.contains(id), "{what}, page {}: `{id}` missing", i + 1);
        }
    }
}

/// Chromium without a window, sandbox, GPU, first-run page or network chatter, with its own
/// profile directory.
fn headless(browser: &str, profile: &Path) -> Command {
    let mut c = Command::new(browser);
    c.args(["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking"])
        .arg(format!("--user-data-dir={}", profile.display()));
    c
}

/// The HTML printed to PDF by Chromium (A4, its own header and footer off: the page's CSS margin
/// boxes are what prints): every word inside the page, and the text of each page.
fn print_html(browser: &str, html: &Path, scratch: &Path) -> Vec<String> {
    let pdf = scratch.join("printed.pdf");
    let out = headless(browser, &scratch.join("print-profile"))
        .arg("--no-pdf-header-footer")
        .arg(format!("--print-to-pdf={}", pdf.display()))
        .arg(format!("file://{}", html.display()))
        .output()
        .unwrap();
    assert!(pdf.exists(), "chromium printed nothing: {}", String::from_utf8_lossy(&out.stderr));
    let (sizes, pages) = pdf_words(&pdf);
    for (p, words) in pages.iter().enumerate() {
        let (w, h) = sizes[p];
        assert!((w - 595.3).abs() < 1.0 && (h - 841.9).abs() < 1.0, "printed page {} is {w} x {h} pt, not A4", p + 1);
        for (x0, y0, x1, y1, t, _) in words {
            assert!(*x0 >= 0.0 && *x1 <= w && *y0 >= 0.0 && *y1 <= h, "printed page {}: `{t}` outside the page", p + 1);
        }
    }
    page_texts(&pdf)
}

#[test]
fn demo_report_reads_well_in_the_browser_and_as_a_pdf() {
    let dir = tempfile::tempdir().unwrap();
    let summary = json(&trueaxis_in(dir.path(), &["demo", "--out", "demo", "--json"]));
    let demo = dir.path().join("demo");
    let html = std::fs::read_to_string(demo.join("report.html")).unwrap();
    let text = text_of(&html);
    for forbidden in ["seed 0", "eq. ", "Table 1", "(unit)", " unit)"] {
        assert!(!text.contains(forbidden), "the report says `{forbidden}`");
    }
    let values = measured_values(&text);
    assert!(values.len() >= 12 + 3 + 6, "{} values with U", values.len());
    numbers_are_readable(&text, "demo HTML");
    // one U per parameter: the report's, in --json and in identification.json, said how obtained
    let written: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(demo.join("identification.json")).unwrap()).unwrap();
    let parameters = summary["parameters"].as_object().unwrap();
    assert_eq!(parameters.len(), 12);
    for (name, p) in parameters {
        let reported = p["reported"].as_str().unwrap();
        assert!(text.contains(reported), "{name}: `{reported}` of --json not in the report");
        let u = p["expanded_uncertainty"].as_f64().unwrap();
        assert_eq!(written["parameters"][name]["expanded_uncertainty"].as_f64(), Some(u), "{name}: identification.json");
        assert_eq!(p["uncertainty_method"], "Monte Carlo, all sources (JCGM 101)");
        assert!(p.get("std_uncertainty").is_none() && written["parameters"][name].get("std_uncertainty").is_none(), "{name}: a second u");
    }
    // a specimen, identified on every page as one
    let identification = ["SPECIMEN: simulated data, not a calibration certificate", "Certificate SPECIMEN-0001", "Specimen Customer Ltd"];
    if let Some(browser) = browser_without_overflow(&demo.join("report.html"), dir.path()) {
        identification_on_every_page(&print_html(&browser, &demo.join("report.html"), dir.path()), &identification, "demo HTML printed");
    }
    if let Some(pdf_text) = checked_pdf_text(&demo.join("report.pdf"), dir.path()) {
        identification_on_every_page(&page_texts(&demo.join("report.pdf")), &identification, "demo PDF");
        numbers_are_readable(&pdf_text, "demo PDF");
        for (name, p) in parameters {
            assert!(pdf_text.contains(p["reported"].as_str().unwrap()), "{name}: not in the PDF");
        }
        // the PDF has the same results as the HTML
        let in_pdf = measured_values(&pdf_text);
        for v in &values {
            assert!(in_pdf.contains(v), "{v:?} is in the HTML but not in the PDF");
        }
        for section in ["Certificate", "Conformity with the tolerances", "Identified parameters", "Uncertainty budget", "Ballbar tests"] {
            assert!(pdf_text.contains(section), "{section}");
        }
    }
}

#[test]
fn imported_files_give_a_certificate_with_values_rounded_by_u_and_equal_to_the_json() {
    let dir = tempfile::tempdir().unwrap();
    // a ballbar export and a Renishaw laser file (ISO 230-2, with its uncertainty): both sections printed
    let rtl = root().join("examples/data/laser_x.rtl");
    let s = imported_report(
        dir.path(),
        &root().join("examples/report/vmc3.toml"),
        &["--controller", "heidenhain", "--positioning", rtl.to_str().unwrap()],
    );
    let text = html_text(&dir.path().join("vmc3.html"));
    // the particulars: from report.toml and from the export's header (serial, date, operator)
    for expected in [
        "EX-2024-0312",
        "Example Parts Ltd",
        "Renishaw QC20-W",
        "B12345",
        "0001",
        "2024-03-12 10:41",
        "A. Example",
        "1000 mm/min",
        "ISO 230-4",
        "ISO 14253-1",
    ] {
        assert!(text.contains(expected), "`{expected}` not in the report");
    }
    // every value with its U; G, F and the diagnostics equal the JSON, rounded by U
    let values = measured_values(&text);
    let b = &s["ballbar"][0];
    let u = b["reading_expanded_uncertainty_um"].as_f64().unwrap();
    assert_eq!(u, 0.5);
    for key in ["G_um", "F_max_um", "F_min_um"] {
        for v in b[key].as_array().unwrap() {
            let v = v.as_f64().unwrap();
            assert!(
                values.iter().any(|(shown, uu, unit)| unit == "um" && *uu == u && rounds_to(v, *shown, u)),
                "{key} {v} not shown as value ± {u} um"
            );
        }
    }
    for (name, d) in b["diagnostics"].as_object().unwrap() {
        let (v, uu) = (d["value"].as_f64().unwrap(), d["expanded_uncertainty"].as_f64().unwrap());
        assert!(
            values
                .iter()
                .any(|(shown, su, unit)| unit == d["unit"].as_str().unwrap() && rounds_to(v, *shown, uu) && rounds_to(uu, *su, uu)),
            "{name}: {v} ± {uu}"
        );
    }
    // every ISO 230-2 result shown as value ± U (um), equal to the JSON, rounded by U
    let positioning = &s["positioning"][0]["results"];
    for symbol in ["A", "A+", "A-", "R", "R+", "R-", "E", "E+", "E-", "M", "B"] {
        let (v, uu) = (positioning[symbol]["value"].as_f64().unwrap(), positioning[symbol]["expanded_uncertainty"].as_f64().unwrap());
        assert!(
            values.iter().any(|(shown, su, unit)| unit == "um" && rounds_to(v, *shown, uu) && rounds_to(uu, *su, uu)),
            "ISO 230-2 {symbol}: {v} ± {uu} um not shown"
        );
    }
    // the map after compensation: the exact correction at each pose (the corrector's tolerance); what
    // the Heidenhain files leave is the compensation page's: less than half the error before, not
    // zero (the vmc3 errors have Abbe terms tables cannot carry)
    let v = &s["volumetric"];
    let (before, after) = (v["max_before_um"].as_f64().unwrap(), v["max_after_um"].as_f64().unwrap());
    assert!(after < 0.01 && before > 1.0, "before {before}, after {after}");
    let c = &s["controller"];
    assert_eq!(c["format"], "heidenhain");
    let (left, was) = (c["worst_um"].as_f64().unwrap(), c["worst_error_um"].as_f64().unwrap());
    assert!(left > 0.1 && left < was / 2.0, "{c}");
    // ISO/IEC 17025:2017 7.8.2.1 and 7.8.4.1 items of a calibration certificate, each named
    for item in [
        "Certificate number",
        "Calibration laboratory",
        "Customer",
        "Machine",
        "Serial number",
        "Location",
        "Date of the tests",
        "Date of issue",
        "Operator",
        "Approved by",
        "Air temperature",
        "Machine temperature",
        "Decision rule",
        "Measuring instruments and their own calibration",
        "Methods and standards applied",
        "Conformity with the tolerances",
    ] {
        assert!(text.contains(item), "the certificate has no `{item}`");
    }
    // each test's date and conditions from its own file: the laser's day and the ballbar's
    for expected in ["2024-03-11 14:05:00 (laser_x.rtl)", "2024-03-12 10:41 (export_xy.txt)", "Date of issue 2024-03-15"] {
        assert!(text.contains(expected), "`{expected}` not in the report");
    }
    assert_eq!(text.matches("UTC").count(), 1, "one date of issue; the file's writing time once, in the inputs");
    numbers_are_readable(&text, "HTML");
    let identification = ["Certificate EX-2024-0312, issued 2024-03-15", "Example Parts Ltd", "serial number 0001"];
    if let Some(browser) = browser_without_overflow(&dir.path().join("vmc3.html"), dir.path()) {
        identification_on_every_page(&print_html(&browser, &dir.path().join("vmc3.html"), dir.path()), &identification, "HTML printed");
    }
    if let Some(pdf_text) = checked_pdf_text(&dir.path().join("vmc3.pdf"), dir.path()) {
        identification_on_every_page(&page_texts(&dir.path().join("vmc3.pdf")), &identification, "PDF");
        assert!(pdf_text.contains("Calibration certificate: circular test"), "the title, whole");
        assert_eq!(measured_values(&pdf_text), values, "the PDF shows the HTML's values");
    }
}

#[test]
fn conformity_decisions_on_tolerances_made_to_pass_to_fail_and_to_be_undecided() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.toml");
    std::fs::write(&plain, "[[instrument]]\nname = \"ballbar\"\nused_for = \"ballbar\"\nexpanded_uncertainty_um = 0.5\n").unwrap();
    let s = imported_report(dir.path(), &plain, &[]);
    assert!(s["conformity"].as_array().unwrap().is_empty());
    let g: Vec<f64> = s["ballbar"][0]["G_um"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let g_max = g.iter().copied().fold(0.0, f64::max);
    let g_min = g.iter().copied().fold(f64::INFINITY, f64::min);
    let squareness = s["ballbar"][0]["diagnostics"]["squareness"]["value"].as_f64().unwrap().abs();
    let u_sq = s["ballbar"][0]["diagnostics"]["squareness"]["expanded_uncertainty"].as_f64().unwrap();
    // G: a tolerance 2 U above the largest run passes; squareness: a tolerance 2 U below fails
    // under both rules; H (hysteresis): a tolerance inside its U is not proven under the guard band
    // but passes by simple acceptance
    let h = s["ballbar"][0]["H_um"].as_f64().unwrap();
    let case = |rule: &str| {
        let file = dir.path().join(format!("{rule}.toml"));
        std::fs::write(
            &file,
            format!(
                "[[instrument]]\nname = \"ballbar\"\nused_for = \"ballbar\"\nexpanded_uncertainty_um = 0.5\n[decision]\nrule = \"{rule}\"\n[tolerances.ballbar]\nG = {}\nsquareness = {}\nH = {}\n",
                g_max + 1.0,
                squareness - 2.0 * u_sq,
                h + 0.25
            ),
        )
        .unwrap();
        let s = imported_report(dir.path(), &file, &[]);
        (decisions(&s), std::fs::read_to_string(dir.path().join("vmc3.html")).unwrap())
    };
    assert!(g_min > 0.0);
    let (guard, html) = case("guard-band");
    let decided = |list: &[(String, String)], what: &str| -> Vec<String> {
        list.iter().filter(|(i, _)| i.contains(what)).map(|(_, d)| d.clone()).collect()
    };
    assert_eq!(decided(&guard, "circular deviation G"), ["pass", "pass"], "{guard:?}");
    assert_eq!(decided(&guard, "squareness"), ["FAIL"], "{guard:?}");
    assert_eq!(decided(&guard, "hysteresis"), ["not proven"], "{guard:?}");
    assert!(
        html.contains("<td class=\"fail\">FAIL</td>")
            && html.contains("<td class=\"pass\">pass</td>")
            && html.contains("<td class=\"undecided\">not proven</td>")
    );
    assert!(text_of(&html).contains("does NOT conform: 1 of the 4 items"), "the statement");
    let (simple, html) = case("simple");
    assert_eq!(decided(&simple, "hysteresis"), ["pass"], "{simple:?}");
    assert_eq!(decided(&simple, "squareness"), ["FAIL"], "{simple:?}");
    assert!(text_of(&html).contains("Simple acceptance"));
}

/// A five-axis job (issue 36): the rotary-axis ballbar steps of the C600U identify the 8 location
/// errors of its A and C axes, each reported with U in the HTML, the PDF and the JSON alike (the
/// JSON's `reported` text in both documents), a tolerance on one of them decided, and a tolerance
/// on an error nobody identified refused by its name.
#[test]
fn a_five_axis_rotary_ballbar_job_is_reported_with_u_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let steps = ["A1", "A2", "C1", "C2"].map(|s| path(&format!("examples/ballbar/{s}.csv"))).join(",");
    let certificate = dir.path().join("five.toml");
    let html = dir.path().join("five.html");
    let pdf = dir.path().join("five.pdf");
    let (machine, errors) = (path("examples/machines/c600u.toml"), path("examples/ballbar/c600u_piges.toml"));
    let args = report_args(&machine, &errors, &["--rotary-ballbar", &steps], Some(&certificate), &html, Some(&pdf));
    let run = |toml: &str| {
        std::fs::write(&certificate, toml).unwrap();
        trueaxis_in(dir.path(), &args)
    };
    let head = "[certificate]\nnumber = \"FIVE-1\"\ncustomer = \"Five Axis Ltd\"\n[decision]\nrule = \"guard-band\"\n";
    let s = json(&run(&format!("{head}[tolerances.parameters]\nEY0A = 15\n")));
    let identified = s["rotary_ballbar"]["errors"].as_object().unwrap();
    assert_eq!(identified.len(), 8, "{identified:?}");
    let text = html_text(&html);
    assert!(text.contains("Rotary axes: ballbar test (location errors)") && text.contains("Jiang (2014)"));
    // the files were simulated with c600u_piges.toml: each value within 2 U of it, or within 1 um / 5 urad
    let truth: toml::Value = toml::from_str(&std::fs::read_to_string(root().join("examples/ballbar/c600u_piges.toml")).unwrap()).unwrap();
    let pdf_pages = if tool("pdftotext", "TRUEAXIS_REQUIRE_POPPLER").is_some() { Some(page_texts(&pdf)) } else { None };
    for (name, e) in identified {
        let (v, u) = (e["value"].as_f64().unwrap(), e["expanded_uncertainty"].as_f64().unwrap());
        let t = truth["constant"][name.as_str()].as_float().unwrap();
        assert!((v - t).abs() <= (2.0 * u).max(5.0), "{name}: {v} ± {u} vs {t}");
        let reported = e["reported"].as_str().unwrap();
        assert!(reported.contains(" ± "), "{name}: `{reported}`");
        assert!(text.contains(reported), "{name}: `{reported}` not in the HTML");
        if let Some(pages) = &pdf_pages {
            assert!(pages.iter().any(|p| p.contains(reported)), "{name}: `{reported}` not in the PDF");
        }
    }
    // EY0A (35 um as simulated) against 15 um fails; the statement says so
    let items = s["conformity"].as_array().unwrap();
    assert_eq!(items.len(), 1);
    assert_eq!(items[0]["decision"], "FAIL", "{items:?}");
    assert!(text.contains("The machine does NOT conform: the toleranced item fails"), "the statement");
    if let Some(pages) = &pdf_pages {
        identification_on_every_page(pages, &["Certificate FIVE-1", "Five Axis Ltd"], "five-axis PDF");
    }
    // a tolerance on an error this report does not identify is refused by its name, nothing written
    std::fs::remove_file(&html).unwrap();
    let o = run(&format!("{head}[tolerances.parameters]\nEX0A = 15\n"));
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("five.toml") && err.contains("tolerances.parameters.EX0A") && err.contains("EY0A"), "{err}");
    assert!(!html.exists());
}

/// The data-quality part: an ISO 230-2 test with run 4 in mm (examples/data/iso230_2_x.csv
/// damaged) beside the clean ballbar export. The section names the file, the run, the kind and
/// the result without the run, and "no finding" for the export; the JSON carries the same; the
/// HTML does not overflow in Chromium and the PDF (pdftotext) keeps every word on its page.
#[test]
fn the_data_quality_part_names_each_finding_and_each_clean_file() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(root().join("examples/data/iso230_2_x.csv")).unwrap();
    let damaged: String = text
        .lines()
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            match (cells.len(), cells.get(3)) {
                (5, Some(&"4")) => {
                    format!("{},{},{},{},{}\n", cells[0], cells[1].parse::<f64>().unwrap() / 1000.0, cells[2], cells[3], cells[4])
                }
                _ => format!("{l}\n"),
            }
        })
        .collect();
    let path = dir.path().join("run4_mm.csv");
    std::fs::write(&path, damaged).unwrap();
    let s = imported_report(dir.path(), &root().join("examples/report/vmc3.toml"), &["--positioning", path.to_str().unwrap()]);
    let quality = s["data_quality"].as_array().unwrap();
    assert_eq!(quality.len(), 2, "{quality:?}");
    let positioning = quality.iter().find(|f| f["file"].as_str().unwrap().ends_with("run4_mm.csv")).unwrap();
    let export = quality.iter().find(|f| f["file"].as_str().unwrap().ends_with("export_xy.txt")).unwrap();
    assert_eq!(export["findings"].as_array().unwrap().len(), 0);
    let finding = &positioning["findings"][0];
    assert_eq!(finding["kind"], "unit");
    assert!(finding["place"].as_str().unwrap().starts_with("run 4"), "{finding}");
    let consequence = finding["consequence"].as_str().unwrap();
    assert!(consequence.contains("without run 4"), "{consequence}");
    let html = std::fs::read_to_string(dir.path().join("vmc3.html")).unwrap();
    let section = &html[html.find("<section id=\"data-quality\">").expect("the data-quality section")..];
    let section = text_of(&section[..section.find("</section>").unwrap()]);
    for expected in ["Data quality", "run4_mm.csv", "run 4", "unit", "without run 4", "export_xy.txt", "no finding"] {
        assert!(section.contains(expected), "`{expected}` not in the data-quality section: {section}");
    }
    browser_without_overflow(&dir.path().join("vmc3.html"), dir.path());
    if let Some(pdf_text) = checked_pdf_text(&dir.path().join("vmc3.pdf"), dir.path()) {
        for expected in ["Data quality", "no finding", "without run 4"] {
            assert!(pdf_text.contains(expected), "`{expected}` not in the PDF");
        }
    }
}

/// `path` with a deterministic noise of about `sigma_um` added to its `dL` column (the last one),
/// comment lines and the header kept: a test file in the style of the shipped ones.
fn with_noise(path: &Path, out: &Path, sigma_um: f64, seed: u64) {
    let mut state = seed;
    let mut uniform = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let text: String = std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| match l.rsplit_once(',') {
            Some((head, v)) if v.trim().parse::<f64>().is_ok() && !l.starts_with('#') => {
                // the sum of 12 uniforms less 6: a normal deviate to within 1e-3 of its quantiles
                let z = (0..12).map(|_| uniform()).sum::<f64>() - 6.0;
                format!("{head},{:.4}\n", v.trim().parse::<f64>().unwrap() + sigma_um * z)
            }
            _ => format!("{l}\n"),
        })
        .collect();
    std::fs::write(out, text).unwrap();
}

/// The number of `key` in a `ballbar ... --json` document, and its expanded uncertainty from `u_key`.
fn value_and_u(doc: &serde_json::Value, key: &str, u_key: &str) -> (f64, f64) {
    (doc[key].as_f64().unwrap(), 2.0 * doc[u_key].as_f64().unwrap())
}

/// A reported error (its JSON entry) equals `(value, U)` of its command, both rounded to 1e-4:
/// within half that place for the value and one place for U; the reported pair.
fn same_as_command(e: &serde_json::Value, (v, u): (f64, f64), what: &str) -> (f64, f64) {
    let (rv, ru) = (e["value"].as_f64().unwrap(), e["expanded_uncertainty"].as_f64().unwrap());
    assert!((rv - v).abs() <= 0.5e-4 + 1e-9 && (ru - u).abs() <= 1e-4 + 1e-9, "{what}: report {rv} ± {ru}, command {v} ± {u}");
    (rv, ru)
}

/// The other ballbar methods (issue 36): the four-setup method of Jiang (2014) ch. 6 and the
/// two-length rotary-table test of Zhu (2008) in one report, each error with the value and U of
/// `ballbar identify --json` / `ballbar tmbb --json` (U = 2 u; both documents round to 1e-4),
/// printed as `value ± U` in the HTML and the PDF alike, tolerances on them decided, every word on
/// its page and no number unreadable; the two-pivot method (ch. 4) gives `identify`'s numbers too.
#[test]
fn other_ballbar_methods_are_reported_with_the_numbers_of_their_commands() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let machine = path("examples/machines/c600u.toml");
    let simulate = |method: &[&str], prefix: &str| -> Vec<String> {
        ["a1", "a2", "c1", "c2"]
            .iter()
            .map(|s| {
                let out = d.join(format!("{prefix}{s}.csv")).display().to_string();
                let truth = path("examples/ballbar/c600u_piges.toml");
                let args = [
                    &["ballbar", "simulate", "--machine", &machine, "--errors", &truth, "--test", s][..],
                    method,
                    &["--noise", "0.3", "--seed", "7", "--out", &out],
                ]
                .concat();
                assert!(trueaxis_in(d, &args).status.success());
                out
            })
            .collect()
    };
    let identify = |method: &[&str], files: &[String]| -> serde_json::Value {
        let steps = ["--a1", &files[0], "--a2", &files[1], "--c1", &files[2], "--c2", &files[3]];
        json(&trueaxis_in(d, &[&["ballbar", "identify", "--machine", &machine, "--json"][..], method, &steps].concat()))
    };
    let four = ["--method", "four-setup", "--outer-positions", "-200,250", "--inner-positions", "0,78"];
    let files = simulate(&four, "six_");
    let expected = identify(&four, &files);
    // the shipped two-length files are noise free: 0.5 um of noise on each bar gives a U to quote
    let (short, long) = (d.join("short.csv"), d.join("long.csv"));
    with_noise(&root().join("examples/ballbar/tmbb_L1.csv"), &short, 0.5, 1);
    with_noise(&root().join("examples/ballbar/tmbb_L2.csv"), &long, 0.5, 2);
    let table = json(&trueaxis_in(d, &["ballbar", "tmbb", "--short", arg(&short), "--long", arg(&long), "--json"]));
    let certificate = d.join("six.toml");
    std::fs::write(
        &certificate,
        "[certificate]\nnumber = \"SIX-1\"\ncustomer = \"Rotary Table Ltd\"\n[decision]\nrule = \"guard-band\"\n[tolerances.parameters]\nEY0A = 50\nEAC = 20\n",
    )
    .unwrap();
    let (html, pdf) = (d.join("six.html"), d.join("six.pdf"));
    let tmbb_files = format!("{},{}", short.display(), long.display());
    let truth = path("examples/ballbar/c600u_piges.toml");
    let steps = files.join(",");
    let inputs = [
        "--rotary-ballbar",
        &steps,
        "--rotary-method",
        "four-setup",
        "--rotary-outer-positions",
        "-200,250",
        "--rotary-inner-positions",
        "0,78",
        "--tmbb",
        &tmbb_files,
    ];
    let s = json(&trueaxis_in(d, &report_args(&machine, &truth, &inputs, Some(&certificate), &html, Some(&pdf))));
    assert_eq!(s["rotary_ballbar"]["method"], "four-setup");
    let mut reported = Vec::new();
    for (name, e) in s["rotary_ballbar"]["errors"].as_object().unwrap() {
        same_as_command(e, value_and_u(&expected["parameters"][name], "value", "std_uncertainty"), &format!("{name}: identify"));
        reported.push(e["reported"].as_str().unwrap().to_string());
    }
    let l2 = &table["l2"];
    for (name, key, unit_key) in [("EAC", "E_x", "urad"), ("EBC", "E_y", "urad"), ("EZC", "D_z", "value")] {
        let u_key = if unit_key == "urad" { "std_uncertainty_urad" } else { "std_uncertainty" };
        let (v, u) = value_and_u(&l2[key], unit_key, u_key);
        let e = &s["tmbb"]["errors"][name];
        let (rv, ru) = same_as_command(e, (v, u), &format!("{name}: tmbb"));
        // the noise-free truth (examples/ballbar/tmbb_errors.toml) within U
        let truth = [("EAC", 38.45), ("EBC", 35.78), ("EZC", 2.68)].iter().find(|t| t.0 == name).unwrap().1;
        assert!((rv - truth).abs() <= ru, "{name}: {rv} ± {ru} vs {truth}");
        reported.push(e["reported"].as_str().unwrap().to_string());
    }
    // EY0A (35 um) within 50 passes, EAC (38 urad) beyond 20 fails
    let decisions = decisions(&s);
    assert_eq!(decisions.len(), 2, "{decisions:?}");
    assert!(
        decisions.iter().any(|(i, d)| i.ends_with("EY0A") && d == "pass")
            && decisions.iter().any(|(i, d)| i.ends_with("EAC") && d == "FAIL")
    );
    let text = html_text(&html);
    for expected in
        ["four-setup method of Lee and Yang as in Jiang (2014) ch. 6", "Zhu (2008) ch. 5", "Rotary table: two-length ballbar test"]
    {
        assert!(text.contains(expected), "`{expected}` not in the report");
    }
    as_printed(&Printed {
        html: &html,
        pdf: &pdf,
        dir: d,
        text: &text,
        reported: &reported,
        identification: &["Certificate SIX-1", "Rotary Table Ltd"],
        what: "ballbar methods",
    });
    // the two-pivot method (ch. 4): the same numbers as `ballbar identify`
    let two = ["--method", "two-pivot", "--outer-offset", "60"];
    let files = simulate(&two, "four_");
    let expected = identify(&two, &files);
    let steps = files.join(",");
    let inputs = ["--rotary-ballbar", &steps, "--rotary-method", "two-pivot", "--rotary-outer-offset", "60"];
    let args = report_args(&machine, &truth, &inputs, None, &html, None);
    let s = json(&trueaxis_in(d, &args));
    for (name, e) in s["rotary_ballbar"]["errors"].as_object().unwrap() {
        same_as_command(e, value_and_u(&expected["parameters"][name], "value", "std_uncertainty"), &format!("{name}: identify"));
    }
    assert!(html_text(&html).contains("two-pivot method of Jiang (2014) ch. 4"));
    // a method without its setup is refused by name, exit status 2
    let o = trueaxis_in(d, &[&args[..7], &["--rotary-method", "four-setup", "--out", html.to_str().unwrap()]].concat());
    failed(&o, 2, &["--rotary-outer-positions"]);
}

/// The documents of `trueaxis fit ... --json` for `args` (both directions: `plus`, `minus`).
fn fit_json(args: &[&str], dir: &Path) -> serde_json::Value {
    json(&trueaxis_in(dir, &[&["fit", "--json"][..], args].concat()))
}

/// The report's fit (its JSON entry) has the coefficients, U = 2 u and residuals of `trueaxis fit --json`.
fn same_fit(reported: &serde_json::Value, fit: &serde_json::Value) {
    let (a, b) = (reported["terms"].as_array().unwrap(), fit["terms"].as_array().unwrap());
    assert_eq!(a.len(), b.len());
    for (r, f) in a.iter().zip(b) {
        assert_eq!(r["function"], f["function"]);
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * y.abs().max(1e-12);
        assert!(close(r["coefficient"].as_f64().unwrap(), f["coefficient"].as_f64().unwrap()), "{r} {f}");
        assert!(close(r["expanded_uncertainty"].as_f64().unwrap(), 2.0 * f["std_uncertainty"].as_f64().unwrap()), "{r} {f}");
    }
    for key in ["residual_std", "residual_rms", "max_abs_residual"] {
        assert!((reported[key].as_f64().unwrap() - fit[key].as_f64().unwrap()).abs() < 1e-12, "{key}");
    }
}

/// Direct measurements (issue 36): the pitch EBX from a level and the positioning error EXX from a
/// laser (both directions) of examples/report/vmc3_fits.toml, and a straightness EYX written here,
/// reported with the numbers of `trueaxis fit --json`; the range a tolerance is decided on equals
/// its closed forms: a straight line's |b| L with U = 2 u(b) L over the travel L, and a parabola's
/// straightness about its least-squares line c (L/2)^2 on a symmetric travel; every `value ± U`
/// in the HTML and the PDF alike, on its page, readable.
#[test]
fn direct_fits_are_reported_with_the_numbers_of_trueaxis_fit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let machine = path("examples/machines/vmc3.toml");
    // a straightness of X (EYX) in the style of the shipped level and laser files: a bow of
    // 2e-5 um/mm^2 and a slope (the setup's alignment), read every 20 mm with +-0.05 um of noise
    let mut csv = String::from(
        "# Laser straightness optics, X axis of examples/machines/vmc3.toml, Y = 0, Z = -200.\n# target (mm), dev (um).\ntarget,dev\n",
    );
    for (k, x) in (-20..=20).map(|k| (k, f64::from(k) * 20.0)) {
        csv.push_str(&format!("{x},{:.4}\n", 2e-5 * x * x + 0.004 * x + if k % 2 == 0 { 0.05 } else { -0.05 }));
    }
    std::fs::write(d.join("straightness_x.csv"), csv).unwrap();
    let shipped = std::fs::read_to_string(root().join("examples/report/vmc3_fits.toml")).unwrap();
    let certificate = d.join("fits.toml");
    let toml = shipped.replace("../data/", &format!("{}/", path("examples/data"))).replace("EXX = 12", "EXX = 12\nEYX = 2")
        + "\n[[fit]]\ndata = \"straightness_x.csv\"\nparameter = \"EYX\"\nat = \"Z=-200\"\n";
    std::fs::write(&certificate, toml).unwrap();
    let (html, pdf) = (d.join("fits.html"), d.join("fits.pdf"));
    let errors = path("examples/errors/vmc3.toml");
    let args = report_args(&machine, &errors, &[], Some(&certificate), &html, Some(&pdf));
    let s = json(&trueaxis_in(d, &args));
    let fits = s["fits"].as_array().unwrap();
    assert_eq!(fits.len(), 4, "EBX, EXX+, EXX-, EYX");
    let level = path("examples/data/level_x.csv");
    let ebx = fit_json(&["--data", &level, "--parameter", "EBX", "--machine", &machine, "--instrument", "level", "--degree", "1"], d);
    same_fit(&fits[0], &ebx);
    let laser = path("examples/data/laser_x.csv");
    let exx = fit_json(
        &[
            "--data",
            &laser,
            "--parameter",
            "EXX",
            "--machine",
            &machine,
            "--at",
            "Z=-200",
            "--knot-spacing",
            "100",
            "--stepwise",
            "0.9999",
            "--drift",
            "--direction",
            "both",
        ],
        d,
    );
    same_fit(&fits[1], &exx["plus"]);
    same_fit(&fits[2], &exx["minus"]);
    let eyx = fit_json(
        &["--data", d.join("straightness_x.csv").to_str().unwrap(), "--parameter", "EYX", "--machine", &machine, "--at", "Z=-200"],
        d,
    );
    same_fit(&fits[3], &eyx);
    // each fit's readings screened as `fit` screens them, in the data-quality part
    let screened: Vec<&str> = s["data_quality"].as_array().unwrap().iter().map(|f| f["input"].as_str().unwrap()).collect();
    for name in ["EBX", "EXX+", "EXX-", "EYX"] {
        assert!(screened.contains(&format!("direct measurement ({name})").as_str()), "{name}: {screened:?}");
    }
    // the level's straight line over its 800 mm: range |b| L, U = 2 u(b) L
    let b = &ebx["terms"][1];
    let (slope, u_slope) = (b["coefficient"].as_f64().unwrap(), b["std_uncertainty"].as_f64().unwrap());
    let range = &fits[0]["range"];
    assert!((range["value"].as_f64().unwrap() - slope.abs() * 800.0).abs() < 1e-9, "{range}");
    assert!((range["expanded_uncertainty"].as_f64().unwrap() - 2.0 * u_slope * 800.0).abs() < 1e-9, "{range}");
    // the straightness about its least-squares line: c (L/2)^2 = c 400^2, whatever the slope
    let c = eyx["terms"].as_array().unwrap().iter().find(|t| t["function"] == "x^2").unwrap()["coefficient"].as_f64().unwrap();
    let range = &fits[3]["range"];
    assert_eq!(range["about_least_squares_line"], true);
    assert!((range["value"].as_f64().unwrap() - c.abs() * 400.0 * 400.0).abs() < 1e-9, "{range} vs c = {c}");
    assert!((c.abs() - 2e-5).abs() < 1e-6, "the bow comes back: {c}");
    // EBX 16 urad within 25 and EXX 2.1 um within 12 pass; the straightness 3.2 um beyond 2 fails
    let decisions: Vec<String> = s["conformity"].as_array().unwrap().iter().map(|i| i["decision"].as_str().unwrap().to_string()).collect();
    assert_eq!(decisions, ["pass", "pass", "pass", "FAIL"], "{}", s["conformity"]);
    let text = html_text(&html);
    assert!(text.contains("Direct measurements: fitted error motions") && text.contains("Soons (1993)"));
    let reported: Vec<String> = fits
        .iter()
        .flat_map(|f| {
            f["terms"]
                .as_array()
                .unwrap()
                .iter()
                .map(|t| t["reported"].as_str().unwrap().to_string())
                .chain([f["range"]["reported"].as_str().unwrap().to_string()])
        })
        .collect();
    as_printed(&Printed {
        html: &html,
        pdf: &pdf,
        dir: d,
        text: &text,
        reported: &reported,
        identification: &["Certificate EX-2024-0313", "Example Parts Ltd"],
        what: "fits",
    });
    // an option the report gives itself is refused by name, nothing written
    std::fs::remove_file(&html).unwrap();
    std::fs::write(&certificate, "[[fit]]\ndata = \"straightness_x.csv\"\nparameter = \"EYX\"\nplot = \"x.svg\"\n").unwrap();
    let o = trueaxis_in(d, &args);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("fits.toml: [[fit]] 1") && err.contains("`plot`"), "{err}");
    assert!(!html.exists());
}

/// A report as a customer sees it: every reported `value ± U` in the HTML text and in the PDF,
/// readable numbers in both, no overflowing box in Chromium, the PDF's pages inside their margins
/// and identified, the same measured values in HTML and PDF.
struct Printed<'a> {
    html: &'a std::path::Path,
    pdf: &'a std::path::Path,
    dir: &'a std::path::Path,
    text: &'a str,
    reported: &'a [String],
    identification: &'a [&'a str],
    what: &'a str,
}

fn as_printed(p: &Printed) {
    for r in p.reported {
        assert!(p.text.contains(r.as_str()), "`{r}` not in the HTML");
    }
    let values = measured_values(p.text);
    numbers_are_readable(p.text, &format!("{} HTML", p.what));
    browser_without_overflow(p.html, p.dir);
    if let Some(pdf_text) = checked_pdf_text(p.pdf, p.dir) {
        numbers_are_readable(&pdf_text, &format!("{} PDF", p.what));
        let pages = page_texts(p.pdf);
        identification_on_every_page(&pages, p.identification, &format!("{} PDF", p.what));
        for r in p.reported {
            assert!(pages.iter().any(|page| page.contains(r.as_str())), "`{r}` not in the PDF");
        }
        assert_eq!(measured_values(&pdf_text), values, "the PDF shows the HTML's values");
    }
}
