//! `trueaxis demo` end to end (issue 7): the summary against the known errors, the files it writes
//! as inputs of the other commands (the report's "repeat each step" commands reproduce its
//! numbers), the HTML report's sections, well-formed inline SVG, and a headless-browser screenshot
//! that shows a rendered page. The browser check needs `chromium` (CI installs it and sets
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

#[test]
fn demo_identifies_the_known_errors_and_compensation_removes_most_of_the_error() {
    let (dir, s) = run_demo();
    let demo = dir.path().join("demo");
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
    // repeat the identification from the written files: the same values
    let again = trueaxis(&["identify", "--machine", "machine.toml", "--campaign", "campaign/campaign.toml", "--json"], &demo);
    assert!(again.status.success(), "{}", String::from_utf8_lossy(&again.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&again.stdout).unwrap();
    for (name, p) in params {
        let (a, b) = (doc["parameters"][name]["value"].as_f64().unwrap(), p["value"].as_f64().unwrap());
        assert!((a - b).abs() < 1e-6, "{name}: identify {a} vs demo {b}");
    }
    // the map files are `predict` inputs: predict reproduces the map
    let csv = std::fs::read_to_string(demo.join("volumetric_map.csv")).unwrap();
    let p = trueaxis(
        &["predict", "--machine", "machine.toml", "--errors", "errors_true.toml", "--poses", "volumetric_map.csv", "--frame", "machine"],
        &demo,
    );
    assert!(p.status.success(), "{}", String::from_utf8_lossy(&p.stderr));
    assert_eq!(String::from_utf8(p.stdout).unwrap(), csv);
    // and the compensation tables and uncertainty inputs exist
    for f in ["compensation/tables.csv", "compensation/grid.csv", "uncertainty/design.csv", "identified.toml", "ballbar/xy_circle.svg"] {
        assert!(std::fs::metadata(demo.join(f)).map(|m| m.len() > 0).unwrap_or(false), "{f}");
    }
}

#[test]
fn report_has_its_sections_well_formed_svg_and_renders_in_a_browser() {
    let (dir, _) = run_demo();
    let report = dir.path().join("demo/report.html");
    let html = std::fs::read_to_string(&report).unwrap();
    for id in ["machine", "campaign", "identification", "uncertainty", "volumetric", "ballbar", "compensation", "reproduce"] {
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
    let png = dir.path().join("report.png");
    let profile = dir.path().join("profile");
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
