//! `trueaxis report` on the shipped examples (issue 7, docs/design.md, Command line): the sections appear for
//! the inputs given and only for them, each part has the numbers of the command that does that step
//! alone (`identify`, `ballbar iso230-4`), every inline SVG parses, no NaN, no external reference,
//! the inputs are listed with their size and SHA-256; bad input exits 2 and writes no file.

use crate::support::{arg, trueaxis, ROOT};
use std::path::Path;

const KX8: [&str; 4] = ["--machine", "examples/machines/kx8five.toml", "--campaign", "examples/campaigns/kx8five/campaign.toml"];
const VMC3: [&str; 10] = [
    "--machine",
    "examples/machines/vmc3.toml",
    "--errors",
    "examples/errors/vmc3.toml",
    "--ballbar",
    "examples/ballbar/vmc3_xy.csv",
    "--ballbar-radius",
    "100",
    "--ballbar-centre",
    "0,0,-200",
];
const SECTIONS: [&str; 13] = [
    "certificate",
    "conformity",
    "machine",
    "campaign",
    "identification",
    "uncertainty",
    "volumetric",
    "thermal-modes",
    "thermal-drift",
    "ballbar",
    "compensation",
    "data-quality",
    "inputs",
];

/// Runs `report` into a temporary folder: the HTML and the JSON summary.
fn report(args: &[&str]) -> (String, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.html");
    let mut all = vec!["report", "--json", "--out", arg(&out)];
    all.extend_from_slice(args);
    let o = trueaxis(&all);
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
    assert!(o.stderr.is_empty(), "quiet when piped: {}", String::from_utf8_lossy(&o.stderr));
    (std::fs::read_to_string(&out).unwrap(), serde_json::from_slice(&o.stdout).unwrap())
}

/// The section ids of a report, checked against the JSON summary and the table of contents; every
/// inline SVG well-formed, no NaN or infinity, nothing loaded from elsewhere.
fn sections_of(html: &str, summary: &serde_json::Value) -> Vec<String> {
    let ids: Vec<String> = SECTIONS.iter().filter(|id| html.contains(&format!("<section id=\"{id}\">"))).map(|id| id.to_string()).collect();
    let listed: Vec<String> = summary["sections"].as_array().unwrap().iter().map(|v| v.as_str().unwrap().to_string()).collect();
    assert_eq!(ids, listed);
    for id in &ids {
        assert!(html.contains(&format!("<a href=\"#{id}\">")), "table of contents entry {id}");
    }
    for bad in ["NaN", "inf<", ">inf", "src=", "href=\"http", "<link", "<script", "<img", "url(", "@import"] {
        assert!(!html.contains(bad), "the report contains `{bad}`");
    }
    let mut rest = html;
    let mut figures = 0;
    while let Some(start) = rest.find("<svg") {
        let end = rest[start..].find("</svg>").expect("closed svg") + start + "</svg>".len();
        let doc = roxmltree::Document::parse(&rest[start..end]).unwrap_or_else(|e| panic!("figure {figures} is not well-formed SVG: {e}"));
        assert!(doc.descendants().count() > 20, "figure {figures} is nearly empty");
        figures += 1;
        rest = &rest[end..];
    }
    assert_eq!(figures, html.matches("<figure>").count());
    ids
}

/// The inputs table lists each file with its size and its SHA-256.
fn assert_inputs(summary: &serde_json::Value, files: &[&str]) {
    let inputs = summary["inputs"].as_array().unwrap();
    let root = Path::new(ROOT);
    for f in files {
        let entry =
            inputs.iter().find(|i| i["path"].as_str().unwrap().ends_with(f)).unwrap_or_else(|| panic!("{f} not listed: {inputs:?}"));
        let bytes = std::fs::read(root.join(f)).unwrap();
        assert_eq!(entry["bytes"].as_u64().unwrap(), bytes.len() as u64, "{f}");
        assert_eq!(entry["sha256"].as_str().unwrap(), hex(&trueaxis_report::calibration::sha256(&bytes)), "{f}");
    }
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

#[test]
fn a_campaign_with_sources_gives_identification_uncertainty_maps_and_compensation() {
    let (html, s) = report(&[&KX8[..], &["--sources", "examples/uncertainty/kx8five_cyclic.toml"]].concat());
    let ids = sections_of(&html, &s);
    assert_eq!(
        ids,
        ["certificate", "machine", "campaign", "identification", "uncertainty", "volumetric", "compensation", "data-quality", "inputs"]
    );
    assert!(html.matches("<figure>").count() >= 5, "residuals, histograms, convergence, two maps");
    assert_inputs(
        &s,
        &[
            "examples/machines/kx8five.toml",
            "examples/campaigns/kx8five/campaign.toml",
            "examples/campaigns/kx8five/capball.csv",
            "examples/uncertainty/kx8five_cyclic.toml",
        ],
    );
    // the identification is `trueaxis identify`'s, and every parameter has a Monte Carlo interval
    // around its value
    let id = trueaxis(&["identify", "--json", KX8[0], KX8[1], KX8[2], KX8[3]]);
    let id: serde_json::Value = serde_json::from_slice(&id.stdout).unwrap();
    let params = s["parameters"].as_object().unwrap();
    assert_eq!(params.len(), 12);
    for (name, p) in params {
        let (v, w) = (p["value"].as_f64().unwrap(), id["parameters"][name]["value"].as_f64().unwrap());
        assert!((v - w).abs() < 1e-9, "{name}: report {v} vs identify {w}");
        let u = id["parameters"][name]["std_uncertainty"].as_f64().unwrap();
        assert!((p["least_squares_std_uncertainty"].as_f64().unwrap() - u).abs() < 1e-9, "{name} u");
        assert_eq!(p["uncertainty_method"], "Monte Carlo, all sources (JCGM 101)", "{name}: the report's one U");
        let (lo, hi) = (p["interval95"][0].as_f64().unwrap(), p["interval95"][1].as_f64().unwrap());
        assert!(lo < v && v < hi, "{name}: {v} outside [{lo}, {hi}]");
    }
    // the maps are of the identified errors without the campaign's set-up, at 12 rotary states: the
    // exact correction removes them to the corrector's tolerance (1e-5 mm); the axis-indexed
    // tables, which cannot follow the rotary axes' location errors as they turn, leave more than
    // the machine has without them (99.5 against 55.6 um), and the report says so in a note
    let v = &s["volumetric"];
    let (before, after, tables) =
        (v["max_before_um"].as_f64().unwrap(), v["max_after_um"].as_f64().unwrap(), v["max_after_tables_um"].as_f64().unwrap());
    assert!(before > 10.0 && after < 0.011, "before {before} um, after {after} um");
    assert!(tables > before, "before {before} um, with the tables {tables} um");
    let warning = "Compensation with the own-axis and cross-axis tables summed leaves a largest error of";
    assert_eq!(html.matches(warning).count(), 1, "the volumetric section warns once");
    assert!(html.contains("do not load them into this machine"), "and says what to do instead");
}

#[test]
fn error_values_and_a_circle_give_maps_ballbar_and_compensation_only() {
    let (html, s) = report(&VMC3);
    let ids = sections_of(&html, &s);
    assert_eq!(ids, ["certificate", "machine", "volumetric", "ballbar", "compensation", "data-quality", "inputs"]);
    assert_inputs(&s, &["examples/machines/vmc3.toml", "examples/errors/vmc3.toml", "examples/ballbar/vmc3_xy.csv"]);
    assert!(s["parameters"].is_null() && !s["volumetric"].is_null());
    // the ballbar values are `ballbar iso230-4`'s
    let b = trueaxis(&["ballbar", "iso230-4", VMC3[5], VMC3[0], VMC3[1], "--radius", VMC3[7], "--centre", VMC3[9], "--json"]);
    let b: serde_json::Value = serde_json::from_slice(&b.stdout).unwrap();
    let g: Vec<f64> = s["ballbar"][0]["G_um"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let runs = b["runs"].as_array().unwrap();
    assert_eq!(g.len(), runs.len());
    for (g, r) in g.iter().zip(runs) {
        assert!((g - r["G_um"].as_f64().unwrap()).abs() < 1e-3, "G {g} vs {}", r["G_um"]);
    }
    // the exact correction of every pose removes the modelled error (to the corrector's tolerance,
    // 1e-5 mm); the vmc3 errors have Abbe terms (angular errors times an offset along another axis)
    // that tables on the axis lines miss: with them, less than before but not zero
    let v = &s["volumetric"];
    let (before, after, tables) =
        (v["max_before_um"].as_f64().unwrap(), v["max_after_um"].as_f64().unwrap(), v["max_after_tables_um"].as_f64().unwrap());
    assert!(before > 5.0 && after < 0.01, "before {before} um, after {after} um");
    assert!(tables < before && tables > 0.1, "before {before} um, with the tables {tables} um");
    // the compensation summary is `compensate`'s
    let dir = tempfile::tempdir().unwrap();
    let c =
        trueaxis(&["compensate", VMC3[0], VMC3[1], VMC3[2], VMC3[3], "--format", "csv", "--json", "--out", dir.path().to_str().unwrap()]);
    let c: serde_json::Value = serde_json::from_slice(&c.stdout).unwrap();
    for key in ["max_correction_um", "max_correction_urad"] {
        assert!((c[key].as_f64().unwrap() - s["compensation"][key].as_f64().unwrap()).abs() < 1e-4, "{key}");
    }
}

#[test]
fn thermal_inputs_give_the_modes_and_the_drift_of_the_thermal_commands() {
    let dir = tempfile::tempdir().unwrap();
    let fitted = dir.path().join("dz.toml");
    let fitted = arg(&fitted);
    let campaign = "examples/thermal/campaign.csv";
    let fit = trueaxis(&["thermal", "fit", "--data", campaign, "--error", "dz", "--train-runs", "warmup", "--out", fitted]);
    assert!(fit.status.success(), "{}", String::from_utf8_lossy(&fit.stderr));
    let model = "examples/thermal/elongation.toml";
    let thermal = ["--thermal-model", model, "--thermal-modes", "5", "--thermal-error", fitted, "--thermal-data", campaign];
    let (html, s) = report(&[&VMC3[..4], &thermal[..]].concat());
    assert_eq!(
        sections_of(&html, &s),
        ["certificate", "machine", "volumetric", "thermal-modes", "thermal-drift", "compensation", "data-quality", "inputs"]
    );
    assert_inputs(&s, &[model, campaign, fitted]);
    // the modes are `thermal modes`'s
    let m: serde_json::Value =
        serde_json::from_slice(&trueaxis(&["thermal", "modes", "--model", model, "--count", "5", "--json"]).stdout).unwrap();
    let modes = m["modes"].as_array().unwrap();
    let tau: Vec<f64> = s["thermal_modes"]["tau_min"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(tau.len(), 5);
    for (t, m) in tau.iter().zip(modes) {
        assert!((t - m["tau_min"].as_f64().unwrap()).abs() <= 1e-9 * t, "tau {t} vs {}", m["tau_min"]);
    }
    assert_eq!(s["thermal_modes"]["dominant"], m["dominant"]);
    // the residuals are `thermal predict`'s, per run
    let p = trueaxis(&["thermal", "predict", "--model", fitted, "--data", campaign, "--json"]);
    let p: serde_json::Value = serde_json::from_slice(&p.stdout).unwrap();
    let runs = s["thermal_drift"]["residuals_um"].as_object().unwrap();
    assert_eq!(runs.len(), 4);
    for (run, r) in runs {
        for key in ["rms", "max_abs", "min", "max"] {
            let (a, b) = (r[key].as_f64().unwrap(), p["residuals"][run][key].as_f64().unwrap());
            assert!((a - b).abs() < 1e-12, "{run} {key}: {a} vs {b}");
        }
        assert!(html.contains(&format!("<td>{run}</td>")), "{run} in the residual table");
    }
    // bad thermal input: exit 2 naming the file, nothing written
    let out = dir.path().join("bad.html");
    for (args, fragment) in [
        (vec!["--thermal-model", "missing_thermal.toml"], "missing_thermal.toml"),
        (vec!["--thermal-error", fitted, "--thermal-data", "examples/thermal/elongation.toml"], "elongation.toml"),
        (vec!["--thermal-model", model, "--thermal-modes", "0"], "at least 1"),
    ] {
        let o = trueaxis(&[&["report", "--out", arg(&out)][..], &VMC3[..4], &args].concat());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(fragment), "{args:?}: `{fragment}` not in {err}");
        assert!(!out.exists());
    }
    let o = trueaxis(&[&["report", "--out", arg(&out)][..], &VMC3[..4], &["--thermal-error", fitted]].concat());
    assert_eq!(o.status.code(), Some(2), "--thermal-error needs --thermal-data");
}

#[test]
fn a_campaign_without_sources_has_no_uncertainty_and_a_deficient_one_names_its_combinations() {
    let (html, s) = report(&KX8);
    assert_eq!(
        sections_of(&html, &s),
        ["certificate", "machine", "campaign", "identification", "volumetric", "compensation", "data-quality", "inputs"]
    );
    assert!(!html.contains("interval (MC)"), "no Monte Carlo column without sources");

    let deficient = ["--machine", "examples/machines/kx8five.toml", "--campaign", "examples/campaigns/kx8five/paper14.toml"];
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.html");
    let o = trueaxis(&[&["report", "--out", arg(&out)][..], &deficient].concat());
    assert_eq!(o.status.code(), Some(1), "rank deficient: a failed computation, as identify");
    assert!(String::from_utf8_lossy(&o.stderr).contains("EY0C"), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!out.exists());
    let (html, _) = report(&[&deficient[..], &["--allow-rank-deficient"]].concat());
    let notes = html.matches("<p class=\"note\">Not identifiable:").count();
    assert_eq!(notes, 2, "the two unseen combinations of Andolfatto et al. 2011's 14 parameters");
}

#[test]
fn bad_input_exits_2_with_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.html");
    let o = arg(&out);
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--machine", "missing.toml", "--errors", "examples/errors/vmc3.toml"], "missing.toml"),
        (vec!["--machine", "examples/machines/vmc3.toml", "--campaign", "missing_campaign.toml"], "missing_campaign.toml"),
        (vec!["--machine", "examples/machines/vmc3.toml", "--errors", "examples/errors/kx8five.toml"], "examples/errors/kx8five.toml"),
        (VMC3[..6].to_vec(), "--ballbar-radius"),
        ([&VMC3[..], &["--ballbar-radius", "50"]].concat(), "--ballbar-radius is given 2 times for 1 circles"),
        (
            vec!["--machine", "examples/machines/vmc3.toml", "--errors", "examples/errors/vmc3.toml", "--ballbar-radius", "100"],
            "need a --ballbar",
        ),
        (
            vec![
                "--machine",
                "examples/machines/vmc3.toml",
                "--errors",
                "examples/errors/vmc3.toml",
                "--ballbar",
                "examples/errors/vmc3.toml",
                "--ballbar-radius",
                "100",
            ],
            "examples/errors/vmc3.toml",
        ),
        (
            vec![
                "--machine",
                "examples/machines/kx8five.toml",
                "--campaign",
                "examples/campaigns/kx8five/campaign.toml",
                "--sources",
                "examples/campaigns/kx8five/campaign.toml",
            ],
            "examples/campaigns/kx8five/campaign.toml",
        ),
        ([&VMC3[..4], &["--certificate", "missing_report.toml"]].concat(), "missing_report.toml"),
        ([&VMC3[..4], &["--certificate", "examples/machines/vmc3.toml"]].concat(), "examples/machines/vmc3.toml"),
        ([&VMC3[..4], &["--controller", "okuma"]].concat(), "okuma"),
    ];
    for (args, fragment) in cases {
        let o = trueaxis(&[&["report", "--out", o][..], &args].concat());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: one line: {err}");
        assert!(err.contains(fragment), "{args:?}: `{fragment}` not in {err}");
        assert!(!out.exists(), "{args:?} wrote the report");
        assert!(o.stdout.is_empty());
    }
    // usage errors (clap): exit 2, no file
    for args in [
        vec!["--machine", "examples/machines/vmc3.toml"],
        vec!["--machine", "examples/machines/vmc3.toml", "--errors", "x", "--sources", "s"],
    ] {
        let o = trueaxis(&[&["report", "--out", o][..], &args].concat());
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!out.exists());
    }
    // a folder that does not exist: the path named once, no temporary file name
    let o = trueaxis(&[&["report", "--out", "no/such/folder/r.html"][..], &VMC3[..4]].concat());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("no/such/folder/r.html") && !err.contains("at path") && !err.contains(".tmp"), "{err}");
    assert_eq!(err.matches("No such file or directory").count(), 1, "{err}");
    let leftovers: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

/// A length campaign (issue 36): the laser-tracer multilateration of the vmc3 (instrument `length`,
/// four stations, motion errors as functions of their axes) gives the parameters of `trueaxis
/// identify --json`, each with U = 2 u (least squares, no sources) printed in the report.
#[test]
fn a_length_campaign_is_reported_with_the_numbers_of_identify() {
    let campaign = ["--machine", "examples/machines/vmc3.toml", "--campaign", "examples/campaigns/vmc3_tracer/campaign.toml"];
    let (html, s) = report(&campaign);
    assert_eq!(
        sections_of(&html, &s),
        ["certificate", "machine", "campaign", "identification", "volumetric", "compensation", "data-quality", "inputs"]
    );
    let id = trueaxis(&[&["identify", "--json"][..], &campaign].concat());
    assert!(id.status.success(), "{}", String::from_utf8_lossy(&id.stderr));
    let id: serde_json::Value = serde_json::from_slice(&id.stdout).unwrap();
    let params = s["parameters"].as_object().unwrap();
    assert_eq!(params.len(), id["parameters"].as_object().unwrap().len());
    assert!(params.len() >= 10, "{} parameters", params.len());
    for (name, p) in params {
        let (v, w) = (p["value"].as_f64().unwrap(), id["parameters"][name]["value"].as_f64().unwrap());
        assert!((v - w).abs() < 1e-9, "{name}: report {v} vs identify {w}");
        let u = id["parameters"][name]["std_uncertainty"].as_f64().unwrap();
        assert!((p["expanded_uncertainty"].as_f64().unwrap() - 2.0 * u).abs() < 1e-9, "{name}: U = 2 u");
        assert!(html.contains(p["reported"].as_str().unwrap()), "{name}: `{}` not in the report", p["reported"]);
    }
}

#[test]
fn the_library_assembles_the_report_the_command_writes() {
    use trueaxis_report::calibration::{assemble, summary_json, CalibrationError, CertificateFile, ReportRequest};
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let file = |relative: &str| root.join(relative);
    let request = ReportRequest {
        errors: Some(file("examples/errors/vmc3.toml")),
        ballbar: vec![file("examples/ballbar/vmc3_xy.csv")],
        ballbar_radius: vec![100.0],
        ballbar_centre: vec![trueaxis::geometry::Vec3::new(0.0, 0.0, -200.0)],
        certificate: Some(file("examples/report/vmc3.toml")),
        controller: Some("heidenhain".into()),
        ..ReportRequest::new(file("examples/machines/vmc3.toml"))
    };
    let machine = trueaxis::machine::Machine::load(&request.machine).unwrap();
    let mut no_fits = |_: &CertificateFile, _: &Path| Ok::<_, CalibrationError>(Vec::new());
    let assembled = assemble(&request, &machine, &mut |_: &str| {}, &mut no_fits).unwrap();
    let sections: Vec<String> = assembled.sections().iter().map(|s| s.id.clone()).collect();
    let out = Path::new("r.html");
    let mut library = summary_json(out, &assembled, &sections, 0, None);
    // the command on the same files, with the same options
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let mut args: Vec<String> = ["--machine", "--errors", "--ballbar", "--certificate"]
        .iter()
        .zip([&request.machine, request.errors.as_ref().unwrap(), &request.ballbar[0], request.certificate.as_ref().unwrap()])
        .flat_map(|(option, p)| [option.to_string(), path(p)])
        .collect();
    args.extend(["--ballbar-radius", "100", "--ballbar-centre", "0,0,-200", "--controller", "heidenhain"].map(String::from));
    let (_, mut command) = report(&args.iter().map(String::as_str).collect::<Vec<_>>());
    for key in ["out", "bytes"] {
        library[key] = serde_json::Value::Null;
        command[key] = serde_json::Value::Null;
    }
    assert_same(&library, &command, "summary");
}

/// The same document, numbers to the last bits (the two runs may sum in another order).
fn assert_same(a: &serde_json::Value, b: &serde_json::Value, place: &str) {
    use serde_json::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!((x - y).abs() <= 1e-12 * x.abs().max(y.abs()), "{place}: {x} vs {y}");
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{place}");
            x.iter().zip(y).enumerate().for_each(|(i, (x, y))| assert_same(x, y, &format!("{place}[{i}]")));
        }
        (Value::Object(x), Value::Object(y)) => {
            assert_eq!(x.keys().collect::<Vec<_>>(), y.keys().collect::<Vec<_>>(), "{place}");
            x.iter().for_each(|(k, v)| assert_same(v, &y[k], &format!("{place}.{k}")));
        }
        _ => assert_eq!(a, b, "{place}"),
    }
}
