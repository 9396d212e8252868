//! Plausibility checks of a table's columns (`io::plausibility`), with messages that say how to
//! fix the unit in this kind of file: a header label for a table, a conversion for a Renishaw file
//! (whose units the format fixes).

use super::{CsvTable, DataError, Layout};
use crate::io::plausibility::Severity;
use crate::io::plausibility::{deviation_scale, targets_per_run, Finding, Place, TargetReading};
use crate::io::ranges::{PhysicalRange, READING_UM};
use crate::io::Format;

/// Checks the size of the deviations (um or urad, as returned by `CsvTable::numbers`) of column
/// `column` (see `io::plausibility::deviation_scale`).
pub fn deviation_finding(table: &CsvTable, column: &str, values: &[f64]) -> Option<Finding> {
    if let Err(e) = physical_range(table, column, values, &READING_UM) {
        return Some(Finding { severity: Severity::Refuse, message: e.to_string() });
    }
    let mut text = table.column_text(column).unwrap_or(column).to_string();
    let name = table.headers().iter().find(|h| h.text == text).map_or(column.to_string(), |h| h.name.clone());
    if let Layout::Wide { run_columns } = table.layout() {
        // the deviations came from the run columns: name those
        text = run_columns.join("`, `");
        let first = run_columns.first().map_or("Run 1 +".to_string(), |c| crate::io::header::Header::parse(c).name);
        let fix = |u: &str| format!("label the run columns with the unit of the values (`{first} [{u}]`)");
        let place = Place { file: table.origin(), column: &text };
        return deviation_scale(values, table.unit_of(column), place, &fix("mm"), &fix("um"));
    }
    let (small, large) = match table.format() {
        Format::Rtl => {
            let fix = "a .rtl file holds mm (deg for a rotary axis); this one does not: convert it with `trueaxis convert FILE --to csv \
                       --out F.csv`, label the deviation column with its real unit (`dev [um]`) and use that file";
            (fix.to_string(), fix.to_string())
        }
        _ => (
            format!("label the header `{name} [mm]`"),
            match table.unit_of(column) {
                Some(u) if u.symbol == "mm" || u.symbol == "m" => format!("label the header `{name} [um]`"),
                _ => format!("label the header with the unit of the values (`{name} [nm]`)"),
            },
        ),
    };
    let place = Place { file: table.origin(), column: &text };
    deviation_scale(values, table.unit_of(column), place, &small, &large)
}

/// Checks the targets of a positioning table (`target`, `dir`, `run` columns; see
/// `io::plausibility::targets_per_run`), `tolerance` the grouping tolerance of targets.
pub fn target_finding(table: &CsvTable, targets: &[f64], tolerance: f64) -> Result<Option<Finding>, DataError> {
    let directions = table.directions("dir")?;
    let runs = table.texts("run")?;
    let readings: Vec<TargetReading> = (0..table.len())
        .map(|i| TargetReading {
            target: targets[i],
            direction: if directions[i] == crate::io::header::RunDirection::Plus { 1 } else { -1 },
            run: runs[i].trim().parse::<f64>().map_or(i64::MIN, |v| v as i64),
            line: table.lines()[i],
        })
        .collect();
    let unit = table.unit_returned("target").map_or("mm", |u| u.symbol);
    let text = table.column_text("target").unwrap_or("target").to_string();
    Ok(targets_per_run(&readings, tolerance, unit, Place { file: table.origin(), column: &text }))
}

/// Refuses the first value of column `column` of `table` (values as read, in `range.unit`) outside
/// the physical range of its quantity (`io::ranges`), naming the file, line and column.
pub fn physical_range(table: &CsvTable, column: &str, values: &[f64], range: &PhysicalRange) -> Result<(), DataError> {
    match range.first_outside(values) {
        None => Ok(()),
        Some((row, message)) => {
            let text = table.column_text(column).unwrap_or(column).to_string();
            Err(table.row_error(row, &format!("column `{text}`: {message}")))
        }
    }
}
