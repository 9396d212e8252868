//! SINUMERIK subprograms (SINUMERIK 840D sl Programming Manual Fundamentals, "Subprogram
//! technique": calling a subprogram by its name, `L` with a number, program repetition `P`, the
//! indirect call `CALL "NAME"`, the end `M17`/`RET`, or `M2`/`M30`): a call runs the file
//! `NAME.SPF` (`NAME.spf`, `_N_NAME_SPF`) found on the search path `P` times (1 without `P`)
//! with the R parameters shared, as the 840D's R parameters are global. A subprogram with
//! parameters (`PROC NAME(...)`, `NAME(1, 2)`) is not read.
//!
//! The corrected program is one file: the call is expanded into the subprogram's moves, as a
//! LinuxCNC or Fanuc call of a subroutine file is (`crate::plan`).

use crate::interpret::{Exec, Flow};
use crate::trace::flags;

use super::Call;

/// The flow of a subprogram call or `RET` at `step`.
pub(crate) fn flow(exec: &mut Exec, call: &Call, step: usize) -> Result<Flow, String> {
    match call {
        Call::Sub { name, passes } => {
            exec.trace.steps[step].flags |= flags::CALL;
            Ok(Flow::CallFile { name: name.clone(), passes: *passes })
        }
        Call::Return if exec.calls.is_empty() => Err("RET outside a subprogram".into()),
        _ => Ok(Flow::Return { value: None, sequence: None }),
    }
}

/// The subprogram name of a block item: `L` and up to 7 digits, or a name of letters, digits
/// and `_` that starts with two letters (or `_`), as the 840D names programs.
pub fn is_name(name: &str) -> bool {
    let b = name.as_bytes();
    let l_number = b.len() > 1 && b.len() <= 8 && b[0] == b'L' && b[1..].iter().all(u8::is_ascii_digit);
    let named = b.len() >= 2
        && b.len() <= 24
        && b[..2].iter().all(|c| c.is_ascii_alphabetic() || *c == b'_')
        && b.iter().all(|c| c.is_ascii_alphanumeric() || *c == b'_');
    l_number || named
}
