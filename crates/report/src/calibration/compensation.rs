//! The compensation part of a calibration report: own-axis and cross-axis tables and a volumetric
//! grid from an error model, solved on the exact chain (Soons 1993 §2.3.5), as `trueaxis compensate`
//! computes them, and what the controller's sum of tables does at any pose.

use super::super::html::Section;
use super::quantity::{pose, quantity};
use super::CalibrationError;
use trueaxis::compensate::export::{self, Coverage, ExportInput, ExportedFile, Extent, Limits};
use trueaxis::compensate::{
    axis_tables, compensation_with, volumetric_grid, CompensationRequest, Corrector, ExportFormat, FormatOptions, FormatResidual, TableSet,
    TableSpec, VolumetricGrid,
};

/// The controller formats whose corrections a report can evaluate (as `trueaxis compensate
/// --format`): what each can represent is applied on the exact chain.
pub const CONTROLLER_FORMATS: [&str; 7] = ["heidenhain", "siemens", "fanuc", "linuxcnc", "linuxcnc-hal", "isg", "lattice"];

/// The name of a controller format as a customer reads it.
pub fn controller_name(format: &str) -> &str {
    match format {
        "heidenhain" => "Heidenhain",
        "siemens" => "Siemens 840D sl",
        "fanuc" => "Fanuc",
        "linuxcnc" => "LinuxCNC",
        "linuxcnc-hal" => "LinuxCNC (HAL component)",
        "isg" => "ISG",
        "lattice" => "lattice",
        other => other,
    }
}

/// What the controller files the user chose (`trueaxis compensate --format`: the kinematic
/// description and tables of a five-axis machine) leave of the errors over the travel.
pub struct ControllerPart {
    pub format: String,
    pub residual: FormatResidual,
    /// What the format cannot carry, one line each with its size.
    pub left_out: Vec<String>,
    /// The files `trueaxis compensate` writes for it.
    pub files: Vec<ExportedFile>,
    /// The kinematic description written, as `trueaxis compensate --json` gives it.
    pub kinematics: Option<serde_json::Value>,
    /// The machine's axis letters, in the order of a pose.
    pub axes: Vec<char>,
}
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// Points per table and grid nodes: the defaults of `trueaxis compensate` (`--points 41 --grid 9,9,9`).
pub const POINTS: usize = 41;
pub const GRID_NODES: [usize; 3] = [9, 9, 9];

/// Tables and grid of one error model.
pub struct CompensationPart {
    pub tables: TableSet,
    /// The grid over X, Y, Z (machines that have the three axes).
    pub grid: Option<VolumetricGrid>,
    pub points: usize,
    pub grid_nodes: [usize; 3],
    /// Largest corrections written (um, urad) and what is left after correction, over the tables
    /// and the grid.
    pub extent: Extent,
    /// Where the error model came from (a file, "the identification").
    pub origin: String,
    /// Files written with the tables (names), if any.
    pub files: Vec<String>,
}

impl CompensationPart {
    pub fn compute(
        machine: &Machine,
        errors: &ErrorModel,
        origin: &str,
        points: usize,
        grid_nodes: [usize; 3],
    ) -> Result<CompensationPart, CalibrationError> {
        // the machine's errors, as `trueaxis compensate` takes them: not the set-up of a measurement
        let errors = &errors.without_setup();
        let corrector = Corrector::new(machine, errors);
        let spec = TableSpec { points, reference: None, temperatures: Vec::new() };
        let tables = axis_tables(&corrector, &spec)?;
        let has_xyz = ['X', 'Y', 'Z'].iter().all(|&l| machine.axis_index(l).is_some());
        let grid = if has_xyz { Some(volumetric_grid(&corrector, grid_nodes, &spec)?) } else { None };
        // what the CSV export (tables and grid) writes, as `trueaxis compensate --format csv` sums it up
        let input = ExportInput { machine, errors, tables: &tables, grid: grid.as_ref(), limits: Limits::default() };
        let extent = export::largest_corrections(&input, Coverage::TABLES_AND_GRID);
        Ok(CompensationPart { tables, grid, points, grid_nodes, extent, origin: origin.into(), files: Vec::new() })
    }

    /// The plain CSV export (`trueaxis compensate --format csv`): tables.csv, and grid.csv.
    pub fn csv_files(&self, machine: &Machine, errors: &ErrorModel) -> Result<Vec<ExportedFile>, CalibrationError> {
        let input = ExportInput { machine, errors, tables: &self.tables, grid: self.grid.as_ref(), limits: Limits::default() };
        Ok(export::plain::export_csv(&input)?)
    }

    /// The correction (mm, deg) of every axis at pose `q_user` (mm, deg) as a controller applies the
    /// tables: the sum of the own-axis and cross-axis tables of each corrected axis, interpolated
    /// linearly at the positions of their driving axes (mean of the two directions of motion). On
    /// the axis lines through the reference pose it is the correction; elsewhere it misses the
    /// terms that depend on two axes at once (NISTIR 5236 §4).
    pub fn table_correction(&self, q_user: &[f64]) -> Vec<f64> {
        let mut dq = vec![0.0; q_user.len()];
        for t in &self.tables.tables {
            dq[t.corrected] += t.mean_at(q_user[t.driver]);
        }
        dq
    }

    /// What the files of controller `format` (one of [`CONTROLLER_FORMATS`]) leave, as `trueaxis
    /// compensate --format` computes them from `errors` (its defaults, the machine file's limits;
    /// files that leave more than they remove are shown, flagged, not refused), judged on the machine
    /// whose errors are `judge` (default `errors`; a simulation judges on its true errors).
    pub fn controller(
        &self,
        machine: &Machine,
        errors: &ErrorModel,
        format: &str,
        judge: Option<&ErrorModel>,
    ) -> Result<ControllerPart, CalibrationError> {
        if !CONTROLLER_FORMATS.contains(&format) {
            return Err(CalibrationError::Input(format!(
                "`{format}` is not a controller format; give one of {}",
                CONTROLLER_FORMATS.join(", ")
            )));
        }
        let request = CompensationRequest {
            format: ExportFormat::parse(format, &FormatOptions { comp_type: 0, ..FormatOptions::default() })
                .map_err(|e| CalibrationError::Input(e.to_string()))?,
            points: self.points,
            grid: self.grid_nodes,
            reference: None,
            limits: Limits::of_machine(machine),
            temperatures: vec![None; errors.sensors().len()],
            poses: None,
            force: true,
        };
        let (job, ()) = compensation_with(&Corrector::new(machine, errors), &request, judge, |_| ())?;
        let residual = job.residual.ok_or_else(|| CalibrationError::Computation(format!("the {format} files leave no residual")))?;
        let axes = machine.axes().iter().map(|a| a.letter).collect();
        Ok(ControllerPart { format: format.into(), residual, left_out: job.left_out, files: job.files, kinematics: job.kinematics, axes })
    }

    pub fn section(&self, controller: Option<&ControllerPart>) -> Section {
        let mut s = Section::new("compensation", "Compensation").paragraph(format!(
            "Corrections (added to the axis set-points) from {}: the correction of the axis set-points iterated on the exact kinematic chain (docs/compensation.md), sampled as own-axis and cross-axis tables of {} points per axis (both directions of motion){}. The controller files (Heidenhain, Siemens, Fanuc, LinuxCNC, ISG, CSV, JSON) are written by `trueaxis compensate`.",
            self.origin,
            self.points,
            self.grid.as_ref().map_or(String::new(), |g| format!(" and a volumetric grid of {} x {} x {} nodes", g.counts[0], g.counts[1], g.counts[2]))
        ));
        s = s.table(
            "Summary (the numbers `trueaxis compensate` prints)",
            &["quantity", "value"],
            vec![
                vec!["tables".into(), self.tables.tables.len().to_string()],
                vec!["points per table".into(), self.points.to_string()],
                vec![
                    "grid nodes".into(),
                    self.grid.as_ref().map_or("none".into(), |g| format!("{}x{}x{}", g.counts[0], g.counts[1], g.counts[2])),
                ],
                vec!["largest correction written, linear axes".into(), quantity(self.extent.max_um, 2, "um")],
                vec!["largest correction written, rotary axes".into(), quantity(self.extent.max_urad, 1, "urad")],
                vec!["position residual after correction".into(), quantity(self.extent.worst_residual_mm * 1e3, 4, "um")],
                vec!["orientation not corrected".into(), quantity(self.extent.worst_uncorrectable_rad * 1e6, 1, "urad")],
            ],
        );
        if let Some(c) = controller {
            let r = &c.residual;
            if r.leaves_more_than_it_removes() {
                s = s.note(format!(
                    "WARNING: the {} files would leave more error than they remove ({} left of {}): `trueaxis compensate` refuses to write them; do not load them into the controller.",
                    controller_name(&c.format),
                    quantity(r.worst_um, 2, "um"),
                    quantity(r.worst_error_um, 2, "um")
                ));
            }
            if let Some(k) = &c.kinematics {
                s = s.paragraph(format!(
                    "The location errors of the rotary axes go into the controller's kinematic description ({}), as the controller's own calibration cycles put them; tables carry what remains.",
                    k["description"].as_str().unwrap_or_default()
                ));
            }
            s = s.table(
                format!(
                    "What the {} files leave of {}, on the exact chain over {} poses and states of motion spread over the travel, rotary axes moving (the workpiece placed by its best fit, as `trueaxis compensate` judges it; not the poses of the volumetric map)",
                    controller_name(&c.format), self.origin, r.samples
                ),
                &["quantity", "value"],
                vec![
                    vec!["largest error before compensation".into(), quantity(r.worst_error_um, 2, "um")],
                    vec!["RMS of the error before compensation".into(), quantity(r.rms_error_um, 2, "um")],
                    vec!["largest error left".into(), quantity(r.worst_um, 2, "um")],
                    vec!["RMS of the error left".into(), quantity(r.rms_um, 2, "um")],
                    vec![
                        "where the most is left".into(),
                        format!(
                            "{} ({}), where the error was {}",
                            pose(&c.axes.iter().copied().zip(r.worst_pose.iter().copied()).collect::<Vec<_>>()),
                            r.worst_state,
                            quantity(r.error_there_um, 2, "um")
                        ),
                    ],
                ],
            );
            for l in &c.left_out {
                s = s.note(format!("The {} format cannot carry: {l}", controller_name(&c.format)));
            }
        }
        if !self.files.is_empty() {
            s = s.table("Files written", &["file"], self.files.iter().map(|f| vec![f.clone()]).collect());
        }
        s
    }
}
