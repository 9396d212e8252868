//! The SINUMERIK drilling cycles CYCLE81-CYCLE83 run (their values and strokes:
//! [`super::drilling`]), called at the current position (`CYCLE81(...)`) or modally (`MCALL
//! CYCLE81(...)`: after every block that programs a position, until `MCALL` alone or another
//! `MCALL CYCLE..`; SINUMERIK 840D sl Programming Manual Fundamentals, "Modal subprogram call
//! (MCALL)"), in G17 along Z.
//!
//! By default each hole is recorded as a [`crate::trace::CycleHole`] (code
//! [`SIEMENS_CODE`] + 10 x the cycle number) and a [`Hole`], to be written as a cycle again with
//! its hole position and levels corrected (`super::kept`); a hole in G91 (its position an
//! increment) or outside G17, and every hole with `expand_cycles`, is expanded into plain moves
//! (each point corrected, the call taken out of the corrected program).

pub use super::drilling::{Drilling, Stroke};
use crate::expr::ExprId;
use crate::interpret::{Exec, Flow};
use crate::modal::{Motion, PlaneSelect};
use crate::program::SourceFile;
use crate::trace::{flags, CycleHole, Role};

/// A cycle call or the end of a modal one.
#[derive(Clone, Debug, PartialEq)]
pub enum Call {
    /// `CYCLE81(...)`-`CYCLE83(...)`, `modal` after `MCALL`; its parameters as written (empty: `None`).
    Cycle { number: u16, args: Vec<Option<ExprId>>, modal: bool },
    /// `MCALL` alone: the modal call off.
    ModalOff,
    /// A subprogram call (`L10`, `NAME`, `CALL "NAME"`) run `passes` times (`P`).
    Sub { name: String, passes: u32 },
    /// `RET` (`M17` is read at run time, as an M code).
    Return,
}

/// The code of a SINUMERIK cycle in [`crate::trace::CycleHole::code`]: this plus 10 x its number
/// (CYCLE81: 10810), apart from the G codes x 10 of the other dialects' cycles.
pub const SIEMENS_CODE: u16 = 10_000;

/// A SINUMERIK hole recorded for writing as a cycle again: the step, the cycle's values, the
/// index of its first stroke among the step's moves (after the block's own positioning move
/// under `MCALL`), and, for a direct call, whether the modal motion was G0 or G1 (a correction of
/// the hole position is then written as a move of its own before the call).
#[derive(Clone, Debug, PartialEq)]
pub struct Hole {
    pub step: u32,
    pub drilling: Drilling,
    pub first: u32,
    pub modal: bool,
    pub linear_motion: bool,
}

/// Runs the cycle call of a block, or sets or ends the modal call; a subprogram call or return
/// is the flow after the block ([`super::subprograms`]).
pub(crate) fn call(exec: &mut Exec, file: &SourceFile, call: &Call, step: usize) -> Result<Option<Flow>, String> {
    let (number, args, modal) = match call {
        Call::ModalOff => {
            exec.siemens_mcall = None;
            return Ok(None);
        }
        Call::Sub { .. } | Call::Return => return super::subprograms::flow(exec, call, step).map(Some),
        Call::Cycle { number, args, modal } => (*number, args, *modal),
    };
    let values = args.iter().map(|a| a.map(|e| exec.eval(file, e)).transpose()).collect::<Result<Vec<_>, _>>()?;
    let text = file.line_text(exec.trace.steps[step].line as usize);
    let written = super::kept::call_spans(text).map_or(String::new(), |(start, end, _)| text[start..end].to_string());
    let drilling = Drilling::of(number, &values, exec.state.frame.inch, written)?;
    if modal {
        // with --expand-cycles the call is not written again: the holes it drills become plain moves
        if exec.expand_cycles {
            exec.trace.steps[step].flags |= flags::EXPAND | flags::SIEMENS_CYCLE;
        }
        exec.siemens_mcall = Some(drilling);
        return Ok(None);
    }
    drill(exec, &drilling, step, false).map(|()| None)
}

/// The modal cycle after a block that programmed a position.
pub(crate) fn modal(exec: &mut Exec, step: usize) -> Result<(), String> {
    let drilling = exec.siemens_mcall.clone().expect("a modal cycle");
    drill(exec, &drilling, step, true)
}

/// One hole at the current position; recorded to be kept as a cycle unless expanded.
fn drill(exec: &mut Exec, d: &Drilling, step: usize, modal: bool) -> Result<(), String> {
    if exec.state.plane != PlaneSelect::Xy {
        return Err(format!("CYCLE{} is read in G17 only", d.number));
    }
    let s = &exec.trace.steps[step];
    let first = exec.trace.moves.len() as u32 - s.moves.start;
    let keep = !exec.expand_cycles && !exec.state.frame.incremental;
    exec.trace.steps[step].flags |= flags::SIEMENS_CYCLE | if keep { 0 } else { flags::EXPAND };
    let initial = exec.state.position[2];
    let mut p = exec.state.position;
    let (mut r_move, mut bottom_move) = (first, first);
    for stroke in d.strokes() {
        let (rapid, level) = match stroke {
            Stroke::Dwell(t) => {
                exec.action(&[(b'G', 4.0), (b'P', t)]);
                continue;
            }
            Stroke::Rapid(l) => (true, l),
            Stroke::Feed(l) => (false, l),
        };
        p[2] = level;
        exec.straight(rapid, p, Role::Generated, false, 0)?;
        let index = exec.trace.moves.len() as u32 - 1 - exec.trace.steps[step].moves.start;
        if index == first {
            r_move = index;
        }
        if !rapid && level == d.depth {
            bottom_move = index;
        }
    }
    if keep {
        let linear_motion = matches!(exec.state.motion, Motion::Rapid | Motion::Feed);
        exec.trace.siemens_holes.push(Hole { step: step as u32, drilling: d.clone(), first, modal, linear_motion });
        exec.trace.holes.push(CycleHole {
            step: step as u32,
            code: SIEMENS_CODE + 10 * d.number,
            plane: PlaneSelect::Xy,
            r: d.start(),
            bottom: d.depth,
            clear: d.rtp,
            initial,
            retract_to_r: false,
            first: true,
            peck: d.pecking.map_or(0.0, |p| p.infeed),
            dwell: d.dwell,
            r_move,
            bottom_move,
        });
    }
    Ok(())
}
