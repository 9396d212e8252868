//! `trueaxis identify` and `trueaxis design` end to end on the shipped KX8-Five campaign: the JSON
//! contract of docs/design.md, Command line, the error-values output accepted by `predict`, exit statuses,
//! and trajectory + simulation + identification from the command line.

use crate::support::{arg, failed, json, read, trueaxis, ROOT};
use std::path::Path;

const MACHINE: &str = "examples/machines/kx8five.toml";
const CAMPAIGN: &str = "examples/campaigns/kx8five/campaign.toml";

#[test]
fn identify_json_contract_on_the_shipped_campaign() {
    let doc = json(&trueaxis(&["identify", "--machine", MACHINE, "--campaign", CAMPAIGN, "--json"]));
    // the shipped data: Andolfatto et al. 2011 Table 1 with the Table 3 noise; these six are separable in both
    // parameter sets and must come back within 3 u of Table 1
    for (name, table1, unit) in [
        ("EC0Y", -8.8, "urad"),
        ("EA0Z", 138.3, "urad"),
        ("EB0Z", -35.7, "urad"),
        ("EA0C", -34.4, "urad"),
        ("TX", -1.1, "um"),
        ("WX", 1.5, "um"),
    ] {
        let p = &doc["parameters"][name];
        assert_eq!(p["unit"], unit, "{name}");
        let (v, u) = (p["value"].as_f64().unwrap(), p["std_uncertainty"].as_f64().unwrap());
        assert!((v - table1).abs() < 3.0 * u, "{name}: {v} vs {table1} (u {u})");
    }
    assert_eq!(doc["parameters"].as_object().unwrap().len(), 12);
    // RMS of the Table 3 noise: sqrt((0.28^2 + 0.28^2 + 0.40^2) / 3) = 0.3266 um
    let rms = doc["residual_rms_um"].as_f64().unwrap();
    assert!((rms / 0.3266 - 1.0).abs() < 0.1, "residual rms {rms}");
    let k = doc["condition_number"].as_f64().unwrap();
    let sv: Vec<f64> = doc["singular_values"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(sv.len(), 12);
    assert!((k - sv[0] / sv[11]).abs() < 1e-9 * k);
    assert_eq!(doc["unidentifiable"].as_array().unwrap().len(), 0);
    assert_eq!(doc["channels"].as_array().unwrap().len(), 3);
}

#[test]
fn rank_deficiency_is_exit_1_unless_allowed_and_bad_input_is_exit_2() {
    let paper = "examples/campaigns/kx8five/paper14.toml";
    let out = trueaxis(&["identify", "--machine", MACHINE, "--campaign", paper]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("EY0C, TY, TZ and WZ cannot be separated"), "{err}");
    assert_eq!(err.trim().lines().count(), 1);
    let doc = json(&trueaxis(&["identify", "--machine", MACHINE, "--campaign", paper, "--allow-rank-deficient", "--json"]));
    let combos = doc["unidentifiable"].as_array().unwrap();
    assert_eq!(combos.len(), 2);
    assert_eq!(combos[1]["parameters"], serde_json::json!(["EY0C", "TY", "TZ", "WZ"]));
    assert!(doc["parameters"]["EY0C"]["std_uncertainty"].is_null());

    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "parameters = [\"EX0Q\"]\n[[measurement]]\ninstrument = \"ball3d\"\ndata = \"x.csv\"\nsigma_um = 1\n").unwrap();
    let out = trueaxis(&["identify", "--machine", MACHINE, "--campaign", arg(&bad)]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.toml") && err.contains("EX0Q"), "{err}");
    std::fs::write(&bad, "parameters = [\"EX0C\"]\n[[measurement]]\ninstrument = \"ball3d\"\ndata = \"missing.csv\"\nsigma_um = 1\n")
        .unwrap();
    let out = trueaxis(&["identify", "--machine", MACHINE, "--campaign", arg(&bad)]);
    failed(&out, 2, &["missing.csv"]);
}

#[test]
fn trajectory_simulate_identify_and_predict_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let poses = d.join("capball.csv");
    let out = trueaxis(&[
        "design",
        "trajectory",
        "--machine",
        MACHINE,
        "--work-point",
        "150,0,100",
        "--sweep",
        "A=0:90",
        "--sweep",
        "C=0:720",
        "--count",
        "200",
        "--out",
        arg(&poses),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let campaign = read(CAMPAIGN);
    std::fs::write(d.join("campaign.toml"), &campaign).unwrap();
    let c = d.join("campaign.toml");
    let out = trueaxis(&[
        "design",
        "simulate",
        "--machine",
        MACHINE,
        "--campaign",
        arg(&c),
        "--errors",
        "examples/errors/kx8five_table1.toml",
        "--noise-free",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let identified = d.join("identified.toml");
    let doc = json(&trueaxis(&["identify", "--machine", MACHINE, "--campaign", arg(&c), "--json", "--out", arg(&identified)]));
    // noise-free: the separable Table 1 values come back to the first-order model accuracy (1e-3)
    assert!((doc["parameters"]["EA0Z"]["value"].as_f64().unwrap() - 138.3).abs() < 0.05);
    assert!(doc["residual_rms_um"].as_f64().unwrap() < 0.01);
    // the written file is an error-values file: predict reproduces the (noise-free) readings
    let text = std::fs::read_to_string(&identified).unwrap();
    assert!(text.contains("EA0Z = "));
    let pred = json(&trueaxis(&[
        "predict",
        "--machine",
        MACHINE,
        "--errors",
        arg(&identified),
        "--poses",
        arg(&poses),
        "--tool-point",
        "0,0,300",
        "--work-point",
        "150,0,100",
        "--frame",
        "machine",
        "--json",
    ]));
    let readings = std::fs::read_to_string(&poses).unwrap();
    let first = readings.lines().find(|l| l.starts_with(|c: char| c.is_ascii_digit() || c == '-')).unwrap();
    let fields: Vec<f64> = first.split(',').map(|f| f.parse().unwrap()).collect();
    for (k, key) in ["dx", "dy", "dz"].iter().enumerate() {
        let p = pred["poses"][0][key].as_f64().unwrap();
        assert!((p - fields[5 + k]).abs() < 0.01, "{key}: predicted {p} vs simulated {}", fields[5 + k]);
    }
    // an optimal subset of 30 poses out of 200
    let opt =
        json(&trueaxis(&["design", "optimal", "--machine", MACHINE, "--campaign", arg(&c), "--count", "30", "--starts", "1", "--json"]));
    assert_eq!(opt["chosen"].as_array().unwrap().len(), 30);
    let (chosen, all) = (opt["criteria"]["d"].as_f64().unwrap(), opt["all_candidates"]["d"].as_f64().unwrap());
    // per-record D of the chosen 30 is better than that of all 200 poses taken together
    assert!(chosen < all, "{chosen} vs {all}");
}

#[test]
fn design_optimal_refuses_designs_that_cannot_determine_the_unknowns() {
    // 3 records of 3 readings for 12 unknowns: bad input naming --count
    let out = trueaxis(&["design", "optimal", "--machine", MACHINE, "--campaign", CAMPAIGN, "--count", "3"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--count 3") && err.contains("9 readings for 12 unknowns") && err.contains("at least 4"), "{err}");
    assert_eq!(err.trim().lines().count(), 1);
    assert!(out.stdout.is_empty());
    // a candidate set that cannot separate two combinations: exit 1, named as `identify` names them
    let paper = "examples/campaigns/kx8five/paper14.toml";
    let out = trueaxis(&["design", "optimal", "--machine", MACHINE, "--campaign", paper, "--count", "30", "--starts", "1"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("paper14.toml") && err.contains("12 of 14"), "{err}");
    assert!(
        err.contains("EB0A, EC0A, EB0C and WY cannot be separated") && err.contains("EY0C, TY, TZ and WZ cannot be separated"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1);
    for (count, starts) in [("0", "1"), ("20", "0")] {
        let out = trueaxis(&["design", "optimal", "--machine", MACHINE, "--campaign", CAMPAIGN, "--count", count, "--starts", starts]);
        assert_eq!(out.status.code(), Some(2), "--count {count} --starts {starts}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("at least 1"), "--count {count} --starts {starts}");
    }
}

/// The body lines of the ```text block that follows the first line containing `marker` in the guide.
fn documented_block(marker: &str) -> Vec<String> {
    let guide = std::fs::read_to_string(Path::new(ROOT).join("docs/identification.md")).unwrap();
    let after = &guide[guide.find(marker).unwrap_or_else(|| panic!("`{marker}` not in the guide"))..];
    let body = &after[after.find("```text\n").unwrap() + 8..];
    body[..body.find("```").unwrap()].lines().map(str::to_string).collect()
}

#[test]
fn the_documented_outputs_come_from_real_runs() {
    for (marker, campaign, machine) in [
        ("(without `--refine`;", CAMPAIGN, MACHINE),
        ("The output lists the coefficients", "examples/campaigns/vmc3_tracer/campaign.toml", "examples/machines/vmc3.toml"),
    ] {
        let out = trueaxis(&["identify", "--machine", machine, "--campaign", campaign]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8_lossy(&out.stdout);
        let lines: Vec<&str> = text.lines().map(str::trim_end).collect();
        let block = documented_block(marker);
        assert!(block.len() >= 3);
        for line in block.iter().filter(|l| l.trim() != "...") {
            assert!(lines.contains(&line.trim_end()), "docs line not in the output of {campaign}:\n{line}\n---\n{text}");
        }
    }
    // walkthrough step 6 (D-optimal 20 of the 807 records) and what the guide says about its G:
    // G >= p for any design, near p (Kiefer-Wolfowitz) for a D-optimal one; one reading's variance less
    let doc = json(&trueaxis(&[
        "design",
        "optimal",
        "--machine",
        MACHINE,
        "--campaign",
        CAMPAIGN,
        "--count",
        "20",
        "--starts",
        "1",
        "--criterion",
        "d",
        "--json",
    ]));
    let (g, reading) = (doc["criteria"]["g"].as_f64().unwrap(), doc["criteria"]["max_reading_variance"].as_f64().unwrap());
    assert!((12.0..12.0 * 1.05).contains(&g), "G {g} for p = 12");
    assert!(reading < g / 2.0, "single reading {reading}");
    let guide = std::fs::read_to_string(Path::new(ROOT).join("docs/identification.md")).unwrap();
    let sentence = format!("have G = {g:.2} for `p = 12` and a largest single-reading variance of {reading:.2}");
    assert!(guide.contains(&sentence), "the guide should say: {sentence}");
}

/// Screening (docs/screening.md): the clean campaign gives no finding and `--exclude-outliers`
/// changes nothing on it (the same values bit for bit, nothing excluded).
#[test]
fn exclude_outliers_leaves_a_clean_campaign_alone() {
    let plain = json(&trueaxis(&["identify", "--machine", MACHINE, "--campaign", CAMPAIGN, "--json"]));
    let excluded = json(&trueaxis(&["identify", "--machine", MACHINE, "--campaign", CAMPAIGN, "--json", "--exclude-outliers"]));
    assert_eq!(plain["data_quality"], serde_json::json!([]));
    assert_eq!(excluded["excluded_records"], 0);
    assert_eq!(plain["parameters"], excluded["parameters"]);
}
