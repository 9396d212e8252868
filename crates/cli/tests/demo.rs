//! `trueaxis demo` end to end (issue 7): the summary against the known errors, every command of the
//! report's "repeat each step" section run in the output folder with its printed numbers compared to
//! the report's, the HTML report's sections, well-formed inline SVG, and a headless-browser
//! screenshot that shows a rendered page. The browser check needs `chromium` (CI installs it and sets
//! TRUEAXIS_REQUIRE_BROWSER=1; elsewhere it is skipped with a message when chromium is missing).

use std::path::Path;
use std::process::{Command, Output};

fn trueaxis(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_trueaxis")).args(args).current_dir(dir).output().unwrap()
}

fn run_demo() -> (tempfile::TempDir, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = trueaxis(&["demo", "--out", "demo", "--json"], dir.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stderr.is_empty(), "no progress output when piped: {}", String::from_utf8_lossy(&out.stderr));
    (dir, serde_json::from_slice(&out.stdout).unwrap())
}

/// One run of the demo (it takes a while on two cores), every check on it.
#[test]
fn demo_end_to_end() {
    let (dir, s) = run_demo();
    let demo = dir.path().join("demo");
    summary_has_the_known_errors_and_compensation_removes_most_of_the_error(&demo, &s);
    every_repeat_command_of_the_report_reproduces_its_numbers(&demo);
    report_has_its_sections_well_formed_svg_and_renders_in_a_browser(&demo, dir.path());
}

fn summary_has_the_known_errors_and_compensation_removes_most_of_the_error(demo: &Path, s: &serde_json::Value) {
    assert_eq!(s["poses"], 3 * 21 * 21);
    let (before, after) = (s["max_position_error_um"].as_f64().unwrap(), s["max_position_error_after_compensation_um"].as_f64().unwrap());
    // seed 004 Table 1 errors over the KX8-Five travel: tens of micrometres
    assert!(before > 20.0 && before < 200.0, "max before {before}");
    // the identification error (drift of 7 um peak-to-valley) leaves well under a fifth
    assert!(after < before / 5.0, "after {after} vs before {before}");
    let params = s["parameters"].as_object().unwrap();
    assert_eq!(params.len(), 12);
    // the Monte Carlo 95 % intervals with the cyclic drift cover the true values (12 independent-ish
    // checks at 95 %: at least 11 must pass; with the fixed seeds all 12 do)
    let covered = params
        .values()
        .filter(|p| {
            let (lo, hi, t) = (p["interval95"][0].as_f64().unwrap(), p["interval95"][1].as_f64().unwrap(), p["true"].as_f64().unwrap());
            lo <= t && t <= hi
        })
        .count();
    assert!(covered >= 11, "{covered} of 12 intervals cover the true value: {params:?}");
    // the ballbar circle sees the XY squareness EC0Y = -8.8 urad: G of a few um on R 150 mm
    for g in s["ballbar_G_um"].as_array().unwrap() {
        let g = g.as_f64().unwrap();
        assert!(g > 0.5 && g < 10.0, "G {g}");
    }
    // the compensation tables and uncertainty inputs exist
    for f in ["compensation/tables.csv", "compensation/grid.csv", "uncertainty/design.csv", "identified.toml", "ballbar/xy_circle.svg"] {
        assert!(std::fs::metadata(demo.join(f)).map(|m| m.len() > 0).unwrap_or(false), "{f}");
    }
}

/// The text of the section `id` of the report.
fn section<'a>(html: &'a str, id: &str) -> &'a str {
    let start = html.find(&format!("<section id=\"{id}\">")).unwrap_or_else(|| panic!("no section {id}"));
    let end = html[start..].find("</section>").unwrap() + start;
    &html[start..end]
}

fn unescape(text: &str) -> String {
    text.replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"").replace("&amp;", "&")
}

/// The contents between `open` (a tag start such as `<td`) and `close`, unescaped, for each occurrence.
fn elements(text: &str, open: &str, close: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find(open) {
        let body_start = rest[i..].find('>').unwrap() + i + 1;
        let end = rest[body_start..].find(close).unwrap() + body_start;
        out.push(unescape(&rest[body_start..end]));
        rest = &rest[end + close.len()..];
    }
    out
}

/// The body rows of the table whose caption starts with `caption`, as cell texts.
fn table(section: &str, caption: &str) -> Vec<Vec<String>> {
    let start = section.find(&format!("<caption>{caption}")).unwrap_or_else(|| panic!("no table `{caption}`"));
    let end = section[start..].find("</table>").unwrap() + start;
    let body = &section[start..end];
    let body = &body[body.find("<tbody>").unwrap()..];
    elements(body, "<tr", "</tr>").iter().map(|row| elements(row, "<td", "</td>")).collect()
}

fn number(text: &str) -> f64 {
    text.trim_matches(|c: char| c == '[' || c == ']' || c == ',' || c.is_whitespace())
        .parse()
        .unwrap_or_else(|_| panic!("`{text}` is not a number"))
}

/// The first number after `label` in `text`.
fn number_after(text: &str, label: &str) -> f64 {
    let i = text.find(label).unwrap_or_else(|| panic!("no `{label}` in {text}")) + label.len();
    number(text[i..].split_whitespace().next().unwrap())
}

/// `trueaxis identify` prints each parameter as `name value u unit independence sensitivity`: the
/// report's identified value and u (2 decimals) and independence (3 decimals) agree.
fn check_identify(html: &str, stdout: &str) {
    let rows = table(section(html, "identification"), "Parameters");
    assert_eq!(rows.len(), 12);
    for row in &rows {
        let line = stdout
            .lines()
            .find(|l| l.split_whitespace().next() == Some(&row[0]))
            .unwrap_or_else(|| panic!("identify does not print {}", row[0]));
        let t: Vec<&str> = line.split_whitespace().collect();
        // report: parameter, unit, true, identified, u (LS), interval, covers, independence
        assert!((number(t[1]) - number(&row[3])).abs() <= 0.005 + 1e-9, "{}: identify {} vs report {}", row[0], t[1], row[3]);
        assert!((number(t[2]) - number(&row[4])).abs() <= 0.005 + 1e-9, "{} u: identify {} vs report {}", row[0], t[2], row[4]);
        assert_eq!((t[3], t[4]), (row[1].as_str(), row[7].as_str()), "{}: unit and independence", row[0]);
    }
}

/// `trueaxis uncertainty` prints per parameter the estimate, u (MC), u (GUM) and the interval, and
/// the budget widths: equal to the report's budget (3 decimals) and intervals (2 decimals).
fn check_uncertainty(html: &str, stdout: &str) {
    let budget = table(section(html, "uncertainty"), "Budget");
    let parameters = table(section(html, "identification"), "Parameters");
    assert_eq!(budget.len(), 12);
    let budget_start = stdout.find("\nbudget:").expect("the budget");
    for row in &budget {
        let name = &row[0];
        let line = |text: &str| -> Vec<String> {
            let line = text.lines().find(|l| l.split_whitespace().next() == Some(name.as_str())).unwrap();
            line.replace(['[', ']', ','], " ").split_whitespace().map(String::from).collect()
        };
        // estimate line: name unit estimate u_MC u_GUM [lo, hi] [gum_lo, gum_hi] (brackets and commas dropped)
        let estimate = line(&stdout[..budget_start]);
        assert_eq!(estimate[4], row[row.len() - 1], "{name}: GUM u");
        let interval = &parameters.iter().find(|p| &p[0] == name).unwrap()[5];
        let (lo, hi) = interval.split_once(',').unwrap();
        assert!((number(&estimate[5]) - number(lo)).abs() <= 0.005 + 1e-9, "{name}: interval {estimate:?} vs {interval}");
        assert!((number(&estimate[6]) - number(hi)).abs() <= 0.005 + 1e-9, "{name}: interval {estimate:?} vs {interval}");
        // budget line: name unit width per source.. rss total
        let widths = line(&stdout[budget_start..]);
        assert_eq!(widths[2..], row[2..row.len() - 1], "{name}: budget");
    }
}

/// `trueaxis ballbar iso230-4` prints the ISO values and diagnostics: the report's lines, exactly.
fn check_ballbar(html: &str, stdout: &str) {
    let printed: Vec<&str> = stdout.lines().map(str::trim).collect();
    let results = table(section(html, "ballbar"), "Results of");
    assert!(results.len() >= 4, "{results:?}");
    for row in &results {
        assert!(printed.contains(&row[0].trim()), "`{}` is not printed by ballbar iso230-4:\n{stdout}", row[0]);
    }
}

/// `trueaxis predict` prints the map: its largest and RMS |d| are the report's.
fn check_predict(html: &str, stdout: &str) {
    let mut lines = stdout.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (ix, iy, iz) = (col("dx"), col("dy"), col("dz"));
    let d: Vec<f64> = lines
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            (f[ix] * f[ix] + f[iy] * f[iy] + f[iz] * f[iz]).sqrt()
        })
        .collect();
    assert_eq!(d.len(), 3 * 21 * 21);
    let max = d.iter().cloned().fold(0.0, f64::max);
    let rms = (d.iter().map(|v| v * v).sum::<f64>() / d.len() as f64).sqrt();
    let text = unescape(section(html, "volumetric"));
    let before = &text[text.find("Before compensation: largest").unwrap()..];
    let (report_max, report_rms) = (number_after(before, "largest"), number_after(before, "RMS"));
    // the CSV carries 4 decimals, the report 2
    assert!((max - report_max).abs() <= 0.005 + 1e-3, "max |d| {max} vs report {report_max}");
    assert!((rms - report_rms).abs() <= 0.005 + 1e-3, "RMS |d| {rms} vs report {report_rms}");
}

/// `trueaxis compensate` prints the table count, points, largest corrections and residuals: the
/// report's summary table, digit for digit.
fn check_compensate(html: &str, stdout: &str) {
    let rows = table(section(html, "compensation"), "Summary");
    let value = |quantity: &str| rows.iter().find(|r| r[0].starts_with(quantity)).unwrap()[1].clone();
    let grid = value("grid nodes");
    let expected = format!(
        "{} tables of {} points{}; largest correction written {} um (linear axes), {} urad (rotary axes)",
        value("tables"),
        value("points per table"),
        if grid == "none" { String::new() } else { format!(", grid of {grid} nodes") },
        value("largest correction written, linear"),
        value("largest correction written, rotary")
    );
    assert!(stdout.contains(&expected), "`{expected}` not in:\n{stdout}");
    let residual = format!(
        "position residual <= {} um; orientation not corrected <= {} urad",
        value("position residual"),
        value("orientation not corrected")
    );
    assert!(stdout.contains(&residual), "`{residual}` not in:\n{stdout}");
}

fn every_repeat_command_of_the_report_reproduces_its_numbers(demo: &Path) {
    let html = std::fs::read_to_string(demo.join("report.html")).unwrap();
    let commands: Vec<String> = elements(section(&html, "reproduce"), "<pre", "</pre>")[0].lines().map(String::from).collect();
    assert_eq!(commands.len(), 5, "{commands:?}");
    let files = ["identified.toml", "compensation/tables.csv", "compensation/grid.csv"];
    let before: Vec<Vec<u8>> = files.iter().map(|f| std::fs::read(demo.join(f)).unwrap()).collect();
    for command in &commands {
        let args: Vec<&str> = command.split_whitespace().collect();
        assert_eq!(args[0], "trueaxis");
        let out = trueaxis(&args[1..], demo);
        assert!(out.status.success(), "`{command}`: {}", String::from_utf8_lossy(&out.stderr));
        let stdout = String::from_utf8(out.stdout).unwrap();
        match args[1] {
            "identify" => check_identify(&html, &stdout),
            "uncertainty" => check_uncertainty(&html, &stdout),
            "ballbar" => check_ballbar(&html, &stdout),
            "predict" => {
                check_predict(&html, &stdout);
                assert_eq!(stdout, std::fs::read_to_string(demo.join("volumetric_map.csv")).unwrap(), "predict reproduces the map file");
            }
            "compensate" => check_compensate(&html, &stdout),
            other => panic!("`{command}`: no check for `{other}`"),
        }
    }
    // the commands that write files rewrite the demo's files with the same values (a comment names
    // the campaign by the path it was read from)
    let values = |bytes: &[u8]| -> Vec<String> {
        String::from_utf8_lossy(bytes).lines().filter(|l| !l.starts_with('#')).map(String::from).collect()
    };
    for (f, b) in files.iter().zip(&before) {
        assert_eq!(values(&std::fs::read(demo.join(f)).unwrap()), values(b), "{f} differs when repeated");
    }
}

fn report_has_its_sections_well_formed_svg_and_renders_in_a_browser(demo: &Path, scratch: &Path) {
    let report = demo.join("report.html");
    let html = std::fs::read_to_string(&report).unwrap();
    for id in ["machine", "campaign", "identification", "uncertainty", "volumetric", "ballbar", "compensation", "reproduce", "inputs"] {
        assert!(html.contains(&format!("<section id=\"{id}\">")), "section {id}");
        assert!(html.contains(&format!("<a href=\"#{id}\">")), "table of contents entry {id}");
    }
    assert!(!html.contains("src=\"http") && !html.contains("href=\"http"), "no network resources");
    assert!(!html.contains("NaN") && !html.contains("inf<"), "no NaN or infinity in the report");
    // every inline SVG parses as XML (a broken figure would not)
    let mut count = 0;
    let mut rest = html.as_str();
    while let Some(start) = rest.find("<svg") {
        let end = rest[start..].find("</svg>").expect("closed svg") + start + "</svg>".len();
        roxmltree::Document::parse(&rest[start..end]).unwrap_or_else(|e| panic!("figure {count} is not well-formed SVG: {e}"));
        count += 1;
        rest = &rest[end..];
    }
    assert!(count >= 6, "{count} figures");

    let browser = ["chromium", "chromium-browser", "google-chrome"].into_iter().find(|b| Command::new(b).arg("--version").output().is_ok());
    let Some(browser) = browser else {
        assert!(std::env::var_os("TRUEAXIS_REQUIRE_BROWSER").is_none(), "TRUEAXIS_REQUIRE_BROWSER is set but no chromium was found");
        eprintln!("skipped the browser check: chromium is not installed");
        return;
    };
    let png = scratch.join("report.png");
    let profile = scratch.join("profile");
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", png.display()))
        .arg("--window-size=1200,2400")
        .arg(format!("file://{}", report.display()))
        .output()
        .unwrap();
    assert!(png.exists(), "no screenshot: {}", String::from_utf8_lossy(&out.stderr));
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (1200, 2400));
    let pixels = &buf[..info.buffer_size()];
    let step = info.line_size / info.width as usize;
    let mut colours = std::collections::HashSet::new();
    let mut non_white = 0usize;
    for p in pixels.chunks(step) {
        colours.insert(p.to_vec());
        if p.iter().take(3).any(|&c| c < 240) {
            non_white += 1;
        }
    }
    // text, tables and the coloured figures: many colours and a good share of ink
    assert!(colours.len() > 50, "{} distinct colours: the page did not render", colours.len());
    let share = non_white as f64 / (pixels.len() / step) as f64;
    assert!(share > 0.02, "only {share} of the page is not white");
}
