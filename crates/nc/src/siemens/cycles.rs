//! The SINUMERIK drilling cycles (SINUMERIK 840D sl Programming Manual Job Planning / Cycles,
//! "Drilling, centering - CYCLE81", "Drilling, counterboring - CYCLE82"), called at the current
//! position (`CYCLE81(...)`) or modally (`MCALL CYCLE81(...)`: after every block that programs a
//! position, until `MCALL` alone), run as the manual's sequence of moves in G17 along Z:
//!
//! - `G0` to the reference plane plus the safety distance, RFP + SDIS;
//! - `G1` at the programmed feed to the final depth: DP (absolute), or RFP - DPR when DPR (the
//!   depth relative to the reference plane, without sign) is given, which then counts;
//! - CYCLE82: the dwell DTB (seconds) at the depth;
//! - `G0` to the retraction plane RTP.
//!
//! Parameters: `CYCLE81(RTP, RFP, SDIS, DP, DPR)`, `CYCLE82(RTP, RFP, SDIS, DP, DPR, DTB)`, each
//! may be left empty (0, as the cycle takes it; DP or DPR must give the depth); the 840D sl's
//! trailing `_GMODE, _DMODE, _AMODE` are read when `_GMODE` and `_AMODE` are empty or 0 (`_DMODE`
//! only sets the display). The holes are written
//! as plain moves (each point corrected), the cycle call taken out of the corrected program.

use crate::expr::ExprId;
use crate::interpret::Exec;
use crate::modal::PlaneSelect;
use crate::program::SourceFile;
use crate::trace::{flags, Role};

/// A cycle call or the end of a modal one.
#[derive(Clone, Debug, PartialEq)]
pub enum Call {
    /// `CYCLE81(...)`-`CYCLE82(...)`, `modal` after `MCALL`; its parameters as written (empty: `None`).
    Cycle { number: u16, args: Vec<Option<ExprId>>, modal: bool },
    /// `MCALL` alone: the modal call off.
    ModalOff,
}

/// A drilling cycle's values (program units, along Z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drilling {
    pub number: u16,
    /// Retraction plane RTP, the plane where the drilling starts (RFP + SDIS), the final depth.
    pub rtp: f64,
    pub start: f64,
    pub depth: f64,
    /// Dwell at the depth (s).
    pub dwell: f64,
}

impl Drilling {
    /// From the values of `CYCLE<number>(...)`.
    fn of(number: u16, v: &[Option<f64>]) -> Result<Drilling, String> {
        let name = format!("CYCLE{number}");
        // the 840D sl's mode parameters _GMODE, _DMODE (display only), _AMODE after the others
        let modes = if number == 81 { 5 } else { 6 };
        if v.len() > modes + 3 {
            return Err(format!("{name} takes {} parameters, not {}", modes + 3, v.len()));
        }
        let get = |k: usize| v.get(k).copied().flatten();
        for (k, mode) in [(modes, "_GMODE"), (modes + 2, "_AMODE")] {
            if let Some(m) = get(k).filter(|&m| m != 0.0) {
                return Err(format!("{name}: {mode} {m} (a mode of the 840D sl's cycle) is not read: leave it empty or 0"));
            }
        }
        let (rtp, rfp, sdis) = (get(0).unwrap_or(0.0), get(1).unwrap_or(0.0), get(2).unwrap_or(0.0).abs());
        let depth = match (get(3), get(4)) {
            (_, Some(dpr)) if dpr != 0.0 => rfp - dpr.abs(),
            (Some(dp), _) => dp,
            _ => return Err(format!("{name} without its final depth DP or DPR")),
        };
        let dwell = get(5).unwrap_or(0.0);
        if dwell < 0.0 {
            return Err(format!("{name}: the dwell DTB in revolutions ({dwell}) is not read: give it in seconds"));
        }
        let start = rfp + sdis;
        if depth >= start {
            return Err(format!("{name}: the final depth {depth} is not below the reference plane plus the safety distance {start}"));
        }
        if rtp < start {
            return Err(format!("{name}: the retraction plane RTP {rtp} is below the reference plane plus the safety distance {start}"));
        }
        Ok(Drilling { number, rtp, start, depth, dwell })
    }
}

/// Runs the cycle call of a block, or sets or ends the modal call.
pub(crate) fn call(exec: &mut Exec, file: &SourceFile, call: &Call, step: usize) -> Result<(), String> {
    let (number, args, modal) = match call {
        Call::ModalOff => {
            exec.siemens_mcall = None;
            return Ok(());
        }
        Call::Cycle { number, args, modal } => (*number, args, *modal),
    };
    let values = args.iter().map(|a| a.map(|e| exec.eval(file, e)).transpose()).collect::<Result<Vec<_>, _>>()?;
    let drilling = Drilling::of(number, &values)?;
    // the call is not written again: the holes it drills become plain moves
    exec.trace.steps[step].flags |= flags::EXPAND | flags::SIEMENS_CYCLE;
    if modal {
        exec.siemens_mcall = Some(drilling);
        return Ok(());
    }
    drill(exec, &drilling, step)
}

/// The modal cycle after a block that programmed a position.
pub(crate) fn modal(exec: &mut Exec, step: usize) -> Result<(), String> {
    let drilling = exec.siemens_mcall.expect("a modal cycle");
    drill(exec, &drilling, step)
}

/// One hole at the current position.
fn drill(exec: &mut Exec, d: &Drilling, step: usize) -> Result<(), String> {
    if exec.state.plane != PlaneSelect::Xy {
        return Err(format!("CYCLE{} is read in G17 only", d.number));
    }
    exec.trace.steps[step].flags |= flags::EXPAND | flags::SIEMENS_CYCLE;
    let mut p = exec.state.position;
    p[2] = d.start;
    exec.straight(true, p, Role::Generated, false, 0)?;
    p[2] = d.depth;
    exec.straight(false, p, Role::Generated, false, 0)?;
    if d.dwell > 0.0 {
        exec.action(&[(b'G', 4.0), (b'P', d.dwell)]);
    }
    p[2] = d.rtp;
    exec.straight(true, p, Role::Generated, false, 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_from_dp_or_dpr_and_the_mode_parameters() {
        let d = Drilling::of(81, &[Some(15.0), Some(0.0), Some(2.0), Some(-12.0), None]).unwrap();
        assert_eq!((d.rtp, d.start, d.depth, d.dwell), (15.0, 2.0, -12.0, 0.0));
        // DPR (without sign) counts over DP
        let d = Drilling::of(82, &[Some(15.0), Some(1.0), Some(2.0), Some(-30.0), Some(-8.0), Some(0.5)]).unwrap();
        assert_eq!((d.start, d.depth, d.dwell), (3.0, -7.0, 0.5));
        let sl = [Some(10.0), Some(0.0), Some(2.0), Some(-4.0), None, Some(0.0), Some(1.0), None];
        assert_eq!(Drilling::of(81, &sl).unwrap().depth, -4.0);
        let mut amode = sl;
        amode[7] = Some(10.0);
        assert!(Drilling::of(81, &amode).unwrap_err().contains("_AMODE 10"));
        assert!(Drilling::of(81, &[Some(10.0), Some(0.0), Some(2.0)]).unwrap_err().contains("without its final depth"));
        assert!(Drilling::of(81, &[Some(1.0), Some(0.0), Some(2.0), Some(-4.0)]).unwrap_err().contains("RTP 1 is below"));
        assert!(Drilling::of(82, &[Some(10.0), Some(0.0), Some(2.0), Some(-4.0), None, Some(-2.0)]).unwrap_err().contains("revolutions"));
    }
}
