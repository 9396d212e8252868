//! A real consumer: LinuxCNC's standalone interpreter `rs274 -g` (Debian package linuxcnc-uspace)
//! runs the original and the corrected programs and prints the canonical moves; every corrected
//! move must equal the original move plus the predicted correction (rs274 prints 4 decimals in the
//! current length unit). Skipped, with the reason printed, when `rs274` is not installed.

mod nc_common;

use nc_common::{expected_corrections, SeenMove};
use std::process::Command;
use trueaxis::compensate::nc::{correct_program, NcOptions};
use trueaxis::compensate::Corrector;
use trueaxis::errors::ErrorModel;
use trueaxis::machine::Machine;

/// A canonical move: end point (mm), arc centre and sense, and the unit it was printed in.
#[derive(Debug, Clone)]
struct Canon {
    moved: SeenMove,
    inch: bool,
}

fn rs274(program: &str) -> Option<String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.ngc");
    std::fs::write(&path, program).unwrap();
    let out = Command::new("rs274").arg("-g").arg(&path).current_dir(dir.path()).output().ok()?;
    assert!(out.status.success(), "rs274 failed: {}", String::from_utf8_lossy(&out.stderr));
    Some(String::from_utf8(out.stdout).unwrap())
}

/// STRAIGHT_TRAVERSE / STRAIGHT_FEED / ARC_FEED (XY plane) in mm, 3 axes.
fn canon(output: &str) -> Vec<Canon> {
    let mut inch = false;
    let mut moves = Vec::new();
    for line in output.lines() {
        if line.contains("USE_LENGTH_UNITS(CANON_UNITS_INCHES)") {
            inch = true;
        } else if line.contains("USE_LENGTH_UNITS(CANON_UNITS_MM)") {
            inch = false;
        }
        let Some(open) = line.find('(') else { continue };
        let name = line[..open].split_whitespace().last().unwrap_or("");
        let args: Vec<f64> = line[open + 1..line.rfind(')').unwrap()].split(',').filter_map(|a| a.trim().parse().ok()).collect();
        let k = if inch { 25.4 } else { 1.0 };
        let moved = match name {
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" => SeenMove { end: vec![args[0] * k, args[1] * k, args[2] * k], arc: None },
            // ARC_FEED(first_end, second_end, first_axis, second_axis, rotation, axis_end_point, a, b, c)
            "ARC_FEED" => {
                SeenMove { end: vec![args[0] * k, args[1] * k, args[5] * k], arc: Some(([args[2] * k, args[3] * k], args[4].signum())) }
            }
            _ => continue,
        };
        moves.push(Canon { moved, inch });
    }
    moves
}

#[test]
fn rs274_sees_every_move_shifted_by_its_correction() {
    if Command::new("rs274").arg("-g").arg("/dev/null").output().is_err() {
        println!("SKIPPED: `rs274` (LinuxCNC, Debian package linuxcnc-uspace) is not installed; install it to run this test");
        return;
    }
    let m = Machine::load("examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load("examples/errors/vmc3_backlash.toml", &m).unwrap();
    let corrector = Corrector::new(&m, &e);
    let options = NcOptions::new(&m);
    let text = std::fs::read_to_string("examples/nc/pocket.ngc").unwrap();
    let temperatures = [24.0];
    let r = correct_program(&corrector, &text, "pocket.ngc", &options, &temperatures).unwrap();
    let original = canon(&rs274(&text).unwrap());
    let corrected = canon(&rs274(&r.text).unwrap());
    assert_eq!(original.len(), 12, "rs274 moves of the example");
    assert_eq!(corrected.len(), original.len() + r.inserted_lines);
    let seen: Vec<SeenMove> = original.iter().map(|c| c.moved.clone()).collect();
    let expected = expected_corrections(&m, &corrector, &seen, &[0.0; 3], &temperatures);
    let mut k = 0;
    let mut unsplit_arcs = 0;
    for (i, (o, c)) in original.iter().zip(&expected).enumerate() {
        let target: Vec<f64> = o.moved.end.iter().zip(c).map(|(a, b)| a + b).collect();
        // rs274 rounds to 4 decimals of its unit, trueaxis writes 4 (mm) or 5 (inch) decimals
        let tolerance = if o.inch { 0.5e-4 * 25.4 + 0.5e-5 * 25.4 + 1e-9 } else { 1e-4 + 1e-9 };
        let j = (k..corrected.len())
            .find(|&j| corrected[j].moved.end.iter().zip(&target).all(|(a, b)| (a - b).abs() <= tolerance))
            .unwrap_or_else(|| panic!("no corrected move ends at {target:?} (original {:?})", o.moved.end));
        // the corrected arc keeps its sense; unsplit, its centre moved by the mean correction of its ends
        if let (Some((centre, sense)), Some((new_centre, new_sense))) = (o.moved.arc, corrected[j].moved.arc) {
            assert_eq!(sense, new_sense);
            if j == k {
                let start_c = if i == 0 { vec![0.0; 3] } else { expected[i - 1].clone() };
                for d in 0..2 {
                    let want = centre[d] + 0.5 * (start_c[d] + c[d]);
                    assert!((new_centre[d] - want).abs() <= 2.0 * tolerance, "arc centre {d}: {} vs {want}", new_centre[d]);
                }
                unsplit_arcs += 1;
            }
        }
        k = j + 1;
    }
    assert_eq!(k, corrected.len(), "every corrected move is accounted for");
    assert!(unsplit_arcs >= 1);
}
