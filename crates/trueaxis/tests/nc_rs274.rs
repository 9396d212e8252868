//! A real consumer: LinuxCNC's standalone interpreter `rs274 -g` (Debian package linuxcnc-uspace)
//! runs the original and the corrected programs and prints the canonical moves; every corrected
//! move must equal the original move plus the predicted correction (rs274 prints 4 decimals in the
//! current length unit, and deg), an unsplit arc's centre must move by the mean correction of its
//! ends. Programs: the vmc3 pocket (backlash, a thermal term, G20/G91), arcs in G17, G18 and G19,
//! and the c600u five-axis program (A and C) with its non-zero example errors. Skipped, with the
//! reason printed, only when `rs274` is not installed; when it is, every case must compare moves.

mod nc_common;

use nc_common::{expected_corrections, SeenArc, SeenMove};
use std::process::Command;
use trueaxis::compensate::nc::{correct_program, NcOptions};
use trueaxis::compensate::Corrector;
use trueaxis::errors::ErrorModel;
use trueaxis::machine::{AxisKind, Machine};

/// A canonical move: end point and arc (machine axes, mm and deg) and whether it was printed in inch.
#[derive(Debug, Clone)]
struct Canon {
    moved: SeenMove,
    inch: bool,
}

fn rs274(program: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.ngc");
    std::fs::write(&path, program).unwrap();
    let out = Command::new("rs274").arg("-g").arg(&path).current_dir(dir.path()).output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.success() && !text.contains("error"), "rs274 failed: {}{text}", String::from_utf8_lossy(&out.stderr));
    text
}

/// STRAIGHT_TRAVERSE / STRAIGHT_FEED (x, y, z, a, b, c) and ARC_FEED(first_end, second_end,
/// first_centre, second_centre, rotation, axis_end, a, b, c) in the plane of the last SELECT_PLANE
/// (XY: first x, second y; XZ: first z, second x; YZ: first y, second z), mapped on the machine's
/// axes by letter; lengths to mm.
fn canon(machine: &Machine, output: &str) -> Vec<Canon> {
    let mut inch = false;
    let mut plane = ['X', 'Y', 'Z'];
    let mut moves = Vec::new();
    let axis = |letter: char| machine.axis_index(letter);
    for line in output.lines() {
        let Some(open) = line.find('(') else { continue };
        let name = line[..open].split_whitespace().last().unwrap_or("");
        let inside = &line[open + 1..line.rfind(')').unwrap()];
        match inside {
            "CANON_UNITS_INCHES" => inch = true,
            "CANON_UNITS_MM" => inch = false,
            "CANON_PLANE_XY" => plane = ['X', 'Y', 'Z'],
            "CANON_PLANE_XZ" => plane = ['Z', 'X', 'Y'],
            "CANON_PLANE_YZ" => plane = ['Y', 'Z', 'X'],
            _ => {}
        }
        let args: Vec<f64> = inside.split(',').filter_map(|a| a.trim().parse().ok()).collect();
        let length = |v: f64| if inch { v * 25.4 } else { v };
        let mut end = vec![0.0; machine.axis_count()];
        let mut set = |letter: char, v: f64| {
            if let Some(k) = axis(letter) {
                end[k] = if machine.axes()[k].kind == AxisKind::Linear { length(v) } else { v };
            }
        };
        let arc = match name {
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" => {
                for (letter, v) in ['X', 'Y', 'Z', 'A', 'B', 'C'].into_iter().zip(&args) {
                    set(letter, *v);
                }
                None
            }
            "ARC_FEED" => {
                set(plane[0], args[0]);
                set(plane[1], args[1]);
                set(plane[2], args[5]);
                for (letter, v) in ['A', 'B', 'C'].into_iter().zip(&args[6..]) {
                    set(letter, *v);
                }
                let axes = [axis(plane[0]).unwrap(), axis(plane[1]).unwrap()];
                Some(SeenArc { axes, centre: [length(args[2]), length(args[3])], sense: args[4].signum() })
            }
            _ => continue,
        };
        moves.push(Canon { moved: SeenMove { end, arc }, inch });
    }
    moves
}

/// Runs one program through rs274 before and after correction; returns the number of canonical
/// moves compared and of unsplit arcs whose centres were checked.
fn compare(machine: &str, errors: &str, program: &str, temperatures: &[f64], moves: usize) -> (usize, usize) {
    let m = Machine::load(format!("../../examples/machines/{machine}.toml")).unwrap();
    let e = ErrorModel::load(format!("../../examples/errors/{errors}.toml"), &m).unwrap();
    let corrector = Corrector::new(&m, &e);
    let options = NcOptions::new(&m);
    let text = std::fs::read_to_string(format!("../../examples/nc/{program}.ngc")).unwrap();
    let r = correct_program(&corrector, &text, program, &options, temperatures).unwrap();
    let original = canon(&m, &rs274(&text));
    let corrected = canon(&m, &rs274(&r.text));
    assert_eq!(original.len(), moves, "{program}: rs274 moves of the example");
    assert_eq!(corrected.len(), original.len() + r.inserted_lines, "{program}");
    let seen: Vec<SeenMove> = original.iter().map(|c| c.moved.clone()).collect();
    let expected = expected_corrections(&m, &corrector, &seen, &options.setup.start, temperatures);
    let (mut k, mut compared, mut unsplit_arcs) = (0, 0, 0);
    for (i, (o, c)) in original.iter().zip(&expected).enumerate() {
        let target: Vec<f64> = o.moved.end.iter().zip(c).map(|(a, b)| a + b).collect();
        // rs274 rounds to 4 decimals of its unit; trueaxis writes 4 (mm, deg) or 5 (inch) decimals
        // and a warm-started correction may differ from a cold one by 0.02 um / 0.2 urad
        let tolerance = |axis: usize| match (m.axes()[axis].kind, o.inch) {
            (AxisKind::Rotary, _) => 0.5e-4 + 0.5e-4 + 2e-7f64.to_degrees(),
            (AxisKind::Linear, true) => (0.5e-4 + 0.5e-5) * 25.4 + 2e-5,
            (AxisKind::Linear, false) => 1e-4 + 2e-5,
        };
        let j = (k..corrected.len())
            .find(|&j| (0..m.axis_count()).all(|a| (corrected[j].moved.end[a] - target[a]).abs() <= tolerance(a)))
            .unwrap_or_else(|| panic!("{program}: no corrected move ends at {target:?} (original {:?})", o.moved.end));
        // the corrected arc keeps its plane and sense; unsplit, its centre moved by the mean
        // correction of its ends
        if let (Some(arc), Some(new)) = (o.moved.arc, corrected[j].moved.arc) {
            assert_eq!((arc.axes, arc.sense), (new.axes, new.sense), "{program}");
            if j == k {
                let start_c = if i == 0 { vec![0.0; m.axis_count()] } else { expected[i - 1].clone() };
                for d in 0..2 {
                    let a = arc.axes[d];
                    let want = arc.centre[d] + 0.5 * (start_c[a] + c[a]);
                    assert!((new.centre[d] - want).abs() <= 2.0 * tolerance(a), "{program}: arc centre {d}: {} vs {want}", new.centre[d]);
                }
                unsplit_arcs += 1;
            }
        }
        compared += 1;
        k = j + 1;
    }
    assert_eq!(k, corrected.len(), "{program}: every corrected move is accounted for");
    (compared, unsplit_arcs)
}

#[test]
fn rs274_sees_every_move_shifted_by_its_correction() {
    if Command::new("rs274").arg("-g").arg("/dev/null").output().is_err() {
        assert!(std::env::var_os("TRUEAXIS_REQUIRE_RS274").is_none(), "TRUEAXIS_REQUIRE_RS274 is set but `rs274` cannot be run");
        println!("SKIPPED: `rs274` (LinuxCNC, Debian package linuxcnc-uspace) is not installed; install it to run this test");
        return;
    }
    let (compared, arcs) = compare("vmc3", "vmc3_backlash", "pocket", &[24.0], 12);
    assert_eq!(compared, 12);
    assert!(arcs >= 1);
    let (compared, arcs) = compare("vmc3", "vmc3_backlash", "arcs", &[22.0], 10);
    assert_eq!(compared, 10);
    assert!(arcs >= 3, "{arcs} unsplit arcs");
    let (compared, _) = compare("c600u", "c600u", "five_axis", &[], 5);
    assert_eq!(compared, 5);
}
