//! The rotary-axis ballbar tests of a request: the four steps A1, A2, C1, C2 of Jiang 2014 (the
//! location errors of the two rotary axes, with U) and the two-length rotary-table test of Zhu
//! 2008 (the table's tilts and axial error, with U); bar lengths and offsets in mm.

use super::super::{CalibrationError, RotaryBallbarPart, TmbbPart};
use super::request::{bad, ReportRequest};
use trueaxis::identify::pige_report::{bar_lengths, method_of, PigeRequest};
use trueaxis::identify::tmbb::TmbbSetup;
use trueaxis::machine::Machine;

/// The rotary-axis ballbar test, if given.
pub fn rotary_ballbar(request: &ReportRequest, machine: &Machine) -> Result<Option<RotaryBallbarPart>, CalibrationError> {
    let files = match request.rotary_ballbar.as_slice() {
        [] => return Ok(None),
        [a1, a2, c1, c2] => [a1.clone(), a2.clone(), c1.clone(), c2.clone()],
        other => return Err(bad(format!("--rotary-ballbar takes the four files A1,A2,C1,C2 in this order, got {}", other.len()))),
    };
    let bars = match request.rotary_bars.as_slice() {
        [normal, extended] => bar_lengths(*normal, *extended).map_err(|_| {
            bad(format!("--rotary-bars {normal},{extended}: the extended length must exceed the normal one, both positive (mm)"))
        })?,
        other => return Err(bad(format!("--rotary-bars takes two lengths R,L_e in mm, got {}", other.len()))),
    };
    let method =
        method_of(&request.rotary_method, request.rotary_outer_offset, request.rotary_outer_positions, request.rotary_inner_positions)
            .map_err(|e| bad(e.to_string().replace("--", "--rotary-")))?;
    let pige = PigeRequest {
        files,
        method,
        bars,
        pivot_offset_outer: request.rotary_pivot_offset_a,
        pivot_offset_inner: request.rotary_pivot_offset_c,
        noise_um: 1.0,
    };
    let part = RotaryBallbarPart::evaluate(machine, pige).map_err(|e| match e {
        // the library names the options of `ballbar identify`; here they are --rotary-...
        CalibrationError::Input(m) => CalibrationError::Input(m.replace("--pivot-offset-", "--rotary-pivot-offset-")),
        other => other,
    })?;
    Ok(Some(part))
}

/// The two-length rotary-table test, if given.
pub fn tmbb(request: &ReportRequest) -> Result<Option<TmbbPart>, CalibrationError> {
    let (short, long) = match request.tmbb.as_slice() {
        [] => return Ok(None),
        [short, long] => (short, long),
        other => return Err(bad(format!("--tmbb takes the two files SHORT,LONG (short bar first), got {}", other.len()))),
    };
    let setup = match request.tmbb_setup.as_slice() {
        &[rx, rz, l1, l2] => TmbbSetup { rx, rz, l1, l2 },
        other => return Err(bad(format!("--tmbb-setup takes RX,RZ,L1,L2 in mm, got {} numbers", other.len()))),
    };
    Ok(Some(TmbbPart::evaluate(&setup, short, long).map_err(|e| prefixed("--tmbb", e))?))
}

/// A bad input of an option's files, named by the option.
fn prefixed(option: &str, e: CalibrationError) -> CalibrationError {
    match e {
        CalibrationError::Input(m) => CalibrationError::Input(format!("{option}: {m}")),
        other => other,
    }
}
