//! Heidenhain nonlinear axis-error compensation (TNC 640 / iTNC 530 / MANUALplus 620 technical
//! manuals, "Nonlinear axis error compensation"; specs/anchors.md §3).
//!
//! One compensation-value table `<L>.COM` per driving axis L: the column `AXISPOS` holds the
//! compensation points, positions of L relative to the machine datum (mm, deg); one column per
//! compensated axis, named by its axis key, holds the compensation values of that axis as a function
//! of L (`X = F(X)` a pitch error, `Z = F(Y)` a sag); `BACKLASH` the own-axis values measured in the
//! negative direction of traverse. A compensation-value assignment table `COMP.CMA` assigns the
//! tables: the `.COM` file in column L of the `.CMA` makes its columns functions of L
//! (`[axis of the .COM column] = F(axis of the .CMA column)`); an `*` in `ACTIVE` activates the
//! line. The older TNC technical manuals (TNC 407, module 9095) name the limit of 256 entries per
//! `.COM` table; the points are equidistant.
//!
//! Layout: Heidenhain's fixed-width tables (`BEGIN <name> MM`, a line of column names, one line per
//! row, `[END]`), each value starting under the first character of its column name and ending before
//! the next name, as the controller's table editor writes them and as public readers of these tables
//! (pyLSV2's `NCTable`) read them back.
//!
//! Values: trueaxis corrections (added to the set-point), mm and deg, 6 decimals. The manuals call
//! the entries "compensation values" without a public statement of their sign: check it on the
//! machine with one point (docs/compensation.md). Cross-axis columns hold the mean of both
//! directions of the driving axis (the controller applies them in both directions) and are zero at
//! the reference pose (see `tables`).

use super::residual::{Branch, Interpolation, TableSum};
use super::{
    check_count, check_equal_spacing, check_rotary_closure, check_user_limits, closure_tolerance, direction_left_out, Export, ExportInput,
    ExportedFile,
};
use crate::compensate::CompensateError;
use std::fmt::Write;

/// Most compensation points per `.COM` table.
pub const MAX_POINTS: usize = 256;

/// Width of every column but `NR` (characters): the name, then spaces up to the next column.
const WIDTH: usize = 16;

/// One fixed-width table: `BEGIN`, the column names, the rows, `[END]`. Each cell is written from
/// the first character of its column; a value longer than its column is refused.
fn table(header: &str, columns: &[(&str, usize)], rows: &[Vec<String>]) -> Result<String, CompensateError> {
    let mut text = format!("{header}\n");
    let line = |cells: &mut dyn Iterator<Item = (&str, usize)>| -> Result<String, CompensateError> {
        let mut l = String::new();
        for (cell, width) in cells {
            if cell.len() >= width {
                return Err(CompensateError::Limit(format!("`{cell}` does not fit a Heidenhain table column of {width} characters")));
            }
            let _ = write!(l, "{cell:<width$}");
        }
        Ok(l.trim_end().to_string())
    };
    let _ = writeln!(text, "{}", line(&mut columns.iter().copied())?);
    for row in rows {
        let _ = writeln!(text, "{}", line(&mut row.iter().map(String::as_str).zip(columns.iter().map(|c| c.1)))?);
    }
    text.push_str("[END]\n");
    Ok(text)
}

/// One `<L>.COM` per axis and `COMP.CMA`.
pub fn export<'a>(input: &ExportInput<'a>) -> Result<Export<'a>, CompensateError> {
    check_user_limits(input)?;
    let m = input.machine;
    let mut files = Vec::new();
    let mut carried = Vec::new();
    for (driver, axis) in m.axes().iter().enumerate() {
        let own = input.tables.table(driver, driver).expect("own-axis table of every axis");
        let what = format!("Heidenhain table {}.COM", axis.letter);
        check_count(own.positions.len(), MAX_POINTS, &what)?;
        check_equal_spacing(&own.positions, &what)?;
        let tables: Vec<_> = input.tables.tables.iter().filter(|t| t.driver == driver).collect();
        for t in &tables {
            check_rotary_closure(m, t, closure_tolerance(m, t.corrected))?;
        }
        let letters: Vec<String> = tables.iter().map(|t| m.axes()[t.corrected].letter.to_string()).collect();
        let mut columns: Vec<(&str, usize)> = vec![("NR", 6), ("AXISPOS", WIDTH)];
        columns.extend(letters.iter().map(|l| (l.as_str(), WIDTH)));
        columns.push(("BACKLASH", WIDTH));
        let rows: Vec<Vec<String>> = own
            .positions
            .iter()
            .enumerate()
            .map(|(i, x)| {
                let mut row = vec![i.to_string(), format!("{x:+.6}")];
                // the own-axis column (first) holds the forward values, BACKLASH the reverse ones
                row.extend(tables.iter().map(|t| {
                    let v = if t.is_own_axis() { t.forward[i] } else { 0.5 * (t.forward[i] + t.reverse[i]) };
                    super::signed(v, 6)
                }));
                row.push(super::signed(own.reverse[i], 6));
                row
            })
            .collect();
        let name = format!("{}.COM", axis.letter);
        files.push(ExportedFile { name: name.clone(), contents: table(&format!("BEGIN {name} MM"), &columns, &rows)? });
        carried.extend(tables.iter().map(|t| ((*t).clone(), if t.is_own_axis() { Branch::Directional } else { Branch::Mean })));
    }
    let names: Vec<String> = m.axes().iter().map(|a| format!("{}.COM", a.letter)).collect();
    let letters: Vec<String> = m.axes().iter().map(|a| a.letter.to_string()).collect();
    let mut columns: Vec<(&str, usize)> = vec![("NR", 6)];
    columns.extend(letters.iter().map(|l| (l.as_str(), WIDTH)));
    columns.push(("ACTIVE", 8));
    let mut row = vec!["0".to_string()];
    row.extend(names);
    row.push("*".into());
    files.push(ExportedFile { name: "COMP.CMA".into(), contents: table("BEGIN COMP.CMA", &columns, &[row])? });
    Ok(Export {
        files,
        applied: Box::new(TableSum { machine: m, tables: carried, interpolation: Interpolation::Linear }),
        // the own-axis tables carry both directions; a cross-axis column only the mean
        left_out: direction_left_out(input, |t| !t.is_own_axis()),
    })
}
