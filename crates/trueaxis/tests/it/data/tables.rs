//! The forgiving table reader (`data::CsvTable`): every variant of a file (separators, decimal
//! commas, byte-order mark, CRLF, case and synonyms of the header names, units in the headers, the
//! wide laser layout, a `Key: value` preamble) gives the same numbers as trueaxis's canonical CSV:
//! the same ISO 230-2 results, poses, thermal campaign and design matrix; errors name the file, the
//! line and the column.

use trueaxis::data::{CsvTable, Layout};
use trueaxis::evaluate::iso230_2::{evaluate, read_runs_from_str, Iso2302Result};
use trueaxis::machine::Machine;
use trueaxis::poses::read_poses_from;
use trueaxis::thermal::thermal_campaign::Campaign;
use trueaxis::uncertainty::DesignMatrix;

/// A positioning test: 4 targets, 3 bidirectional runs, deviations in um with 4 decimals.
fn readings() -> Vec<(f64, f64, char, i64)> {
    let mut out = Vec::new();
    for run in 1..=3i64 {
        for dir in ['+', '-'] {
            for (i, t) in [0.0, 125.0, 250.0, 375.0].into_iter().enumerate() {
                let b = if dir == '+' { 0.9 } else { -0.9 };
                let dev = 0.0123 * t + b + 0.0731 * ((i as f64 + 1.0) * run as f64).sin();
                out.push((t, (dev * 1e4_f64).round() / 1e4, dir, run));
            }
        }
    }
    out
}

fn canonical() -> String {
    let mut s = String::from("target,dev,dir,run\n");
    for (t, d, dir, run) in readings() {
        s.push_str(&format!("{t},{d},{dir},{run}\n"));
    }
    s
}

fn comma(v: f64) -> String {
    format!("{v}").replace('.', ",")
}

fn assert_same(name: &str, a: &Iso2302Result, b: &Iso2302Result) {
    assert_eq!(a.positions.len(), b.positions.len(), "{name}");
    for ((s, _, x), (_, _, y)) in a.axis_table().iter().zip(b.axis_table()) {
        assert!((x - y).abs() < 1e-9, "{name}: {s} {x} vs {y}");
    }
    for (p, q) in a.positions.iter().zip(&b.positions) {
        assert!((p.target - q.target).abs() < 1e-12 && (p.mean - q.mean).abs() < 1e-9, "{name}: {p:?} vs {q:?}");
    }
}

#[test]
fn every_variant_of_a_positioning_file_gives_the_results_of_the_canonical_csv() {
    let reference = evaluate(&read_runs_from_str(&canonical(), "canonical.csv").unwrap()).unwrap();
    let rows = readings();
    let mut variants: Vec<(&str, String)> = Vec::new();
    // `;`, decimal comma, deviations in mm, headers with units and other names, a BOM and CRLF
    let mut s = String::from("\u{feff}# Machine: DMU 50\r\nPosition (mm);Deviation [mm];Direction;Run\r\n");
    for (t, d, dir, run) in &rows {
        s.push_str(&format!("{};{};{dir};{run}\r\n", comma(*t), comma(d / 1000.0)));
    }
    variants.push(("semicolon, decimal comma, mm", s));
    // tabs, upper case, `Dev_um`, words for the directions, run numbers as `3.0`
    let mut s = String::from("TARGET\tDev_um\tDIR\tRUN\n");
    for (t, d, dir, run) in &rows {
        let word = if *dir == '+' { "up" } else { "down" };
        s.push_str(&format!("{t}\t{d}\t{word}\t{run}.0\n"));
    }
    variants.push(("tab, case, Dev_um, up/down", s));
    // the wide laser layout: one row per target, one column per run and direction (nm, CR only)
    let mut s = String::from("Target [mm],Run 1 + [nm],Run 1 - [nm],Run 2 + [nm],Run 2 - [nm],Run 3 + [nm],Run 3 - [nm]\r");
    for t in [0.0, 125.0, 250.0, 375.0] {
        s.push_str(&format!("{t}"));
        for run in 1..=3 {
            for dir in ['+', '-'] {
                let d = rows.iter().find(|r| r.0 == t && r.2 == dir && r.3 == run).unwrap().1;
                s.push_str(&format!(",{:.1}", d * 1000.0));
            }
        }
        s.push('\r');
    }
    variants.push(("wide layout in nm", s));
    // a preamble of `Key: value` lines and prose before the header, quoted fields, spaces
    let mut s = String::from("Laser test export\nMachine: DMU 50\nOperator: J. Smith\n\n\"target\" , \"dev\" , \"dir\" , \"run\"\n");
    for (t, d, dir, run) in &rows {
        s.push_str(&format!(" {t} , \"{d}\" , {dir} , {run}\n"));
    }
    variants.push(("preamble and quotes", s));
    for (name, text) in &variants {
        let table = CsvTable::from_text(text, name).unwrap_or_else(|e| panic!("{name}: {e}"));
        let data = trueaxis::evaluate::iso230_2::runs_of(&table).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_same(name, &evaluate(&data).unwrap(), &reference);
    }
    let wide = CsvTable::from_text(&variants[2].1, "wide.csv").unwrap();
    assert!(matches!(wide.layout(), Layout::Wide { run_columns } if run_columns.len() == 6));
    let pre = CsvTable::from_text(&variants[3].1, "pre.csv").unwrap();
    assert_eq!(pre.metadata().operator.as_deref(), Some("J. Smith"));
}

#[test]
fn canonical_csv_written_from_a_variant_reads_the_same() {
    let mut s = String::from("Position (mm);Deviation [mm];Direction;Run\n");
    for (t, d, dir, run) in readings() {
        s.push_str(&format!("{};{};{dir};{run}\n", comma(t), comma(d / 1000.0)));
    }
    let table = CsvTable::from_text(&s, "variant.csv").unwrap();
    let written = table.to_canonical_csv().unwrap();
    assert!(written.starts_with("target [mm],dev [um],dir,run\n"), "{written}");
    let a = evaluate(&read_runs_from_str(&written, "written.csv").unwrap()).unwrap();
    let b = evaluate(&read_runs_from_str(&canonical(), "canonical.csv").unwrap()).unwrap();
    assert_same("rewritten", &a, &b);
}

#[test]
fn poses_campaigns_and_designs_read_forgivingly() {
    let machine = Machine::from_toml_str(include_str!("../../../../../examples/machines/c600u.toml"), "c600u").unwrap();
    let canonical = read_poses_from("X,Y,Z,A,C,T:spindle\n10,20,-30,45,90,21.5\n-5,0,-1,0,180,22\n".as_bytes(), "p.csv", &machine).unwrap();
    let variant = "\u{feff}x [mm];y [mm];Z [um];a [rad];C [deg];T:spindle [K]\r\n10;20;-30000;0,785398163397448;90;294,65\r\n-5;0;-1000;0;180;295,15\r\n";
    let read = read_poses_from(variant.as_bytes(), "v.csv", &machine).unwrap();
    for (a, b) in read.user.iter().zip(&canonical.user) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    for (a, b) in read.temperatures[0].1.iter().zip(&canonical.temperatures[0].1) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    assert_eq!(read.temperatures[0].0, "T:spindle");
    // a thermal campaign: time in min, an error in mm
    let c1 = Campaign::parse("t,T:p1,dz\n0,20,0\n600,21,3.5\n", "c1.csv").unwrap();
    let c2 = Campaign::parse("t [min];T:p1;dz [mm]\n0;20;0\n10;21;0,0035\n", "c2.csv").unwrap();
    for name in ["t", "T:p1", "dz"] {
        let (a, b) = (c1.column(name).unwrap(), c2.column(name).unwrap());
        assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9), "{name}: {a:?} vs {b:?}");
    }
    // a design matrix with `;` and decimal commas
    let d1 = DesignMatrix::from_csv_reader("channel,t,EX0C,EY0C\nx,0,1,0.5\ny,1,0,2\nx,2,1,1.5\n".as_bytes(), "d1.csv").unwrap();
    let d2 = DesignMatrix::from_csv_reader("Channel;T;EX0C;EY0C\nx;0;1;0,5\ny;1;0;2\nx;2;1;1,5\n".as_bytes(), "d2.csv").unwrap();
    assert_eq!(d1.to_csv(), d2.to_csv());
}

#[test]
fn errors_name_the_file_line_and_column() {
    let cases: Vec<(&str, &str)> = vec![
        ("target;dev;dir;run\n0;1;+;1\n0;1,x;+;2\n", "bad.csv: line 3: column dev: `1,x` is not a number"),
        (
            "target,dev,dir,run\n0,1,+,1\n0,1,5,+,2\n",
            "line 3: 5 fields, but the header (line 1) has 4 (decimal commas in a comma-separated file?",
        ),
        ("target,dev [mm],dir,run\n0,1,sideways,1\n", "line 2: column dir: `sideways` is not a direction"),
        ("target,dev [deg],dir,run\n0,1,+,1\n", "column dev [deg]: deg is an angle, but a length (um) is expected here"),
        ("Target,Run 1 +,Run 1 - [mm]\n0,1,2\n", "the run columns `Run 1 +` and `Run 1 - [mm]` have different units"),
        ("Dev,DEV,dir,run,target\n1,1,+,1,0\n", "line 1: columns 1 (`Dev`) and 2 (`DEV`) are the same column"),
    ];
    for (text, expected) in cases {
        let e = read_runs_from_str(text, "bad.csv").unwrap_err().to_string();
        assert!(e.contains(expected), "expected `{expected}` in: {e}");
        assert!(e.starts_with("bad.csv: "), "{e}");
    }
    let e = CsvTable::from_text("a,b\n", "empty.csv").unwrap_err().to_string();
    assert_eq!(e, "empty.csv: no data: the file has a header but no rows");
}
