//! Renishaw `.rtl` laser files: round trips (readings known -> file written in the vendor layout ->
//! read -> the same numbers), the shipped example against the CSV it was written from (the ISO
//! 230-2 results equal), directions from the order of the targets, rotary axes, errors naming the
//! line, and the unit check of a file that holds um instead of mm.

use std::path::Path;
use trueaxis::data::checks::deviation_finding;
use trueaxis::data::CsvTable;
use trueaxis::evaluate::iso230_2::{evaluate, read_runs, runs_of, Direction};
use trueaxis::io::header::RunDirection;
use trueaxis::io::rtl::{parse, RtlFile, RtlReading, RtlRun};
use trueaxis::io::{Metadata, Severity};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// A known positioning test: 11 targets over 500 mm, 5 bidirectional runs; deviation (mm, to 1 nm
/// as the writer keeps it) = 12 um/m scale error + 1.5 um bow + backlash 2 um + a run-dependent 0.1 um.
fn known(rotary: bool) -> RtlFile {
    let targets: Vec<f64> = (0..11).map(|i| i as f64 * 50.0).collect();
    let deviation = |x: f64, dir: f64, run: i64| {
        let um = 0.012 * x + 1.5 * (x / 250.0 - 1.0).powi(2) + dir * 1.0 + 0.1 * run as f64;
        (um * 1e3).round() / 1e6 // mm, 1 nm resolution
    };
    let mut runs = Vec::new();
    for run in 1..=5i64 {
        for (k, dir) in [(0, 1.0), (1, -1.0)] {
            let order: Vec<usize> = if dir > 0.0 { (0..11).collect() } else { (0..11).rev().collect() };
            let readings =
                order.iter().map(|&i| RtlReading { target: i + 1, deviation: deviation(targets[i], dir, run), line: 0 }).collect();
            let direction = if dir > 0.0 { RunDirection::Plus } else { RunDirection::Minus };
            runs.push(RtlRun { number: 2 * run - 1 + k, direction, readings });
        }
    }
    let metadata = Metadata::from_pairs([
        ("Machine", "Test machine"),
        ("Serial No", "SN 42"),
        ("Date", "2024-01-02"),
        ("By", "Tester"),
        ("Axis", if rotary { "C" } else { "X" }),
        ("Mat temp 1", "20.8"),
        ("Exp coeff", "11.5"),
    ]);
    RtlFile { targets, runs, rotary, metadata, warnings: Vec::new() }
}

#[test]
fn written_files_read_back_to_the_same_readings() {
    let file = known(false);
    let text = file.to_text();
    assert!(text.contains("\r\n") && text.contains("TARGET DATA::") && text.contains("Run Target Data:"));
    let back = parse(&text, "known.rtl").unwrap();
    assert_eq!(back.targets, file.targets);
    assert_eq!(back.runs.len(), 10);
    for (a, b) in back.runs.iter().zip(&file.runs) {
        assert_eq!((a.number, a.direction), (b.number, b.direction));
        for (x, y) in a.readings.iter().zip(&b.readings) {
            assert_eq!(x.target, y.target);
            assert!((x.deviation - y.deviation).abs() < 1e-12, "{} vs {}", x.deviation, y.deviation);
        }
    }
    assert_eq!(back.metadata.named(), file.metadata.named());
    assert_eq!(back.metadata.environment, file.metadata.environment);
    // as a positioning test: targets in mm, deviations in um, directions from the target order
    let data = runs_of(&CsvTable::from_text(&text, "known.rtl").unwrap()).unwrap();
    assert!(!data.rotary);
    assert_eq!(data.readings.len(), 110);
    for r in &data.readings {
        let dir = if r.direction == Direction::Plus { 1.0 } else { -1.0 };
        let run = (r.run + 1) / 2;
        let um = 0.012 * r.target + 1.5 * (r.target / 250.0 - 1.0).powi(2) + dir + 0.1 * run as f64;
        assert!((r.dev - um).abs() < 5e-4 + 1e-9, "{} at {}: {} vs {um}", r.run, r.target, r.dev);
        let line_text = text.lines().nth(r.line as usize - 1).unwrap();
        assert!(line_text.starts_with(&format!("{}   ", r.run)), "line {} is `{line_text}`", r.line);
    }
}

#[test]
fn the_shipped_example_holds_the_readings_of_its_csv() {
    let rtl = runs_of(&CsvTable::read(root().join("examples/data/laser_x.rtl")).unwrap()).unwrap();
    let csv = read_runs(root().join("examples/data/laser_x.csv")).unwrap();
    assert_eq!(rtl.readings.len(), csv.readings.len());
    // the writer numbered run r's + pass 2r-1 and its - pass 2r
    for r in &csv.readings {
        let run = if r.direction == Direction::Plus { 2 * r.run - 1 } else { 2 * r.run };
        let hit = rtl.readings.iter().find(|x| x.run == run && x.target == r.target && x.direction == r.direction).expect("same reading");
        assert!((hit.dev - r.dev).abs() < 1e-9, "{} um vs {} um", hit.dev, r.dev);
    }
    let (a, b) = (evaluate(&rtl).unwrap(), evaluate(&csv).unwrap());
    for ((s, _, x), (_, _, y)) in a.axis_table().iter().zip(b.axis_table()) {
        assert!((x - y).abs() < 1e-9, "{s}: {x} vs {y}");
    }
    assert_eq!(rtl.metadata.machine.as_deref(), Some("VMC3 example machine (examples/machines/vmc3.toml)"));
    assert_eq!(rtl.metadata.environment.material_temperatures_degc, vec![21.1, 21.3, 21.2]);
    assert_eq!(rtl.metadata.environment.expansion_coefficient_um_per_m_k, Some(11.5));
}

#[test]
fn a_rotary_axis_is_read_in_degrees_and_microradians() {
    let mut file = known(true);
    file.targets = (0..11).map(|i| i as f64 * 36.0).collect();
    for r in &mut file.runs {
        for x in &mut r.readings {
            x.deviation = 0.001; // deg
        }
    }
    let data = runs_of(&CsvTable::from_text(&file.to_text(), "c.rtl").unwrap()).unwrap();
    assert!(data.rotary);
    assert_eq!((data.position_unit(), data.unit()), ("deg", "urad"));
    assert!(data.readings.iter().all(|r| (r.dev - 17.453_292_519_943).abs() < 1e-6));
    let result = evaluate(&data).unwrap();
    assert_eq!(result.unit, "urad");
    assert_eq!(result.to_json()["position_unit"], "deg");
}

#[test]
fn runs_out_of_order_and_counts_that_differ_are_warned() {
    let mut file = known(false);
    file.runs[0].readings.swap(3, 4);
    let text = file.to_text().replace("Run-count: 10", "Run-count: 12");
    let back = parse(&text, "odd.rtl").unwrap();
    assert_eq!(back.runs[0].direction, RunDirection::Plus);
    assert!(back.warnings.iter().any(|w| w.contains("run 1") && w.contains("not list its targets in order")), "{:?}", back.warnings);
    assert!(back.warnings.iter().any(|w| w.contains("Run-count is 12 but 10 runs")), "{:?}", back.warnings);
}

#[test]
fn bad_files_are_refused_naming_the_line() {
    let text = known(false).to_text();
    let cases: Vec<(String, &str)> = vec![
        (text.replace("Target-count: 11", "Target-count: 12"), "Target-count is 12"),
        (text.replacen("1   2      ", "1   20      ", 1), "target number 20, but Target-count is 11"),
        (text.replacen("1   3      ", "1   2      ", 1), "run 1, target 2 is given twice"),
        (text.replacen("1   4      ", "1   4 x     ", 1), "expected three fields"),
        (text.replace("Run Target Data:\r\n", ""), "before `Run Target Data:`"),
        (text.replace("Targets :", "Targets : abc"), "target `abc` is not a number"),
    ];
    for (bad, expected) in cases {
        let e = parse(&bad, "bad.rtl").unwrap_err().to_string();
        assert!(e.starts_with("bad.rtl: line ") && e.contains(expected), "expected `{expected}` in: {e}");
    }
    let e = parse("HEADER::\nTARGET DATA::\nTarget-count: 2\nTargets :\n0 1\n", "x.rtl").unwrap_err().to_string();
    assert!(e.contains("no readings"), "{e}");
}

#[test]
fn a_file_holding_um_instead_of_mm_is_refused() {
    let mut file = known(false);
    // a program that writes um into the mm field (public writers do)
    for r in &mut file.runs {
        for x in &mut r.readings {
            x.deviation *= 1000.0;
        }
    }
    let table = CsvTable::from_text(&file.to_text(), "um.rtl").unwrap();
    let devs = table.numbers("dev").unwrap();
    let f = deviation_finding(&table, "dev", &devs).expect("refused");
    assert_eq!(f.severity, Severity::Refuse);
    assert!(f.message.contains("um.rtl") && f.message.contains("trueaxis convert"), "{}", f.message);
    let good = CsvTable::from_text(&known(false).to_text(), "mm.rtl").unwrap();
    assert_eq!(deviation_finding(&good, "dev", &good.numbers("dev").unwrap()), None);
}
