//! ISO 230-2 test of examples/data/iso230_2_x.csv (5 runs, 11 targets, 0 ... 500 mm) with one
//! damage each: a run in mm, a run of another axis, a beam-interruption reading, targets in
//! metres, an air-temperature drift.

use crate::support::damage::{all, example, of_run, Csv};
use trueaxis::data::CsvTable;
use trueaxis::evaluate::positioning_test::{evaluate_table, PositioningTest};
use trueaxis::instruments::TemperatureOptions;
use trueaxis::screen::Kind;

/// The ISO 230-2 example every damage here starts from.
pub const FILE: &str = "examples/data/iso230_2_x.csv";

fn test_of(text: &str) -> Result<PositioningTest, String> {
    let table = CsvTable::from_text(text, "damaged.csv").map_err(|e| e.to_string())?;
    evaluate_table(&table, &TemperatureOptions::default()).map_err(|e| e.to_string())
}

/// A number following `key` in `text` ("R would be 4.1 um": key "R would be").
pub fn number_after(text: &str, key: &str) -> f64 {
    let rest = &text[text.find(key).unwrap_or_else(|| panic!("`{key}` in {text}")) + key.len()..];
    rest.split_whitespace().next().unwrap().trim_end_matches([',', ';']).parse().unwrap()
}

#[test]
fn the_clean_example_gives_no_finding() {
    let clean = test_of(&example(FILE)).unwrap();
    assert!(clean.findings.is_empty(), "{:?}", clean.findings);
    assert_eq!(clean.to_json()["data_quality"].as_array().unwrap().len(), 0);
}

#[test]
fn a_run_in_mm_is_named_with_the_result_without_it() {
    let clean = test_of(&example(FILE)).unwrap().result;
    for run in ["1", "3", "5"] {
        let text = Csv::parse(&example(FILE)).map("dev", of_run(run), |v| v / 1000.0).text();
        let t = test_of(&text).unwrap();
        assert_eq!(t.findings.len(), 1, "{:?}", t.findings);
        let f = &t.findings[0];
        assert_eq!(f.kind, Kind::Unit);
        assert!(f.place.starts_with(&format!("run {run} (lines")), "{}", f.place);
        assert!(f.line().starts_with("damaged.csv: run"), "{}", f.line());
        // the standard's result is kept, the one without the run stated beside it
        let without = number_after(&f.consequence, "and R");
        assert!(t.result.r > 1.5 * clean.r, "damaged R {} clean {}", t.result.r, clean.r);
        assert!((without - clean.r).abs() < 0.35 * clean.r, "R without run {run}: {without}, clean {}", clean.r);
        assert_eq!(f.lines.len(), 22);
    }
}

#[test]
fn a_run_of_another_axis_is_inconsistent() {
    let clean = test_of(&example(FILE)).unwrap().result;
    for amplitude in [8.0, 20.0] {
        let text = Csv::parse(&example(FILE)).map("dev", of_run("4"), |v| v + amplitude * (v / 3.0).sin() - 0.5 * amplitude).text();
        let t = test_of(&text).unwrap();
        let f = t.findings.iter().find(|f| f.kind == Kind::Inconsistent).unwrap_or_else(|| panic!("{:?}", t.findings));
        assert!(f.place.starts_with("run 4"), "{}", f.place);
        let without = number_after(&f.consequence, "and R");
        assert!((without - clean.r).abs() < 0.35 * clean.r, "{without} vs {}", clean.r);
    }
}

#[test]
fn a_beam_interruption_is_an_outlier_at_its_line() {
    let clean = test_of(&example(FILE)).unwrap().result;
    for (row, size) in [(13usize, 50.0), (40, 10.0), (77, -5.0)] {
        let mut csv = Csv::parse(&example(FILE));
        let v = csv.value(row, "dev");
        csv.set(row, "dev", v + size);
        let line = csv.line(row);
        let t = test_of(&csv.text()).unwrap();
        assert_eq!(t.findings.len(), 1, "{size} um: {:?}", t.findings);
        let f = &t.findings[0];
        assert_eq!(f.kind, Kind::Outlier);
        assert_eq!(f.lines, vec![line]);
        assert!(f.place.starts_with(&format!("line {line}, run")), "{}", f.place);
        let (a, r) = (number_after(&f.consequence, "A would be"), number_after(&f.consequence, "and R"));
        assert!((a - clean.a).abs() < 0.1 * clean.a && (r - clean.r).abs() < 0.1 * clean.r, "A {a} R {r}: clean {} {}", clean.a, clean.r);
    }
}

#[test]
fn targets_in_metres_are_refused() {
    let text = Csv::parse(&example(FILE)).map("target", all, |v| v / 1000.0).text();
    let e = test_of(&text).unwrap_err();
    assert!(e.contains("column target") && e.contains("metres"), "{e}");
}

#[test]
fn an_air_temperature_drift_is_reported_with_its_effect() {
    for drift in [1.0, 3.0] {
        let csv = Csv::parse(&example(FILE));
        let n = csv.rows.len() as f64;
        let text = csv.add_column("T_air", |i| 20.0 + drift * i as f64 / (n - 1.0)).text();
        let t = test_of(&text).unwrap();
        assert_eq!(t.findings.len(), 1, "{:?}", t.findings);
        let f = &t.findings[0];
        assert_eq!((f.kind, f.place.as_str()), (Kind::Drift, "column T_air"));
        // 0.93 um/(m K) over the 500 mm travel
        let effect = number_after(&f.consequence, "up to");
        assert!((effect - 0.93e-3 * 500.0 * drift).abs() < 0.06, "{effect}");
    }
    // 0.3 degC is within the limit
    let csv = Csv::parse(&example(FILE));
    let n = csv.rows.len() as f64;
    assert!(test_of(&csv.add_column("T_air", |i| 20.0 + 0.3 * i as f64 / n).text()).unwrap().findings.is_empty());
}
