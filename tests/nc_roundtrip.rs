//! NC-program correction round trip: the corrected program, read back, puts every programmed point
//! at the original point plus its correction; split pieces lie on the corrected path; lines without
//! moves are untouched; a zero error model changes nothing; what cannot be handled is refused with
//! the line number.

mod nc_common;

use nc_common::{expected_corrections, SeenMove};
use trueaxis::compensate::nc::interpret::{interpret, Move, MoveKind};
use trueaxis::compensate::nc::parse::parse_program;
use trueaxis::compensate::nc::{correct_program, NcOptions};
use trueaxis::compensate::Corrector;
use trueaxis::errors::ErrorModel;
use trueaxis::machine::Machine;

fn vmc3(errors: &str) -> (Machine, ErrorModel) {
    let m = Machine::load("examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load(format!("examples/errors/{errors}.toml"), &m).unwrap();
    (m, e)
}

fn seen(moves: &[Move]) -> Vec<SeenMove> {
    moves
        .iter()
        .map(|m| SeenMove {
            end: m.end.clone(),
            arc: match m.kind {
                MoveKind::Arc { clockwise, centre, .. } => Some((centre, if clockwise { -1.0 } else { 1.0 })),
                _ => None,
            },
        })
        .collect()
}

fn moves_of(machine: &Machine, text: &str, options: &NcOptions) -> Vec<Move> {
    interpret(machine, &parse_program(text).unwrap(), &options.setup).unwrap()
}

#[test]
fn zero_errors_leave_the_program_byte_for_byte() {
    for (machine, program) in [("vmc3", "pocket"), ("c600u", "five_axis")] {
        let m = Machine::load(format!("examples/machines/{machine}.toml")).unwrap();
        let zero = ErrorModel::zero(&m);
        let text = std::fs::read_to_string(format!("examples/nc/{program}.ngc")).unwrap();
        let r = correct_program(&Corrector::new(&m, &zero), &text, program, &NcOptions::new(&m), &[]).unwrap();
        assert_eq!(r.text, text);
        assert_eq!((r.changed_lines, r.inserted_lines), (0, 0));
        assert!(r.moves >= 5);
    }
}

#[test]
fn every_programmed_point_moves_by_its_correction() {
    let (m, e) = vmc3("vmc3_backlash");
    let corrector = Corrector::new(&m, &e);
    let options = NcOptions::new(&m);
    let text = std::fs::read_to_string("examples/nc/pocket.ngc").unwrap();
    let temperatures = [23.0];
    let r = correct_program(&corrector, &text, "pocket.ngc", &options, &temperatures).unwrap();
    let original = moves_of(&m, &text, &options);
    let corrected = moves_of(&m, &r.text, &options);
    assert_eq!(corrected.len(), original.len() + r.inserted_lines);
    let expected = expected_corrections(&m, &corrector, &seen(&original), &options.setup.start, &temperatures);
    // walk the corrected moves: the pieces of a split move come first, its last piece ends at the
    // corrected end point
    let mut k = 0;
    for (o, c) in original.iter().zip(&expected) {
        let target: Vec<f64> = o.end.iter().zip(c).map(|(a, b)| a + b).collect();
        let tolerance = if o.inch { 0.6e-5 * 25.4 } else { 0.6e-4 }; // half a unit of the last decimal
        let found = (k..corrected.len()).find(|&j| corrected[j].end.iter().zip(&target).all(|(a, b)| (a - b).abs() <= tolerance));
        let j = found.unwrap_or_else(|| panic!("line {}: no corrected move ends at {target:?}", o.block + 1));
        // every move skipped on the way is a piece of this one: its end is on the corrected path
        for piece in &corrected[k..j] {
            let off_path = distance_to_corrected_path(&m, &corrector, o, &piece.end);
            assert!(
                off_path < 1e-3 + 2.0 * tolerance,
                "line {}: piece {:?} is {off_path} mm off the corrected path",
                o.block + 1,
                piece.end
            );
        }
        k = j + 1;
    }
    assert_eq!(k, corrected.len());
    assert!(r.inserted_lines >= 2, "the long X move and the semicircle are split: {}", r.inserted_lines);
    // lines without moves are untouched
    for (a, b) in text.lines().zip(r.text.lines().filter(|l| !l.starts_with('G'))) {
        if a.starts_with('%') || a.starts_with('(') || a.contains("M2") || a.starts_with("N10 ") {
            assert_eq!(a, b);
        }
    }
    assert!(r.text.contains("(plunge)") && r.text.contains("; back to the corner"));
}

/// Distance (mm) from `p` to the original move's path plus the correction along it, sampled finely
/// (both directions of motion are tried, so that a point at a reversal counts).
fn distance_to_corrected_path(m: &Machine, corrector: &Corrector, o: &Move, p: &[f64]) -> f64 {
    use trueaxis::compensate::nc::path::{arc_geometry, point_at};
    use trueaxis::compensate::CorrectionWorkspace;
    let arc = arc_geometry(o);
    let mut ws = CorrectionWorkspace::new(m);
    let mut best = f64::INFINITY;
    let mut x = vec![0.0; m.axis_count()];
    let mut q = vec![0.0; m.axis_count()];
    for i in 0..=2000 {
        point_at(o, arc.as_ref(), i as f64 / 2000.0, &mut x);
        m.pose_to_internal(&x, &mut q);
        for d in [trueaxis::errors::Direction::Positive, trueaxis::errors::Direction::Negative] {
            let dirs = vec![Some(d); m.axis_count()];
            let c =
                corrector.correct_state(&q, &trueaxis::errors::MachineState { directions: Some(&dirs), temperatures: &[23.0] }, &mut ws);
            let dist = (0..3).map(|k| (x[k] + c.dq[k] - p[k]).powi(2)).sum::<f64>().sqrt();
            best = best.min(dist);
        }
    }
    best
}

#[test]
fn incremental_inch_and_work_offsets_are_honoured() {
    let (m, e) = vmc3("vmc3");
    let corrector = Corrector::new(&m, &e);
    let mut options = NcOptions::new(&m);
    options.setup.work_offsets[1] = vec![100.0, 50.0, -200.0];
    let text = "G21 G90 G55\nG0 X10 Y20 Z5\nG91 G0 X-30\nG90 G20 G0 X1\n";
    let r = correct_program(&corrector, text, "t.ngc", &options, &[]).unwrap();
    let moves = moves_of(&m, &r.text, &options);
    let ends = [[110.0, 70.0, -195.0], [80.0, 70.0, -195.0], [125.4, 70.0, -195.0]];
    let expected = expected_corrections(
        &m,
        &corrector,
        &ends.iter().map(|e| SeenMove { end: e.to_vec(), arc: None }).collect::<Vec<_>>(),
        &[0.0; 3],
        &[],
    );
    for (i, (mv, (end, c))) in moves.iter().zip(ends.iter().zip(&expected)).enumerate() {
        let tol = if i == 2 { 0.6e-5 * 25.4 } else { 0.6e-4 };
        for a in 0..3 {
            assert!((mv.end[a] - end[a] - c[a]).abs() <= tol, "move {i} axis {a}: {} vs {}", mv.end[a], end[a] + c[a]);
        }
    }
    // the incremental line stays incremental: X-30 plus the change of correction
    let line = r.text.lines().nth(2).unwrap();
    assert!(line.starts_with("G91 G0 X-30.") || line.starts_with("G91 G0 X-29.9"), "{line}");
}

#[test]
fn unsupported_programs_are_refused_with_the_line() {
    let (m, e) = vmc3("vmc3");
    let corrector = Corrector::new(&m, &e);
    let options = NcOptions::new(&m);
    for (text, needle) in [
        ("G0 X1\nG41 D1 G1 X10\n", "line 2: cutter radius compensation"),
        ("G43 H1\n", "line 1: tool length compensation"),
        ("G1 X#1 F100\n", "line 1: parameters"),
        ("o100 sub\n", "line 1: subroutines"),
        ("G0 X1\nG0 A10\n", "line 2: axis A is not an axis of machine"),
        ("G28\n", "line 1: G28 is not supported"),
        ("G92 X0\n", "line 1: G92 is not supported"),
        ("G0 X1000\n", "line 1: the end point leaves the machine's travel"),
        ("X1\n", "line 1: axis words without a motion mode"),
        ("G2 X10 Y0 R2\n", "line 1: no arc of radius 2 mm"),
    ] {
        let err = correct_program(&corrector, text, "bad.ngc", &options, &[]).unwrap_err();
        assert!(err.is_input(), "{text}");
        assert!(err.to_string().starts_with("bad.ngc: ") && err.to_string().contains(needle), "{text}: {err}");
    }
}
