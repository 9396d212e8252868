//! `trueaxis fit`.

use crate::{output, parse, Failure};
use std::path::{Path, PathBuf};
use trueaxis::data::checks::deviation_finding;
use trueaxis::data::{CsvTable, OutputSet};
use trueaxis::error_model::{set_error_function, BasisSpec, Direction, ErrorModel, PeriodicSpec};
use trueaxis::geometry::Vec3;
use trueaxis::identify::{run_direct_fit, DirectFitReport, DirectFitRequest, DirectModel, FitOptions, ResidualPeriod};
use trueaxis::instruments::{motion_error_axis, AppliedCorrection, DirectError, DirectInstrument, DirectKind, DirectSetup, LevelBody};
use trueaxis::io::plausibility::split_findings;
use trueaxis::io::Dimension;
use trueaxis::machine::{Axis, AxisKind, Machine, ParameterId, Side};
use trueaxis::model::Setup;

/// Fit a parametric error function (piecewise polynomial, Legendre, periodic terms) to one error
/// measured along its axis (laser, level, straightedge), with stepwise selection, and write it into
/// an error-values file that `predict` accepts.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis fit --data examples/data/laser_x.csv --parameter EXX --machine examples/machines/vmc3.toml \\\n      \
      --knot-spacing 100 --stepwise 0.9999 --errors-out errors.toml --plot exx.svg\n  \
trueaxis fit --data examples/data/laser_x.csv --parameter EXX --machine examples/machines/vmc3.toml \\\n      \
--at Z=-200 --instrument laser-linear --optics-offset 0,150 --errors-in angular.toml --scale-temperature 21.3 --scale-expansion 11.5 --json\n\n\
Positions in mm (deg for rotary axes), values in um (urad for angular errors). Only motion errors\n\
(EXX, EYX, EBX, ECC, ...) are functions of a position; --errors-out needs --machine."
)]
pub struct FitArgs {
    /// Measured data: a table (read forgivingly: `;` or tab, decimal commas, units in the headers,
    /// one column per run and direction) or a Renishaw .rtl laser file.
    #[arg(long)]
    pub(crate) data: PathBuf,
    /// ISO 230 name of the measured error, e.g. EXX, EBX, EYZ.
    #[arg(long)]
    parameter: String,
    /// Machine description: checks the parameter, gives the axis range as the default domain and
    /// relates the readings to the parameter through the exact kinematic chain.
    #[arg(long)]
    machine: Option<PathBuf>,
    /// The instrument (needs --machine): laser-linear, laser-straightness, laser-angular or level.
    /// Default: linear optics for the positioning error, straightness optics for the other
    /// translations, angular optics for rotations.
    #[arg(long, value_parser = DirectKind::NAMES)]
    instrument: Option<String>,
    /// Laser linear / straightness optics: offsets A,B (mm) of the beam line from the tool point,
    /// in the two coordinates perpendicular to the beam (y,z for a beam along x; x,z along y; x,y
    /// along z), at the measurement pose (default 0,0: both optics at the tool point). The Abbe
    /// terms of known angular errors (--errors-in) then come from the chain.
    #[arg(long, value_parser = parse::offsets, allow_hyphen_values = true, value_name = "A,B")]
    optics_offset: Option<[f64; 2]>,
    /// The body that carries the interferometer (fixes the beam): tool or workpiece. Default: the
    /// side that does not carry the measured axis.
    #[arg(long, value_parser = ["tool", "workpiece"])]
    beam_on: Option<String>,
    /// Level: the body of the reference level of a differential pair: base (a single level) or the
    /// letter of the axis whose body carries it.
    #[arg(long, default_value = "base")]
    level_reference: String,
    #[command(flatten)]
    temperature: crate::temperature::TemperatureArgs,
    /// Errors already known (e.g. the angular errors fitted first): their Abbe contributions are
    /// removed from the readings (needs --machine).
    #[arg(long)]
    errors_in: Option<PathBuf>,
    /// Tool point x,y,z in mm, in M at home, that the optics are placed from (default: the machine's
    /// tool point); with --work-point, the tool-side optic itself.
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    tool_point: Option<Vec3>,
    /// The workpiece-side optic x,y,z in mm, in M at home: with --tool-point, places the two optics
    /// explicitly (instead of --optics-offset).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    work_point: Option<Vec3>,
    /// Positions of the other axes during the measurement, e.g. `Y=0,Z=-200` (default 0).
    #[arg(long, allow_hyphen_values = true)]
    at: Option<String>,
    /// Position column (default: `target` if present, else the letter of the parameter's axis).
    #[arg(long)]
    position: Option<String>,
    /// Value column (um or urad).
    #[arg(long, default_value = "dev")]
    value: String,
    /// Basis domain MIN,MAX (default: the axis range, else the data range).
    #[arg(long, value_parser = parse::interval, allow_hyphen_values = true)]
    domain: Option<[f64; 2]>,
    /// Basis family: piecewise (truncated powers), bspline (the same splines of continuity degree - 1,
    /// well conditioned with many knots), legendre, none.
    #[arg(long, default_value = "piecewise")]
    family: String,
    /// Polynomial degree.
    #[arg(long, default_value_t = 2)]
    degree: usize,
    /// Interior knots, comma separated (mm or deg).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    knots: Vec<f64>,
    /// Equally spaced knots at this spacing across the domain (instead of --knots).
    #[arg(long)]
    knot_spacing: Option<f64>,
    /// Continuity order at the knots (1 = continuous slope).
    #[arg(long, default_value_t = 1)]
    continuity: usize,
    /// Leave out the constant term (by default it is fitted: a laser reading has an arbitrary zero,
    /// and the constants of the + and - fits carry the backlash).
    #[arg(long)]
    no_constant: bool,
    /// none, straightness (no linear trend over the domain) or revolution (no once-per-turn term).
    #[arg(long, default_value = "none")]
    constraint: String,
    /// A periodic term: WAVELENGTH[:DEGREE[:KNOT;KNOT...]] (knots as fractions of the wavelength). Repeatable.
    #[arg(long)]
    periodic: Vec<String>,
    /// Refine the periodic wavelengths within this relative bracket (e.g. 0.002).
    #[arg(long)]
    refine_wavelength: Option<f64>,
    /// Stepwise selection at this confidence (e.g. 0.9999); default keeps every function.
    #[arg(long)]
    stepwise: Option<f64>,
    /// Bidirectional model (needs a `dir` column): `both` fits the `+` and the `-` rows separately and
    /// writes `EXX+` and `EXX-`; `+` or `-` fits and writes one direction, keeping the other's.
    #[arg(long, allow_hyphen_values = true, value_parser = ["+", "-", "both"])]
    direction: Option<String>,
    /// Remove per-cycle linear drift (needs `run` and `t` columns).
    #[arg(long)]
    drift: bool,
    /// Write or update this error-values file with the fitted function (atomically, comments kept).
    #[arg(long, value_parser = crate::output::file)]
    errors_out: Option<crate::output::OutputPath>,
    /// Write an SVG of the data, the fit and its 95 % prediction band.
    #[arg(long, value_parser = crate::output::file)]
    plot: Option<crate::output::OutputPath>,
    /// Print one JSON document instead of text.
    #[arg(long)]
    json: bool,
}

fn parse_periodic(text: &str) -> Result<PeriodicSpec, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let bad = || format!("--periodic `{text}`: expected WAVELENGTH[:DEGREE[:KNOT;KNOT...]]");
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

/// Sorts the findings of plausibility checks (`io::plausibility::split_findings`): the first
/// refusal is the error; the warnings (with those of reading the file) are returned, to be printed
/// with `output::warn` once the command has succeeded (a refused command prints its one line only).
fn report_findings(findings: Vec<trueaxis::io::Finding>, warnings: &[String]) -> Result<Vec<String>, Failure> {
    split_findings(findings, warnings).map_err(Failure::of)
}

fn input(message: impl std::fmt::Display) -> Failure {
    Failure::input(anyhow::anyhow!("{message}"))
}

/// What one `fit` computes before it writes anything: the parameter, the machine and the measured
/// axis, the table read, its temperature correction, warnings, and one fit per direction.
pub(crate) struct FitRun {
    pub parameter: ParameterId,
    pub machine: Option<Machine>,
    pub axis: Option<Axis>,
    pub table: CsvTable,
    pub applied: AppliedCorrection,
    pub warnings: Vec<String>,
    pub reports: Vec<(Option<Direction>, DirectFitReport)>,
}

impl FitRun {
    /// The unit of the axis positions: deg for a rotary axis, else mm.
    pub fn position_unit(&self) -> &'static str {
        self.axis.as_ref().map_or("mm", |a| if a.kind == AxisKind::Rotary { "deg" } else { "mm" })
    }
}

/// Reads the data and fits the parameter (each direction asked for), as `trueaxis fit` does.
pub(crate) fn compute(args: &FitArgs) -> Result<FitRun, Failure> {
    let parameter = motion_error(&args.parameter)?;
    let machine = args.machine.as_ref().map(Machine::load).transpose().map_err(Failure::input)?;
    let axis = match &machine {
        Some(m) => Some(m.axes()[motion_error_axis(m, &parameter).map_err(|e| input(format!("--parameter: {e}")))?].clone()),
        None => {
            refuse_without_machine(args)?;
            None
        }
    };
    let table = CsvTable::read(&args.data).map_err(Failure::input)?;
    let warnings = plausibility_warnings(&table, &args.value, &parameter)?;
    let applied = temperature_correction(args, &table, &parameter)?;
    let position_column = position_column(args, &table, &parameter)?;
    let spec = basis_spec(args, axis.as_ref(), &table, &position_column)?;
    let model = machine.as_ref().map(|m| direct_model(m, &parameter, args)).transpose()?;
    let request = DirectFitRequest {
        model,
        parameter,
        position_column,
        value_column: args.value.clone(),
        direction: None,
        remove_drift: args.drift,
        refine_wavelength: args.refine_wavelength,
        options: FitOptions { spec, stepwise_level: args.stepwise, prediction_level: 0.95 },
        corrections: applied.corrections.clone(),
    };
    let reports = fit_each_direction(args, &table, &request)?;
    Ok(FitRun { parameter, machine, axis, table, applied, warnings, reports })
}

/// The parameter of `--parameter`: only a motion error is a function of its axis position, the
/// others are refused before anything is read.
fn motion_error(name: &str) -> Result<ParameterId, Failure> {
    let parameter = ParameterId::parse(name).map_err(|e| Failure::of(e.for_parameter("--parameter")))?;
    if !matches!(parameter, ParameterId::Motion { .. }) {
        return Err(input(format!("--parameter: {}", DirectError::NotMotion(parameter))));
    }
    Ok(parameter)
}

/// Refuses the options that need `--machine` when it is not given.
fn refuse_without_machine(args: &FitArgs) -> Result<(), Failure> {
    let needs_machine = [
        ("--errors-out", args.errors_out.is_some()),
        ("--errors-in", args.errors_in.is_some()),
        ("--at", args.at.is_some()),
        ("--instrument", args.instrument.is_some()),
        ("--optics-offset", args.optics_offset.is_some()),
        ("--beam-on", args.beam_on.is_some()),
        ("--tool-point", args.tool_point.is_some()),
        ("--work-point", args.work_point.is_some()),
    ];
    match needs_machine.iter().find(|(_, given)| *given) {
        Some((option, _)) => Err(input(format!(
            "{option} needs --machine (the error-values file is checked against the machine, and the measurement equation uses \
             its kinematic chain)"
        ))),
        None => Ok(()),
    }
}

/// The warnings of the plausibility of the readings' unit (a column that answers to the value
/// name, read in the parameter's unit; a missing or bad column is reported by the fit itself).
fn plausibility_warnings(table: &CsvTable, value: &str, parameter: &ParameterId) -> Result<Vec<String>, Failure> {
    let value_dimension = if parameter.component().is_rotation() { Dimension::Angle } else { Dimension::Length };
    let findings = match table.numbers_as(value, value_dimension) {
        Ok(values) => deviation_finding(table, value, &values).into_iter().collect(),
        Err(_) => Vec::new(),
    };
    report_findings(findings, table.warnings())
}

/// The correction to 20 degC of the options or of the file; the file's material temperature
/// applies to a positioning error only.
fn temperature_correction(args: &FitArgs, table: &CsvTable, parameter: &ParameterId) -> Result<AppliedCorrection, Failure> {
    let data_name = args.data.display().to_string();
    let mut applied = args.temperature.applied(table.metadata(), &data_name)?;
    let positioning = matches!(parameter, ParameterId::Motion { axis, component } if component.letter() == *axis);
    if applied.json.get("source").and_then(|s| s.as_str()) == Some("file") && !positioning {
        applied.corrections.clear();
        applied.json = serde_json::Value::Null;
        applied.notes =
            vec![format!("{data_name}: the file's material temperature is not applied: {parameter} is not a positioning error")];
    }
    Ok(applied)
}

/// `--position`, else `target` when the table has it, else the letter of the parameter's axis.
fn position_column(args: &FitArgs, table: &CsvTable, parameter: &ParameterId) -> Result<String, Failure> {
    match (&args.position, parameter.axis()) {
        (Some(p), _) => Ok(p.clone()),
        (None, _) if table.has_column("target") => Ok("target".into()),
        (None, Some(a)) => Ok(a.to_string()),
        (None, None) => Err(Failure::input(anyhow::anyhow!("--position: name the position column"))),
    }
}

/// The basis of the fitted function: its family, degree and constraint, over `--domain` (else the
/// axis range, else the range of the positions), with the knots and periodic terms asked for.
fn basis_spec(args: &FitArgs, axis: Option<&Axis>, table: &CsvTable, position_column: &str) -> Result<BasisSpec, Failure> {
    let domain = match (args.domain, axis.and_then(|a| a.range)) {
        (Some(d), _) | (None, Some(d)) => d,
        (None, None) => {
            let p = table.numbers(position_column).map_err(Failure::input)?;
            let (lo, hi) = p.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
            [lo, hi]
        }
    };
    let knots = match args.knot_spacing {
        Some(s) if s > 0.0 => {
            let n = ((domain[1] - domain[0]) / s).ceil() as usize;
            (1..n).map(|k| domain[0] + s * k as f64).filter(|k| *k < domain[1] - 1e-9).collect()
        }
        Some(s) => return Err(Failure::input(anyhow::anyhow!("--knot-spacing {s} must be positive"))),
        None => args.knots.clone(),
    };
    let periodic =
        args.periodic.iter().map(|p| parse_periodic(p)).collect::<Result<Vec<_>, _>>().map_err(|m| Failure::input(anyhow::anyhow!(m)))?;
    Ok(BasisSpec {
        family: args.family.clone(),
        degree: args.degree,
        knots,
        continuity: vec![args.continuity],
        constant: !args.no_constant,
        constraint: args.constraint.clone(),
        domain,
        periodic,
    })
}

/// One fit of `request` per direction of `--direction` (both, +, -, or the rows of either).
fn fit_each_direction(
    args: &FitArgs,
    table: &CsvTable,
    request: &DirectFitRequest,
) -> Result<Vec<(Option<Direction>, DirectFitReport)>, Failure> {
    let directions: Vec<Option<Direction>> = match args.direction.as_deref() {
        Some("both") => vec![Some(Direction::Positive), Some(Direction::Negative)],
        Some("+") => vec![Some(Direction::Positive)],
        Some("-") => vec![Some(Direction::Negative)],
        _ => vec![None],
    };
    let mut reports = Vec::new();
    for direction in directions {
        let request = DirectFitRequest { direction: direction.map(direction_symbol), ..request.clone() };
        let report = run_direct_fit(table, &request).map_err(Failure::of)?;
        if let Some(what) = report.non_finite() {
            return Err(Failure::computation(anyhow::anyhow!(
                "{}: the fit of {} overflowed: {what} is not a finite number (readings too large?); nothing written",
                args.data.display(),
                request.parameter
            )));
        }
        reports.push((direction, report));
    }
    Ok(reports)
}

pub fn run(args: FitArgs) -> Result<(), Failure> {
    let run = compute(&args)?;
    output::warn(&run.warnings);
    for note in &run.applied.notes {
        eprintln!("trueaxis: {note}");
    }
    let written = write_outputs(&args, &run)?;
    if args.json {
        return output::json(&fit_json(&run));
    }
    let mut text: String = run.table.metadata().lines().iter().map(|line| format!("{line}\n")).collect();
    for (direction, report) in &run.reports {
        text += &fit_text(&run.parameter, *direction, report);
    }
    for path in written {
        text += &format!("  wrote {}\n", path.display());
    }
    output::print(&text)
}

/// Writes the plots and the error-values file, all or none (docs/reliability.md); returns the
/// paths written, the error-values file first.
fn write_outputs(args: &FitArgs, run: &FitRun) -> Result<Vec<PathBuf>, Failure> {
    let mut outputs = OutputSet::new();
    let mut written = Vec::new();
    if let Some(path) = &args.plot {
        for (direction, report) in &run.reports {
            let path =
                if run.reports.len() > 1 { plot_path_of_direction(path, direction.map(direction_symbol)) } else { path.to_path_buf() };
            let svg = trueaxis_report::direct_fit_svg(report, run.position_unit()).map_err(Failure::computation)?;
            outputs.file(&path, svg);
            written.push(path);
        }
    }
    if let Some(path) = &args.errors_out {
        outputs.file(path, error_values_text(path, run)?);
        written.insert(0, path.to_path_buf());
    }
    outputs.commit().map_err(Failure::input)?;
    Ok(written)
}

/// The error-values file at `path` (or a new one) with the fitted functions set, checked to load
/// on the machine.
fn error_values_text(path: &Path, run: &FitRun) -> Result<String, Failure> {
    let mut text = if path.exists() {
        std::fs::read_to_string(path).map_err(|e| Failure::input(anyhow::anyhow!("{}: {e}", path.display())))?
    } else {
        String::new()
    };
    for (direction, report) in &run.reports {
        text = set_error_function(&text, &run.parameter, *direction, &report.fitted.function)
            .map_err(|m| Failure::input(anyhow::anyhow!("{}: {m}", path.display())))?;
    }
    let m = run.machine.as_ref().expect("--errors-out needs --machine, checked above");
    ErrorModel::from_toml_str(&text, &path.display().to_string(), m).map_err(|e| {
        let hint = if run.reports.len() == 1 && run.reports[0].0.is_some() {
            " (fit the other direction into the same file too, or use --direction both)"
        } else {
            ""
        };
        Failure::input(anyhow::anyhow!("{e}{hint}"))
    })?;
    Ok(text)
}

/// The JSON document: the fit (or the fits `plus` and `minus`), the file's metadata and the
/// correction to 20 degC.
fn fit_json(run: &FitRun) -> serde_json::Value {
    let docs: Vec<_> = run.reports.iter().map(|(_, r)| r.to_json()).collect();
    let metadata = run.table.metadata().to_json();
    match docs.as_slice() {
        [one] => {
            let mut one = one.clone();
            one["metadata"] = metadata;
            one["temperature_correction"] = run.applied.json.clone();
            one
        }
        _ => serde_json::json!({ "plus": docs[0], "minus": docs[1], "metadata": metadata, "temperature_correction": run.applied.json }),
    }
}

/// The measurement equation of the fit on machine `m`: known errors, the other axes' positions,
/// the instrument and where its optics are.
fn direct_model(m: &Machine, parameter: &ParameterId, args: &FitArgs) -> Result<DirectModel, Failure> {
    let known = match &args.errors_in {
        Some(path) => ErrorModel::load(path, m).map_err(Failure::input)?,
        None => ErrorModel::zero(m),
    };
    let fixed_pose = fixed_pose(m, args.at.as_deref())?;
    let level_reference = level_reference(m, &args.level_reference)?;
    let setup = DirectSetup {
        setup: Setup { tool_point: args.tool_point.unwrap_or(m.tool_point), work_point: args.work_point.unwrap_or_else(Vec3::zeros) },
        beam_on: args.beam_on.as_deref().map(|b| if b == "tool" { Side::Tool } else { Side::Workpiece }),
        level_reference,
        up: Vec3::z(),
    };
    let kind = args.instrument.as_deref().map(DirectKind::parse).transpose().map_err(input)?;
    let mut instrument = DirectInstrument::for_parameter(m, parameter, kind, &setup).map_err(|e| input(format!("--instrument: {e}")))?;
    // the optics on the beam line through the tool point (offset by --optics-offset), unless both
    // optics are given by --tool-point and --work-point
    let offset = match (args.optics_offset, args.work_point) {
        (Some(_), Some(_)) => return Err(input("--optics-offset places both optics on the beam line; give it or --work-point, not both")),
        (None, None) if instrument.reads_a_displacement() => Some([0.0, 0.0]),
        (offset, _) => offset,
    };
    if let Some(offset) = offset {
        let mut q = vec![0.0; m.axis_count()];
        m.pose_to_internal(&fixed_pose, &mut q);
        instrument = instrument.with_optics_offset(m, &q, offset).map_err(|e| input(format!("--optics-offset: {e}")))?;
    }
    Ok(DirectModel { machine: m.clone(), known, fixed_pose, instrument })
}

/// The positions of the other axes, `--at Y=0,Z=-200` (mm, deg; 0 when not given).
fn fixed_pose(m: &Machine, at: Option<&str>) -> Result<Vec<f64>, Failure> {
    let mut fixed_pose = vec![0.0; m.axis_count()];
    for item in at.iter().flat_map(|s| s.split(',')).filter(|s| !s.trim().is_empty()) {
        let (letter, value) = item.split_once('=').ok_or_else(|| input(format!("--at `{item}`: expected AXIS=POSITION")))?;
        let i = letter
            .trim()
            .chars()
            .next()
            .and_then(|c| m.axis_index(c))
            .ok_or_else(|| input(format!("--at: the machine has no axis `{letter}`")))?;
        fixed_pose[i] =
            value.trim().parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| input(format!("--at `{item}`: not a number")))?;
    }
    Ok(fixed_pose)
}

/// The body of the reference level, `--level-reference`: base or an axis letter of the machine.
fn level_reference(m: &Machine, text: &str) -> Result<LevelBody, Failure> {
    match text.trim() {
        "base" => Ok(LevelBody::Base),
        other => match other.chars().collect::<Vec<_>>().as_slice() {
            [c] if m.axis_index(c.to_ascii_uppercase()).is_some() => Ok(LevelBody::CarriedBy(c.to_ascii_uppercase())),
            _ => Err(input(format!("--level-reference `{other}`: expected base or an axis letter of the machine ({})", m.axis_letters()))),
        },
    }
}

fn direction_symbol(d: Direction) -> char {
    match d {
        Direction::Positive => '+',
        Direction::Negative => '-',
    }
}

/// `exx.svg` -> `exx_plus.svg` / `exx_minus.svg` when both directions are fitted.
fn plot_path_of_direction(path: &std::path::Path, direction: Option<char>) -> std::path::PathBuf {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let tag = if direction == Some('-') { "minus" } else { "plus" };
    let ext = path.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    path.with_file_name(format!("{stem}_{tag}{ext}"))
}

/// The readable summary of one fit.
fn fit_text(parameter: &ParameterId, direction: Option<Direction>, report: &DirectFitReport) -> String {
    let f = &report.fitted;
    let unit = parameter.unit();
    let suffix = direction.map(|d| direction_symbol(d).to_string()).unwrap_or_default();
    let mut out = format!(
        "{parameter}{suffix}: {} observations, {} functions kept ({} removed by stepwise selection)\n",
        report.positions.len(),
        f.names.len(),
        f.removed.len()
    );
    for ((n, c), u) in f.names.iter().zip(&f.coefficients).zip(&f.std_uncertainties) {
        out += &format!("  {n:<40} {c:>14.6e} +- {u:.2e}\n");
    }
    out += &format!(
        "  residual standard deviation {:.4} {unit}, RMS {:.4} {unit}, largest |residual| {:.4} {unit}\n",
        f.fit.sigma, f.rms, f.max_abs_residual
    );
    out += &format!("  95 % prediction interval: +- {:.4} {unit} at most\n", f.max_prediction_half_width);
    out += &format!("  largest Cook's distance {:.3} (observation {})\n", f.max_cooks_distance.1, f.max_cooks_distance.0 + 1);
    for w in &report.wavelengths {
        out += &format!("  periodic wavelength {w}\n");
    }
    out += &output::data_quality_text(&report.findings);
    if let Some(r) = &report.residual_period {
        out += &residual_period_text(r, unit);
    }
    out
}

/// The strongest periodic residual, and the aliases a uniform sampling cannot tell it from.
fn residual_period_text(r: &ResidualPeriod, unit: &str) -> String {
    let verdict = if r.significant { "significant at 1 %" } else { "not significant at 1 %" };
    let mut out = format!(
        "  strongest periodic residual: period {:.4}, amplitude {:.4} {unit} ({verdict}; periods from {:.4}, twice the sampling step, searched)\n",
        r.period, r.amplitude, r.limit
    );
    let aliases = r.aliases(2);
    if r.significant && !aliases.is_empty() {
        let list: Vec<String> = aliases.iter().map(|a| format!("{a:.4}")).collect();
        out += &format!(
            "  warning: samples every {:.4} cannot tell this period from its aliases {}, ... (1/|k/step +- 1/period|): a periodic error \
             of such a wavelength (scale pitch, screw lead) looks the same; name it with --periodic or sample at finer or random intervals\n",
            r.uniform_step.unwrap_or(0.0),
            list.join(", ")
        );
    }
    out
}
