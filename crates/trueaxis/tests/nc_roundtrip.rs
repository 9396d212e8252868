//! NC-program correction round trip: the corrected program, read back, puts every programmed point
//! at the original point plus its correction (computed here with the pose corrector); every piece of
//! a split move lies on the corrected path, in order, none a jump; no line is a bare motion word;
//! lines without moves are untouched; a zero error model changes nothing; what cannot be handled is
//! refused with the line number. Programs: the vmc3 pocket (backlash and a thermal term), arcs in
//! G17/G18/G19, and the c600u five-axis program through the singularity at A = 0.

mod nc_common;

use nc_common::{expected_corrections, SeenArc, SeenMove};
use trueaxis::compensate::nc::interpret::{interpret, Move, MoveKind};
use trueaxis::compensate::nc::parse::parse_program;
use trueaxis::compensate::nc::path::{arc_geometry, point_at};
use trueaxis::compensate::nc::{correct_program, NcOptions, NcResult, MM_PER_INCH};
use trueaxis::compensate::{CorrectionWorkspace, Corrector};
use trueaxis::errors::{Direction, ErrorModel, MachineState};
use trueaxis::machine::{AxisKind, Machine};

fn vmc3(errors: &str) -> (Machine, ErrorModel) {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load(format!("../../examples/errors/{errors}.toml"), &m).unwrap();
    (m, e)
}

fn seen(moves: &[Move]) -> Vec<SeenMove> {
    moves
        .iter()
        .map(|m| SeenMove {
            end: m.end.clone(),
            arc: match m.kind {
                MoveKind::Arc { clockwise, centre, plane, .. } => {
                    Some(SeenArc { axes: [plane.first, plane.second], centre, sense: if clockwise { -1.0 } else { 1.0 } })
                }
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
        let m = Machine::load(format!("../../examples/machines/{machine}.toml")).unwrap();
        let zero = ErrorModel::zero(&m);
        let text = std::fs::read_to_string(format!("../../examples/nc/{program}.ngc")).unwrap();
        let r = correct_program(&Corrector::new(&m, &zero), &text, program, &NcOptions::new(&m), &[]).unwrap();
        assert_eq!(r.text, text);
        assert_eq!((r.changed_lines, r.inserted_lines), (0, 0));
        assert!(r.moves >= 5);
    }
}

/// What a written coordinate may differ from the exact corrected one: half a unit of the last
/// decimal (4 in mm and deg, 5 in inch) plus the difference between a warm-started and a cold
/// correction (0.02 um, 0.2 urad).
fn tolerance(machine: &Machine, axis: usize, inch: bool) -> f64 {
    match machine.axes()[axis].kind {
        AxisKind::Rotary => 0.5e-4 + 2e-7f64.to_degrees(),
        AxisKind::Linear if inch => 0.5e-5 * MM_PER_INCH + 2e-5,
        AxisKind::Linear => 0.5e-4 + 2e-5,
    }
}

/// Parameter in [0, 1] of the point of move `o` nearest to `x` (mm, deg): the projection on the
/// straight move in axis space, or the angle around an arc's centre.
fn parameter_of(o: &Move, x: &[f64]) -> f64 {
    match (o.kind, arc_geometry(o)) {
        (MoveKind::Arc { plane, centre, .. }, Some(g)) => {
            let angle = (x[plane.second] - centre[1]).atan2(x[plane.first] - centre[0]);
            let turn = std::f64::consts::TAU;
            let d = (angle - g.start_angle).rem_euclid(turn);
            let d = if g.sweep < 0.0 && d > 0.0 { d - turn } else { d };
            (d / g.sweep).clamp(0.0, 1.0)
        }
        _ => {
            let (mut along, mut length) = (0.0, 0.0);
            for ((x, s), e) in x.iter().zip(&o.start).zip(&o.end) {
                along += (x - s) * (e - s);
                length += (e - s).powi(2);
            }
            (along / length).clamp(0.0, 1.0)
        }
    }
}

/// Where on the corrected path of move `o` the point `piece` lies: the parameter `t` with
/// `piece = point(t) + correction(t)` (a few fixed-point steps, the correction being micrometres),
/// and the largest deviation in units of [`tolerance`] (directions of motion: each uniform sign is
/// tried, the library holds them constant over a piece).
fn locate(m: &Machine, corrector: &Corrector, o: &Move, piece: &[f64], temperatures: &[f64]) -> (f64, f64) {
    let n = m.axis_count();
    let mut ws = CorrectionWorkspace::new(m);
    let arc = arc_geometry(o);
    let (mut x, mut q) = (vec![0.0; n], vec![0.0; n]);
    let mut best = (0.0, f64::INFINITY);
    for d in [Direction::Positive, Direction::Negative] {
        let dirs = vec![Some(d); n];
        let mut correction = |t: f64, x: &mut Vec<f64>| {
            point_at(o, arc.as_ref(), t, x);
            m.pose_to_internal(x, &mut q);
            corrector.correct_state(&q, &MachineState { directions: Some(&dirs), temperatures }, &mut ws).dq_user(m)
        };
        let mut t = parameter_of(o, piece);
        for _ in 0..4 {
            let c = correction(t, &mut x);
            let shifted: Vec<f64> = piece.iter().zip(&c).map(|(p, c)| p - c).collect();
            t = parameter_of(o, &shifted);
        }
        let c = correction(t, &mut x);
        let deviation = (0..n).map(|k| (x[k] + c[k] - piece[k]).abs() / tolerance(m, k, o.inch)).fold(0.0, f64::max);
        if deviation < best.1 {
            best = (t, deviation);
        }
    }
    best
}

/// Corrects `program` and reads it back: every original end point at the original plus its
/// correction, every piece on the corrected path in order, none shorter than 1e-4 of its move (a
/// jump of the correction would be isolated in a piece of 1e-6), no bare motion word. Returns the
/// result and the number of pieces checked.
fn check_round_trip(m: &Machine, e: &ErrorModel, program: &str, temperatures: &[f64]) -> (NcResult, usize) {
    let corrector = Corrector::new(m, e);
    let options = NcOptions::new(m);
    let text = std::fs::read_to_string(program).unwrap();
    let r = correct_program(&corrector, &text, program, &options, temperatures).unwrap();
    for line in r.text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        assert!(!(words.len() == 1 && ["G0", "G1", "G2", "G3"].contains(&words[0])), "{program}: a bare `{line}`");
    }
    let original = moves_of(m, &text, &options);
    let corrected = moves_of(m, &r.text, &options);
    assert_eq!(corrected.len(), original.len() + r.inserted_lines);
    let expected = expected_corrections(m, &corrector, &seen(&original), &options.setup.start, temperatures);
    let mut k = 0;
    let mut pieces = 0;
    for (o, c) in original.iter().zip(&expected) {
        let target: Vec<f64> = o.end.iter().zip(c).map(|(a, b)| a + b).collect();
        let on_target = |j: usize| (0..m.axis_count()).all(|a| (corrected[j].end[a] - target[a]).abs() <= tolerance(m, a, o.inch));
        let j = (k..corrected.len())
            .find(|&j| on_target(j))
            .unwrap_or_else(|| panic!("line {}: no corrected move ends at {target:?}", o.block + 1));
        // every move skipped on the way is a piece of this one, on its corrected path, in order
        let mut t_before = 0.0;
        for piece in &corrected[k..j] {
            let (t, deviation) = locate(m, &corrector, o, &piece.end, temperatures);
            assert!(deviation <= 1.0, "line {}: piece {:?} is {deviation} tolerances off the corrected path", o.block + 1, piece.end);
            assert!(t - t_before >= 1e-4, "line {}: a piece from t = {t_before} to {t}", o.block + 1);
            t_before = t;
            pieces += 1;
        }
        assert!(corrected[k..j].is_empty() || 1.0 - t_before >= 1e-4, "line {}: last piece from t = {t_before}", o.block + 1);
        k = j + 1;
    }
    assert_eq!(k, corrected.len());
    (r, pieces)
}

#[test]
fn every_programmed_point_moves_by_its_correction() {
    let (m, e) = vmc3("vmc3_backlash");
    let (r, pieces) = check_round_trip(&m, &e, "../../examples/nc/pocket.ngc", &[23.0]);
    assert!(pieces >= 2 && r.inserted_lines >= 2, "the long X move and the semicircle are split: {}", r.inserted_lines);
    // lines without moves are untouched
    let text = std::fs::read_to_string("../../examples/nc/pocket.ngc").unwrap();
    for (a, b) in text.lines().zip(r.text.lines().filter(|l| !l.starts_with('G'))) {
        if a.starts_with('%') || a.starts_with('(') || a.contains("M2") || a.starts_with("N10 ") {
            assert_eq!(a, b);
        }
    }
    assert!(r.text.contains("(plunge)") && r.text.contains("; back to the corner"));
}

#[test]
fn arcs_in_the_three_planes_move_by_their_corrections() {
    let (m, e) = vmc3("vmc3_backlash");
    let (r, pieces) = check_round_trip(&m, &e, "../../examples/nc/arcs.ngc", &[22.0]);
    assert_eq!(r.moves, 10);
    assert!(pieces >= 1, "{pieces}");
    // each plane's centre words are rewritten in place: I J, then K I (G18), then J K (G19)
    let lines: Vec<&str> = r.text.lines().collect();
    assert!(lines.iter().any(|l| l.starts_with("G18 G2 ") && l.contains(" I") && l.contains(" K")));
    assert!(lines.iter().any(|l| l.starts_with("G19 G2 ") && l.contains(" J") && l.contains(" K")));
}

#[test]
fn the_five_axis_program_through_the_singularity_moves_by_its_corrections() {
    // c600u with its non-zero example errors (seed 001 Table 3.1 sizes): `G1 A30` from A = 0 passes
    // the singularity, where the C correction fades in continuously (up to 0.2 deg), so the move is
    // split into pieces that follow it; none of them swings C alone
    let m = Machine::load("../../examples/machines/c600u.toml").unwrap();
    let e = ErrorModel::load("../../examples/errors/c600u.toml", &m).unwrap();
    let (r, pieces) = check_round_trip(&m, &e, "../../examples/nc/five_axis.ngc", &[]);
    assert_eq!(r.moves, 5);
    assert!(pieces >= 20, "{pieces} pieces");
    assert!(r.max_residual_um < 0.01, "{}", r.max_residual_um);
    // at A = 0 the C-axis tilts (EB0A + EB0C = 349.066 urad) cannot be corrected and are reported
    assert!((r.max_uncorrectable_urad - 349.066).abs() < 1e-3, "{}", r.max_uncorrectable_urad);
    // the largest C correction is the damped maximum, at most t / eps = 3490.7 urad
    assert!(r.max_correction_urad > 3000.0 && r.max_correction_urad < 3491.0, "{}", r.max_correction_urad);
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
