//! Ballbar text exports: a circle simulated on the exact chain with known errors, written as an
//! export (a `Key: value` header with radius, feed rate, direction, sample rate and arc; sample
//! numbers instead of angles; deviations in mm with decimal commas; CRLF), read back: the same
//! angles and readings, the same ISO 230-4 results as the trueaxis CSV of the same circle. Bar
//! lengths instead of deviations; the checks of radians, radius and arc, tripped and not.

use trueaxis::data::CsvTable;
use trueaxis::error_model::ErrorModel;
use trueaxis::evaluate::ballbar_diagnostics::DiagnosticOptions;
use trueaxis::evaluate::iso230_4::{evaluate, read_circular_table, CircularFile};
use trueaxis::instruments::ballbar::{circle_test, read_trace, trace_of, CircleSpec, Plane, Rotation};
use trueaxis::machine::Machine;

const RADIUS: f64 = 100.0;
const FEED: f64 = 1000.0;
/// Samples per turn: the sample rate makes the step 360/377 deg at 1000 mm/min on R 100.
const SAMPLES: usize = 377;

fn vmc3() -> (Machine, ErrorModel) {
    let m = Machine::from_toml_str(include_str!("../../../../../examples/machines/vmc3.toml"), "vmc3").unwrap();
    let e = ErrorModel::from_toml_str(include_str!("../../../../../examples/ballbar/vmc3_circle.toml"), "vmc3_circle", &m).unwrap();
    (m, e)
}

fn rate() -> f64 {
    FEED / 60.0 / RADIUS / (std::f64::consts::TAU / SAMPLES as f64)
}

/// Angles (deg) and readings (um, rounded to 0.1 nm) of a CCW and a CW run.
fn simulated() -> Vec<(Rotation, Vec<f64>, Vec<f64>)> {
    let (m, e) = vmc3();
    let centre = vec![0.0, 0.0, -200.0];
    [Rotation::Ccw, Rotation::Cw]
        .into_iter()
        .map(|rotation| {
            let angles: Vec<f64> = (0..SAMPLES).map(|k| rotation.sign() * 360.0 * k as f64 / SAMPLES as f64).collect();
            let spec = CircleSpec {
                plane: Plane::Xy,
                centre: centre.clone(),
                radius: RADIUS,
                angles: angles.iter().map(|a| a.to_radians()).collect(),
                rotation,
            };
            let dl: Vec<f64> = circle_test(&m, &spec).unwrap().simulate(&m, &e).iter().map(|v| (v * 1e7).round() / 1e4).collect();
            (rotation, angles, dl)
        })
        .collect()
}

fn export_text(header_extra: &str) -> String {
    let mut s = format!(
        "Ballbar export\r\nMachine: VMC3\r\nDate: 2024-03-12\r\nRadius: {RADIUS} mm\r\nFeed rate: {FEED} mm/min\r\nDirection: both\r\n\
         Sample rate: {} Hz\r\nArc: 360\r\n{header_extra}\r\nSample;Direction;Deviation [mm]\r\n",
        rate()
    );
    for (rotation, _, dl) in simulated() {
        for (k, v) in dl.iter().enumerate() {
            s.push_str(&format!("{k};{};{}\r\n", rotation.name().to_uppercase(), format!("{:.7}", v / 1000.0).replace('.', ",")));
        }
    }
    s
}

fn canonical_text() -> String {
    let mut s = String::from("angle,dir,dL\n");
    for (rotation, angles, dl) in simulated() {
        for (a, v) in angles.iter().zip(&dl) {
            s.push_str(&format!("{a},{},{v}\n", rotation.name()));
        }
    }
    s
}

fn circular(text: &str, name: &str) -> Result<CircularFile, String> {
    let (m, _) = vmc3();
    let table = CsvTable::from_text(text, name).map_err(|e| e.to_string())?;
    read_circular_table(&table, name, &m, Plane::Xy, RADIUS, &[0.0, 0.0, -200.0]).map_err(|e| e.to_string())
}

#[test]
fn an_export_reads_back_to_the_simulated_angles_and_readings() {
    let file = circular(&export_text(""), "export.txt").unwrap();
    assert!(file.warnings.is_empty(), "{:?}", file.warnings);
    assert_eq!(file.header.radius_mm, Some(RADIUS));
    assert_eq!(file.metadata.machine.as_deref(), Some("VMC3"));
    for ((rotation, angles, dl), run) in simulated().iter().zip(&file.runs) {
        assert_eq!(*rotation, run.rotation);
        for k in 0..SAMPLES {
            assert!(
                (run.test.angles[k].to_degrees() - angles[k]).abs() < 1e-9,
                "{k}: {} vs {}",
                run.test.angles[k].to_degrees(),
                angles[k]
            );
            assert!((run.dl[k] * 1e3 - dl[k]).abs() < 1e-9, "{k}: {} vs {}", run.dl[k] * 1e3, dl[k]);
        }
    }
    // the ISO 230-4 results of the export equal those of the trueaxis CSV
    let canonical = circular(&canonical_text(), "circle.csv").unwrap();
    let (m, _) = vmc3();
    let options =
        DiagnosticOptions { plane: Plane::Xy, radius: RADIUS, centre: [0.0, 0.0], pitch: None, spike_width: 3f64.to_radians(), feed: None };
    let (a, b) = (evaluate(&m, &file.runs, &options).unwrap(), evaluate(&m, &canonical.runs, &options).unwrap());
    for (x, y) in a.runs.iter().zip(&b.runs) {
        assert!((x.g_um - y.g_um).abs() < 1e-9 && (x.f_max_um - y.f_max_um).abs() < 1e-9, "{x:?} vs {y:?}");
    }
    assert!((a.hysteresis_um.unwrap() - b.hysteresis_um.unwrap()).abs() < 1e-9);
}

#[test]
fn bar_lengths_become_deviations() {
    let mut s = String::from("Radius: 100 mm\nangle;Length [mm]\n");
    let (_, angles, dl) = &simulated()[0];
    for (a, v) in angles.iter().zip(dl) {
        s.push_str(&format!("{a};{}\n", format!("{:.7}", RADIUS + v / 1000.0).replace('.', ",")));
    }
    let table = CsvTable::from_text(&s, "lengths.txt").unwrap();
    let trace = trace_of(&table, &["angle"]).unwrap();
    for (x, y) in trace.dl_um.iter().zip(dl) {
        assert!((x - y).abs() < 1e-6, "{x} vs {y}");
    }
}

#[test]
fn the_checks_trip_on_bad_exports_and_not_on_good_ones() {
    // radians in an angle column: refused (degrees pass: the canonical file above)
    let mut rad = String::from("angle,dL\n");
    for (_, angles, dl) in simulated().iter().take(1) {
        for (a, v) in angles.iter().zip(dl) {
            rad.push_str(&format!("{},{v}\n", a.to_radians()));
        }
    }
    let e = circular(&rad, "rad.csv").unwrap_err();
    assert!(e.contains("rad.csv: column `angle`") && e.contains("look like radians") && e.contains("`angle [rad]`"), "{e}");
    // a header radius that disagrees with the test's
    let e = circular(&export_text("").replace("Radius: 100 mm", "Radius: 150 mm"), "r.txt").unwrap_err();
    assert!(e.contains("header gives the radius 150 mm") && e.contains("100 mm"), "{e}");
    // lengths of another bar
    let e = trace_of(&CsvTable::from_text("Radius: 100 mm\nangle,Length\n0,150.001\n10,150.002\n", "l.txt").unwrap(), &["angle"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("l.txt: column `Length`: the bar lengths are about 150.0015 mm") && e.contains("radius is 100 mm"), "{e}");
    // a sample rate ten times too high: the samples cover 36 deg of a claimed 360 deg arc
    let e = circular(&export_text("").replace(&format!("Sample rate: {}", rate()), &format!("Sample rate: {}", 10.0 * rate())), "arc.txt")
        .unwrap_err();
    assert!(e.contains("cover") && e.contains("arc of 360 deg"), "{e}");
    // a claimed arc slightly larger than covered: a warning only
    let file = circular(&export_text("").replace("Arc: 360", "Arc: 400"), "arc.txt").unwrap();
    assert!(file.warnings.iter().any(|w| w.contains("arc of 400 deg")), "{:?}", file.warnings);
    // the shipped export and trace files pass every check
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/ballbar/");
    for f in ["A1.csv", "C2.csv", "tmbb_L1.csv"] {
        let t = read_trace(format!("{root}{f}"), &["A", "C", "angle"]).unwrap();
        assert!(t.warnings.is_empty(), "{f}: {:?}", t.warnings);
    }
}
