//! The geometric-thermal model of NISTIR 5236 (NISTIR 5236 §3.6) from the command line: a simulated
//! characterisation of a slide (five back-and-forth runs per spindle speed through a warm-up) whose
//! positioning error differs by direction of travel and between two position ranges, with a
//! thermal part driven by a bed temperature and the spindle speed. `thermal fit --by-direction
//! --ranges --geometric-degree 2 --degree 1` recovers the coefficients of every segment; the model
//! validates on a run at another spindle speed; its error terms through `predict` equal `thermal
//! predict`. And the geometric/thermal split alone (Zhu 2008 §4.4.2): a cubic geometric part with a
//! linear thermal part.

use crate::support::{arg, json, ok, trueaxis, vmc3};
use std::fmt::Write;

/// Truth of the segment (direction, range): geometric quadratic [a0, a1, a2] (um, um/mm, um/mm^2)
/// and thermal rows [c_bed, c_S] for P^0 and P^1 (um/degC, um/rpm, per mm).
fn truth(plus: bool, upper: bool) -> ([f64; 3], [[f64; 2]; 2]) {
    let hysteresis = if plus { 1.2 } else { -1.2 };
    match upper {
        false => ([hysteresis - 0.5, 0.012, -2.0e-5], [[0.8, 3.0e-4], [0.004, 1.0e-6]]),
        true => ([hysteresis + 1.5, 0.002, -1.0e-5], [[0.9, 2.5e-4], [0.003, 1.5e-6]]),
    }
}

fn error(x: f64, plus: bool, bed: f64, spindle: f64) -> f64 {
    let (g, t) = truth(plus, x >= 200.0);
    g[0] + g[1] * x + g[2] * x * x + (t[0][0] * bed + t[0][1] * spindle) + x * (t[1][0] * bed + t[1][1] * spindle)
}

/// Campaign CSV: runs at 1000, 3000, 5000 rpm (training) and 4000 rpm (validation); 5 back-and-forth
/// runs of X over 0..400 mm in 20 mm steps through a warm-up of the bed; noise 0.05 um.
fn campaign(noise: f64) -> String {
    let mut text = String::from("run,t,X,dir,T:bed,S:spindle,dx\n");
    let mut gauss = crate::support::thermal::normal(7);
    for rpm in [1000.0, 3000.0, 5000.0, 4000.0] {
        let mut t = 0.0;
        for cycle in 0..5 {
            for (plus, steps) in [(true, (0..=20).collect::<Vec<i32>>()), (false, (0..=20).rev().collect())] {
                for k in steps {
                    let x = 20.0 * k as f64;
                    let bed = 20.0 + 4.0 * (1.0 - (-t / 5400.0_f64).exp()) * (rpm / 5000.0) + 0.1 * cycle as f64;
                    let dx = error(x, plus, bed, rpm) + noise * gauss();
                    let _ = writeln!(text, "s{rpm},{t},{x},{},{bed:.9},{rpm},{dx:.9}", if plus { "+" } else { "-" });
                    t += 30.0;
                }
            }
        }
    }
    text
}

/// `thermal fit` of `data`'s dx on T:bed and S:spindle in four segments (by direction, the ranges
/// split at X = 200 mm), geometric degree 2 and thermal degree 1, trained on the runs at 1000, 3000
/// and 5000 rpm; then `more`.
fn segments_fit<'a>(data: &'a str, more: &[&'a str]) -> Vec<&'a str> {
    let fit = ["thermal", "fit", "--data", data, "--error", "dx", "--sensors", "T:bed,S:spindle", "--position", "X", "--by-direction"];
    let degrees = ["--ranges", "200", "--geometric-degree", "2", "--degree", "1", "--train-runs", "s1000,s3000,s5000"];
    [&fit[..], &degrees, more].concat()
}

#[test]
fn gt_segments_are_recovered_and_enter_the_chain() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("gt.csv");
    std::fs::write(&data, campaign(0.0)).unwrap();
    let model = dir.path().join("gt.toml");
    let terms = dir.path().join("gt_terms.toml");
    let more =
        ["--out", arg(&model), "--parameter", "EXX", "--terms-out", arg(&terms), "--machine", "examples/machines/vmc3.toml", "--json"];
    let doc = json(&trueaxis(&segments_fit(arg(&data), &more)));
    let segments = doc["model"]["segment"].as_array().unwrap();
    assert_eq!(segments.len(), 4);
    for s in segments {
        let plus = s["direction"] == "+";
        // JSON has no infinity: the open ends are null
        let upper = s["range"][0].as_f64() == Some(200.0);
        assert!(if upper { s["range"][1].is_null() } else { s["range"][0].is_null() });
        let (g, t) = truth(plus, upper);
        let c: Vec<Vec<f64>> = serde_json::from_value(s["coefficients"].clone()).unwrap();
        // rows: [a_k, c_k,bed, c_k,S] for k = 0, 1, 2 (no thermal term at k = 2)
        let want = [[g[0], t[0][0], t[0][1]], [g[1], t[1][0], t[1][1]], [g[2], 0.0, 0.0]];
        for k in 0..3 {
            for j in 0..3 {
                let tol = 1e-5 * want[k][j].abs() + 1e-12;
                assert!((c[k][j] - want[k][j]).abs() < tol, "{s}: row {k} col {j}: {} vs {}", c[k][j], want[k][j]);
            }
        }
    }
    // validation at 4000 rpm: exact model, residual at the rounding of the file (1e-9)
    assert!(doc["validation"]["s4000"]["max_abs"].as_f64().unwrap() < 1e-6);
    // the terms through the kinematic chain: EXX of vmc3 moves the tool by -EXX along x (X
    // carries the table, direction -1), per pose with its direction and inputs
    let text = std::fs::read_to_string(&terms).unwrap();
    assert!(text.contains("[[term.\"EXX+\"]]") && text.contains("range = [-inf, 200.0]") && text.contains("\"S:spindle\" = 1"), "{text}");
    let mut poses = String::from("X,Y,Z,dir:X,T:bed,S:spindle\n");
    let states = [(35.0, true, 21.3, 4000.0), (199.0, false, 23.9, 1200.0), (200.0, true, 20.4, 0.0), (380.0, false, 22.2, 4800.0)];
    for (x, plus, bed, s) in states {
        let _ = writeln!(poses, "{x},0,0,{},{bed},{s}", if plus { "+" } else { "-" });
    }
    let poses_path = dir.path().join("poses.csv");
    std::fs::write(&poses_path, poses).unwrap();
    let predicted = json(&trueaxis(&vmc3(&["predict"], &["--errors", arg(&terms), "--poses", arg(&poses_path), "--json"])));
    for ((x, plus, bed, s), p) in states.iter().zip(predicted["poses"].as_array().unwrap()) {
        let want = error(*x, *plus, *bed, *s);
        let dx = p["dx"].as_f64().unwrap();
        assert!((dx.abs() - want.abs()).abs() < 1e-4 && dx * want <= 0.0, "X {x}: dx {dx} vs EXX {want}");
    }
    // thermal predict of the model file reads the dir column and the segments
    let back = json(&trueaxis(&["thermal", "predict", "--model", arg(&model), "--data", arg(&data), "--json"]));
    assert!(back["residuals"]["s4000"]["max_abs"].as_f64().unwrap() < 1e-4);
}

#[test]
fn shipped_campaign_is_the_simulation() {
    // examples/thermal/gt_slide.csv: the same characterisation with 0.05 um of noise
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/thermal/gt_slide.csv");
    let text = format!("# A slide characterised through warm-ups at four spindle speeds (simulated by crates/cli/tests/it/thermal/gt.rs):\n# X (mm), dir (+/-), T:bed (degC), S:spindle (rpm), dx (um, positioning error), noise 0.05 um\n{}", campaign(0.05));
    if std::env::var_os("TRUEAXIS_REGENERATE").is_some() {
        std::fs::write(&path, &text).unwrap();
    }
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
    // the segments fitted to the noisy file predict the 4000 rpm run to the noise
    let doc = json(&trueaxis(&segments_fit("examples/thermal/gt_slide.csv", &["--json"])));
    let rms = doc["validation"]["s4000"]["rms"].as_f64().unwrap();
    assert!((0.04..0.07).contains(&rms), "{rms}");
}

#[test]
fn geometric_thermal_split_has_its_own_degrees() {
    // E = cubic geometric part + (c0 + c1 P) T: degree 3 and 1; a common degree 3 for both would
    // fit two spurious thermal terms, a common degree 1 could not follow the geometry
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("run,t,X,T:a,dx\n");
    let geometric = |x: f64| 2.0 + 0.01 * x - 4.0e-5 * x * x + 6.0e-8 * x * x * x;
    for (r, amp) in [("a", 3.0), ("b", 5.0)] {
        for k in 0..200 {
            let x = (k % 21) as f64 * 20.0;
            let ta = 20.0 + amp * (1.0 - (-(k as f64) / 60.0).exp());
            let dx = geometric(x) + (0.5 + 0.003 * x) * (ta - 20.0);
            let _ = writeln!(text, "{r},{},{x},{ta:.9},{dx:.9}", 60 * k);
        }
    }
    let data = dir.path().join("split.csv");
    std::fs::write(&data, text).unwrap();
    let doc = json(&trueaxis(&[
        "thermal",
        "fit",
        "--data",
        arg(&data),
        "--error",
        "dx",
        "--position",
        "X",
        "--geometric-degree",
        "3",
        "--degree",
        "1",
        "--train-runs",
        "a",
        "--json",
    ]));
    let c: Vec<Vec<f64>> = serde_json::from_value(doc["model"]["coefficients"].clone()).unwrap();
    // intercepts at T = 0 degC: a_k - 20 c_k; thermal rows c_0 = 0.5, c_1 = 0.003; none beyond
    let want = [[2.0 - 10.0, 0.5], [0.01 - 0.06, 0.003], [-4.0e-5, 0.0], [6.0e-8, 0.0]];
    for k in 0..4 {
        for j in 0..2 {
            assert!((c[k][j] - want[k][j]).abs() < 1e-6 * [1.0, 1e-2, 1e-4, 1e-6][k], "row {k} col {j}: {} vs {}", c[k][j], want[k][j]);
        }
    }
    assert!(doc["validation"]["b"]["max_abs"].as_f64().unwrap() < 1e-5);
    ok(&trueaxis(&["thermal", "fit", "--data", arg(&data), "--error", "dx", "--position", "X", "--degree", "1", "--train-runs", "a"]));
    // refusals: split without a position, segments of a state-space model
    let out = trueaxis(&["thermal", "fit", "--data", arg(&data), "--error", "dx", "--geometric-degree", "3"]);
    assert_eq!(out.status.code(), Some(2));
    let out = trueaxis(&["thermal", "fit", "--data", arg(&data), "--error", "dx", "--position", "X", "--by-direction"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("need the column `dir`"), "{}", String::from_utf8_lossy(&out.stderr));
}
