//! Which subprogram calls a controller runs besides LinuxCNC's O-word subroutines, and where a
//! local call goes:
//!
//! - `M98 P<program> L<repeats>` / `M99`: the Fanuc family (Fanuc 0i/30i operator's manual,
//!   "Subprogram"), and Mach3/Mach4, which read RS274/NGC but call subprograms the Fanuc way
//!   ("Using Mach3Mill", 10.7: a subprogram starts with `O<program>` on a line of its own, after the
//!   main program's `M30`, and ends with `M99`; `L` repeats it): the controllers whose table lists
//!   M98 among their codes;
//! - `M97 P<N label> L<repeats>`: Haas's local subprogram call (Haas Mill Operator's Manual, "M97
//!   Local Sub-Program Call"): the block numbered `N<label>` of the same program is the first block
//!   of the subprogram, which ends with `M99` and returns to the block after the `M97`.
//!
//! A call runs its body `L` times (`L0`: not at all); the same machinery runs both (one level of
//! the call stack each, [`crate::interpret::MAX_CALL_LEVELS`] at most).

use crate::dialect::Dialect;
use crate::dialects::{Controller, DialectTable};
use crate::program::SourceFile;

/// Whether the controller of `table` runs `M98 P.. L..` calls of `O` programs and their `M99`.
pub(crate) fn runs_m98(table: &DialectTable) -> bool {
    table.family == Dialect::Fanuc
        || table.m_codes.is_some_and(|lists| lists.iter().flat_map(|l| l.iter()).any(|e| (e.from..=e.to).contains(&98)))
}

/// Whether `M99 P<N>` returns to block `N` of the caller (Fanuc 0i operator's manual, "Subprogram":
/// P the sequence number of the return destination; Haas, Fadal and Mach4 read it so). Mach3's
/// manual gives `M99` no `P` ("Using Mach3Mill", 10.7: `M99` returns to the block after the
/// `M98`), so a Mach3 program with one is refused rather than read as a Fanuc's.
pub(crate) fn m99_returns_to_block(table: &DialectTable) -> bool {
    !std::ptr::eq(table, Controller::Mach3.table())
}

/// Whether the controller of `table` runs Haas's `M97 P<N label>` local calls.
pub(crate) fn runs_m97(table: &DialectTable) -> bool {
    std::ptr::eq(table, Controller::Haas.table())
}

/// The line of block `N<label>` in the program (the `O` section of the file) that holds line `from`:
/// where an `M97 P<label>` at `from` goes.
pub(crate) fn local_label(file: &SourceFile, from: usize, label: u32) -> Result<usize, String> {
    let section = |k: usize| file.programs.values().filter(|&&p| p <= k).max().copied().unwrap_or(0);
    let here = section(from);
    file.sequence
        .get(&label)
        .and_then(|lines| lines.iter().copied().find(|&k| section(k) == here))
        .ok_or_else(|| format!("M97 P{label}: no block N{label} in this program (a local subprogram starts at its N number)"))
}

/// The number and the repeats of an `M98 P.. L..` call: `P` the program, `L` the repeats (1 without
/// it); without `L`, a `P` of more than four digits holds the repeats in its upper digits
/// (`M98 P30010`: O0010 three times, Fanuc 0i).
pub(crate) fn m98_call(p: f64, l: Option<f64>) -> (u32, u32) {
    let (mut number, mut repeat) = (p.round() as u64, l.map_or(1, |v| v.round() as u32));
    if l.is_none() && number > 9999 {
        repeat = (number / 10_000) as u32;
        number %= 10_000;
    }
    (number as u32, repeat)
}

#[cfg(test)]
mod tests {
    use crate::axes::{AxisSpec, MachineAxes};
    use crate::{Controller, ProgramSetup};

    fn mill() -> MachineAxes {
        let axis = |letter| AxisSpec { letter, rotary: false, range: None };
        MachineAxes { name: "mill".into(), axes: vec![axis('X'), axis('Y'), axis('Z')] }
    }

    /// X Y of the end of every move, or the error with its line.
    fn ends(text: &str, controller: Controller) -> Result<Vec<[f64; 2]>, String> {
        let axes = mill();
        let setup = ProgramSetup::zero(&axes);
        crate::run(&axes, text.as_bytes(), "p.nc", Some(controller), &setup)
            .map(|(trace, _)| trace.moves.iter().map(|m| [m.end[0], m.end[1]]).collect())
            .map_err(|e| format!("line {}: {}", e.line, e.message))
    }

    /// Haas `M97 P100 L3`: the blocks from `N100` to its `M99` run three times (incremental steps
    /// add up: X 1, 2, 3 and Y 2, 4, 6), then the block after the `M97`; an `N` number that is
    /// not in the program is refused with the line; a Fanuc passes M97 (its builder's code).
    #[test]
    fn haas_m97_repeats_the_local_subprogram_and_returns() {
        let text = "%\nO1\nG21 G90 G0 X0. Y0. Z0.\nM97 P100 L3\nG0 X50.\nM30\nN100 G91 G1 X1. F100.\nY2.\nG90 M99\n%\n";
        let expected = [[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [2.0, 2.0], [2.0, 4.0], [3.0, 4.0], [3.0, 6.0], [50.0, 6.0]];
        assert_eq!(ends(text, Controller::Haas), Ok(expected.to_vec()));
        // L0 runs it not at all; without L once
        assert_eq!(ends(&text.replace(" L3", " L0"), Controller::Haas), Ok(vec![[0.0, 0.0], [50.0, 0.0]]));
        assert_eq!(ends(&text.replace(" L3", ""), Controller::Haas).map(|e| e.len()), Ok(4));
        // nested: the local subprogram calls another one
        let nested = "%\nO1\nG21 G90 G0 X0. Y0. Z0.\nM97 P100 L2\nM30\nN100 M97 P200\nG91 G1 Y1. F100.\nG90 M99\nN200 G91 G1 X1. F100.\nG90 M99\n%\n";
        let expected = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 1.0], [2.0, 2.0]];
        assert_eq!(ends(nested, Controller::Haas), Ok(expected.to_vec()));
        assert_eq!(
            ends(&text.replace("P100", "P101"), Controller::Haas),
            Err("line 4: M97 P101: no block N101 in this program (a local subprogram starts at its N number)".into())
        );
        // the label is looked for in the caller's program only (`O2` is another program)
        let other = "%\nO1\nG21 G90 G0 X0. Y0. Z0.\nM97 P100\nM30\nO2\nN100 G1 X1. F100.\nM99\n%\n";
        assert_eq!(
            ends(other, Controller::Haas).unwrap_err(),
            "line 4: M97 P100: no block N100 in this program (a local subprogram starts at its N number)"
        );
        assert_eq!(ends(text, Controller::Fanuc).map(|e| e.len()), Ok(2));
    }

    /// Mach3/Mach4 `M98 P1001 L2` with `O1001` after `M30` (RS274/NGC numbers: no decimal point
    /// needed): the subprogram's incremental step runs twice; `M99` in the main program and an
    /// `O` program that is not there are refused with the line; LinuxCNC refuses `M98` and the
    /// bare `O1001` as rs274 does.
    #[test]
    fn mach_m98_calls_an_o_subprogram_after_m30() {
        let text = "G21 G90\nG0 X0 Y0 Z0\nM98 P1001 L2\nG0 X-5\nM30\nO1001 (STEP)\nG91 G1 X10 F100\nG90\nM99\n";
        for mach in [Controller::Mach3, Controller::Mach4] {
            assert_eq!(ends(text, mach), Ok(vec![[0.0, 0.0], [10.0, 0.0], [20.0, 0.0], [-5.0, 0.0]]));
            assert_eq!(ends("G21 G90\nG0 X1\nM99\n", mach), Err("line 3: M99 in the main program restarts it endlessly".into()));
            let missing = ends(&text.replace("P1001", "P1002"), mach).unwrap_err();
            assert!(missing.starts_with("line 3: program O1002 is neither in the file"), "{missing}");
        }
        // M99 P<N>: a Fanuc's return to block N of the caller, which Mach3's manual does not give
        let back = "G21 G90\nG0 X0 Y0 Z0\nM98 P1001\nG0 X-5\nN40 G0 Y7\nM30\nO1001\nG91 G1 X10 F100\nG90\nM99 P40\n";
        assert_eq!(ends(back, Controller::Mach4), Ok(vec![[0.0, 0.0], [10.0, 0.0], [10.0, 7.0]]));
        assert_eq!(
            ends(back, Controller::Mach3),
            Err("line 10: M99 P40: Mach3's M99 has no P (\"Using Mach3Mill\", 10.7: it returns to the block after the M98): not supported"
                .into())
        );
        let linuxcnc = ends(text, Controller::LinuxCnc).unwrap_err();
        assert!(linuxcnc.starts_with("line 3: M98 is a Fanuc subprogram call"), "{linuxcnc}");
        let bare = "G21 G90\nO1001\nG0 X1\nM2\n";
        assert_eq!(
            ends(bare, Controller::LinuxCnc),
            Err("line 2: `o1001` is not followed by sub, endsub, call, return, if, elseif, else, endif, while, endwhile, do, repeat, endrepeat, break or continue".into())
        );
        assert_eq!(ends(bare, Controller::Mach3), Ok(vec![[1.0, 0.0]]));
        // an O-word statement stays one in Mach3 (`o100 sub` is no program number)
        assert!(ends("o100 sub\nG0 X1\no100 endsub\nM2\n", Controller::Mach3).is_ok());
    }
}
