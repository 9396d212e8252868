//! The controller formats by name, with what each writes, and the summaries of `trueaxis
//! compensate --json` and `trueaxis nc --json` (also the dictionaries of the Python package).
//! Units: corrections in um (linear axes) and urad (rotary axes), rounded to 1e-4.

use super::export::{self, linuxcnc::CompType, Coverage, ExportInput, ExportedFile, Extent};
use super::nc::NcResult;
use super::CompensateError;
use serde_json::{json, Value};

/// A controller format of `trueaxis compensate`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// LinuxCNC joint compensation files (COMP_FILE_TYPE 1 trims, 0 positions).
    Linuxcnc(CompType),
    /// ISG / Beckhoff TF5280 volumetric CSV.
    Isg,
    /// Heidenhain .COM tables and a .CMA assignment.
    Heidenhain,
    /// Fanuc-style 3D lattice, at most `max_points` lattice points when given.
    Fanuc3d { max_points: Option<usize> },
    /// tables.csv (and grid.csv with axes X, Y, Z).
    Csv,
    /// compensation.json.
    Json,
}

impl ExportFormat {
    /// The format of a name (`linuxcnc`, `isg`, `heidenhain`, `fanuc3d`, `csv`, `json`).
    pub fn parse(name: &str, comp_type: CompType, max_points: Option<usize>) -> Result<ExportFormat, String> {
        match name {
            "linuxcnc" => Ok(ExportFormat::Linuxcnc(comp_type)),
            "isg" => Ok(ExportFormat::Isg),
            "heidenhain" => Ok(ExportFormat::Heidenhain),
            "fanuc3d" => Ok(ExportFormat::Fanuc3d { max_points }),
            "csv" => Ok(ExportFormat::Csv),
            "json" => Ok(ExportFormat::Json),
            other => Err(format!("format `{other}`: expected linuxcnc, isg, heidenhain, fanuc3d, csv or json")),
        }
    }

    /// True when the format writes the volumetric grid (machines with axes X, Y and Z for CSV and JSON).
    pub fn wants_grid(&self, has_xyz: bool) -> bool {
        match self {
            ExportFormat::Fanuc3d { .. } => true,
            ExportFormat::Csv | ExportFormat::Json => has_xyz,
            _ => false,
        }
    }

    /// What the format writes, for the summary: LinuxCNC the own-axis tables, Fanuc the lattice,
    /// CSV / JSON tables and grid, ISG (implied corrections) and Heidenhain all tables.
    pub fn coverage(&self) -> Coverage {
        match self {
            ExportFormat::Linuxcnc(_) => Coverage::OWN_AXIS_TABLES,
            ExportFormat::Isg | ExportFormat::Heidenhain => Coverage::TABLES,
            ExportFormat::Fanuc3d { .. } => Coverage::GRID,
            ExportFormat::Csv | ExportFormat::Json => Coverage::TABLES_AND_GRID,
        }
    }

    /// The files of the format.
    pub fn export(&self, input: &ExportInput) -> Result<Vec<ExportedFile>, CompensateError> {
        match *self {
            ExportFormat::Linuxcnc(comp_type) => export::linuxcnc::export(input, comp_type),
            ExportFormat::Isg => export::isg::export(input),
            ExportFormat::Heidenhain => export::heidenhain::export(input),
            ExportFormat::Fanuc3d { max_points } => export::fanuc3d::export(input, max_points),
            ExportFormat::Csv => export::plain::export_csv(input),
            ExportFormat::Json => export::plain::to_json(input)
                .map(|doc| vec![ExportedFile { name: "compensation.json".into(), contents: format!("{doc:#}\n") }]),
        }
    }
}

/// Rounded to 1e-4 (um or urad), as the summaries print.
pub fn round4(v: f64) -> f64 {
    (v * 1e4).round() / 1e4
}

/// The summary of `trueaxis compensate --json`: output directory, files, number of tables and
/// points, the largest corrections written (um, urad), the worst residual after correction (um)
/// and uncorrectable orientation (urad), and the summary of the corrected poses when given.
pub fn compensation_json(out: &str, files: &[&str], tables: usize, points: usize, extent: &Extent, poses: Option<&Value>) -> Value {
    json!({
        "out": out,
        "files": files,
        "tables": tables,
        "points": points,
        "max_correction_um": round4(extent.max_um),
        "max_correction_urad": round4(extent.max_urad),
        "worst_residual_um": round4(extent.worst_residual_mm * 1e3),
        "worst_uncorrectable_urad": round4(extent.worst_uncorrectable_rad * 1e6),
        "poses": poses,
    })
}

/// The summary of `trueaxis nc --json`; the program text when it was not written to `out`.
pub fn nc_json(result: &NcResult, out: Option<&str>) -> Value {
    json!({
        "moves": result.moves,
        "changed_lines": result.changed_lines,
        "inserted_lines": result.inserted_lines,
        "max_correction_um": result.max_correction_um,
        "max_correction_urad": result.max_correction_urad,
        "max_residual_um": result.max_residual_um,
        "max_uncorrectable_urad": result.max_uncorrectable_urad,
        "out": out,
        "program": if out.is_none() { Some(result.text.clone()) } else { None },
    })
}
