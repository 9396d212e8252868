//! `thermal place --score` (Zhu 2008 §3.4.2): placements compared by the error of the elongation
//! model they lead to, Gauss points as the baseline. The elongation weights integrate a uniform
//! rise exactly (alpha L), the Gauss placement is the nodes nearest the Gauss-Legendre points, the
//! exhaustive yardstick has the smallest training error of all, and more Gauss sensors predict
//! better.

use crate::support::thermal::place_elongation;
use crate::support::{json, ROOT};
use std::path::Path;
use trueaxis::thermal::model_file::load_model;
use trueaxis::thermal::placement_score::{elongation_weights, gauss_points};

#[test]
fn weights_and_gauss_points_of_the_elongation_element() {
    let model = load_model(Path::new(ROOT).join("examples/thermal/elongation.toml")).unwrap();
    // a uniform rise of 1 K lengthens the 1 m bar by alpha L: the weights sum to L
    let w = elongation_weights(&model).unwrap();
    assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    // Gauss-Legendre points 0.5 -+ 0.5/sqrt(3) = 0.2113, 0.7887 m: candidates every 0.125 m
    assert_eq!(gauss_points(&model, 2).unwrap(), vec![6, 18]);
    // 0.1127, 0.5, 0.8873 m
    assert_eq!(gauss_points(&model, 3).unwrap(), vec![3, 12, 21]);
    assert!(gauss_points(&load_model(Path::new(ROOT).join("examples/thermal/plate.toml")).unwrap(), 2).is_err());
}

fn scores(sensors: &str) -> Vec<serde_json::Value> {
    let doc = json(&place_elongation(&["--sensors", sensors, "--score", "--json"]));
    doc["scores"].as_array().unwrap().clone()
}

#[test]
fn placements_are_scored_against_the_gauss_baseline() {
    let rows = scores("3");
    let names: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
    assert_eq!(names, ["modal", "efi", "gauss (baseline)", "exhaustive (smallest training error)"]);
    let train = |r: &serde_json::Value| r["training_rms_um"].as_f64().unwrap();
    let best = train(rows.last().unwrap());
    for r in &rows {
        assert!(best <= train(r) + 1e-12, "{r}");
        assert_eq!(r["validation"].as_array().unwrap().len(), 2);
    }
    let gauss = |rows: &[serde_json::Value]| {
        rows.iter().find(|r| r["method"] == "gauss (baseline)").unwrap()["validation"][1]["rms_um"].as_f64().unwrap()
    };
    // more Gauss points, a better integral of the temperature field
    let (two, five) = (gauss(&scores("2")), gauss(&scores("5")));
    assert!(five < two, "{five} vs {two}");
    // the elongation is of tens of um; the residuals are small against it
    assert!(two < 3.0);
}
