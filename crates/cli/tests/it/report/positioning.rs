//! `trueaxis report --positioning`: an ISO 230-2 laser test in the calibration report. The results
//! equal `trueaxis iso230-2` on the same file; each U equals the ISO 230-2 Annex A contributors
//! built by hand from report.toml and the temperatures the Renishaw file records; the HTML shows
//! each result rounded by its U; the conformity decisions under the guard band follow from value,
//! U and tolerance; the certificate takes the serial number from the file.

use crate::support::{arg, trueaxis, vmc3, ROOT};
use std::process::Output;
use trueaxis::evaluate::iso230_2::{evaluate, Iso2302Result};
use trueaxis::evaluate::positioning_test::evaluate_file;
use trueaxis::evaluate::positioning_uncertainty::{positioning_uncertainty, PositioningUncertaintyInputs};
use trueaxis::instruments::TemperatureOptions;
use trueaxis_report::calibration::quantity::with_uncertainty;

const RTL: &str = "examples/data/laser_x.rtl";

/// `trueaxis report` of vmc3 with the Renishaw file as positioning tests and `certificate`, into
/// `out` (HTML), the summary on stdout.
fn run_report(certificate: &str, out: &std::path::Path) -> Output {
    trueaxis(&vmc3(
        &["report", "--json"],
        &["--errors", "examples/errors/vmc3.toml", "--positioning", RTL, "--certificate", certificate, "--out", arg(out)],
    ))
}

fn report(certificate: &str) -> (String, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.html");
    let o = run_report(certificate, &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (std::fs::read_to_string(&out).unwrap(), serde_json::from_slice(&o.stdout).unwrap())
}

/// The inputs of examples/report/vmc3_laser.toml and the file's environment, written out.
fn inputs_by_hand() -> PositioningUncertaintyInputs {
    PositioningUncertaintyInputs {
        device_um: 0.2,
        device_um_per_m: 0.5,
        temperature_k: 0.1,
        expansion_um_per_m_k: 11.5,
        expansion_fraction: 0.10,
        // Mat temp 1..3 of the file: 21.1, 21.3, 21.2 degC
        temperature_offset_k: (21.1 + 21.3 + 21.2) / 3.0 - 20.0,
        misalignment_um: 0.3,
        eve_um: 0.4,
    }
}

fn laser_result() -> Iso2302Result {
    let test = evaluate_file(format!("{ROOT}/{RTL}"), &TemperatureOptions::default()).unwrap();
    assert!(!test.temperature_correction.is_null(), "the file's material temperature corrects the readings");
    evaluate(&test.data).unwrap()
}

#[test]
fn results_equal_iso230_2_and_each_u_the_annex_a_contributors() {
    let (html, summary) = report("examples/report/vmc3_laser.toml");
    let cli = trueaxis(&["iso230-2", RTL, "--json"]);
    assert!(cli.status.success());
    let cli: serde_json::Value = serde_json::from_slice(&cli.stdout).unwrap();
    let p = &summary["positioning"][0];
    assert_eq!(p["axis"], "X");
    assert_eq!(p["unit"], "um");
    assert!((p["length"].as_f64().unwrap() - 800.0).abs() < 1e-9);
    let result = laser_result();
    let u = positioning_uncertainty(&result, &inputs_by_hand(), false);
    for (symbol, key) in [("A", "A"), ("E", "E"), ("M", "M"), ("R", "R"), ("B", "B")] {
        let value = p["results"][symbol]["value"].as_f64().unwrap();
        let expanded = p["results"][symbol]["expanded_uncertainty"].as_f64().unwrap();
        let from_cli = cli[key].as_f64().unwrap_or_else(|| panic!("iso230-2 --json has no {key}: {cli}"));
        assert!((value - from_cli).abs() < 1e-9, "{symbol}: report {value} vs iso230-2 {from_cli}");
        let by_hand = u.of(symbol).unwrap();
        assert!((expanded - by_hand).abs() < 1e-12, "{symbol}: U {expanded} vs {by_hand}");
        assert!(expanded > 0.0 && expanded < 5.0, "{symbol}: U = {expanded} um is implausible for a 0.8 m laser test");
        // the HTML shows the value rounded by its U, with the unit
        let shown = with_uncertainty(value, Some(expanded), "um", 3);
        assert!(html.contains(&shown), "{symbol}: `{shown}` not in the report");
    }
    // the length-dependent terms: the device's (0.2 + 0.5 x 0.8) / 2 = 0.3 um
    assert!((p["budget"]["measuring device (calibration certificate)"].as_f64().unwrap() - 0.3).abs() < 1e-12);
    assert!(html.contains("<section id=\"positioning\">"));
    assert!(html.contains("ISO 230-2:2014, with the measurement uncertainty of its Annex A"), "method listed");
    assert!(html.contains("L98765"), "the laser's serial number in the instruments");
    assert!(html.contains("0001"), "the machine's serial number from the .rtl");
    // the guard-band decisions from value, U and tolerance
    let tolerances = [("A", 12.0), ("E", 8.0), ("R", 3.0), ("B", 4.0)];
    let items = summary["conformity"].as_array().unwrap();
    assert_eq!(items.len(), tolerances.len());
    for (symbol, tol) in tolerances {
        let item = items
            .iter()
            .find(|i| i["item"].as_str().unwrap().ends_with(&format!(" {symbol} (ISO 230-2)")))
            .unwrap_or_else(|| panic!("{symbol} not decided: {items:?}"));
        let (v, uu) = (item["value"].as_f64().unwrap().abs(), item["expanded_uncertainty"].as_f64().unwrap());
        let expected = if v + uu <= tol {
            "pass"
        } else if v - uu > tol {
            "FAIL"
        } else if v > tol {
            "fails (within U)"
        } else {
            "not proven"
        };
        assert_eq!(item["decision"], expected, "{symbol}: {v} ± {uu} against {tol}");
    }
}

#[test]
fn tolerances_made_to_pass_fail_and_sit_on_the_limit_are_decided_so() {
    let result = laser_result();
    let u = positioning_uncertainty(&result, &inputs_by_hand(), false);
    let base = std::fs::read_to_string(format!("{ROOT}/examples/report/vmc3_laser.toml")).unwrap();
    let base = &base[..base.find("[tolerances.positioning]").unwrap()];
    // A passes with margin, E fails beyond U, R sits on its limit (inside U of it)
    let text = format!(
        "{base}[tolerances.positioning]\nA = {}\nE = {}\nR = {}\n",
        result.a + u.a + 1.0,
        (result.e - u.e - 0.5).max(0.01),
        result.r
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("report.toml");
    std::fs::write(&path, text).unwrap();
    let (_, summary) = report(arg(&path));
    let decision = |symbol: &str| {
        summary["conformity"]
            .as_array()
            .unwrap()
            .iter()
            .find(|i| i["item"].as_str().unwrap().ends_with(&format!(" {symbol} (ISO 230-2)")))
            .unwrap()["decision"]
            .as_str()
            .unwrap()
            .to_string()
    };
    assert_eq!(decision("A"), "pass");
    assert_eq!(decision("E"), "FAIL");
    assert_eq!(decision("R"), "not proven");
    // a tolerance on a result ISO 230-2 does not define is refused with the file named
    std::fs::write(&path, format!("{base}[tolerances.positioning]\nQ = 3\n")).unwrap();
    let out = dir.path().join("bad.html");
    let o = run_report(arg(&path), &out);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("report.toml") && err.contains("tolerances.positioning.Q"), "{err}");
    assert!(!out.exists());
}
