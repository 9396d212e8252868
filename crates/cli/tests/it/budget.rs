//! `trueaxis budget` end to end: the analysis equals the library's on the same poses, the allocation
//! round trip (allocate -> budget file -> analyse meets the target), the configuration counts and
//! ranking, the miniaturisation findings, the figures and files, and bad input.

use crate::support::{json, trueaxis, trueaxis_in, vmc3, ROOT};
use std::path::Path;
use trueaxis::budget::analyse;
use trueaxis::budget::poses::part_grid;
use trueaxis::budget::spec::{BudgetSpec, KindValues};
use trueaxis::machine::Machine;
use trueaxis::model::{Frame, Setup};

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    (a - b).abs() <= tolerance * b.abs().max(1e-9)
}

#[test]
fn analyse_equals_the_library_and_shows_the_abbe_effect() {
    let out = trueaxis(&vmc3(&["budget", "analyse"], &["--part", "200x150x100", "--part", "600x400x300", "--json"]));
    let doc = json(&out);
    let sets = doc["sets"].as_array().unwrap();
    assert_eq!(sets.len(), 2);
    let machine = Machine::load(Path::new(ROOT).join("examples/machines/vmc3.toml")).unwrap();
    let spec = BudgetSpec::standard(&machine, KindValues::DEFAULT);
    let setup = Setup::of_machine(&machine);
    for (set, size) in sets.iter().zip([[200.0, 150.0, 100.0], [600.0, 400.0, 300.0]]) {
        let user = part_grid(&machine, &setup, size, 5, &[]).unwrap();
        let mut q = vec![0.0; user.len()];
        for (u, x) in user.chunks(3).zip(q.chunks_mut(3)) {
            machine.pose_to_internal(u, x);
        }
        let a = analyse(&machine, &spec, &q, &setup, Frame::Workpiece).unwrap();
        assert_eq!(set["poses"], 125);
        assert!(close(set["rss_um"]["max"].as_f64().unwrap(), a.rss_max().1, 1e-12));
        assert!(close(set["rss_um"]["rms"].as_f64().unwrap(), a.rss_rms, 1e-12));
        assert!(close(set["worst_case_um"]["max"].as_f64().unwrap(), a.worst_max().1, 1e-12));
        assert!(close(set["condition_number"].as_f64().unwrap(), a.condition.unwrap(), 1e-12));
        let shares: f64 = set["by_kind"].as_array().unwrap().iter().map(|g| g["share_percent"].as_f64().unwrap()).sum();
        assert!(close(shares, 100.0, 1e-9));
        let exact = &set["exact_check"];
        assert!(close(exact["exact_um"].as_f64().unwrap(), exact["linear_um"].as_f64().unwrap(), 1e-3));
        // Abbe: X carries the table, its pitch EBX turns the part about y through the X reference point
        // (the workpiece origin): the lever arm at a tool tip (x, y, z) of the part is sqrt(x^2 + z^2),
        // its root mean square over the 5 x 5 x 5 grid sqrt(mean x^2 + mean z^2)
        let mean_square = |lo: f64, hi: f64| (0..5).map(|i| (lo + (hi - lo) * i as f64 / 4.0).powi(2)).sum::<f64>() / 5.0;
        let lever = (mean_square(-size[0] / 2.0, size[0] / 2.0) + mean_square(0.0, size[2])).sqrt();
        let ebx = set["components"].as_array().unwrap().iter().find(|c| c["name"] == "EBX").unwrap();
        assert!(close(ebx["lever_mm"].as_f64().unwrap(), lever, 1e-9), "{ebx} vs {lever} mm");
    }
    // Abbe effect: the larger part moves the tool over longer lever arms, angular errors weigh more
    let angular = |set: &serde_json::Value| {
        set["by_kind"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|g| g["group"] != "linear")
            .map(|g| g["share_percent"].as_f64().unwrap())
            .sum::<f64>()
    };
    assert!(angular(&sets[1]) > angular(&sets[0]));
    // the table output names the groups
    let text = trueaxis(&vmc3(&["budget", "analyse"], &["--part", "200"]));
    let text = String::from_utf8(text.stdout).unwrap();
    for needle in ["root-sum-square, largest", "worst case, largest", "condition number", "squareness", "mm lever"] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
}

#[test]
fn analyse_writes_figures_report_and_tables() {
    let dir = tempfile::tempdir().unwrap();
    let machine = format!("{ROOT}/examples/machines/c600u.toml");
    let out = trueaxis_in(
        dir.path(),
        &[
            "budget",
            "analyse",
            "--machine",
            &machine,
            "--grid",
            "3",
            "--rotary",
            "A=45",
            "--plots",
            "plots",
            "--report",
            "budget.html",
            "--out",
            "poses.csv",
            "--sensitivity",
            "s.csv",
        ],
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for name in ["plots/contributions.svg", "plots/volume_map.svg"] {
        let svg = std::fs::read_to_string(dir.path().join(name)).unwrap();
        roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!svg.contains("NaN"), "{name}");
    }
    let html = std::fs::read_to_string(dir.path().join("budget.html")).unwrap();
    assert!(html.contains("Error budget") && html.contains("<svg") && !html.contains("NaN"));
    let poses = std::fs::read_to_string(dir.path().join("poses.csv")).unwrap();
    assert_eq!(poses.lines().count(), 1 + 27);
    assert!(poses.lines().nth(1).unwrap().contains(",45,"), "{poses}");
    let s = std::fs::read_to_string(dir.path().join("s.csv")).unwrap();
    assert_eq!(s.lines().count(), 1 + 3 * 27);
    // set, pose, 5 axes, direction, 41 components
    assert_eq!(s.lines().next().unwrap().split(',').count(), 2 + 5 + 1 + 41);
}

#[test]
fn allocation_round_trip_meets_the_target() {
    let dir = tempfile::tempdir().unwrap();
    let machine = format!("{ROOT}/examples/machines/vmc3.toml");
    let doc = json(&trueaxis_in(
        dir.path(),
        &[
            "budget",
            "allocate",
            "--machine",
            &machine,
            "--part",
            "300x200x150",
            "--part-nodes",
            "3",
            "--target-um",
            "10",
            "--out",
            "alloc.toml",
            "--json",
        ],
    ));
    assert!(doc["kkt_residual"].as_f64().unwrap() < 1e-6);
    assert!(doc["cost"].as_f64().unwrap() <= doc["global_stage_cost"].as_f64().unwrap());
    assert!(!doc["active"].as_array().unwrap().is_empty());
    let check = json(&trueaxis_in(
        dir.path(),
        &["budget", "analyse", "--machine", &machine, "--part", "300x200x150", "--part-nodes", "3", "--budget", "alloc.toml", "--json"],
    ));
    let largest = check["sets"][0]["rss_um"]["max"].as_f64().unwrap();
    assert!(close(largest, 10.0, 1e-6), "largest RSS 3D error {largest} um after allocating for 10 um");
    // same seed, same tolerances; the written budget file keeps the components
    let again = json(&trueaxis_in(
        dir.path(),
        &["budget", "allocate", "--machine", &machine, "--part", "300x200x150", "--part-nodes", "3", "--target-um", "10", "--json"],
    ));
    assert_eq!(doc["components"], again["components"]);
    let text = std::fs::read_to_string(dir.path().join("alloc.toml")).unwrap();
    assert!(text.contains("EC0X = ") && text.contains("[cost.table]"));
}

#[test]
fn configurations_reproduce_the_counts_and_rank() {
    let doc = json(&trueaxis(&["budget", "configurations", "--part", "100", "--tool-length", "100", "--nodes", "2", "--json"]));
    let counts = &doc["counts"];
    assert_eq!((counts["five_of_six_axes"].as_u64(), counts["three_linear_axes"].as_u64()), (Some(720), Some(360)));
    assert_eq!((counts["three_categories"].as_u64(), counts["five_degrees_of_freedom"].as_u64()), (Some(432), Some(288)));
    let ranking = doc["ranking"].as_array().unwrap();
    assert_eq!(ranking.len(), 288);
    for pair in ranking.windows(2) {
        assert!(pair[0]["rss_rms_um"].as_f64().unwrap() <= pair[1]["rss_rms_um"].as_f64().unwrap());
    }
    let travel = doc["travel"].as_array().unwrap();
    // three categories x the four orders of rotary axes with five degrees of freedom (AB, BA, CA, CB)
    assert_eq!(travel.len(), 12);
    let xyzab = travel.iter().find(|t| t["axes"] == "XYZAB").unwrap();
    for t in xyzab["travel_mm"].as_array().unwrap() {
        assert!(close(t.as_f64().unwrap(), 200.0, 1e-9), "{xyzab}"); // p + l (Table C.2)
    }
}

#[test]
fn miniaturisation_reproduces_the_findings() {
    let doc = json(&trueaxis(&["budget", "miniaturisation", "--sizes", "10,300", "--json"]));
    let sizes = doc["sizes"].as_array().unwrap();
    let share = |s: &serde_json::Value, key: &str, group: &str| {
        s[key].as_array().unwrap().iter().find(|g| g["group"] == group).unwrap()["share_percent"].as_f64().unwrap()
    };
    assert!(share(&sizes[0], "by_kind", "linear") > 90.0);
    assert!(share(&sizes[1], "by_kind", "linear") < 50.0);
    assert!(share(&sizes[1], "by_axis", "X") > share(&sizes[1], "by_axis", "Z"));
    assert!(sizes[1]["ri1"].as_f64().unwrap() > sizes[0]["ri1"].as_f64().unwrap());
}

#[test]
fn bad_input_is_refused_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.toml"), "[tolerance]\nEXC = 1\n").unwrap();
    std::fs::write(dir.path().join("high.toml"), "[cost.lower]\nlinear = 50\n").unwrap();
    let machine = format!("{ROOT}/examples/machines/vmc3.toml");
    for (args, code, needle) in [
        (vec!["budget", "analyse", "--machine", "nope.toml"], 2, "nope.toml"),
        (vec!["budget", "analyse", "--machine", &machine, "--budget", "bad.toml"], 2, "bad.toml: [tolerance]: EXC refers to axis C"),
        (vec!["budget", "analyse", "--machine", &machine, "--part", "0x1x1"], 2, "not a part size"),
        (vec!["budget", "analyse", "--machine", &machine, "--part", "2000"], 2, "does not fit"),
        (vec!["budget", "analyse", "--machine", &machine, "--rotary", "C=10"], 2, "no rotary axis C"),
        (vec!["budget", "allocate", "--machine", &machine, "--target-um", "-1"], 2, "positive"),
        (vec!["budget", "allocate", "--machine", &machine, "--budget", "high.toml", "--target-um", "5"], 1, "lower limits alone"),
        (vec!["budget", "configurations", "--tool-length", "0"], 2, "--tool-length"),
    ] {
        let out = trueaxis_in(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty());
    }
}
