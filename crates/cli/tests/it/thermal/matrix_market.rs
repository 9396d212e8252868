//! Models imported as Matrix Market files (`kind = "matrix_market"`): the shipped
//! `examples/thermal/fin_mm.toml` holds K and C of `examples/thermal/fin.toml` written by
//! `matrix_market::write_symmetric`; its modes equal those of the bar it came from, through the
//! command line.

use crate::support::{json, trueaxis, ROOT};
use std::path::Path;
use trueaxis::thermal::matrix_market::write_symmetric;
use trueaxis::thermal::model_file::load_model;

fn example(name: &str) -> std::path::PathBuf {
    Path::new(ROOT).join("examples/thermal").join(name)
}

#[test]
fn shipped_matrices_are_those_of_the_fin() {
    let fin = load_model(example("fin.toml")).unwrap();
    for (file, matrix) in [("fin_C.mtx", &fin.system.capacity), ("fin_K.mtx", &fin.system.conductivity)] {
        let text = write_symmetric(matrix);
        if std::env::var_os("TRUEAXIS_REGENERATE").is_some() {
            std::fs::write(example(file), &text).unwrap();
        }
        assert_eq!(std::fs::read_to_string(example(file)).unwrap(), text, "{file} is not the writer's output for fin.toml");
    }
}

fn modes_json(model: &str) -> serde_json::Value {
    json(&trueaxis(&["thermal", "modes", "--model", example(model).to_str().unwrap(), "--count", "12", "--json"]))
}

#[test]
fn modes_of_the_imported_fin_equal_those_of_the_bar() {
    let (bar, imported) = (modes_json("fin.toml"), modes_json("fin_mm.toml"));
    assert_eq!(imported["nodes"], 23);
    assert_eq!(imported["dominant"], bar["dominant"]);
    let (a, b) = (bar["modes"].as_array().unwrap(), imported["modes"].as_array().unwrap());
    assert_eq!(a.len(), 12);
    for (x, y) in a.iter().zip(b) {
        for key in ["tau_s", "weight", "share"] {
            let (p, q) = (x[key].as_f64().unwrap(), y[key].as_f64().unwrap());
            assert!((p - q).abs() <= 1e-12 * p.abs(), "mode {}: {key} {p} vs {q}", x["mode"]);
        }
    }
    // tau_1 of the fin with insulated ends: 140.98 min (Zhu 2008 Table 3.1)
    assert!((b[0]["tau_min"].as_f64().unwrap() - 140.978).abs() < 1e-3);
}
