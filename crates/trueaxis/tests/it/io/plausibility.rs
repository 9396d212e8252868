//! Every plausibility check of `io::plausibility` with an input that trips it (refusal or warning,
//! as documented) and one that does not; the messages name the file, the column and the fix.

use trueaxis::io::plausibility::*;
use trueaxis::io::{Severity, Unit};

const AT: Place = Place { file: "run.csv", column: "dev [mm]" };

fn severity(f: Option<Finding>) -> Option<Severity> {
    f.map(|f| {
        assert!(f.message.starts_with("run.csv: column `dev [mm]`"), "file and column named: {}", f.message);
        f.severity
    })
}

#[test]
fn deviations_in_the_wrong_unit() {
    // laser deviations of a few um, written in mm in a column read as um: 1000 times too small
    let mm_as_um = [0.0012, -0.0035, 0.0021];
    let f = deviation_scale(&mm_as_um, None, AT, "label the header `dev [mm]`", "x").unwrap();
    assert_eq!(f.severity, Severity::Refuse);
    assert!(f.message.contains("most likely mm") && f.message.contains("label the header `dev [mm]`"), "{}", f.message);
    // the same readings in um: plausible
    assert_eq!(severity(deviation_scale(&[1.2, -3.5, 2.1], None, AT, "a", "b")), None);
    // um written in a column labelled mm: 1000 times too large
    let um_as_mm: Vec<f64> = [1.2, -3.5, 12.0].iter().map(|v| v * 1000.0).collect();
    assert_eq!(severity(deviation_scale(&um_as_mm, Some(Unit::MM), AT, "a", "label `dev [um]`")), Some(Severity::Refuse));
    // suspicious only: 0.05 um at most, 0.8 mm at most
    assert_eq!(severity(deviation_scale(&[0.05, -0.03], None, AT, "a", "b")), Some(Severity::Warn));
    assert_eq!(severity(deviation_scale(&[800.0], None, AT, "a", "b")), Some(Severity::Warn));
    // an error-free simulation
    assert_eq!(severity(deviation_scale(&[0.0, 0.0], None, AT, "a", "b")), None);
}

#[test]
fn radians_where_degrees_are_expected() {
    let rad: Vec<f64> = (0..360).map(|k| (k as f64).to_radians()).collect();
    let f = angles_in_radians(&rad, AT, "label the header `angle [rad]`").unwrap();
    assert_eq!(f.severity, Severity::Refuse);
    assert!(f.message.contains("look like radians") && f.message.contains("`angle [rad]`"), "{}", f.message);
    let deg: Vec<f64> = (0..360).map(|k| k as f64).collect();
    assert_eq!(angles_in_radians(&deg, AT, "x"), None);
    // a 4 deg sweep reads as radians (a ballbar or rotary sweep needs far more than 6.3 deg, so
    // refusing it loses nothing); 0.8 deg is too short to tell
    assert_eq!(angles_in_radians(&[0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0], AT, "x").unwrap().severity, Severity::Refuse);
    assert_eq!(angles_in_radians(&[0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8], AT, "x"), None);
}

fn readings(targets: &[f64], runs: i64) -> Vec<TargetReading> {
    let mut out = Vec::new();
    let mut line = 2;
    for run in 1..=runs {
        for d in [1, -1] {
            for &t in targets {
                out.push(TargetReading { target: t, direction: d, run, line });
                line += 1;
            }
        }
    }
    out
}

#[test]
fn targets_not_repeated_in_every_run() {
    let t = [0.0, 100.0, 200.0, 300.0];
    assert_eq!(targets_per_run(&readings(&t, 3), 1e-6, "mm", AT), None);
    // one target written 100.0004 in run 2: refused (it would be a target of its own with one run)
    let mut r = readings(&t, 3);
    r[9].target = 100.0004;
    let f = targets_per_run(&r, 1e-6, "mm", AT).unwrap();
    assert_eq!(f.severity, Severity::Refuse);
    assert!(f.message.contains("100 mm") && f.message.contains("100.0004 mm") && f.message.contains("one value"), "{}", f.message);
    // a target missing from one run: warned, the run named
    let mut r = readings(&t, 3);
    r.retain(|x| !(x.run == 2 && x.direction == -1 && x.target == 300.0));
    let f = targets_per_run(&r, 1e-6, "mm", AT).unwrap();
    assert_eq!(f.severity, Severity::Warn);
    assert!(f.message.contains("300 mm from run 2 (-)"), "{}", f.message);
    // targets in um read as mm: 300 m of travel
    let um: Vec<f64> = t.iter().map(|x| x * 1000.0).collect();
    assert_eq!(targets_per_run(&readings(&um, 2), 1e-6, "mm", AT).unwrap().severity, Severity::Refuse);
}

#[test]
fn ballbar_radius_against_the_readings() {
    let dev = [1.2, -3.4, 2.2, 0.5];
    assert_eq!(ballbar_readings(&dev, 100.0, AT), None);
    // absolute lengths of a 150 mm bar where the radius is 100 mm
    let lengths: Vec<f64> = dev.iter().map(|d| 150_000.0 + d).collect();
    let f = ballbar_readings(&lengths, 100.0, AT).unwrap();
    assert_eq!(f.severity, Severity::Refuse);
    assert!(f.message.contains("150.0") && f.message.contains("radius is 100 mm"), "{}", f.message);
    // a length column of another bar
    assert_eq!(bar_lengths(&[150.001, 150.002], 100.0, AT).unwrap().severity, Severity::Refuse);
    assert_eq!(bar_lengths(&[100.001, 99.998], 100.0, AT), None);
    // beyond the +-1 mm range of a ballbar
    assert_eq!(ballbar_readings(&[1500.0, -20.0], 100.0, AT).unwrap().severity, Severity::Refuse);
    // a circle of axis positions
    assert_eq!(circle_radius(100.02, 100.0, AT), None);
    assert_eq!(circle_radius(150.0, 100.0, AT).unwrap().severity, Severity::Refuse);
}

#[test]
fn sample_angles_against_the_claimed_arc() {
    let full: Vec<f64> = (0..360).map(|k| k as f64).collect();
    assert_eq!(arc_coverage(&full, 360.0, AT), None);
    assert_eq!(arc_coverage(&full[..300], 360.0, AT).unwrap().severity, Severity::Warn);
    let f = arc_coverage(&full[..120], 360.0, AT).unwrap();
    assert_eq!(f.severity, Severity::Refuse);
    assert!(f.message.contains("cover 119.0 deg") && f.message.contains("arc of 360 deg"), "{}", f.message);
    // clockwise and across the +-180 deg seam: unwrapped
    let cw: Vec<f64> = (0..360).map(|k| 90.0 - k as f64).map(|a: f64| if a < -180.0 { a + 360.0 } else { a }).collect();
    assert_eq!(arc_coverage(&cw, 360.0, AT), None);
}

#[test]
fn error_parameters_and_temperatures() {
    assert_eq!(error_parameter_scale(0.0123, false, "[EXX]"), None);
    assert_eq!(error_parameter_scale(12.3, false, "[EXX]").unwrap().severity, Severity::Refuse);
    assert_eq!(error_parameter_scale(0.8, false, "[EXX]").unwrap().severity, Severity::Warn);
    assert_eq!(error_parameter_scale(2.2e-5, true, "[C0B]"), None);
    assert_eq!(error_parameter_scale(22.0, true, "[C0B]").unwrap().severity, Severity::Refuse);
    assert_eq!(temperature_degc(21.3, "material temperature", AT), None);
    assert_eq!(temperature_degc(294.45, "material temperature", AT).unwrap().severity, Severity::Refuse);
    assert_eq!(temperature_degc(38.0, "material temperature", AT).unwrap().severity, Severity::Warn);
}
