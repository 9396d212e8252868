//! A compensation job end to end, as `trueaxis compensate` and the Python package run it: the
//! own-axis / cross-axis tables and the volumetric grid, the controller files, the error the format
//! leaves on the exact chain, the corrections of the poses of a CSV in their own state
//! (`corrections.csv`, streamed: memory does not grow with the number of poses), the summary
//! document, and the files written whole or not at all.
//!
//! Units: corrections in um (linear axes) and urad (rotary axes) in CSV and JSON, positions in mm
//! and deg, temperatures in degC.

use super::export::{check_limit, largest_corrections, to_micro, ExportInput, ExportedFile, Extent, Limits};
use super::{
    axis_tables, compensation_json, correct_batch, residual_of_format, round4, volumetric_grid, CompensateError, Corrector, ExportFormat,
    FormatResidual, TableSet, TableSpec, VolumetricGrid,
};
use crate::data::{push_fixed, OutputSet, PoseStream, CHUNK};
use crate::errors::ErrorModel;
use crate::machine::Machine;
use serde_json::{json, Value};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The file of the corrected poses.
const CORRECTIONS: &str = "corrections.csv";

/// What to compensate and how.
#[derive(Clone, Debug)]
pub struct CompensationRequest {
    pub format: ExportFormat,
    /// Points per own-axis / cross-axis table.
    pub points: usize,
    /// Volumetric grid nodes along X, Y, Z.
    pub grid: [usize; 3],
    /// Reference pose of the tables (mm, deg); none: home clamped into the travel.
    pub reference: Option<Vec<f64>>,
    pub limits: Limits,
    /// Each input of the error model (its order: temperatures in degC, spindle speeds in rpm, ...),
    /// none where not given: the tables are computed at the given values and the others at their
    /// reference (20 degC, 0 rpm, 0 N).
    pub temperatures: Vec<Option<f64>>,
    /// Poses to correct each in its state (`dir:<axis>`, `T:<sensor>` columns): corrections.csv.
    pub poses: Option<PathBuf>,
}

/// The tables, the files and what they leave.
#[derive(Debug)]
pub struct Compensation {
    pub tables: TableSet,
    pub grid: Option<VolumetricGrid>,
    /// Every file to write (the format's, then corrections.csv).
    pub files: Vec<ExportedFile>,
    /// What the format could not carry, one line each.
    pub left_out: Vec<String>,
    /// The error the format leaves over the travel on the exact chain (controller formats).
    pub residual: Option<FormatResidual>,
    /// The largest corrections written and residuals of the poses they were sampled at.
    pub extent: Extent,
    /// The summary of the corrected poses (`count`, `max_error_um`, `max_residual_um`,
    /// `max_uncorrectable_urad`), once [`Compensation::write`] has corrected them.
    pub poses: Option<Value>,
    /// The poses to correct into corrections.csv as the files are written.
    poses_request: Option<(PathBuf, Vec<Option<f64>>, Limits)>,
}

impl Compensation {
    /// The document of `trueaxis compensate --json` for the output directory `out`.
    pub fn to_json(&self, machine: &Machine, out: &str, points: usize) -> Value {
        let names = self.file_names();
        compensation_json(
            machine,
            out,
            &names,
            self.tables.tables.len(),
            points,
            &self.extent,
            &self.left_out,
            self.residual.as_ref(),
            self.poses.as_ref(),
        )
    }

    /// Every file written: the format's, then corrections.csv.
    pub fn file_names(&self) -> Vec<&str> {
        self.files.iter().map(|f| f.name.as_str()).chain(self.poses_request.as_ref().map(|_| CORRECTIONS)).collect()
    }

    /// Writes every file into `out` (created if missing) as one set: the directory is swapped in
    /// whole, a directory holding files this job does not write is refused, and nothing is
    /// written when any file fails ([`crate::data::OutputSet`]). The poses of the request are
    /// corrected (by `corrector`, the one of [`compensation`]) as corrections.csv is streamed.
    pub fn write(&mut self, corrector: &Corrector, out: &Path) -> Result<(), CompensateError> {
        let mut set = OutputSet::new();
        set.directory(out);
        for f in &self.files {
            set.in_directory(out, &f.name, f.contents.as_bytes());
        }
        if self.poses_request.is_some() {
            set.streamed_in_directory(out, CORRECTIONS);
        }
        let mut prepared = set.prepare()?;
        if let Some((path, temperatures, limits)) = &self.poses_request {
            let target = out.join(CORRECTIONS);
            let summary = correct_poses(corrector, path, temperatures, limits, prepared.stream(&target)?, &target)?;
            self.poses = Some(summary);
        }
        Ok(prepared.commit()?)
    }
}

/// The index of sensor `name` (`T:<sensor>`) in the error model's order; an unknown name is an
/// error naming the model's sensors.
pub fn sensor_index(errors: &ErrorModel, name: &str) -> Result<usize, CompensateError> {
    errors.sensors().iter().position(|s| s == name).ok_or_else(|| {
        CompensateError::Input(format!("--temperature: the error model has no sensor `{name}` (sensors: {})", errors.sensors().join(", ")))
    })
}

/// Sensor temperatures from `(sensor, degC)` pairs, in the model's order (`None`: not given).
pub fn sensor_temperatures(errors: &ErrorModel, given: &[(String, f64)]) -> Result<Vec<Option<f64>>, CompensateError> {
    let mut values = vec![None; errors.sensors().len()];
    for (name, value) in given {
        values[sensor_index(errors, name)?] = Some(*value);
    }
    Ok(values)
}

/// The tables, grid and files of `request` for `corrector`'s machine and errors (corrections on
/// the exact chain, seed 000 §2.3.5), with the error the format leaves and the corrected poses.
pub fn compensation(corrector: &Corrector, request: &CompensationRequest) -> Result<Compensation, CompensateError> {
    let machine = corrector.machine;
    let temperatures: Vec<f64> =
        request.temperatures.iter().zip(corrector.errors.input_references()).map(|(t, r)| t.unwrap_or(*r)).collect();
    let spec = TableSpec { points: request.points, reference: request.reference.clone(), temperatures: temperatures.clone() };
    let tables = axis_tables(corrector, &spec)?;
    let has_xyz = ['X', 'Y', 'Z'].iter().all(|&l| machine.axis_index(l).is_some());
    let grid = if request.format.wants_grid(has_xyz) { Some(volumetric_grid(corrector, request.grid, &spec)?) } else { None };
    let input = ExportInput { machine, errors: corrector.errors, tables: &tables, grid: grid.as_ref(), limits: request.limits };
    let (files, exported) = request.format.export(&input)?;
    // what the controller format leaves: its corrections applied over the travel, on the exact chain
    let residual = match &exported {
        Some(e) => Some(residual_of_format(corrector, &temperatures, e.applied.as_ref())?),
        None => None,
    };
    let left_out: Vec<String> = exported.as_ref().map_or_else(Vec::new, |e| e.left_out.clone());
    let extent = largest_corrections(&input, request.format.coverage());
    // the export borrows the tables and the grid, which the result takes
    drop(exported);
    // the poses are corrected as they are written; the head of a file that can be read twice (not
    // a pipe) and the inputs it gives are checked now
    if let Some(path) = request.poses.as_ref().filter(|p| p.is_file()) {
        pose_stream(corrector, path, &request.temperatures)?;
    }
    let poses_request = request.poses.clone().map(|p| (p, request.temperatures.clone(), request.limits));
    Ok(Compensation { tables, grid, files, left_out, residual, extent, poses: None, poses_request })
}

/// The poses of `path` with the inputs of the error model per pose (the model's sensors: degC,
/// rpm, N, mm): a sensor's column of the poses file (`T:<name>`, `S:`, `F:`, `P:`; drift lags
/// from `t` and `run`), else its given value.
fn pose_stream<'m>(
    corrector: &Corrector<'m>,
    path: &Path,
    given: &[Option<f64>],
) -> Result<PoseStream<'m, std::io::BufReader<std::fs::File>>, CompensateError> {
    let errors = corrector.errors;
    let given: Vec<(String, f64)> = errors.sensors().iter().zip(given).filter_map(|(s, g)| g.map(|v| (s.clone(), v))).collect();
    Ok(PoseStream::open(path, corrector.machine)?.with_inputs(errors, &given)?)
}

/// Corrections of every pose of a CSV, each in its state (the `dir:<axis>` and `T:<sensor>` columns,
/// else the given temperatures), streamed to `out` (named `target` in messages) as corrections.csv:
/// the axis columns, `d<axis>` (um or urad), the error before and the residual after (um), the
/// orientation not corrected (urad); returns its summary.
pub fn correct_poses(
    corrector: &Corrector,
    path: &Path,
    given_temperatures: &[Option<f64>],
    limits: &Limits,
    out: &mut dyn Write,
    target: &Path,
) -> Result<Value, CompensateError> {
    let machine = corrector.machine;
    let mut poses = pose_stream(corrector, path, given_temperatures)?;
    let n = machine.axis_count();
    let mut header: Vec<String> = machine.axes().iter().map(|a| a.letter.to_string()).collect();
    header.extend(machine.axes().iter().map(|a| format!("d{}", a.letter)));
    header.extend(["error_um", "residual_um", "uncorrectable_urad"].map(String::from));
    let write = |out: &mut dyn Write, text: &str| {
        out.write_all(text.as_bytes()).map_err(|source| crate::data::DataError::Write { path: target.display().to_string(), source })
    };
    write(out, &(header.join(",") + "\n"))?;
    let (mut count, mut worst_error, mut worst_residual, mut worst_orientation) = (0, 0.0f64, 0.0f64, 0.0f64);
    while let Some(chunk) = poses.next_chunk(CHUNK)? {
        let (user, lines) = (&chunk.poses.user, &chunk.poses.lines);
        let corrections = correct_batch(corrector, &chunk.poses.internal(machine), chunk.poses.directions.as_deref(), &chunk.inputs);
        let mut text = String::with_capacity(corrections.len() * 16 * (2 * n + 3));
        use std::fmt::Write as _;
        for (i, c) in corrections.iter().enumerate() {
            if !c.converged {
                return Err(CompensateError::Computation(format!(
                    "{}: line {}: the correction did not converge",
                    path.display(),
                    lines[i]
                )));
            }
            for (k, &d) in c.dq.iter().take(n).enumerate() {
                let place = || format!("the pose of line {}", lines[i]);
                check_limit(machine, limits, k, machine.axes()[k].position_to_user(d), &place).map_err(|e| match e {
                    CompensateError::Limit(m) => CompensateError::Limit(format!("{}: {m}", path.display())),
                    e => e,
                })?;
            }
            for v in &user[i * n..(i + 1) * n] {
                let _ = write!(text, "{v},");
            }
            for k in 0..n {
                push_fixed(&mut text, to_micro(machine, k, machine.axes()[k].position_to_user(c.dq[k])), 4);
                text.push(',');
            }
            let (e, r, o) = (c.original_position.norm() * 1e3, c.residual_position.norm() * 1e3, c.uncorrectable_orientation.norm() * 1e6);
            for (v, decimals, end) in [(e, 4, ','), (r, 6, ','), (o, 3, '\n')] {
                push_fixed(&mut text, v, decimals);
                text.push(end);
            }
            worst_error = worst_error.max(e);
            worst_residual = worst_residual.max(r);
            worst_orientation = worst_orientation.max(o);
        }
        write(out, &text)?;
        count += corrections.len();
    }
    Ok(json!({
        "count": count,
        "max_error_um": round4(worst_error),
        "max_residual_um": round4(worst_residual),
        "max_uncorrectable_urad": round4(worst_orientation),
    }))
}
