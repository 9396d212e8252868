//! Raw instrument streams and method planning from the command line: a raw ballbar capture read by
//! `ballbar iso230-4` as its capture arc, `design steady` on a 3D-ball recording, the single-run
//! PIGE uncertainty of `ballbar identify`, `ballbar sensitivity` and `ballbar tmbb-setup`.

use crate::support::{arg, identify_c600u, json_of, trueaxis, utf8, ROOT};
use trueaxis::identify::pige_sensitivity::method_sensitivity;
use trueaxis::instruments::ballbar::{method_step, BarLengths, JiangStep, Method, RotaryPair};
use trueaxis::machine::Machine;

#[test]
fn raw_capture_gives_the_circle_of_its_capture_arc() {
    let iso = |file: &str| {
        json_of(&["ballbar", "iso230-4", file, "--machine", "examples/machines/vmc3.toml", "--centre", "0,0,-200", "--json"])["runs"][0]
            .clone()
    };
    // raw_xy.txt is the counter-clockwise run of export_xy.txt with its feed moves and 45 deg
    // overshoots: the same samples once the capture arc is found (plus the closing sample at 360)
    let (raw, export) = (iso("examples/ballbar/raw_xy.txt"), iso("examples/ballbar/export_xy.txt"));
    assert_eq!(raw["dir"], "ccw");
    assert_eq!(raw["samples"].as_u64().unwrap(), export["samples"].as_u64().unwrap() + 1);
    for key in ["G_um", "F_max_um", "F_min_um"] {
        let (a, b) = (raw[key].as_f64().unwrap(), export[key].as_f64().unwrap());
        assert!((a - b).abs() < 0.01, "{key}: {a} vs {b}");
    }
    for k in 0..2 {
        let (a, b) = (raw["centre_um"][k].as_f64().unwrap(), export["centre_um"][k].as_f64().unwrap());
        assert!((a - b).abs() < 0.01, "centre {k}: {a} vs {b}");
    }
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(format!("{ROOT}/examples/ballbar/raw_xy.txt")).unwrap();
    // without the capture arc in the header: refused, naming the key
    let no_arc = dir.path().join("no_arc.txt");
    std::fs::write(&no_arc, text.replace("Arc: 360 deg\n", "")).unwrap();
    let out = trueaxis(&["ballbar", "iso230-4", arg(&no_arc), "--machine", "examples/machines/vmc3.toml", "--centre", "0,0,-200"]);
    assert_eq!(out.status.code(), Some(2), "{}", utf8(&out.stderr));
    assert!(utf8(&out.stderr).contains("`Arc: <deg>`"), "{}", utf8(&out.stderr));
    // without the overshoot: every sample is taken, and the feed moves are pointed out
    let no_overshoot = dir.path().join("no_overshoot.txt");
    std::fs::write(&no_overshoot, text.lines().filter(|l| !l.starts_with("Overshoot")).collect::<Vec<_>>().join("\n")).unwrap();
    let out = trueaxis(&["ballbar", "iso230-4", arg(&no_overshoot), "--machine", "examples/machines/vmc3.toml", "--centre", "0,0,-200"]);
    assert!(utf8(&out.stderr).contains("state `Overshoot: <deg>`"), "{}", utf8(&out.stderr));
}

#[test]
fn design_steady_reduces_a_recording_to_the_readings_of_its_poses() {
    let dir = tempfile::tempdir().unwrap();
    let out_path = dir.path().join("readings.csv");
    let out = trueaxis(&[
        "design",
        "steady",
        "examples/campaigns/kx8five/stream_20.csv",
        "--poses",
        "examples/campaigns/kx8five/poses_20.csv",
        "--out",
        arg(&out_path),
    ]);
    assert!(out.status.success(), "{}", utf8(&out.stderr));
    assert!(utf8(&out.stderr).contains("20 dwells for 20 poses"), "{}", utf8(&out.stderr));
    let rows = |text: &str| -> Vec<Vec<f64>> {
        text.lines().filter(|l| !l.starts_with('#')).skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect()
    };
    let ours = rows(&std::fs::read_to_string(&out_path).unwrap());
    let truth = rows(&std::fs::read_to_string(format!("{ROOT}/examples/campaigns/kx8five/capball.csv")).unwrap());
    assert_eq!(ours.len(), 20);
    for (o, t) in ours.iter().zip(&truth) {
        assert_eq!(o[..5], t[..5], "the poses are copied");
        // about 80 samples per dwell at 200 Hz: sigma / sqrt(80) = 0.045 um for 0.40 um of noise
        for c in 5..8 {
            assert!((o[c] - t[c]).abs() < 0.25, "{o:?} vs {t:?}");
        }
    }
    // a pose more than the recording holds: refused with the count
    let poses = std::fs::read_to_string(format!("{ROOT}/examples/campaigns/kx8five/poses_20.csv")).unwrap();
    let extra = dir.path().join("poses_21.csv");
    std::fs::write(&extra, format!("{poses}151,0,-200,1,2\n")).unwrap();
    let out = trueaxis(&["design", "steady", "examples/campaigns/kx8five/stream_20.csv", "--poses", arg(&extra)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(utf8(&out.stderr).contains("20 steady stretches found for 21 poses"), "{}", utf8(&out.stderr));
    let out =
        trueaxis(&["design", "steady", "examples/campaigns/kx8five/poses_20.csv", "--poses", "examples/campaigns/kx8five/poses_20.csv"]);
    assert_eq!(out.status.code(), Some(2), "a pose file is no recording: {}", utf8(&out.stderr));
}

#[test]
fn single_run_pige_uncertainty_covers_the_simulated_truth() {
    let doc = json_of(&identify_c600u(&["--json"]));
    // the traces were simulated from c600u_piges.toml with 0.3 um of bar noise
    let truth =
        [("EY0A", 35.3), ("EZ0A", -33.4), ("EB0A", -6.25), ("EC0A", 5.8), ("EX0C", 1.3), ("EY0C", -52.9), ("EA0C", -108.0), ("EB0C", 21.7)];
    for (name, t) in truth {
        let p = &doc["parameters"][name];
        let (v, u) = (p["value"].as_f64().unwrap(), p["std_uncertainty"].as_f64().unwrap());
        assert!(u > 0.0 && (v - t).abs() < 4.0 * u.max(0.01), "{name}: {v} +- {u} vs {t}");
    }
}

#[test]
fn sensitivity_and_tmbb_setup_agree_with_the_library_and_the_closed_forms() {
    let doc = json_of(&["ballbar", "sensitivity", "--machine", "examples/machines/c600u.toml", "--json"]);
    let m = Machine::load(format!("{ROOT}/examples/machines/c600u.toml")).unwrap();
    let pair = RotaryPair::of_machine(&m).unwrap();
    let bars = BarLengths { normal: 100.0, extended: 150.0 };
    let steps: Vec<_> = [JiangStep::A1, JiangStep::A2, JiangStep::C1, JiangStep::C2]
        .into_iter()
        .map(|s| (s, method_step(&m, pair, Method::ExtendedBar, s, bars, 1.0).unwrap()))
        .collect();
    let library = method_sensitivity(&m, pair, &steps).unwrap();
    for (k, p) in doc["parameters"].as_array().unwrap().iter().enumerate() {
        let scale = if p["unit"] == "urad" { 1e3 } else { 1.0 };
        let noise = p["noise_per_um"].as_f64().unwrap();
        assert!((noise - library.noise[k] * scale).abs() < 1e-5, "{}", p["name"]);
        for s in p["setup"].as_array().unwrap().iter().filter(|s| s["source"] == "bar length") {
            assert!(s["per_um"].as_f64().unwrap().abs() < 1e-3, "{}: {s}", p["name"]);
        }
    }
    let ey0a = &doc["parameters"][0];
    assert_eq!(ey0a["name"], "EY0A");
    let a1_y = ey0a["setup"].as_array().unwrap().iter().find(|s| s["step"] == "A1" && s["source"] == "tool-side ball Y").unwrap();
    assert!((a1_y["per_um"].as_f64().unwrap().abs() - 1.0).abs() < 0.01, "{a1_y}");
    let doc = json_of(&["ballbar", "tmbb-setup", "--rx-scan", "20:80:20", "--deviations", "1", "--json"]);
    let rx: Vec<f64> = doc["rx"].as_array().unwrap().iter().map(|r| r["rx_mm"].as_f64().unwrap()).collect();
    assert_eq!(rx, [20.0, 40.0, 60.0, 80.0]);
    let u: Vec<f64> = doc["rx"].as_array().unwrap().iter().map(|r| r["u_ex_urad"].as_f64().unwrap()).collect();
    assert!(u.windows(2).all(|w| w[1] < w[0]), "{u:?}");
    let dev =
        |dim: &str| doc["setup_deviations"].as_array().unwrap().iter().find(|d| d["dimension"] == dim).unwrap()["dz_um"].as_f64().unwrap();
    assert!((dev("R_z") - 1000.0).abs() < 0.01 && (dev("H") + 1000.0).abs() < 0.01 && dev("R_x").abs() < 0.01);
    let out = trueaxis(&["ballbar", "tmbb-setup", "--rx-scan", "20:95:5"]);
    assert_eq!(out.status.code(), Some(2), "a radius beyond the short bar is refused");
}
