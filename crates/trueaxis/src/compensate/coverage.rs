//! Coverage of the error tables: an error table of a motion error holds its end values past its
//! ends (`error_model::function`), so a correction beyond a table's range rests on values nobody
//! measured. Compensation refuses it: tables and grids whose travel a table does not cover, NC
//! points outside a table's range (docs/limits.md). Periodic tables (a rotary axis over a full
//! turn) cover everything.

use super::CompensateError;
use crate::error_model::{ErrorFunction, ErrorModel};
use crate::machine::{Machine, ParameterId};

/// The range (mm or deg) of one error table of a motion error of axis `axis` (index).
#[derive(Clone, Debug, PartialEq)]
pub struct TableRange {
    pub axis: usize,
    /// The parameter as written (`EXX`, `EXX+`).
    pub name: String,
    pub range: [f64; 2],
}

/// The ranges of the non-periodic error tables of `errors`.
pub fn table_ranges(machine: &Machine, errors: &ErrorModel) -> Vec<TableRange> {
    errors
        .directional_entries()
        .filter_map(|(id, direction, f)| match (id, f) {
            (ParameterId::Motion { axis, .. }, ErrorFunction::Table { positions, period: None, .. }) => Some(TableRange {
                axis: machine.axis_index(*axis)?,
                name: format!("{id}{}", direction.map_or(String::new(), |d| d.symbol().to_string())),
                range: [positions[0], positions[positions.len() - 1]],
            }),
            _ => None,
        })
        .collect()
}

/// Refuses positions `[lo, hi]` (mm or deg) of axis `axis` that a table of `ranges` does not
/// cover (within 1e-9 of the span); `what` says where they come from (for the message).
pub fn check_covered(
    machine: &Machine,
    ranges: &[TableRange],
    axis: usize,
    lo: f64,
    hi: f64,
    what: &dyn Fn() -> String,
) -> Result<(), CompensateError> {
    for t in ranges.iter().filter(|t| t.axis == axis) {
        let slack = 1e-9 * (t.range[1] - t.range[0]).abs().max(1.0);
        if lo < t.range[0] - slack || hi > t.range[1] + slack {
            let a = &machine.axes()[axis];
            let unit = a.position_unit();
            return Err(CompensateError::Coverage(format!(
                "the error table {} covers {} from {} to {} {unit}, but {} reaches {} {unit}: beyond its ends the table would hold its \
                 end values, which nobody measured; measure the whole travel, or narrow `range` of {} in the machine file \
                 (docs/limits.md); nothing was written",
                t.name,
                a.letter,
                t.range[0],
                t.range[1],
                what(),
                if lo < t.range[0] - slack { lo } else { hi },
                a.letter
            )));
        }
    }
    Ok(())
}
