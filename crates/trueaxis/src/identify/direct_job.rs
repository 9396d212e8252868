//! A direct fit end to end, as `trueaxis fit`, the `[[fit]]` tables of `trueaxis report` and the
//! Python package's `trueaxis.fit` run it: the parameter checked to be a motion error (a function
//! of its own axis position), the machine and the known errors, the table read forgivingly with the
//! plausibility of its unit, the correction of positioning readings to 20 degC (ISO 1), the basis
//! of the fitted function (piecewise polynomials, B-splines, Legendre, periodic terms over a domain
//! in mm or deg), the measurement equation of the instrument on the exact chain, and one fit per
//! direction of motion (Soons 1993 §3.2), with the error-values file the fit goes into.
//!
//! Units: positions in mm (deg for rotary axes), values in um (urad for angular errors), points in
//! mm in the machine frame at home, temperatures in degC, expansion coefficients in um/m/K. The
//! messages name the options of `trueaxis fit` (`--parameter`, `--at`, ...), which the Python
//! package takes as keyword arguments of the same names.

use super::{run_direct_fit, DirectFitReport, DirectFitRequest, DirectModel, FitOptions};
use crate::data::checks::deviation_finding;
use crate::data::CsvTable;
use crate::error::{Error, ErrorKind};
use crate::error_model::{set_error_function, BasisSpec, Direction, ErrorModel, PeriodicSpec};
use crate::geometry::Vec3;
use crate::instruments::{
    motion_error_axis, AppliedCorrection, DirectError, DirectInstrument, DirectKind, DirectSetup, LevelBody, TemperatureOptions,
};
use crate::io::plausibility::split_findings;
use crate::io::Dimension;
use crate::machine::{Axis, AxisKind, Machine, ParameterId, Side};
use crate::model::Setup;
use std::path::{Path, PathBuf};

/// An input given as a file to read or as the value itself (the command line reads files, the
/// Python package passes the objects it holds).
#[derive(Clone, Debug)]
pub enum Given<T> {
    File(PathBuf),
    Value(T),
}

/// What to fit and how, in plain values: the options of `trueaxis fit` by name.
#[derive(Clone, Debug)]
pub struct DirectFitJob {
    /// The measured data: a table or a Renishaw .rtl laser file.
    pub data: PathBuf,
    /// ISO 230 name of the measured error (EXX, EBX, ...).
    pub parameter: String,
    pub machine: Option<Given<Machine>>,
    /// laser-linear, laser-straightness, laser-angular or level (default by the parameter).
    pub instrument: Option<String>,
    /// Offsets A,B (mm) of the beam line from the tool point, perpendicular to the beam.
    pub optics_offset: Option<[f64; 2]>,
    /// `tool` or `workpiece`: the body carrying the interferometer.
    pub beam_on: Option<String>,
    /// `base` or the letter of the axis whose body carries the reference level.
    pub level_reference: String,
    pub temperature: TemperatureOptions,
    /// Errors already known, whose Abbe contributions are removed from the readings.
    pub errors_in: Option<Given<ErrorModel>>,
    /// The error-values file the fit will be written into (it needs the machine); the job only
    /// checks this, [`DirectFitRun::error_values_text`] makes the text.
    pub errors_out: Option<PathBuf>,
    pub tool_point: Option<Vec3>,
    pub work_point: Option<Vec3>,
    /// Positions of the other axes, `Y=0,Z=-200` (mm, deg; 0 when not given).
    pub at: Option<String>,
    /// Position column (default `target` if present, else the letter of the parameter's axis).
    pub position: Option<String>,
    /// Value column (um or urad).
    pub value: String,
    /// Basis domain (default the axis range, else the data range).
    pub domain: Option<[f64; 2]>,
    /// piecewise, bspline, legendre or none.
    pub family: String,
    pub degree: usize,
    pub knots: Vec<f64>,
    /// Equally spaced knots at this spacing across the domain (instead of `knots`).
    pub knot_spacing: Option<f64>,
    pub continuity: usize,
    /// Fit the constant term.
    pub constant: bool,
    /// none, straightness or revolution.
    pub constraint: String,
    /// Periodic terms, each `WAVELENGTH[:DEGREE[:KNOT;KNOT...]]`.
    pub periodic: Vec<String>,
    pub refine_wavelength: Option<f64>,
    pub stepwise: Option<f64>,
    /// `+`, `-` or `both` (none: every row, one fit).
    pub direction: Option<String>,
    /// Remove per-cycle linear drift (`run` and `t` columns).
    pub drift: bool,
}

impl DirectFitJob {
    /// The job of `parameter` measured in `data` with the defaults of `trueaxis fit`.
    pub fn new(data: impl Into<PathBuf>, parameter: impl Into<String>) -> DirectFitJob {
        DirectFitJob {
            data: data.into(),
            parameter: parameter.into(),
            machine: None,
            instrument: None,
            optics_offset: None,
            beam_on: None,
            level_reference: "base".into(),
            temperature: TemperatureOptions::default(),
            errors_in: None,
            errors_out: None,
            tool_point: None,
            work_point: None,
            at: None,
            position: None,
            value: "dev".into(),
            domain: None,
            family: "piecewise".into(),
            degree: 2,
            knots: Vec::new(),
            knot_spacing: None,
            continuity: 1,
            constant: true,
            constraint: "none".into(),
            periodic: Vec::new(),
            refine_wavelength: None,
            stepwise: None,
            direction: None,
            drift: false,
        }
    }
}

/// What one fit computed: the parameter, the machine and the measured axis, the table read, its
/// temperature correction, warnings, and one fit per direction.
pub struct DirectFitRun {
    pub parameter: ParameterId,
    pub machine: Option<Machine>,
    pub axis: Option<Axis>,
    pub table: CsvTable,
    pub applied: AppliedCorrection,
    /// Warnings of reading the table and of the plausibility of its unit.
    pub warnings: Vec<String>,
    pub reports: Vec<(Option<Direction>, DirectFitReport)>,
}

/// The same error as bad input (the file or option it names is the user's to fix), its cause kept.
fn as_input(e: impl Into<Error>) -> Error {
    let e = e.into();
    if e.kind() == ErrorKind::Input {
        e
    } else {
        Error::input(e.to_string()).caused_by(e)
    }
}

/// Reads the data and fits the parameter, each direction asked for.
pub fn run_direct_job(job: &DirectFitJob) -> Result<DirectFitRun, Error> {
    let parameter = motion_error(&job.parameter)?;
    let machine = job.machine.clone().map(given_machine).transpose()?;
    let axis = match &machine {
        Some(m) => Some(m.axes()[motion_error_axis(m, &parameter).map_err(|e| Error::input(format!("--parameter: {e}")))?].clone()),
        None => {
            refuse_without_machine(job)?;
            None
        }
    };
    let table = CsvTable::read(&job.data).map_err(as_input)?;
    let warnings = plausibility_warnings(&table, &job.value, &parameter)?;
    let applied = temperature_correction(job, &table, &parameter)?;
    let position_column = position_column(job, &table, &parameter)?;
    let spec = basis_spec(job, axis.as_ref(), &table, &position_column)?;
    let model = machine.as_ref().map(|m| direct_model(m, &parameter, job)).transpose()?;
    let request = DirectFitRequest {
        model,
        parameter,
        position_column,
        value_column: job.value.clone(),
        direction: None,
        remove_drift: job.drift,
        refine_wavelength: job.refine_wavelength,
        options: FitOptions { spec, stepwise_level: job.stepwise, prediction_level: 0.95 },
        corrections: applied.corrections.clone(),
    };
    let reports = fit_each_direction(job, &table, &request)?;
    Ok(DirectFitRun { parameter, machine, axis, table, applied, warnings, reports })
}

fn given_machine(machine: Given<Machine>) -> Result<Machine, Error> {
    match machine {
        Given::File(path) => Machine::load(path).map_err(as_input),
        Given::Value(m) => Ok(m),
    }
}

/// The parameter: only a motion error is a function of its axis position, the others are refused
/// before anything is read.
fn motion_error(name: &str) -> Result<ParameterId, Error> {
    let parameter = ParameterId::parse(name).map_err(|e| e.for_parameter("--parameter"))?;
    if !matches!(parameter, ParameterId::Motion { .. }) {
        return Err(Error::input(DirectError::NotMotion(parameter).to_string()).for_parameter("--parameter"));
    }
    Ok(parameter)
}

/// Refuses the options that need the machine when it is not given.
fn refuse_without_machine(job: &DirectFitJob) -> Result<(), Error> {
    let needs_machine = [
        ("--errors-out", job.errors_out.is_some()),
        ("--errors-in", job.errors_in.is_some()),
        ("--at", job.at.is_some()),
        ("--instrument", job.instrument.is_some()),
        ("--optics-offset", job.optics_offset.is_some()),
        ("--beam-on", job.beam_on.is_some()),
        ("--tool-point", job.tool_point.is_some()),
        ("--work-point", job.work_point.is_some()),
    ];
    match needs_machine.iter().find(|(_, given)| *given) {
        Some((option, _)) => Err(Error::input(format!(
            "{option} needs --machine (the error-values file is checked against the machine, and the measurement equation uses \
             its kinematic chain)"
        ))),
        None => Ok(()),
    }
}

/// The warnings of the plausibility of the readings' unit (a column that answers to the value
/// name, read in the parameter's unit; a missing or bad column is reported by the fit itself),
/// with those of reading the table; the first refusal is the error.
fn plausibility_warnings(table: &CsvTable, value: &str, parameter: &ParameterId) -> Result<Vec<String>, Error> {
    let value_dimension = if parameter.component().is_rotation() { Dimension::Angle } else { Dimension::Length };
    let findings = match table.numbers_as(value, value_dimension) {
        Ok(values) => deviation_finding(table, value, &values).into_iter().collect(),
        Err(_) => Vec::new(),
    };
    split_findings(findings, table.warnings())
}

/// The correction to 20 degC of the options or of the file; the file's material temperature
/// applies to a positioning error only.
fn temperature_correction(job: &DirectFitJob, table: &CsvTable, parameter: &ParameterId) -> Result<AppliedCorrection, Error> {
    let data_name = job.data.display().to_string();
    let mut applied = job.temperature.resolve(table.metadata(), &data_name).map_err(as_input)?;
    let positioning = matches!(parameter, ParameterId::Motion { axis, component } if component.letter() == *axis);
    if applied.json.get("source").and_then(|s| s.as_str()) == Some("file") && !positioning {
        applied.corrections.clear();
        applied.json = serde_json::Value::Null;
        applied.notes =
            vec![format!("{data_name}: the file's material temperature is not applied: {parameter} is not a positioning error")];
    }
    Ok(applied)
}

/// `position`, else `target` when the table has it, else the letter of the parameter's axis.
fn position_column(job: &DirectFitJob, table: &CsvTable, parameter: &ParameterId) -> Result<String, Error> {
    match (&job.position, parameter.axis()) {
        (Some(p), _) => Ok(p.clone()),
        (None, _) if table.has_column("target") => Ok("target".into()),
        (None, Some(a)) => Ok(a.to_string()),
        (None, None) => Err(Error::input("--position: name the position column")),
    }
}

/// The basis of the fitted function: its family, degree and constraint, over the domain (else the
/// axis range, else the range of the positions), with the knots and periodic terms asked for.
fn basis_spec(job: &DirectFitJob, axis: Option<&Axis>, table: &CsvTable, position_column: &str) -> Result<BasisSpec, Error> {
    let domain = match (job.domain, axis.and_then(|a| a.range)) {
        (Some(d), _) | (None, Some(d)) => d,
        (None, None) => {
            let p = table.numbers(position_column).map_err(as_input)?;
            let (lo, hi) = p.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
            [lo, hi]
        }
    };
    let knots = match job.knot_spacing {
        Some(s) if s > 0.0 => {
            let n = ((domain[1] - domain[0]) / s).ceil() as usize;
            (1..n).map(|k| domain[0] + s * k as f64).filter(|k| *k < domain[1] - 1e-9).collect()
        }
        Some(s) => return Err(Error::input(format!("--knot-spacing {s} must be positive"))),
        None => job.knots.clone(),
    };
    let periodic = job.periodic.iter().map(|p| periodic_term(p)).collect::<Result<Vec<_>, _>>()?;
    Ok(BasisSpec {
        family: job.family.clone(),
        degree: job.degree,
        knots,
        continuity: vec![job.continuity],
        constant: job.constant,
        constraint: job.constraint.clone(),
        domain,
        periodic,
    })
}

/// A periodic term `WAVELENGTH[:DEGREE[:KNOT;KNOT...]]` (knots as fractions of the wavelength;
/// degree 2 and knots at a third and two thirds by default).
pub fn periodic_term(text: &str) -> Result<PeriodicSpec, Error> {
    let parts: Vec<&str> = text.split(':').collect();
    let bad = || Error::input(format!("--periodic `{text}`: expected WAVELENGTH[:DEGREE[:KNOT;KNOT...]]"));
    let wavelength: f64 = parts[0].trim().parse().map_err(|_| bad())?;
    let degree = match parts.get(1) {
        Some(d) => d.trim().parse().map_err(|_| bad())?,
        None => 2,
    };
    let knots = match parts.get(2) {
        Some(k) if !k.trim().is_empty() => {
            k.split(';').map(|v| v.trim().parse::<f64>()).collect::<Result<Vec<_>, _>>().map_err(|_| bad())?
        }
        _ => vec![1.0 / 3.0, 2.0 / 3.0],
    };
    if parts.len() > 3 {
        return Err(bad());
    }
    Ok(PeriodicSpec { wavelength, phase: 0.0, degree, knots, continuity: degree.saturating_sub(1).min(1) })
}

/// The directions to fit: both, `+`, `-`, or the rows of either.
fn directions(job: &DirectFitJob) -> Result<Vec<Option<Direction>>, Error> {
    match job.direction.as_deref() {
        Some("both") => Ok(vec![Some(Direction::Positive), Some(Direction::Negative)]),
        Some("+") => Ok(vec![Some(Direction::Positive)]),
        Some("-") => Ok(vec![Some(Direction::Negative)]),
        None => Ok(vec![None]),
        Some(other) => Err(Error::input(format!("--direction `{other}`: expected +, - or both"))),
    }
}

/// One fit of `request` per direction asked for; a fit that overflowed is a failed computation.
fn fit_each_direction(
    job: &DirectFitJob,
    table: &CsvTable,
    request: &DirectFitRequest,
) -> Result<Vec<(Option<Direction>, DirectFitReport)>, Error> {
    let mut reports = Vec::new();
    for direction in directions(job)? {
        let request = DirectFitRequest { direction: direction.map(direction_symbol), ..request.clone() };
        let report = run_direct_fit(table, &request)?;
        if let Some(what) = report.non_finite() {
            return Err(Error::computation(format!(
                "{}: the fit of {} overflowed: {what} is not a finite number (readings too large?); nothing written",
                job.data.display(),
                request.parameter
            )));
        }
        reports.push((direction, report));
    }
    Ok(reports)
}

/// The measurement equation of the fit on machine `m`: known errors, the other axes' positions,
/// the instrument and where its optics are.
fn direct_model(m: &Machine, parameter: &ParameterId, job: &DirectFitJob) -> Result<DirectModel, Error> {
    let known = match &job.errors_in {
        Some(Given::File(path)) => ErrorModel::load(path, m).map_err(as_input)?,
        Some(Given::Value(known)) => known.clone(),
        None => ErrorModel::zero(m),
    };
    let fixed_pose = fixed_pose(m, job.at.as_deref())?;
    let level_reference = level_reference(m, &job.level_reference)?;
    let setup = DirectSetup {
        setup: Setup { tool_point: job.tool_point.unwrap_or(m.tool_point), work_point: job.work_point.unwrap_or_else(Vec3::zeros) },
        beam_on: job.beam_on.as_deref().map(beam_side).transpose()?,
        level_reference,
        up: Vec3::z(),
    };
    let kind = job.instrument.as_deref().map(DirectKind::parse).transpose().map_err(|e| Error::input(e.to_string()))?;
    let instrument = DirectInstrument::for_parameter(m, parameter, kind, &setup).map_err(|e| Error::input(format!("--instrument: {e}")))?;
    let instrument = with_optics(m, job, &fixed_pose, instrument)?;
    Ok(DirectModel { machine: m.clone(), known, fixed_pose, instrument })
}

/// The optics on the beam line through the tool point (offset by `optics_offset`), unless both
/// optics are given by the tool and work points.
fn with_optics(m: &Machine, job: &DirectFitJob, fixed_pose: &[f64], instrument: DirectInstrument) -> Result<DirectInstrument, Error> {
    let offset = match (job.optics_offset, job.work_point) {
        (Some(_), Some(_)) => {
            return Err(Error::input("--optics-offset places both optics on the beam line; give it or --work-point, not both"))
        }
        (None, None) if instrument.reads_a_displacement() => Some([0.0, 0.0]),
        (offset, _) => offset,
    };
    let Some(offset) = offset else { return Ok(instrument) };
    let mut q = vec![0.0; m.axis_count()];
    m.pose_to_internal(fixed_pose, &mut q);
    instrument.with_optics_offset(m, &q, offset).map_err(|e| Error::input(format!("--optics-offset: {e}")))
}

/// The body that carries the interferometer: `tool` or `workpiece`.
fn beam_side(text: &str) -> Result<Side, Error> {
    match text {
        "tool" => Ok(Side::Tool),
        "workpiece" => Ok(Side::Workpiece),
        other => Err(Error::input(format!("--beam-on `{other}`: expected tool or workpiece"))),
    }
}

/// The positions of the other axes, `Y=0,Z=-200` (mm, deg; 0 when not given).
fn fixed_pose(m: &Machine, at: Option<&str>) -> Result<Vec<f64>, Error> {
    let mut fixed_pose = vec![0.0; m.axis_count()];
    for item in at.iter().flat_map(|s| s.split(',')).filter(|s| !s.trim().is_empty()) {
        let (letter, value) = item.split_once('=').ok_or_else(|| Error::input(format!("--at `{item}`: expected AXIS=POSITION")))?;
        let i = letter
            .trim()
            .chars()
            .next()
            .and_then(|c| m.axis_index(c))
            .ok_or_else(|| Error::input(format!("--at: the machine has no axis `{letter}`")))?;
        fixed_pose[i] = value
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| Error::input(format!("--at `{item}`: not a number")))?;
    }
    Ok(fixed_pose)
}

/// The body of the reference level: base or an axis letter of the machine.
fn level_reference(m: &Machine, text: &str) -> Result<LevelBody, Error> {
    match text.trim() {
        "base" => Ok(LevelBody::Base),
        other => match other.chars().collect::<Vec<_>>().as_slice() {
            [c] if m.axis_index(c.to_ascii_uppercase()).is_some() => Ok(LevelBody::CarriedBy(c.to_ascii_uppercase())),
            _ => Err(Error::input(format!(
                "--level-reference `{other}`: expected base or an axis letter of the machine ({})",
                m.axis_letters()
            ))),
        },
    }
}

/// `+` or `-`.
pub fn direction_symbol(d: Direction) -> char {
    match d {
        Direction::Positive => '+',
        Direction::Negative => '-',
    }
}

impl DirectFitRun {
    /// The unit of the axis positions: deg for a rotary axis, else mm.
    pub fn position_unit(&self) -> &'static str {
        self.axis.as_ref().map_or("mm", |a| if a.kind == AxisKind::Rotary { "deg" } else { "mm" })
    }

    /// The document of `trueaxis fit --json`: the fit (or the fits `plus` and `minus`), the file's
    /// metadata and the correction to 20 degC.
    pub fn to_json(&self) -> serde_json::Value {
        let docs: Vec<_> = self.reports.iter().map(|(_, r)| r.to_json()).collect();
        let metadata = self.table.metadata().to_json();
        match docs.as_slice() {
            [one] => {
                let mut one = one.clone();
                one["metadata"] = metadata;
                one["temperature_correction"] = self.applied.json.clone();
                one
            }
            _ => {
                serde_json::json!({ "plus": docs[0], "minus": docs[1], "metadata": metadata, "temperature_correction": self.applied.json })
            }
        }
    }

    /// The error-values file at `path` (or a new one when there is none) with the fitted functions
    /// set, checked to load on the machine (comments and other entries kept).
    pub fn error_values_text(&self, path: &Path) -> Result<String, Error> {
        let mut text = if path.exists() {
            std::fs::read_to_string(path).map_err(|e| Error::input(format!("{}: {e}", path.display())))?
        } else {
            String::new()
        };
        for (direction, report) in &self.reports {
            text = set_error_function(&text, &self.parameter, *direction, &report.fitted.function)
                .map_err(|m| Error::input(format!("{}: {m}", path.display())))?;
        }
        let Some(m) = self.machine.as_ref() else { return Err(Error::input("--errors-out needs --machine")) };
        ErrorModel::from_toml_str(&text, &path.display().to_string(), m).map_err(|e| {
            let hint = if self.reports.len() == 1 && self.reports[0].0.is_some() {
                " (fit the other direction into the same file too, or use --direction both)"
            } else {
                ""
            };
            Error::input(format!("{e}{hint}"))
        })?;
        Ok(text)
    }
}
