//! The controller formats by name, with what each writes, and the summaries of `trueaxis
//! compensate --json` and `trueaxis nc --json` (also the dictionaries of the Python package).
//! Units: corrections in um (linear axes) and urad (rotary axes), rounded to 1e-4.

use super::export::{
    self, fanuc::FanucLimits, linuxcnc::CompType, siemens::SiemensLimits, Coverage, Export, ExportInput, ExportedFile, Extent,
};
use super::kinematic::{Carried, KinematicCorrection, KinematicDescription, RotaryLayout};
use super::nc::NcResult;
use super::{CompensateError, FormatResidual};
use crate::machine::Machine;
use serde_json::{json, Value};

/// A controller format of `trueaxis compensate`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// LinuxCNC joint compensation files (COMP_FILE_TYPE 1 trims, 0 positions).
    Linuxcnc(CompType),
    /// LinuxCNC 2.9 HAL component (halcompile) driving external offsets, with its HAL and INI lines.
    LinuxcncHal { component: String },
    /// ISG / Beckhoff TF5280 volumetric CSV and its list file.
    Isg,
    /// Heidenhain .COM tables and a .CMA assignment.
    Heidenhain,
    /// Siemens 840D sl init programs: leadscrew ($AA_ENC_COMP) and sag/angularity ($AN_CEC) tables.
    Siemens(SiemensLimits),
    /// Fanuc pitch-error compensation as programmable parameter input (G10 L50).
    Fanuc(FanucLimits),
    /// A plain 3D lattice over X, Y, Z (data, no controller format), at most `max_points` points.
    Lattice { max_points: Option<usize> },
    /// tables.csv (and grid.csv with axes X, Y, Z).
    Csv,
    /// compensation.json.
    Json,
}

/// The options of the formats that take any.
#[derive(Clone, Debug, PartialEq)]
pub struct FormatOptions {
    /// LinuxCNC comp files: 0 positions, 1 trims.
    pub comp_type: u8,
    /// Most points of the lattice.
    pub max_lattice_points: Option<usize>,
    /// Most points of a Siemens or Fanuc table (the controller's configured size).
    pub max_table_points: Option<usize>,
    /// Most Siemens sag-compensation (CEC) tables.
    pub max_cec_tables: Option<usize>,
    /// Name of the LinuxCNC HAL component.
    pub hal_component: String,
}

impl Default for FormatOptions {
    fn default() -> Self {
        FormatOptions {
            comp_type: 1,
            max_lattice_points: None,
            max_table_points: None,
            max_cec_tables: None,
            hal_component: "trueaxis_comp".into(),
        }
    }
}

impl ExportFormat {
    /// The format of a name (`linuxcnc`, `linuxcnc-hal`, `isg`, `heidenhain`, `siemens`, `fanuc`,
    /// `lattice` (also `fanuc3d`, its former name), `csv`, `json`).
    pub fn parse(name: &str, options: &FormatOptions) -> Result<ExportFormat, crate::error::Error> {
        let comp_type = match options.comp_type {
            0 => CompType::Positions,
            1 => CompType::Trims,
            other => crate::bail!(input, "comp type {other}: expected 0 (positions) or 1 (trims)"),
        };
        Ok(match name {
            "linuxcnc" => ExportFormat::Linuxcnc(comp_type),
            "linuxcnc-hal" => ExportFormat::LinuxcncHal { component: options.hal_component.clone() },
            "isg" => ExportFormat::Isg,
            "heidenhain" => ExportFormat::Heidenhain,
            "siemens" => ExportFormat::Siemens(SiemensLimits {
                max_points: options.max_table_points.unwrap_or(SiemensLimits::default().max_points),
                max_cec_tables: options.max_cec_tables.unwrap_or(SiemensLimits::default().max_cec_tables),
            }),
            "fanuc" => ExportFormat::Fanuc(FanucLimits {
                max_points_per_axis: options.max_table_points.unwrap_or(FanucLimits::default().max_points_per_axis),
                ..FanucLimits::default()
            }),
            "lattice" | "fanuc3d" => ExportFormat::Lattice { max_points: options.max_lattice_points },
            "csv" => ExportFormat::Csv,
            "json" => ExportFormat::Json,
            other => {
                crate::bail!(
                    input,
                    "format `{other}`: expected linuxcnc, linuxcnc-hal, isg, heidenhain, siemens, fanuc, lattice, csv or json"
                )
            }
        })
    }

    /// True when the format writes the volumetric grid (machines with axes X, Y and Z for the HAL
    /// component, CSV and JSON).
    pub fn wants_grid(&self, has_xyz: bool) -> bool {
        match self {
            ExportFormat::Lattice { .. } => true,
            ExportFormat::Csv | ExportFormat::Json | ExportFormat::LinuxcncHal { .. } => has_xyz,
            _ => false,
        }
    }

    /// What the format writes, for the summary: LinuxCNC and Fanuc the own-axis tables, the lattice
    /// its grid, CSV / JSON and the HAL component tables and grid, the others all tables.
    pub fn coverage(&self) -> Coverage {
        match self {
            ExportFormat::Linuxcnc(_) | ExportFormat::Fanuc(_) => Coverage::OWN_AXIS_TABLES,
            ExportFormat::Isg | ExportFormat::Heidenhain | ExportFormat::Siemens(_) => Coverage::TABLES,
            ExportFormat::Lattice { .. } => Coverage::GRID,
            ExportFormat::Csv | ExportFormat::Json | ExportFormat::LinuxcncHal { .. } => Coverage::TABLES_AND_GRID,
        }
    }

    /// What the format's kinematic description carries on a machine with rotary axes (`None`: the
    /// format has none, or the machine has no rotary axis): the rotary axes' lines and zero offsets
    /// for Heidenhain (kinematics description, cycle 451) and Siemens (swivel data, CYCLE996), their
    /// positions and zero offsets for Fanuc (tool centre point parameters, reference position),
    /// everything for LinuxCNC (a generated kinematics module, [`export::linuxcnc_kins`]).
    pub fn kinematics(&self, machine: &Machine) -> Option<Carried> {
        RotaryLayout::of(machine)?;
        match self {
            ExportFormat::Heidenhain | ExportFormat::Siemens(_) => Some(Carried::ROTARY_AXES),
            ExportFormat::Linuxcnc(_) => Some(Carried::ALL),
            ExportFormat::Fanuc(_) => Some(Carried { rotary_directions: false, ..Carried::ROTARY_AXES }),
            _ => None,
        }
    }

    /// What the format's kinematic description is, in the controller's words (for the summary).
    pub fn kinematics_name(&self) -> &'static str {
        match self {
            ExportFormat::Heidenhain => {
                "Heidenhain kinematics description: rotary axis positions and orientations as cycle 451 (KinematicsOpt) changes them"
            }
            ExportFormat::Siemens(_) => "SINUMERIK swivel data (CYCLE800 / TRAORI toolholder) with the fine offsets CYCLE996 writes",
            ExportFormat::Fanuc(_) => "Fanuc tool centre point parameters (rotary table position and intersection offsets)",
            ExportFormat::Linuxcnc(_) => "a LinuxCNC kinematics module generated from the identified model (halcompile)",
            _ => "",
        }
    }

    /// The files of the format's kinematic description (`kinematics` is what
    /// [`Self::kinematics`] asked for), and what the description leaves out.
    pub fn kinematic_files(
        &self,
        machine: &Machine,
        kinematics: &KinematicCorrection,
    ) -> Result<(Vec<ExportedFile>, Vec<String>), CompensateError> {
        let layout = RotaryLayout::of(machine).expect("a machine with rotary axes");
        let nominal = KinematicDescription::nominal(machine);
        let written = &kinematics.written;
        Ok(match self {
            ExportFormat::Heidenhain => (vec![export::heidenhain_kinematics::export(machine, &layout, &nominal, written)], Vec::new()),
            ExportFormat::Siemens(_) => (vec![export::siemens_swivel::export(machine, &layout, &nominal, written, 1)?], Vec::new()),
            ExportFormat::Fanuc(_) => export::fanuc_tcp::export(machine, &layout, kinematics)?,
            _ => (Vec::new(), Vec::new()),
        })
    }

    /// The files of the format, and for a controller format what the controller applies and what
    /// the format leaves out (`None` for CSV and JSON, which are data).
    pub fn export<'a>(&self, input: &ExportInput<'a>) -> Result<(Vec<ExportedFile>, Option<Export<'a>>), CompensateError> {
        let controller = match self {
            ExportFormat::Linuxcnc(comp_type) => export::linuxcnc::export(input, *comp_type)?,
            ExportFormat::LinuxcncHal { component } => export::linuxcnc_hal::export(input, component)?,
            ExportFormat::Isg => export::isg::export(input)?,
            ExportFormat::Heidenhain => export::heidenhain::export(input)?,
            ExportFormat::Siemens(limits) => export::siemens::export(input, *limits)?,
            ExportFormat::Fanuc(limits) => export::fanuc::export(input, *limits)?,
            ExportFormat::Lattice { max_points } => export::lattice::export(input, *max_points)?,
            ExportFormat::Csv => return Ok((export::plain::export_csv(input)?, None)),
            ExportFormat::Json => {
                let doc = export::plain::to_json(input)?;
                return Ok((vec![ExportedFile { name: "compensation.json".into(), contents: format!("{doc:#}\n") }], None));
            }
        };
        Ok((controller.files.clone(), Some(controller)))
    }
}

/// Rounded to 1e-4 (um or urad), as the summaries print.
pub fn round4(v: f64) -> f64 {
    (v * 1e4).round() / 1e4
}

/// The summary of `trueaxis compensate --json`: output directory, files, number of tables and
/// points, the largest corrections written (um, urad), the worst residual after correction (um)
/// and uncorrectable orientation (urad), what the format leaves out and the error it leaves over
/// the travel (`format_residual`, null for data formats), and the summary of the corrected poses.
#[allow(clippy::too_many_arguments)]
pub fn compensation_json(
    machine: &Machine,
    out: &str,
    files: &[&str],
    tables: usize,
    points: usize,
    extent: &Extent,
    left_out: &[String],
    residual: Option<&FormatResidual>,
    left_uncertainty: Option<&super::LeftUncertainty>,
    kinematics: Option<&Value>,
    poses: Option<&Value>,
) -> Value {
    json!({
        "out": out,
        "files": files,
        "tables": tables,
        "points": points,
        "max_correction_um": round4(extent.max_um),
        "max_correction_urad": round4(extent.max_urad),
        "worst_residual_um": round4(extent.worst_residual_mm * 1e3),
        "worst_uncorrectable_urad": round4(extent.worst_uncorrectable_rad * 1e6),
        "left_out": left_out,
        "format_residual": residual.map(|r| json!({
            "worst_um": round4(r.worst_um),
            "rms_um": round4(r.rms_um),
            "worst_pose": machine.axes().iter().zip(&r.worst_pose).map(|(a, v)| (a.letter.to_string(), json!(round4(*v)))).collect::<serde_json::Map<_, _>>(),
            "worst_state": r.worst_state,
            "error_there_um": round4(r.error_there_um),
            "worst_error_um": round4(r.worst_error_um),
            "rms_error_um": round4(r.rms_error_um),
            "samples": r.samples,
            "leaves_more_than_it_removes": r.leaves_more_than_it_removes(),
            "placement_before": placement_json(&r.placement_before),
            "placement_after": placement_json(&r.placement_after),
        })),
        "error_left_uncertainty": left_uncertainty.map(|u| json!({
            "expanded_um": round4(u.expanded_um),
            "rms_expanded_um": round4(u.rms_expanded_um),
            "coverage_factor": 2,
            "parameters": u.parameters,
        })),
        "kinematics": kinematics,
        "poses": poses,
    })
}

/// The best placement of the workpiece frame: shift (um) and rotation vector (urad).
fn placement_json(fit: &super::export::rigid_fit::RigidFit) -> Value {
    let w = fit.rotation_vector() * 1e6;
    json!({
        "shift_um": (fit.translation * 1e3).iter().map(|v| round4(*v)).collect::<Vec<_>>(),
        "rotation_urad": w.iter().map(|v| round4(*v)).collect::<Vec<_>>(),
    })
}

/// The kinematic description a compensation writes, for its summary: what it carries and, per
/// rotary axis, the shift of its line (um), its tilt (urad) and its zero offset (urad).
pub fn kinematics_json(machine: &Machine, kinematics: &KinematicCorrection, description: &str) -> Value {
    let nominal = KinematicDescription::nominal(machine);
    let axes: serde_json::Map<String, Value> = machine
        .axes()
        .iter()
        .enumerate()
        .filter(|(_, a)| a.kind == crate::machine::AxisKind::Rotary)
        .map(|(k, a)| {
            let c = export::heidenhain_kinematics::axis_change(&nominal, &kinematics.written, k);
            (
                a.letter.to_string(),
                json!({
                    "shift_um": (c.shift * 1e3).iter().map(|v| round4(*v)).collect::<Vec<_>>(),
                    "tilt_urad": (c.tilt * 1e6).iter().map(|v| round4(*v)).collect::<Vec<_>>(),
                    "zero_offset_urad": round4(c.zero_offset * 1e6),
                }),
            )
        })
        .collect();
    let c = kinematics.carried;
    json!({
        "description": description,
        "carried": {
            "rotary_positions": c.rotary_positions,
            "rotary_directions": c.rotary_directions,
            "zero_offsets": c.zero_offsets,
            "linear_directions": c.linear_directions,
            "tool_end": c.tool_end,
        },
        "axes": axes,
    })
}

/// The drilling axes of canned cycles (G19, G18, G17).
const AXIS_NAMES: [&str; 3] = ["X", "Y", "Z"];

/// The summary of `trueaxis nc --json`; the program text when it was not written to `out`.
pub fn nc_json(result: &NcResult, out: Option<&str>) -> Value {
    json!({
        "dialect": result.dialect.to_string(),
        "moves": result.moves,
        "blocks": result.blocks,
        "changed_lines": result.changed_lines,
        "inserted_lines": result.inserted_lines,
        "expanded": result.expanded,
        "warnings": result.warnings,
        "assumed_tools": result.assumed_tools,
        "tool_length_um_per_100mm": result.tool_length_um_per_100mm,
        "max_correction_um": result.max_correction_um,
        "max_correction_urad": result.max_correction_urad,
        "max_residual_um": result.max_residual_um,
        "max_uncorrectable_urad": result.max_uncorrectable_urad,
        "holes": result.holes.iter().map(|h| json!({
            "line": h.line,
            "cycle": format!("G{}", trueaxis_nc::dialects::gcode_text(h.code)),
            "axis": AXIS_NAMES[h.axis.min(2)],
            "lean_um": round4(h.lean_um),
            "clearance_um": round4(h.clearance_um),
        })).collect::<Vec<_>>(),
        "out": out,
        "program": if out.is_none() { Some(result.text().into_owned()) } else { None },
    })
}
