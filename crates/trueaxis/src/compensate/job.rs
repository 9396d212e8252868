//! A compensation job end to end, as `trueaxis compensate` and the Python package run it: the
//! own-axis / cross-axis tables and the volumetric grid, the controller files, the error the format
//! leaves on the exact chain, the corrections of the poses of a CSV in their own state
//! (`corrections.csv`, streamed: memory does not grow with the number of poses), the summary
//! document, and the files written whole or not at all.
//!
//! Units: corrections in um (linear axes) and urad (rotary axes) in CSV and JSON, positions in mm
//! and deg, temperatures in degC.

use super::export::linuxcnc_kins;
use super::export::residual::Applied;
use super::export::{check_limit, largest_corrections, to_micro, ExportInput, ExportedFile, Extent, Limits};
use super::kinematic::{plan_tables, KinematicCorrection, PlanApplied};
use super::tables::reference_pose;
use super::{
    axis_tables, compensation_json, correct_batch, kinematics_json, residual_of_format, round4, volumetric_grid, CompensateError,
    Corrector, ExportFormat, FormatResidual, TableSet, TableSpec, VolumetricGrid,
};
use crate::data::{push_fixed, OutputSet};
use crate::error_model::ErrorModel;
use crate::machine::{Machine, ParameterId};
use crate::poses::{PoseStream, CHUNK};
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
    /// Write the files even when they leave more error than they remove.
    pub force: bool,
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
    /// The kinematic description written ([`super::summary::kinematics_json`]), if any.
    pub kinematics: Option<Value>,
    /// The uncertainty of the error left from the error values' stated uncertainties, if they state any.
    pub left_uncertainty: Option<super::LeftUncertainty>,
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
            self.left_uncertainty.as_ref(),
            self.kinematics.as_ref(),
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
/// the exact chain, Soons 1993 §2.3.5), with the error the format leaves and the corrected poses.
///
/// The compensation is of the machine: the set-up errors of a measurement (`TX .. WZ`, the position
/// of a master ball and of a probe head) are left out of it and of the error before and after. On
/// a machine with rotary axes, a controller whose kinematic description can hold their location
/// errors gets them there ([`crate::compensate::kinematic`]), and its tables carry what the
/// corrected kinematics leaves (the full correction minus the kinematic one along each line).
/// Files that would leave more error than they remove are refused unless `request.force`.
pub fn compensation(full: &Corrector, request: &CompensationRequest) -> Result<Compensation, CompensateError> {
    compensation_with(full, request, None, |_| ()).map(|(c, ())| c)
}

/// [`compensation`], the error before and after judged on the machine whose errors are `judge`
/// (default: the errors compensated; a simulation judges on its true errors), and `then` called
/// with what the controller applies with the files (`None` for the data formats) before it is
/// dropped (a report maps it).
pub fn compensation_with<R>(
    full: &Corrector,
    request: &CompensationRequest,
    judge: Option<&ErrorModel>,
    then: impl FnOnce(Option<&dyn Applied>) -> R,
) -> Result<(Compensation, R), CompensateError> {
    let machine = full.machine;
    let machine_errors = full.errors.without_setup();
    let corrector = Corrector { errors: &machine_errors, ..*full };
    let judged_errors = judge.map(ErrorModel::without_setup);
    let judged = Corrector { errors: judged_errors.as_ref().unwrap_or(&machine_errors), ..corrector };
    let temperatures: Vec<f64> =
        request.temperatures.iter().zip(corrector.errors.input_references()).map(|(t, r)| t.unwrap_or(*r)).collect();
    let spec = TableSpec { points: request.points, reference: request.reference.clone(), temperatures: temperatures.clone() };
    let kinematics = kinematic_part(&corrector, request, &temperatures)?;
    // a kinematics module carries the whole model: no tables; other descriptions get tables for the rest
    let module = matches!(request.format, ExportFormat::Linuxcnc(_)) && kinematics.is_some();
    let tables = match &kinematics {
        Some(k) if !module => plan_tables(&corrector, k, &spec)?,
        _ => axis_tables(&corrector, &spec)?,
    };
    let has_xyz = ['X', 'Y', 'Z'].iter().all(|&l| machine.axis_index(l).is_some());
    let grid = if request.format.wants_grid(has_xyz) { Some(volumetric_grid(&corrector, request.grid, &spec)?) } else { None };
    let (files, left_out, residual, extent, result) = {
        let input = ExportInput { machine, errors: corrector.errors, tables: &tables, grid: grid.as_ref(), limits: request.limits };
        let plan = match &kinematics {
            Some(k) if module => module_plan(&corrector, k)?,
            _ => table_plan(&input, &request.format, kinematics.as_ref())?,
        };
        let mut left_out = setup_left_out(machine, full.errors);
        left_out.extend(plan.left_out);
        // what the controller's files leave: its corrections applied over the travel, on the exact chain
        let residual = match &plan.applied {
            Some(applied) => Some(residual_of_format(&judged, &temperatures, applied.as_ref())?),
            None => None,
        };
        let coverage = if module { super::export::Coverage::TABLES } else { request.format.coverage() };
        let result = then(plan.applied.as_deref());
        (plan.files, left_out, residual, largest_corrections(&input, coverage), result)
    };
    if let Some(r) = residual.as_ref().filter(|r| r.leaves_more_than_it_removes() && !request.force) {
        return Err(CompensateError::Limit(worse_refusal(machine, &request.format, r)));
    }
    // the poses are corrected as they are written; the head of a file that can be read twice (not
    // a pipe) and the inputs it gives are checked now
    if let Some(path) = request.poses.as_ref().filter(|p| p.is_file()) {
        pose_stream(full, path, &request.temperatures)?;
    }
    let poses_request = request.poses.clone().map(|p| (p, request.temperatures.clone(), request.limits));
    let kinematics = kinematics.as_ref().map(|k| kinematics_json(machine, k, request.format.kinematics_name()));
    let left_uncertainty = match &residual {
        Some(_) => super::uncertainty_of_error_left(&corrector, &temperatures)?,
        None => None,
    };
    let compensation =
        Compensation { tables, grid, files, left_out, residual, extent, poses: None, kinematics, left_uncertainty, poses_request };
    Ok((compensation, result))
}

/// The kinematic description the format writes, if it has one and the machine rotary axes: the
/// location errors at the reference pose and the given inputs.
fn kinematic_part(
    corrector: &Corrector,
    request: &CompensationRequest,
    temperatures: &[f64],
) -> Result<Option<KinematicCorrection>, CompensateError> {
    let machine = corrector.machine;
    let Some(carried) = request.format.kinematics(machine) else { return Ok(None) };
    let mut q = vec![0.0; machine.axis_count()];
    machine.pose_to_internal(&reference_pose(machine, request.reference.as_deref())?, &mut q);
    Ok(Some(KinematicCorrection::new(machine, corrector.errors, &q, temperatures, carried)))
}

/// The refusal of files that leave more error than they remove, with the better option.
fn worse_refusal(machine: &Machine, format: &ExportFormat, r: &FormatResidual) -> String {
    let rotary = machine.axes().iter().any(|a| a.kind == crate::machine::AxisKind::Rotary);
    let better = match format {
        ExportFormat::Linuxcnc(_) if !rotary => "--format linuxcnc-hal (a HAL component that carries the volumetric grid)",
        ExportFormat::LinuxcncHal { .. } if rotary => "--format linuxcnc (a kinematics module generated from the identified model)",
        _ => "a corrected NC program (`trueaxis nc`), which carries every error at every point",
    };
    let moving = if rotary { ", rotary axes moving" } else { "" };
    format!(
        "the files of this format would leave a worst error of {:.3} um of the {:.3} um before (exact chain, {} poses over the travel{moving}): \
         more than they remove, so they would not make the machine better; nothing was written. Use {better}, or pass --force to write \
         them anyway (docs/compensation.md)",
        r.worst_um, r.worst_error_um, r.samples
    )
}

/// What a format writes: its files, what they leave out, and what the controller applies with
/// them (`None` for the data formats).
struct Plan<'a> {
    files: Vec<ExportedFile>,
    left_out: Vec<String>,
    applied: Option<Box<dyn Applied + 'a>>,
}

/// The format's tables (and grid), after the kinematic description when the format has one.
fn table_plan<'a>(
    input: &ExportInput<'a>,
    format: &ExportFormat,
    kinematics: Option<&KinematicCorrection>,
) -> Result<Plan<'a>, CompensateError> {
    let (mut files, exported) = format.export(input)?;
    let Some(e) = exported else { return Ok(Plan { files, left_out: Vec::new(), applied: None }) };
    let mut left_out = e.left_out.clone();
    let applied: Box<dyn Applied + 'a> = match kinematics {
        Some(k) => {
            let (kinematic_files, kinematic_left_out) = format.kinematic_files(input.machine, k)?;
            files.splice(0..0, kinematic_files);
            left_out.splice(0..0, kinematic_left_out);
            Box::new(PlanApplied { machine: input.machine, kinematics: k.errors.clone(), datum: k.datum_written, tables: Some(e.applied) })
        }
        None => e.applied,
    };
    Ok(Plan { files, left_out, applied: Some(applied) })
}

/// A generated LinuxCNC kinematics module carrying the whole model (five-axis machines).
fn module_plan<'a>(corrector: &Corrector<'a>, kinematics: &KinematicCorrection) -> Result<Plan<'a>, CompensateError> {
    let machine = corrector.machine;
    let model = linuxcnc_kins::model(machine, corrector.errors, kinematics)?;
    let files = linuxcnc_kins::export(machine, &model, linuxcnc_kins::DEFAULT_NAME)?;
    let applied = PlanApplied { machine, kinematics: model.errors, datum: model.datum, tables: None };
    Ok(Plan { files, left_out: model.left_out, applied: Some(Box::new(applied)) })
}

/// The line of "left out" for the set-up errors of a measurement in `errors` (none without them):
/// they place the master ball and the probe head of the measurement, not anything of the machine.
fn setup_left_out(machine: &Machine, errors: &ErrorModel) -> Vec<String> {
    let mut values = vec![0.0; machine.parameter_count()];
    errors.values_at(machine, &vec![0.0; machine.axis_count()], &mut values);
    let setup: Vec<(String, f64)> = (0..machine.parameter_count())
        .filter_map(|i| match machine.parameter_id(i) {
            id @ ParameterId::Setup { .. } if values[i] != 0.0 => Some((id.to_string(), values[i] * 1e3)),
            _ => None,
        })
        .collect();
    if setup.is_empty() {
        return Vec::new();
    }
    let largest = setup.iter().map(|s| s.1.abs()).fold(0.0, f64::max);
    let names: Vec<&str> = setup.iter().map(|s| s.0.as_str()).collect();
    vec![format!(
        "set-up of the measurement ({}): the position of the instrument on the tool and the workpiece, not an error of the machine; \
         not compensated and not in the errors before and after (largest {largest:.3} um)",
        names.join(" ")
    )]
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
