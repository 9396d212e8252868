//! `trueaxis iso230-2`: ISO 230-2:2014 positioning accuracy from bidirectional runs.
//! (1) a hand-calculated data set, (2) synthetic data with a known line, backlash and bounded noise,
//! (3) bad input through the binary, (4) the JSON contract, (5) the SVG plot; plus the shipped example.

use crate::support::{arg, failed, trueaxis, ROOT};
use std::path::Path;
use trueaxis::evaluate::iso230_2::{evaluate, read_runs, read_runs_from, Iso2302Result};

const EXAMPLE: &str = "examples/data/iso230_2_x.csv";

fn evaluate_text(text: &str) -> Iso2302Result {
    evaluate(&read_runs_from(text.as_bytes(), "test.csv").unwrap()).unwrap()
}

fn close(name: &str, got: f64, want: f64, tol: f64) {
    assert!((got - want).abs() <= tol, "{name}: got {got}, want {want} (tolerance {tol})");
}

// ---------------------------------------------------------------------------------------------
// (1) Hand-calculated: 3 targets x 3 runs x 2 directions (deviations in um).
//
// target 0 mm:   + : 1, 2, 3   mean 2, s = sqrt((1 + 0 + 1)/2) = 1
//                - : -1, 0, 1  mean 0, s = 1
//                B_0 = 2, mean 1, R_0+ = 4, R_0- = 4, R_0 = max(2 + 2 + 2, 4, 4) = 6
// target 100 mm: + : 4, 4, 4   mean 4, s = 0
//                - : 0, 2, 4   mean 2, s = sqrt((4 + 0 + 4)/2) = 2
//                B_1 = 2, mean 3, R_1+ = 0, R_1- = 8, R_1 = max(0 + 4 + 2, 0, 8) = 8
// target 200 mm: + : -2, -1, 0 mean -1, s = 1
//                - : 1, 1, 4   mean 2, s = sqrt((1 + 1 + 4)/2) = sqrt(3)
//                B_2 = -3, mean 0.5, R_2+ = 4, R_2- = 4 sqrt(3) = 6.928,
//                R_2 = max(2 + 2 sqrt(3) + 3, 4, 4 sqrt(3)) = 5 + 2 sqrt(3) = 8.464
// axis: B = max|B_i| = 3, B_mean = (2 + 2 - 3)/3 = 1/3
//       R+ = 4, R- = 8, R = 5 + 2 sqrt(3)
//       E+ = 4 - (-1) = 5, E- = 2 - 0 = 2, E = max(2, 4, 2) - min(0, 2, -1) = 4 - (-1) = 5
//       M = 3 - 0.5 = 2.5
//       A+ = max(2 + 2, 4 + 0, -1 + 2) - min(2 - 2, 4 - 0, -1 - 2) = 4 - (-3) = 7
//       A- = max(0 + 2, 2 + 4, 2 + 2 sqrt(3)) - min(0 - 2, 2 - 4, 2 - 2 sqrt(3)) = 6 - (-2) = 8
//       A  = max(4, 6) - min(-3, -2) = 9
//
// The file mixes the order of the rows, pads fields with blanks, has comments and an extra column,
// and writes one of the 100 mm targets as 100.0000004 (grouped with 100 within 1e-6 mm).
const HAND: &str = "\
# hand-calculated ISO 230-2 example
 target , dev , dir , run , note
200, 1, -, 1, x
200, 1, -, 2, x
200, 4, -, 3, x
0, 1, +, 1, first
0, 2, +, 2,
0, 3, +, 3,
# the - runs at 0
0, -1, -, 1,
0, 0, -, 2,
0, 1, -, 3,
100, 4, +, 1,
100.0000004, 4, +, 2,
100, 4, +, 3,
100, 0, -, 1,
100, 2, -, 2,
100, 4, -, 3,
200, -2, +, 1,
200, -1, +, 2,
200, 0, +, 3,
";

#[test]
fn hand_calculated_data_set() {
    let r = evaluate_text(HAND);
    let tol = 1e-9;
    let s3 = 3f64.sqrt();
    assert_eq!(r.positions.len(), 3);
    assert_eq!(r.runs, 3);
    // per position: (target, mean+, mean-, mean, s+, s-, B_i, R_i+, R_i-, R_i)
    let want = [
        [0.0, 2.0, 0.0, 1.0, 1.0, 1.0, 2.0, 4.0, 4.0, 6.0],
        [100.0, 4.0, 2.0, 3.0, 0.0, 2.0, 2.0, 0.0, 8.0, 8.0],
        [200.0, -1.0, 2.0, 0.5, 1.0, s3, -3.0, 4.0, 4.0 * s3, 5.0 + 2.0 * s3],
    ];
    for (p, w) in r.positions.iter().zip(&want) {
        let got = [p.target, p.mean_plus, p.mean_minus, p.mean, p.s_plus, p.s_minus, p.reversal, p.r_plus, p.r_minus, p.r];
        for (k, (g, w)) in got.iter().zip(w).enumerate() {
            close(&format!("target {} value {k}", w), *g, *w, if k == 0 { 1e-6 } else { tol });
        }
        assert_eq!((p.n_plus, p.n_minus), (3, 3));
    }
    close("B", r.b, 3.0, tol);
    close("B_mean", r.b_mean, 1.0 / 3.0, tol);
    close("R+", r.r_plus, 4.0, tol);
    close("R-", r.r_minus, 8.0, tol);
    close("R", r.r, 5.0 + 2.0 * s3, tol);
    close("E+", r.e_plus, 5.0, tol);
    close("E-", r.e_minus, 2.0, tol);
    close("E", r.e, 5.0, tol);
    close("M", r.m, 2.5, tol);
    close("A+", r.a_plus, 7.0, tol);
    close("A-", r.a_minus, 8.0, tol);
    close("A", r.a, 9.0, tol);
}

// ---------------------------------------------------------------------------------------------
// (2) Synthetic: dev = 0.01 um/mm * target + 1.5 um (+ runs) or - 1.5 um (- runs) + noise, the
// noise uniform in [-a, a] from a fixed-seed LCG. 21 targets over 0..1000 mm, 5 runs each way.
// Known: mean+ = 0.01 x + 1.5, mean- = 0.01 x - 1.5, so B_i = 3, E+ = E- = M = 10 (the line over
// 1000 mm), E = 13, and without noise s = 0, R = |B_i| = 3, R+- = 0, A = E, A+- = E+-.
// With noise, every mean is within a of its true value (a mean of values within a), so B, B_mean,
// E, E+, E-, M are within 2a of the above; every s <= a sqrt(n/(n-1)) (largest sample standard
// deviation of n values in an interval of width 2a), so R+-, = 4 s <= 4 a sqrt(5/4), R lies in
// [3 - 2a, 3 + 2a + 4 s_max] and A lies in [E, E + 4 s_max], likewise for the directions.

struct Lcg(u64);

impl Lcg {
    /// Uniform in [-1, 1).
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

fn synthetic(noise: f64, seed: u64) -> String {
    let mut rng = Lcg(seed);
    let mut text = String::from("# synthetic: 0.01 um/mm, backlash 3 um\ntarget,dev,dir,run\n");
    for run in 1..=5 {
        for (dir, offset) in [("+", 1.5), ("-", -1.5)] {
            for i in 0..=20 {
                let x = 50.0 * i as f64;
                text += &format!("{x},{:.12},{dir},{run}\n", 0.01 * x + offset + noise * rng.next());
            }
        }
    }
    text
}

/// The results the known line and backlash of [`synthetic`] fix whatever the noise: (name, result,
/// value without noise).
fn line_and_backlash(r: &Iso2302Result) -> [(&'static str, f64, f64); 6] {
    [("B", r.b, 3.0), ("B_mean", r.b_mean, 3.0), ("E+", r.e_plus, 10.0), ("E-", r.e_minus, 10.0), ("E", r.e, 13.0), ("M", r.m, 10.0)]
}

#[test]
fn synthetic_without_noise_is_exact() {
    let r = evaluate_text(&synthetic(0.0, 1));
    let tol = 1e-9;
    assert_eq!((r.positions.len(), r.runs), (21, 5));
    let spread =
        [("R", r.r, 3.0), ("R+", r.r_plus, 0.0), ("R-", r.r_minus, 0.0), ("A", r.a, 13.0), ("A+", r.a_plus, 10.0), ("A-", r.a_minus, 10.0)];
    for (name, got, want) in line_and_backlash(&r).into_iter().chain(spread) {
        close(name, got, want, tol);
    }
    for p in &r.positions {
        close("x̄_i", p.mean, 0.01 * p.target, tol);
    }
}

#[test]
fn synthetic_with_noise_follows_the_known_line_and_backlash() {
    let a = 0.2;
    let s_max = a * (5.0f64 / 4.0).sqrt();
    let slack = 1e-9;
    for seed in [7, 2302, 99991] {
        let r = evaluate_text(&synthetic(a, seed));
        for (name, got, want) in line_and_backlash(&r) {
            close(name, got, want, 2.0 * a + slack);
        }
        for p in &r.positions {
            close("B_i", p.reversal, 3.0, 2.0 * a + slack);
            close("x̄_i", p.mean, 0.01 * p.target, a + slack);
            assert!(p.s_plus > 0.0 && p.s_plus <= s_max + slack && p.s_minus > 0.0 && p.s_minus <= s_max + slack);
        }
        assert!(r.r_plus > 0.0 && r.r_plus <= 4.0 * s_max + slack, "R+ {}", r.r_plus);
        assert!(r.r_minus > 0.0 && r.r_minus <= 4.0 * s_max + slack, "R- {}", r.r_minus);
        assert!(r.r >= 3.0 - 2.0 * a - slack && r.r <= 3.0 + 2.0 * a + 4.0 * s_max + slack, "R {}", r.r);
        for (name, acc, sys) in [("A", r.a, r.e), ("A+", r.a_plus, r.e_plus), ("A-", r.a_minus, r.e_minus)] {
            assert!(acc >= sys - slack && acc <= sys + 4.0 * s_max + slack, "{name} {acc} vs E {sys}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// (3) Bad input through the binary: exit status 2, one line on stderr naming the file (and line).

fn refuse(dir: &Path, name: &str, text: &str, expected: &[&str]) {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let out = trueaxis(&["iso230-2", arg(&path)]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
    assert!(out.stdout.is_empty(), "{name}: printed {}", String::from_utf8_lossy(&out.stdout));
    assert_eq!(stderr.trim_end().lines().count(), 1, "{name}: not one line: {stderr}");
    assert!(stderr.contains(arg(&path)), "{name}: file not named: {stderr}");
    for e in expected {
        assert!(stderr.contains(e), "{name}: `{e}` not in: {stderr}");
    }
}

#[test]
fn bad_input_is_refused_with_one_line_and_status_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = "target,dev,dir,run\n0,1,+,1\n0,2,+,2\n0,0,-,1\n0,1,-,2\n";
    assert!(evaluate(&read_runs_from(good.as_bytes(), "good").unwrap()).is_ok());
    refuse(d, "missing.csv", "target,dev,dir\n0,1,+\n", &["missing column `run`"]);
    refuse(
        d,
        "few.csv",
        "target,dev,dir,run\n0,1,+,1\n0,2,+,2\n100,0,+,1\n100,1,+,2\n100,0,-,1\n0,0,-,1\n0,1,-,2\n",
        &["line 4", "target 100 mm", "1 run(s) in the - direction"],
    );
    refuse(d, "onedir.csv", "target,dev,dir,run\n0,1,+,1\n0,2,+,2\n", &["line 2", "target 0 mm", "0 run(s) in the - direction"]);
    refuse(
        d,
        "dir.csv",
        "target,dev,dir,run\n0,1,+,1\n# comment\n0,2,sideways,2\n0,0,-,1\n0,1,-,2\n",
        &["line 4", "column dir", "`sideways`"],
    );
    refuse(
        d,
        "duplicate.csv",
        "target,dev,dir,run\n0,1,+,1\n0,2,+,2\n0,0,-,1\n0,1,-,2\n0.0000001,3,+,2\n",
        &["line 6", "run 2 is given twice", "first on line 3"],
    );
    refuse(d, "number.csv", "target,dev,dir,run\n0,1,+,1\n0,abc,+,2\n0,0,-,1\n0,1,-,2\n", &["line 3", "column dev", "`abc`"]);
    refuse(d, "run.csv", "target,dev,dir,run\n0,1,+,1\n0,2,+,2.5\n0,0,-,1\n0,1,-,2\n", &["line 3", "column run"]);
    refuse(d, "empty.csv", "target,dev,dir,run\n", &["no data"]);
    refuse(d, "blank.csv", "target,dev,dir,run\n0,1,+,1\n\n# comment\n\n0,2,+,x\n0,0,-,1\n0,1,-,2\n", &["line 6", "column run", "`x`"]);
    let out = trueaxis(&["iso230-2", d.join("absent.csv").to_str().unwrap()]);
    failed(&out, 2, &["absent.csv"]);
}

#[test]
fn readings_too_large_to_be_deviations_are_bad_input_with_status_2() {
    // 1e308 um would overflow the evaluation (status 1); the plausibility check of the unit refuses
    // them first, naming the column and the fix
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.csv");
    std::fs::write(&path, "target,dev,dir,run\n0,1e308,+,1\n0,1e308,+,2\n0,0,-,1\n0,1,-,2\n").unwrap();
    let out = trueaxis(&["iso230-2", arg(&path), "--json"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        out.stdout.is_empty() && stderr.trim_end().lines().count() == 1 && stderr.contains("huge.csv: line 2: column `dev`"),
        "{stderr}"
    );
}

#[test]
fn fewer_than_five_runs_are_evaluated_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hand.csv");
    std::fs::write(&path, HAND).unwrap();
    let out = trueaxis(&["iso230-2", arg(&path)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("3 target positions from 0.000 to 200.000 mm, 3 runs in each direction"), "{text}");
    assert!(text.contains("note: the ISO 230-2 test cycle approaches each target 5 times"), "{text}");
    assert!(text.lines().any(|l| l.trim_start().starts_with("A ") && l.contains("9.000 um")), "{text}");
}

// ---------------------------------------------------------------------------------------------
// (4) The JSON contract (docs/design.md, Command line), on the shipped example, and agreement with the library.

#[test]
fn json_has_the_contract_keys_and_the_library_values() {
    let out = trueaxis(&["iso230-2", EXAMPLE, "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let keys: std::collections::BTreeSet<&str> = doc.as_object().unwrap().keys().map(String::as_str).collect();
    let contract = ["A", "A_plus", "A_minus", "B", "E", "E_plus", "E_minus", "M", "R", "R_plus", "R_minus"];
    let allowed_extra =
        ["B_mean", "unit", "position_unit", "targets", "runs", "positions", "metadata", "temperature_correction", "data_quality"];
    for k in contract {
        assert!(doc[k].as_f64().is_some_and(f64::is_finite), "key {k}: {}", doc[k]);
    }
    let expected: std::collections::BTreeSet<&str> = contract.iter().chain(&allowed_extra).copied().collect();
    assert_eq!(keys, expected);
    assert_eq!(doc["unit"], "um");
    assert_eq!(doc["position_unit"], "mm");
    assert!(doc["metadata"].is_object() && doc["temperature_correction"].is_null());
    // the clean example: screening finds nothing (docs/screening.md)
    assert_eq!(doc["data_quality"], serde_json::json!([]));
    assert_eq!(doc["targets"], 11);
    assert_eq!(doc["runs"], 5);

    let lib = evaluate(&read_runs(Path::new(ROOT).join(EXAMPLE)).unwrap()).unwrap();
    for (k, v) in
        contract.iter().zip([lib.a, lib.a_plus, lib.a_minus, lib.b, lib.e, lib.e_plus, lib.e_minus, lib.m, lib.r, lib.r_plus, lib.r_minus])
    {
        close(k, doc[k].as_f64().unwrap(), v, 1e-12);
    }
    let positions = doc["positions"].as_array().unwrap();
    assert_eq!(positions.len(), 11);
    for (p, q) in positions.iter().zip(&lib.positions) {
        close("target", p["target"].as_f64().unwrap(), q.target, 1e-12);
        close("B_i", p["B_i"].as_f64().unwrap(), q.reversal, 1e-12);
        close("R_i", p["R_i"].as_f64().unwrap(), q.r, 1e-12);
        for k in ["mean_plus", "mean_minus", "s_plus", "s_minus", "R_i_plus", "R_i_minus"] {
            assert!(p[k].as_f64().is_some(), "position key {k}");
        }
    }
    // The example was simulated with a backlash of 2.0 um at 0 mm to 2.8 um at 500 mm, a 0.012 um/mm
    // scale error with a 1.4 um bow, and 0.25 um noise: plausibility, not an exact check.
    assert!(lib.b > 2.0 && lib.b < 3.6, "B {}", lib.b);
    assert!(lib.b_mean > 2.0 && lib.b_mean < 3.0, "B_mean {}", lib.b_mean);
    assert!(lib.r_plus < 2.0 && lib.r_minus < 2.0, "R+ {} R- {}", lib.r_plus, lib.r_minus);
    assert!(lib.a > lib.e && lib.e > lib.m, "A {} E {} M {}", lib.a, lib.e, lib.m);
}

#[test]
fn the_table_lists_every_position_and_the_axis_results() {
    let out = trueaxis(&["iso230-2", EXAMPLE]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let lib = evaluate(&read_runs(Path::new(ROOT).join(EXAMPLE)).unwrap()).unwrap();
    assert!(text.contains("ISO 230-2"));
    assert!(text.contains("target (mm)"));
    for p in &lib.positions {
        assert!(text.contains(&format!("{:.3}", p.target)), "target {} missing", p.target);
    }
    for (symbol, _, value) in lib.axis_table() {
        let line = text.lines().find(|l| l.trim_start().starts_with(&format!("{symbol} "))).unwrap_or_else(|| panic!("no {symbol}"));
        assert!(line.contains(&format!("{value:.3} um")), "{line}");
    }
}

// ---------------------------------------------------------------------------------------------
// (5) The plot.

#[test]
fn plot_is_written_with_axis_labels() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("x.svg");
    let out = trueaxis(&["iso230-2", EXAMPLE, "--json", "--plot", arg(&svg)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
    assert!(text.contains("target position (mm)"));
    assert!(text.contains("positional deviation, actual minus target (um)"));
    assert!(!text.contains("NaN"));
    // 55 + readings as circles, 55 - readings as triangles (polygons), plus legend markers
    assert!(text.matches("<circle").count() >= 55);
    // nothing else left in the directory (written atomically)
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

/// `--scale-temperature` / `--scale-expansion` correct every deviation by `-alpha (T - 20) x / 1000`
/// (machine scale, Soons 1993 §3.2.4) before the evaluation: the results equal those of the
/// hand-corrected file; with a temperature column, point by point; an artefact corrects the other way.
#[test]
fn temperature_options_correct_the_deviations_to_20c() {
    let dir = tempfile::tempdir().unwrap();
    let data = read_runs(Path::new(ROOT).join(EXAMPLE)).unwrap();
    // hand corrections: uniform 23.4 degC, and a per-reading temperature 21 + 0.001 * run * target
    let write = |name: &str, body: String| {
        let path = dir.path().join(name);
        std::fs::write(&path, body).unwrap();
        path
    };
    let mut uniform = String::from("target,dev,dir,run\n");
    let mut per_point = String::from("target,dev,dir,run\n");
    let mut with_column = String::from("target,dev,dir,run,T:scale\n");
    for r in &data.readings {
        let t = 21.0 + 0.001 * r.run as f64 * r.target;
        let dir = r.direction.symbol();
        uniform += &format!("{},{},{dir},{}\n", r.target, r.dev - 11.5 * 3.4 * r.target * 1e-3, r.run);
        per_point += &format!("{},{},{dir},{}\n", r.target, r.dev - 11.5 * (t - 20.0) * r.target * 1e-3, r.run);
        with_column += &format!("{},{},{dir},{},{t}\n", r.target, r.dev, r.run);
    }
    let json = |args: &[&str]| -> serde_json::Value {
        let out = trueaxis(args);
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let same = |a: &serde_json::Value, b: &serde_json::Value| {
        for key in ["A", "A_plus", "A_minus", "B", "E", "E_plus", "E_minus", "M", "R", "R_plus", "R_minus"] {
            close(key, a[key].as_f64().unwrap(), b[key].as_f64().unwrap(), 1e-9);
        }
    };
    let (u, p, c) = (write("u.csv", uniform), write("p.csv", per_point), write("c.csv", with_column));
    same(
        &json(&["iso230-2", EXAMPLE, "--json", "--scale-temperature", "23.4", "--scale-expansion", "11.5"]),
        &json(&["iso230-2", arg(&u), "--json"]),
    );
    same(
        &json(&["iso230-2", arg(&c), "--json", "--scale-temperature", "T:scale", "--scale-expansion", "11.5"]),
        &json(&["iso230-2", arg(&p), "--json"]),
    );
    // a warm step gauge instead of a warm scale: the opposite sign, so both together cancel
    let both = json(&[
        "iso230-2",
        EXAMPLE,
        "--json",
        "--scale-temperature",
        "23.4",
        "--scale-expansion",
        "11.5",
        "--artefact-temperature",
        "23.4",
        "--artefact-expansion",
        "11.5",
    ]);
    same(&both, &json(&["iso230-2", EXAMPLE, "--json"]));
    // the correction changes the result: 11.5 * 3.4 um/m over 500 mm is 19.55 um of slope
    let raw = json(&["iso230-2", EXAMPLE, "--json"]);
    let corrected = json(&["iso230-2", arg(&u), "--json"]);
    assert!((raw["E"].as_f64().unwrap() - corrected["E"].as_f64().unwrap()).abs() > 5.0);
    // bad input: a missing column, an expansion without a temperature
    let out = trueaxis(&["iso230-2", EXAMPLE, "--scale-temperature", "T:scale", "--scale-expansion", "11.5"]);
    failed(&out, 2, &["missing column `T:scale`"]);
    let out = trueaxis(&["iso230-2", EXAMPLE, "--scale-expansion", "11.5"]);
    assert_eq!(out.status.code(), Some(2));
}

// ---------------------------------------------------------------------------------------------
// (6) Screening (docs/screening.md): a run typed in mm is named in the printed report and in the
// JSON, with the result without it beside the standard's; the evaluation itself is unchanged.

#[test]
fn a_run_in_mm_is_reported_next_to_the_standard_result() {
    let root = Path::new(ROOT);
    let text = std::fs::read_to_string(root.join(EXAMPLE)).unwrap();
    let damaged: String = text
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            if f.len() == 5 && f[3] == "4" {
                format!("{},{},{},{},{}\n", f[0], f[1].parse::<f64>().unwrap() / 1000.0, f[2], f[3], f[4])
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let dir = std::env::temp_dir().join(format!("trueaxis-iso230-2-screening-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run4_mm.csv");
    std::fs::write(&path, &damaged).unwrap();
    let p = arg(&path);
    let out = trueaxis(&["iso230-2", p]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let printed = String::from_utf8(out.stdout).unwrap();
    assert!(printed.contains("data quality (1 finding(s), docs/screening.md):"), "{printed}");
    assert!(
        printed.contains(&format!("{p}: run 4 (lines ")) && printed.contains(": unit: ") && printed.contains("without run 4"),
        "{printed}"
    );
    let json = trueaxis(&["iso230-2", p, "--json"]);
    let doc: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let finding = &doc["data_quality"][0];
    assert_eq!((finding["kind"].as_str(), finding["refused"].as_bool()), (Some("unit"), Some(false)));
    assert_eq!(finding["lines"].as_array().unwrap().len(), 22);
    // the standard's R of every reading, several times the clean one (4.1 um)
    let clean = evaluate(&read_runs(root.join(EXAMPLE)).unwrap()).unwrap();
    assert!(doc["R"].as_f64().unwrap() > 2.0 * clean.r);
    let _ = std::fs::remove_dir_all(&dir);
}
