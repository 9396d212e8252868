//! `trueaxis ballbar simulate|identify|iso230-4|tmbb` end to end on the shipped examples
//! (`examples/ballbar/`, the commands of docs/ballbar.md): JSON values against the error files the
//! examples were simulated from, exit status 2 with a one-line message for bad input.

use crate::support::{arg, identify_c600u, json, trueaxis, vmc3, ROOT};

#[test]
fn identify_recovers_the_piges_the_examples_were_simulated_with() {
    // examples/ballbar/A1..C2.csv: simulated from c600u_piges.toml with 0.3 um noise (seed 7). The
    // tolerances are 3 standard deviations of each PIGE at 0.3 um noise: 0.3 x the 1 um standard
    // deviations of the Monte Carlo in crates/trueaxis/tests/it/identify/pige.rs (EY0A 0.99, EZ0A 0.51, EX0C 0.08,
    // EY0C 0.99 um; EB0A 8.5, EC0A 16.5, EA0C 1.24, EB0C 8.7 urad): the A-axis orientation from a
    // 90 deg arc is the weakest value, as the thesis found.
    let out = trueaxis(&identify_c600u(&["--json"]));
    let doc = json(&out);
    let sd_at_1_um = [
        ("EY0A", 35.3, 0.99),
        ("EZ0A", -33.4, 0.51),
        ("EX0C", 1.3, 0.08),
        ("EY0C", -52.9, 0.99),
        ("EB0A", -6.25, 8.5),
        ("EC0A", 5.8, 16.5),
        ("EA0C", -108.0, 1.24),
        ("EB0C", 21.7, 8.7),
    ];
    let truth = sd_at_1_um.map(|(name, value, sd)| (name, value, 3.0 * 0.3 * sd));
    for (name, value, tol) in truth {
        let got = doc["parameters"][name]["value"].as_f64().unwrap();
        assert!((got - value).abs() < tol, "{name}: {got} vs {value}");
    }
    // The normal-bar steps leave the 0.3 um noise; the extended-bar ones also the error of the
    // identified orientation times D = 111.8 mm (the PIGEs are two circle centres, not a fit of
    // each trace): below the warning threshold of identify (3 x --noise, 1 um by default).
    for step in doc["compensation_residual"].as_array().unwrap() {
        let rms = step["rms_um"].as_f64().unwrap();
        let extended = step["step"] == "A2" || step["step"] == "C2";
        let range = if extended { 0.2..1.0 } else { 0.2..0.45 };
        assert!(range.contains(&rms), "{step}: the residual is the 0.3 um noise");
    }
    assert!(doc["warnings"].as_array().unwrap().is_empty());
}

#[test]
fn iso230_4_example_gives_the_simulated_diagnostics() {
    // examples/ballbar/vmc3_xy.csv: simulated from vmc3_circle.toml with 0.1 um noise.
    let out = trueaxis(&vmc3(
        &["ballbar", "iso230-4", "examples/ballbar/vmc3_xy.csv"],
        &["--radius", "100", "--centre", "0,0,-200", "--feed", "1000", "--pitch", "10", "--json"],
    ));
    let doc = json(&out);
    // a term refitted out as not significant (listed in "omitted") counts as 0
    let value = |name: &str| match doc["diagnostics"].as_array().unwrap().iter().find(|d| d["name"] == name) {
        Some(d) => d["value"].as_f64().unwrap(),
        None => {
            let omitted = doc["omitted"].as_array().unwrap();
            assert!(omitted.iter().any(|o| o.as_str().unwrap().starts_with(&format!("{name}: not significant"))), "{name}: {omitted:?}");
            0.0
        }
    };
    for (name, truth, tol) in [
        ("squareness", 25.0, 0.5),
        ("scale mismatch", 18.0, 0.5),
        ("backlash X", 3.0, 0.1),
        ("backlash Y", 2.0, 0.1),
        ("lateral play X", 1.2, 0.1),
        ("straightness Y", 1.0, 0.1),
        ("reversal spike X", 0.0, 0.2),
    ] {
        assert!((value(name) - truth).abs() < tol, "{name}: {} vs {truth}", value(name));
    }
    assert_eq!(doc["runs"].as_array().unwrap().len(), 2);
    assert!(doc["H_um"].as_f64().unwrap() > 2.0);
}

#[test]
fn tmbb_example_recovers_table_5_2_values() {
    let doc = json(&trueaxis(&[
        "ballbar",
        "tmbb",
        "--short",
        "examples/ballbar/tmbb_L1.csv",
        "--long",
        "examples/ballbar/tmbb_L2.csv",
        "--json",
    ]));
    for fit in ["l2", "linf"] {
        assert!((doc[fit]["E_x"]["value"].as_f64().unwrap() - 7.93).abs() < 0.05);
        assert!((doc[fit]["E_y"]["value"].as_f64().unwrap() - 7.38).abs() < 0.05);
        assert!((doc[fit]["D_z"]["value"].as_f64().unwrap() - 2.68).abs() < 0.01);
    }
    assert!((doc["condition_number"]["m_rad"].as_f64().unwrap() - 19.96).abs() < 0.01);
    let names: Vec<&str> = doc["unidentifiable"].as_array().unwrap().iter().map(|u| u["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["D_x", "D_y", "E_z"]);
}

#[test]
fn simulate_writes_a_trace_that_identify_reads() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c1.csv");
    let p = arg(&path);
    let out = trueaxis(&[
        "ballbar",
        "simulate",
        "--machine",
        "examples/machines/c600u.toml",
        "--errors",
        "examples/ballbar/c600u_piges.toml",
        "--test",
        "c1",
        "--step",
        "5",
        "--out",
        p,
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().nth(1).unwrap(), "X,Y,Z,A,C,angle,dir,dL");
    assert_eq!(text.lines().count(), 2 + 72);
    // C1: dL = e_x0c cos c + (e_y0c + e_y0a) sin c (Jiang 2014, digest 2.5): at c = 90 deg, -17.6 um
    let at_90 = text.lines().find(|l| l.starts_with("0,0,0,0,90,")).unwrap();
    let dl: f64 = at_90.rsplit(',').next().unwrap().parse().unwrap();
    assert!((dl - (-52.9 + 35.3)).abs() < 0.01, "{dl}");
}

#[test]
fn iso230_4_on_a_partial_arc_leaves_out_what_it_cannot_separate() {
    // the first quarter of the ccw circle of vmc3_xy.csv (angles 0.5 ... 89.5 deg): the evaluation
    // runs and omits the inseparable terms (A1.csv, a rotary-axis test, is no XY arc: refused below)
    let root = std::path::Path::new(ROOT);
    let text = std::fs::read_to_string(root.join("examples/ballbar/vmc3_xy.csv")).unwrap();
    let quarter: Vec<&str> = text.lines().take(2 + 90).collect();
    let path = std::env::temp_dir().join(format!("trueaxis-quarter-{}.csv", std::process::id()));
    std::fs::write(&path, quarter.join("\n") + "\n").unwrap();
    let doc = json(&trueaxis(&["ballbar", "iso230-4", arg(&path), "--radius", "100", "--json"]));
    let _ = std::fs::remove_file(&path);
    assert!((doc["runs"][0]["arc_deg"].as_f64().unwrap() - 89.0).abs() < 1e-9, "{}", doc["runs"][0]["arc_deg"]);
    assert!(doc["omitted"].as_array().unwrap().iter().any(|o| o.as_str().unwrap().contains("not separable")));
}

#[test]
fn bad_input_is_one_line_and_exit_2() {
    let cases: [&[&str]; 4] = [
        &["ballbar", "tmbb", "--short", "examples/ballbar/tmbb_L1.csv", "--long", "examples/ballbar/A1.csv"],
        &["ballbar", "iso230-4", "examples/ballbar/tmbb_poses.csv", "--radius", "100"],
        &vmc3(&["ballbar", "simulate"], &["--test", "a1"]),
        &["ballbar", "iso230-4", "examples/ballbar/vmc3_xy.csv", "--radius", "100", "--pitch", "0"],
    ];
    for args in cases {
        let out = trueaxis(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("trueaxis: error: "), "{err}");
    }
}

/// Screening (docs/screening.md): the rotary-axis test A1 (X, Y, Z still, A sweeping) is no XY
/// circle; `ballbar iso230-4` refuses it with exit 2 naming the columns, instead of a squareness
/// of thousands of urad. The clean circle has an empty `data_quality`.
#[test]
fn iso230_4_refuses_a_rotary_axis_file_and_reports_clean_circles_clean() {
    let out = trueaxis(&["ballbar", "iso230-4", "examples/ballbar/A1.csv", "--machine", "examples/machines/c600u.toml", "--radius", "100"]);
    assert_eq!(out.status.code(), Some(2));
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(message.contains("examples/ballbar/A1.csv: columns X, Y, A: geometry:") && message.lines().count() == 1, "{message}");
    let doc = json(&trueaxis(&["ballbar", "iso230-4", "examples/ballbar/vmc3_xy.csv", "--radius", "100", "--json"]));
    assert_eq!(doc["data_quality"], serde_json::json!([]));
}
