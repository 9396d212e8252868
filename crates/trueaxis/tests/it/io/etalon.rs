//! The Etalon exchange format (LaserTRACER / TRAC-CAL results as Beckhoff TF5280 reads them) into an
//! error-values file: known errors written in the exchange layout (mm, rad) -> converted -> the same
//! parameter values (um, urad) at every position and the same volumetric errors as the errors
//! written directly; the shipped example against examples/errors/vmc3.toml; refusals naming the line.

use trueaxis::error_model::{from_etalon, ErrorModel};
use trueaxis::io::etalon::parse;
use trueaxis::machine::Machine;
use trueaxis::model::{volumetric_error, Frame, Setup};

fn vmc3() -> Machine {
    Machine::from_toml_str(include_str!("../../../../../examples/machines/vmc3.toml"), "vmc3").unwrap()
}

/// Known errors: squareness EC0X = 12 urad, EB0Z = -7.5 urad; EXX a table (um), EBY a table (urad).
const KNOWN_TOML: &str = "[constant]\nEC0X = 12.0\nEB0Z = -7.5\n\
[table.EXX]\nposition = [-400, -100, 200, 400]\nvalue = [-5.0, -1.25, 3.0, 6.5]\n\
[table.EBY]\nposition = [-250, 0, 250]\nvalue = [4.0, 0.0, -2.5]\n";

fn exchange() -> String {
    // the same errors in the exchange layout: values in mm and rad, a comment, blocks in any order
    "// TRAC-CAL, Vendor\n[EBY]\nGridpoints = {\n  250.0 -0.0000025\n  -250.0 0.000004\n  0.0 0.0\n}  // end of EBY\n\
     [C0X]\nVALUE = 0.000012\n[B0Z]\nVALUE = -0.0000075\n\
     [EXX]\nGridpoints = {\n -400.0 -0.005\n -100.0 -0.00125\n 200.0 0.003\n 400.0 0.0065\n}\n"
        .to_string()
}

#[test]
fn converted_errors_equal_the_known_ones_everywhere() {
    let m = vmc3();
    let conversion = from_etalon(&parse(&exchange(), "known.exc").unwrap(), &m, "known.exc").unwrap();
    assert_eq!(conversion.written, vec!["EBY", "EC0X", "EB0Z", "EXX"]);
    let converted = ErrorModel::from_toml_str(&conversion.toml, "converted", &m).unwrap();
    let known = ErrorModel::from_toml_str(KNOWN_TOML, "known", &m).unwrap();
    let (mut a, mut b) = (vec![0.0; m.parameter_count()], vec![0.0; m.parameter_count()]);
    let setup = Setup { tool_point: m.tool_point, work_point: trueaxis::geometry::Vec3::zeros() };
    for i in 0..40 {
        let q = [-400.0 + 20.0 * i as f64, -250.0 + 12.5 * i as f64, -10.0 * i as f64];
        converted.values_at(&m, &q, &mut a);
        known.values_at(&m, &q, &mut b);
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!((x - y).abs() < 1e-15, "parameter {} at {q:?}: {x} vs {y}", m.parameter_id(k));
        }
        let (ea, eb) = (volumetric_error(&m, &q, &a, &setup, Frame::Workpiece), volumetric_error(&m, &q, &b, &setup, Frame::Workpiece));
        assert!((ea.to_user_units()[0] - eb.to_user_units()[0]).abs() < 1e-9);
    }
    // the squareness gives dx = EC0X * Y: 12 urad * 250 mm = 3 um (a check of the um/urad scaling)
    converted.values_at(&m, &[0.0, 0.0, 0.0], &mut a);
    let i = m.parameter_index(&trueaxis::machine::ParameterId::parse("EC0X").unwrap()).unwrap();
    assert!((a[i] - 12e-6).abs() < 1e-18, "{}", a[i]);
}

#[test]
fn the_shipped_example_is_the_vmc3_example_errors() {
    let m = vmc3();
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/data/vmc3_etalon.exc")).unwrap();
    let conversion = from_etalon(&parse(&text, "vmc3_etalon.exc").unwrap(), &m, "vmc3_etalon.exc").unwrap();
    assert_eq!(conversion.written.len(), 21);
    assert!(conversion.warnings.iter().any(|w| w.contains("[P0Z]") && w.contains("not converted")), "{:?}", conversion.warnings);
    let converted = ErrorModel::from_toml_str(&conversion.toml, "converted", &m).unwrap();
    let original = ErrorModel::from_toml_str(include_str!("../../../../../examples/errors/vmc3.toml"), "vmc3.toml", &m).unwrap();
    let (mut a, mut b) = (vec![0.0; m.parameter_count()], vec![0.0; m.parameter_count()]);
    // at the 50 mm grid points the tables equal the polynomials of the original
    for x in (-8..=8).map(|k| 50.0 * k as f64) {
        for y in (-5..=5).map(|k| 50.0 * k as f64) {
            let q = [x, y, -200.0];
            converted.values_at(&m, &q, &mut a);
            original.values_at(&m, &q, &mut b);
            for (k, (u, v)) in a.iter().zip(&b).enumerate() {
                assert!((u - v).abs() < 1e-12, "{} at {q:?}: {u} vs {v}", m.parameter_id(k));
            }
        }
    }
}

#[test]
fn bad_blocks_are_refused_naming_the_line() {
    let m = vmc3();
    let cases = [
        ("[EXA]\nGridpoints = { 0 0.001 10 0.002 }\n", "line 1: [EXA]: EXA refers to axis A"),
        ("[X0C]\nVALUE = 0.001\n", "line 1: [X0C]: EX0C refers to axis C"),
        ("[C0X]\nGridpoints = { 0 0.001 10 0.002 }\n", "is a position error, a constant"),
        ("[EXX]\nGridpoints = { 0 12.5 10 0.002 }\n", "the file holds um, not mm"),
        ("[C0X]\nVALUE = 12.0\n", "the file holds urad, not rad"),
        ("[EXX]\nGridpoints = { 0 0.001 0 0.002 }\n", "the argument 0 is given twice"),
        ("[EQX]\nVALUE = 0.0\n", "is not an ISO 230 parameter name"),
    ];
    for (text, expected) in cases {
        let e = parse(text, "bad.exc").map_err(trueaxis::Error::from).and_then(|f| from_etalon(&f, &m, "bad.exc")).unwrap_err().to_string();
        assert!(e.starts_with("bad.exc: line ") && e.contains(expected), "expected `{expected}` in: {e}");
    }
    let e = parse("[EXX]\nVALUE = 0.001\n[EXX]\nVALUE = 0.002\n", "dup.exc").unwrap_err().to_string();
    assert!(e.contains("line 3: [EXX] is given twice (first on line 1)"), "{e}");
}
