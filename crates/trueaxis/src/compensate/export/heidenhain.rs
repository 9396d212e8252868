//! Heidenhain non-linear axis error compensation (specs/anchors.md §3; iTNC 530 / TNC 640 technical
//! manuals): one `*.COM` table per driving axis with the columns `NR`, `AXISPOS` (position of the
//! driving axis, mm or deg, relative to the machine datum) and one column per compensated axis (named
//! by its axis key), plus `BACKLASH` (the own-axis compensation value for negative traverse); a
//! `*.CMA` table assigns the `.COM` files to the driving axes (`[compensated axis] = F(driving axis)`)
//! and marks the line `ACTIVE`. At most 256 equidistant points per table.
//!
//! Values are trueaxis corrections (added to the position) in mm, deg for rotary axes; the header
//! unit is `MM`. Cross-axis columns are zero at the reference pose (see `tables`).

use super::{
    check_count, check_equal_spacing, check_rotary_closure, check_user_limits, closure_tolerance, signed, ExportInput, ExportedFile,
};
use crate::compensate::CompensateError;
use std::fmt::Write;

/// Most compensation points per `.COM` table.
pub const MAX_POINTS: usize = 256;

/// One `<L>.COM` per axis and `COMP.CMA`.
pub fn export(input: &ExportInput) -> Result<Vec<ExportedFile>, CompensateError> {
    check_user_limits(input)?;
    let m = input.machine;
    let mut files = Vec::new();
    for (driver, axis) in m.axes().iter().enumerate() {
        let own = input.tables.table(driver, driver).expect("own-axis table of every axis");
        let what = format!("Heidenhain table {}.COM", axis.letter);
        check_count(own.positions.len(), MAX_POINTS, &what)?;
        check_equal_spacing(&own.positions, &what)?;
        let columns: Vec<_> = input.tables.tables.iter().filter(|t| t.driver == driver).collect();
        for t in &columns {
            check_rotary_closure(m, t, closure_tolerance(m, t.corrected))?;
        }
        let name = format!("{}.COM", axis.letter);
        let mut text = format!("BEGIN {name} MM\n");
        let mut header = format!("{:<5} {:>12}", "NR", "AXISPOS");
        for t in &columns {
            let _ = write!(header, " {:>12}", m.axes()[t.corrected].letter);
        }
        let _ = writeln!(text, "{header} {:>12}", "BACKLASH");
        for (i, x) in own.positions.iter().enumerate() {
            let _ = write!(text, "{i:<5} {:>12}", signed(*x, 6));
            for t in &columns {
                let _ = write!(text, " {:>12}", signed(t.forward[i], 6));
            }
            let _ = writeln!(text, " {:>12}", signed(own.reverse[i], 6));
        }
        text.push_str("[END]\n");
        files.push(ExportedFile { name, contents: text });
    }
    let letters: Vec<char> = m.axes().iter().map(|a| a.letter).collect();
    let mut cma = String::from("BEGIN COMP.CMA\n");
    let _ = write!(cma, "{:<5}", "NR");
    for l in &letters {
        let _ = write!(cma, " {l:>8}");
    }
    let _ = writeln!(cma, " {:>6}", "ACTIVE");
    let _ = write!(cma, "{:<5}", 0);
    for l in &letters {
        let _ = write!(cma, " {:>8}", format!("{l}.COM"));
    }
    let _ = writeln!(cma, " {:>6}\n[END]", "*");
    files.push(ExportedFile { name: "COMP.CMA".into(), contents: cma });
    Ok(files)
}
