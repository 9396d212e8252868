//! Shared by the NC tests: the expected correction of a programmed point, computed directly with the
//! pose corrector and directions of motion derived here from the moves; LinuxCNC's rs274 as an
//! independent reader ([`rs274`]); the check of corrected moves through the erroneous machine
//! ([`oracle`]). Each test uses a part.
#![allow(dead_code)]

pub mod fadal_to_ngc;
pub mod fanuc_to_ngc;
pub mod oracle;
pub mod rs274;
pub mod siemens_to_ngc;

use trueaxis::compensate::nc::{Move, MoveKind, Role};

/// The canonical moves rs274 prints for the moves trueaxis reads: one per move, but one for all
/// the turns of a multi-turn arc (trueaxis writes its turns as separate arcs); their number and
/// the indices of the moves not corrected by design: the returns to the G28/G30 positions, and an
/// intermediate point of G28/G30 where the machine already is (`G28 G91 X0. Y0.` after `G28 G91
/// Z0.`: the controller stays where the last written point put it).
pub fn canonical_homes(machine: &Machine, moves: &[Move]) -> (usize, Vec<usize>) {
    let mut count = 0;
    let mut homes = Vec::new();
    for (i, m) in moves.iter().enumerate() {
        let turn = continues_arc(moves, i);
        if turn {
            continue;
        }
        let _ = machine;
        if m.role == Role::Home || matches!(m.role, Role::Intermediate { .. }) && m.start == m.end {
            homes.push(count);
        }
        count += 1;
    }
    (count, homes)
}

/// Whether move `i` is a generated arc continuing the arc before it in the same block (one
/// canonical arc for rs274, several moves for the interpreter: a multi-turn arc's turns).
fn continues_arc(moves: &[Move], i: usize) -> bool {
    let m = &moves[i];
    i > 0
        && m.role == Role::Generated
        && matches!(m.kind, MoveKind::Arc { .. })
        && moves[i - 1].step == m.step
        && matches!(moves[i - 1].kind, MoveKind::Arc { .. })
}

/// The slack of the canned cycles kept as cycles, per canonical move (see [`canonical_homes`]):
/// the bottom of each hole exact (its path within the hole's clearance), its R point exact along
/// the cycle axis and within the reported lean across it, its other points within the reported
/// clearance.
pub fn hole_slack(moves: &[Move], holes: &[trueaxis::compensate::nc::write::HoleReport]) -> Vec<oracle::Slack> {
    let mut canonical = Vec::with_capacity(moves.len());
    let mut count = 0usize;
    for i in 0..moves.len() {
        let turn = continues_arc(moves, i);
        canonical.push(if turn { count - 1 } else { count });
        count += usize::from(!turn);
    }
    let mut slack = vec![oracle::Slack::default(); count];
    for h in holes {
        for i in h.moves.clone() {
            let path_um = h.clearance_um.max(h.lean_um) + 0.01;
            slack[canonical[i as usize]] = if i == h.bottom_move {
                oracle::Slack { end_um: 0.0, along_exact: false, axis: h.axis, path_um }
            } else if i == h.r_move {
                oracle::Slack { end_um: h.lean_um + 0.01, along_exact: true, axis: h.axis, path_um }
            } else {
                oracle::Slack { end_um: h.clearance_um + 0.01, along_exact: false, axis: h.axis, path_um }
            };
        }
    }
    slack
}

use trueaxis::compensate::{CorrectionWorkspace, Corrector};
use trueaxis::error_model::{Direction, MachineState};
use trueaxis::machine::Machine;

/// A move as a consumer sees it: end point (mm, deg, machine axis order) and, for an arc, its plane
/// and centre.
#[derive(Clone, Debug)]
pub struct SeenMove {
    pub end: Vec<f64>,
    pub arc: Option<SeenArc>,
}

/// An arc: the machine axes of its plane's first and second coordinates (X Y for G17, Z X for G18,
/// Y Z for G19), the centre in them (mm) and the sense (+1 counterclockwise in that plane, -1
/// clockwise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeenArc {
    pub axes: [usize; 2],
    pub centre: [f64; 2],
    pub sense: f64,
}

/// The direction of a motion `v` (mm or deg), `None` below 1e-12 (no motion).
pub fn direction_of(v: f64) -> Option<Direction> {
    if v > 1e-12 {
        Some(Direction::Positive)
    } else if v < -1e-12 {
        Some(Direction::Negative)
    } else {
        None
    }
}

/// Directions of motion at the end of each move (an axis that does not move keeps its last
/// direction; along an arc the sign of the tangent at the end), then the correction there (mm, deg).
pub fn expected_corrections(
    machine: &Machine,
    corrector: &Corrector,
    moves: &[SeenMove],
    start: &[f64],
    temperatures: &[f64],
) -> Vec<Vec<f64>> {
    let n = machine.axis_count();
    let mut ws = CorrectionWorkspace::new(machine);
    let mut dirs: Vec<Option<Direction>> = vec![None; n];
    let mut previous = start.to_vec();
    let sign = direction_of;
    let mut out = Vec::new();
    for mv in moves {
        for k in 0..n {
            if let Some(d) = sign(mv.end[k] - previous[k]) {
                dirs[k] = Some(d);
            }
        }
        if let Some(SeenArc { axes: [a, b], centre, sense }) = mv.arc {
            let (rx, ry) = (mv.end[a] - centre[0], mv.end[b] - centre[1]);
            // tangent of a counterclockwise arc at angle t is (-sin t, cos t)
            for (k, v) in [(a, -ry * sense), (b, rx * sense)] {
                if let Some(d) = sign(v) {
                    dirs[k] = Some(d);
                }
            }
        }
        let mut q = vec![0.0; n];
        machine.pose_to_internal(&mv.end, &mut q);
        let c = corrector.correct_state(&q, &MachineState { directions: Some(&dirs), temperatures }, &mut ws);
        assert!(c.converged);
        out.push(c.dq_user(machine));
        previous = mv.end.clone();
    }
    out
}
