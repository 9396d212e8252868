//! `trueaxis demo` end to end (issue 7): the summary against the known errors, every command of the
//! report's "repeat each step" section run in the output folder with its printed numbers compared to
//! the report's, the HTML report's sections, well-formed inline SVG, and a headless-browser
//! screenshot that shows a rendered page. The browser check needs `chromium` (CI installs it and sets
//! TRUEAXIS_REQUIRE_BROWSER=1; elsewhere it is skipped with a message when chromium is missing).

use crate::support::trueaxis_in;
use std::path::Path;
use std::process::Command;

fn run_demo() -> (tempfile::TempDir, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = trueaxis_in(dir.path(), &["demo", "--out", "demo", "--json"]);
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
    // the three mid-planes (21 x 21 nodes) at 12 rotary states: A 0, 90, 180 deg x C 0, 90, 180, 270
    assert_eq!(s["poses"], 12 * 3 * 21 * 21);
    let (before, after) = (s["max_position_error_um"].as_f64().unwrap(), s["max_position_error_after_compensation_um"].as_f64().unwrap());
    // Andolfatto et al. 2011 Table 1 errors over the KX8-Five travel: tens of micrometres
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
    elements(body, "<tr", "</tr>").iter().map(|row| elements(row, "<td", "</td>").iter().map(|c| strip_tags(c)).collect()).collect()
}

/// The text of a cell without its markup (a link).
fn strip_tags(html: &str) -> String {
    let mut out = String::new();
    let mut inside = false;
    for c in html.chars() {
        match c {
            '<' => inside = true,
            '>' => inside = false,
            c if !inside => out.push(c),
            _ => {}
        }
    }
    out
}

fn number(text: &str) -> f64 {
    text.trim_matches(|c: char| c == '[' || c == ']' || c == ',' || c.is_whitespace())
        .parse()
        .unwrap_or_else(|_| panic!("`{text}` is not a number"))
}

/// The first number after `label` in `text`.
fn number_after(text: &str, label: &str) -> f64 {
    let i = text.find(label).unwrap_or_else(|| panic!("no `{label}` in {text}")) + label.len();
    number(text[i..].split_whitespace().next().unwrap().trim_end_matches('.'))
}

/// `value ± U unit` of a report cell: value, U and the decimal places the value is given to.
fn measured(cell: &str) -> (f64, f64, usize) {
    let (value, rest) = cell.split_once(" ± ").unwrap_or_else(|| panic!("`{cell}` is not `value ± U unit`"));
    let u = rest.split_whitespace().next().unwrap();
    let decimals = |t: &str| t.split_once('.').map_or(0, |(_, d)| d.len());
    // U to two significant digits, the value to the same decimal place
    let digits: String = u.chars().filter(char::is_ascii_digit).collect::<String>().trim_start_matches('0').to_string();
    assert!(digits.len() == 2 || (digits.len() == 3 && digits.ends_with('0') && !u.contains('.')), "U `{u}` has two significant digits");
    assert_eq!(decimals(value), decimals(u), "`{cell}`: the value to the decimal place of U");
    (number(value), number(u), decimals(value))
}

/// `trueaxis identify` prints each parameter as `name value u unit independence sensitivity`: the
/// report's identified value agrees to its rounding, and its U is twice the Monte Carlo standard
/// uncertainty that `trueaxis uncertainty` prints.
fn check_identify(html: &str, stdout: &str) {
    let rows = table(section(html, "identification"), "Parameters");
    assert_eq!(rows.len(), 12);
    for row in &rows {
        let line = stdout
            .lines()
            .find(|l| l.split_whitespace().next() == Some(&row[0]))
            .unwrap_or_else(|| panic!("identify does not print {}", row[0]));
        let t: Vec<&str> = line.split_whitespace().collect();
        // report: parameter, true value, identified value ± U unit, uncertainty from, within U, independence
        let (value, _, decimals) = measured(&row[2]);
        assert!(
            (number(t[1]) - value).abs() <= 0.5 * 10f64.powi(-(decimals as i32)) + 1e-9,
            "{}: identify {} vs report {}",
            row[0],
            t[1],
            row[2]
        );
        assert!(row[2].ends_with(t[3]) && row[1].ends_with(t[3]), "{}: unit {} in `{}`", row[0], t[3], row[2]);
        assert!((number(t[4]) - number(&row[5])).abs() <= 0.005 + 1e-9, "{}: independence", row[0]);
        assert_eq!(row[3], "Monte Carlo, all sources (JCGM 101)");
    }
}

/// `trueaxis uncertainty` prints per parameter the estimate, u (MC), u (GUM) and the interval, and
/// the budget widths: the report's U is 2 u (MC) and its budget widths those printed, each to two
/// significant digits.
fn check_uncertainty(html: &str, stdout: &str) {
    let budget = table(section(html, "uncertainty"), "Budget");
    let parameters = table(section(html, "identification"), "Parameters");
    assert_eq!(budget.len(), 12);
    let budget_start = stdout.find("\nbudget:").expect("the budget");
    let two_digits = |reported: &str, printed: f64| {
        let (v, unit) = reported.split_once(' ').unwrap();
        let d = v.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
        assert!((number(v) - printed).abs() <= 0.5 * 10f64.powi(-d) + 1e-9, "`{reported}` vs {printed}");
        assert!(unit == "um" || unit == "urad", "{reported}");
    };
    for row in &budget {
        let name = &row[0];
        let line = |text: &str| -> Vec<String> {
            let line = text.lines().find(|l| l.split_whitespace().next() == Some(name.as_str())).unwrap();
            line.replace(['[', ']', ','], " ").split_whitespace().map(String::from).collect()
        };
        // estimate line: name unit estimate u_MC u_GUM [lo, hi] [gum_lo, gum_hi] (brackets and commas dropped)
        let estimate = line(&stdout[..budget_start]);
        let u_mc = number(&estimate[3]);
        two_digits(&row[row.len() - 1], 2.0 * u_mc);
        let (_, u, _) = measured(&parameters.iter().find(|p| &p[0] == name).unwrap()[2]);
        two_digits(&format!("{u} um"), 2.0 * u_mc);
        // budget line: name unit width per source.. rss total
        let widths = line(&stdout[budget_start..]);
        for (reported, printed) in row[1..row.len() - 1].iter().zip(&widths[2..]) {
            two_digits(reported, number(printed));
        }
    }
}

/// `trueaxis ballbar iso230-4` prints the ISO values and diagnostics: the report's lines, exactly.
fn check_ballbar(html: &str, stdout: &str) {
    let printed: Vec<&str> = stdout.lines().map(str::trim).collect();
    // the G of each run, rounded by its U, is the printed one
    let values = table(section(html, "ballbar"), "ISO 230-4 values of");
    assert_eq!(values.len(), 3, "{values:?}");
    for row in &values[..2] {
        let line = printed.iter().find(|l| l.starts_with(&format!("{}: G = ", row[0]))).unwrap_or_else(|| panic!("{}: {stdout}", row[0]));
        let g = number(line.split("G = ").nth(1).unwrap().split_whitespace().next().unwrap());
        let (value, u, decimals) = measured(&row[1]);
        assert!((value - g).abs() <= 0.5 * 10f64.powi(-(decimals as i32)) + 1e-9, "G {g} vs `{}`", row[1]);
        assert_eq!(u, 1.0, "the ballbar's U of report.toml");
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
    assert_eq!(d.len(), 12 * 3 * 21 * 21, "the mid-planes at 12 rotary states");
    let max = d.iter().cloned().fold(0.0, f64::max);
    let rms = (d.iter().map(|v| v * v).sum::<f64>() / d.len() as f64).sqrt();
    let text = unescape(section(html, "volumetric"));
    let before = &text[text.find("Before compensation: largest").unwrap()..];
    let before = before.replace(" um", "");
    let (report_max, report_rms) = (number_after(&before, "largest"), number_after(&before, "RMS"));
    // the CSV carries 4 decimals, the report 2
    assert!((max - report_max).abs() <= 0.005 + 1e-3, "max |d| {max} vs report {report_max}");
    assert!((rms - report_rms).abs() <= 0.005 + 1e-3, "RMS |d| {rms} vs report {report_rms}");
}

/// `trueaxis compensate --format heidenhain` prints the error before and the error its files leave:
/// the report's figures (2 decimals there, 3 printed).
fn check_controller(html: &str, stdout: &str) {
    let compensation = section(html, "compensation");
    let caption = "What the Heidenhain files leave";
    let rows = table(&compensation[compensation.find(&format!("<caption>{caption}")).unwrap()..], caption);
    let value = |quantity: &str| -> f64 {
        rows.iter().find(|r| r[0] == quantity).unwrap_or_else(|| panic!("no row {quantity}"))[1].trim_end_matches(" um").parse().unwrap()
    };
    let printed = |prefix: &str| -> f64 {
        let line = stdout.lines().find(|l| l.starts_with(prefix)).unwrap_or_else(|| panic!("no `{prefix}` in {stdout}"));
        number_after(line, "worst")
    };
    for (row, line) in [("largest error before compensation", "error before"), ("largest error left", "error left with these files")] {
        let (shown, repeated) = (value(row), printed(line));
        assert!((shown - repeated).abs() <= 0.005 + 1e-3, "{row}: report {shown} um, `trueaxis compensate` {repeated} um");
    }
    assert!(
        value("largest error left") < 0.1 * value("largest error before compensation"),
        "the demo's compensation removes most of the error"
    );
}

/// `trueaxis compensate` prints the table count, points, largest corrections and residuals: the
/// report's summary table, each number the printed one rounded to the report's resolution (0.01 um,
/// 0.1 urad).
fn check_compensate(html: &str, stdout: &str) {
    let rows = table(section(html, "compensation"), "Summary");
    let value = |quantity: &str| {
        rows.iter().find(|r| r[0].starts_with(quantity)).unwrap()[1].trim_end_matches(" um").trim_end_matches(" urad").to_string()
    };
    let grid = value("grid nodes");
    let counts = format!(
        "{} tables of {} points{}; largest correction written",
        value("tables"),
        value("points per table"),
        if grid == "none" { String::new() } else { format!(", grid of {grid} nodes") },
    );
    let line = stdout.lines().find(|l| l.starts_with(&counts)).unwrap_or_else(|| panic!("`{counts}` not in:\n{stdout}"));
    let rounded = |shown: &str, printed: f64| {
        let place = shown.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
        assert!((number(shown) - printed).abs() <= 0.5 * 10f64.powi(-place) + 1e-9, "report `{shown}` vs printed {printed}");
    };
    rounded(&value("largest correction written, linear"), number_after(line, "written"));
    rounded(&value("largest correction written, rotary"), number_after(line, "(linear axes),"));
    let residual = stdout.lines().find(|l| l.contains("position residual <=")).unwrap_or_else(|| panic!("no residual in:\n{stdout}"));
    rounded(&value("position residual"), number_after(residual, "residual <="));
    rounded(&value("orientation not corrected"), number_after(residual, "not corrected <="));
}

fn every_repeat_command_of_the_report_reproduces_its_numbers(demo: &Path) {
    let html = std::fs::read_to_string(demo.join("report.html")).unwrap();
    let commands: Vec<String> = elements(section(&html, "reproduce"), "<pre", "</pre>")[0].lines().map(String::from).collect();
    assert_eq!(commands.len(), 6, "{commands:?}");
    let files = ["identified.toml", "compensation/tables.csv", "compensation/grid.csv"];
    let before: Vec<Vec<u8>> = files.iter().map(|f| std::fs::read(demo.join(f)).unwrap()).collect();
    for command in &commands {
        let args: Vec<&str> = command.split_whitespace().collect();
        assert_eq!(args[0], "trueaxis");
        let out = trueaxis_in(demo, &args[1..]);
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
            "compensate" if command.contains("--format csv") => check_compensate(&html, &stdout),
            "compensate" => check_controller(&html, &stdout),
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
    for id in [
        "certificate",
        "conformity",
        "machine",
        "campaign",
        "identification",
        "uncertainty",
        "volumetric",
        "ballbar",
        "compensation",
        "reproduce",
        "inputs",
    ] {
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
