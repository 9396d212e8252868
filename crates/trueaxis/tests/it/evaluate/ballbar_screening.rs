//! ISO 230-4 circular test examples/ballbar/vmc3_xy.csv (R 100 mm, ccw and cw) with a feed-rate
//! overshoot spike; the rotary-axis file examples/ballbar/A1.csv evaluated as a circle.

use crate::support::damage::{example, Csv};
use trueaxis::data::CsvTable;
use trueaxis::evaluate::circular_test::{cartesian_machine, circular_test, CircularTest, CircularTestOptions};
use trueaxis::machine::Machine;
use trueaxis::screen::Kind;

fn test_of(text: &str, machine: &Machine) -> Result<CircularTest, String> {
    let table = CsvTable::from_text(text, "circle.csv").map_err(|e| e.to_string())?;
    let options = CircularTestOptions { radius_mm: Some(100.0), ..CircularTestOptions::default() };
    circular_test(&table, machine, &options).map_err(|e| e.to_string())
}

#[test]
fn the_clean_circle_gives_no_finding() {
    let t = test_of(&example("examples/ballbar/vmc3_xy.csv"), &cartesian_machine()).unwrap();
    assert!(t.findings.is_empty(), "{:?}", t.findings);
}

#[test]
fn a_feed_overshoot_spike_is_named_with_g_without_it() {
    let machine = cartesian_machine();
    let clean = test_of(&example("examples/ballbar/vmc3_xy.csv"), &machine).unwrap();
    for (row, size, width) in [(40usize, 23.0, 1usize), (200, 8.0, 2), (500, -12.0, 3)] {
        let csv = Csv::parse(&example("examples/ballbar/vmc3_xy.csv")).map("dL", |_, i| (row..row + width).contains(&i), |v| v + size);
        let t = test_of(&csv.text(), &machine).unwrap();
        assert_eq!(t.findings.len(), 1, "{:?}", t.findings);
        let f = &t.findings[0];
        assert_eq!(f.kind, Kind::Outlier);
        let run = if row < 360 { 0 } else { 1 };
        assert!(f.place.starts_with(&format!("{} run, sample(s) {}", ["ccw", "cw"][run], row - 360 * run + 1)), "{}", f.place);
        let without: f64 = f.consequence.split_whitespace().nth(6).unwrap().parse().unwrap();
        assert!((without - clean.result.runs[run].g_um).abs() < 0.1, "G without {without}, clean {}", clean.result.runs[run].g_um);
        assert!(t.result.runs[run].g_um > clean.result.runs[run].g_um + 0.5 * size.abs());
    }
}

#[test]
fn a_rotary_axis_file_is_refused_as_a_circle() {
    let machine = Machine::load(crate::support::damage::example_path("examples/machines/c600u.toml")).unwrap();
    let e = test_of(&example("examples/ballbar/A1.csv"), &machine).unwrap_err();
    assert!(e.contains("columns X, Y, A: geometry:") && e.contains("rotary-axis ballbar test"), "{e}");
}
