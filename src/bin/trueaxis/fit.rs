//! `trueaxis fit`.

use crate::Failure;
use std::path::PathBuf;
use trueaxis::data::{write_atomically, CsvTable};
use trueaxis::errors::{set_error_function, BasisSpec, Direction, ErrorModel, PeriodicSpec};
use trueaxis::geometry::Vec3;
use trueaxis::identify::{run_direct_fit, DirectFitReport, DirectFitRequest, DirectModel, FitOptions, IdentifyError};
use trueaxis::machine::{AxisKind, Machine, ParameterId};
use trueaxis::model::Setup;

/// Fit a parametric error function (piecewise polynomial, Legendre, periodic terms) to one error
/// measured along its axis (laser, level, straightedge), with stepwise selection, and write it into
/// an error-values file that `predict` accepts.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis fit --data examples/data/laser_x.csv --parameter EXX --machine examples/machines/vmc3.toml \\\n      \
      --knot-spacing 100 --stepwise 0.9999 --errors-out errors.toml --plot exx.svg\n\n\
Positions in mm (deg for rotary axes), values in um (urad for angular errors)."
)]
pub struct FitArgs {
    /// Measured data (CSV).
    #[arg(long)]
    data: PathBuf,
    /// ISO 230 name of the measured error, e.g. EXX, EBX, EYZ.
    #[arg(long)]
    parameter: String,
    /// Machine description: checks the parameter and gives the axis range as the default domain.
    #[arg(long)]
    machine: Option<PathBuf>,
    /// Errors already known (e.g. the angular errors fitted first): their Abbe contributions are
    /// removed from the readings (needs --machine).
    #[arg(long)]
    errors_in: Option<PathBuf>,
    /// Instrument point on the tool side x,y,z in mm, in M at home (default: the machine's tool point).
    #[arg(long, value_parser = crate::predict::parse_point, allow_hyphen_values = true)]
    tool_point: Option<Vec3>,
    /// Instrument point on the workpiece side x,y,z in mm, in M at home (default: 0,0,0).
    #[arg(long, value_parser = crate::predict::parse_point, allow_hyphen_values = true)]
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
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true)]
    domain: Option<[f64; 2]>,
    /// Basis family: piecewise, legendre, none.
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
    #[arg(long)]
    errors_out: Option<PathBuf>,
    /// Write an SVG of the data, the fit and its 95 % prediction band.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Print one JSON document instead of text.
    #[arg(long)]
    json: bool,
}

fn parse_pair(text: &str) -> Result<[f64; 2], String> {
    let v: Vec<f64> =
        text.split(',').map(|p| p.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| format!("`{text}` is not MIN,MAX"))?;
    match v.as_slice() {
        [a, b] if a.is_finite() && b.is_finite() && a < b => Ok([*a, *b]),
        _ => Err(format!("`{text}` is not MIN,MAX with MIN < MAX")),
    }
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

pub fn run(args: FitArgs) -> Result<(), Failure> {
    let parameter = ParameterId::parse(&args.parameter).map_err(|m| Failure::input(anyhow::anyhow!("--parameter: {m}")))?;
    let machine = args.machine.as_ref().map(Machine::load).transpose().map_err(Failure::input)?;
    let axis = match (&machine, parameter.axis()) {
        (Some(m), _) => {
            m.parameter_index(&parameter).map_err(|e| Failure::input(anyhow::anyhow!("--parameter: {e}")))?;
            parameter.axis().and_then(|a| m.axis_index(a)).map(|i| m.axes()[i].clone())
        }
        _ => None,
    };
    let table = CsvTable::read(&args.data).map_err(Failure::input)?;
    let position_column = match (&args.position, parameter.axis()) {
        (Some(p), _) => p.clone(),
        (None, _) if table.has_column("target") => "target".into(),
        (None, Some(a)) => a.to_string(),
        (None, None) => return Err(Failure::input(anyhow::anyhow!("--position: name the position column"))),
    };
    let domain = match (args.domain, axis.as_ref().and_then(|a| a.range)) {
        (Some(d), _) | (None, Some(d)) => d,
        (None, None) => {
            let p = table.numbers(&position_column).map_err(Failure::input)?;
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
    let spec = BasisSpec {
        family: args.family.clone(),
        degree: args.degree,
        knots,
        continuity: vec![args.continuity],
        constant: !args.no_constant,
        constraint: args.constraint.clone(),
        domain,
        periodic,
    };
    let model = match &machine {
        Some(m) => {
            let known = match &args.errors_in {
                Some(path) => ErrorModel::load(path, m).map_err(Failure::input)?,
                None => ErrorModel::zero(m),
            };
            let mut fixed_pose = vec![0.0; m.axis_count()];
            for item in args.at.iter().flat_map(|s| s.split(',')).filter(|s| !s.trim().is_empty()) {
                let (letter, value) =
                    item.split_once('=').ok_or_else(|| Failure::input(anyhow::anyhow!("--at `{item}`: expected AXIS=POSITION")))?;
                let i = letter
                    .trim()
                    .chars()
                    .next()
                    .and_then(|c| m.axis_index(c))
                    .ok_or_else(|| Failure::input(anyhow::anyhow!("--at: the machine has no axis `{letter}`")))?;
                fixed_pose[i] = value.trim().parse().map_err(|_| Failure::input(anyhow::anyhow!("--at `{item}`: not a number")))?;
            }
            let setup =
                Setup { tool_point: args.tool_point.unwrap_or(m.tool_point), work_point: args.work_point.unwrap_or_else(Vec3::zeros) };
            Some(DirectModel { machine: m.clone(), known, fixed_pose, setup })
        }
        None if args.errors_in.is_some() || args.at.is_some() => {
            return Err(Failure::input(anyhow::anyhow!(
                "--errors-in and --at need --machine (the measurement equation uses the kinematic model)"
            )))
        }
        None => None,
    };
    let directions: Vec<Option<Direction>> = match args.direction.as_deref() {
        Some("both") => vec![Some(Direction::Positive), Some(Direction::Negative)],
        Some("+") => vec![Some(Direction::Positive)],
        Some("-") => vec![Some(Direction::Negative)],
        _ => vec![None],
    };
    let mut reports = Vec::new();
    for &direction in &directions {
        let request = DirectFitRequest {
            model: model.clone(),
            parameter,
            position_column: position_column.clone(),
            value_column: args.value.clone(),
            direction: direction.map(direction_symbol),
            remove_drift: args.drift,
            refine_wavelength: args.refine_wavelength,
            options: FitOptions { spec: spec.clone(), stepwise_level: args.stepwise, prediction_level: 0.95 },
        };
        let report = run_direct_fit(&table, &request).map_err(|e| match e {
            IdentifyError::RankDeficient { .. } => Failure::computation(e),
            other => Failure::input(other),
        })?;
        reports.push((direction, report));
    }

    let mut written = Vec::new();
    if let Some(path) = &args.plot {
        let unit = axis.as_ref().map_or("mm", |a| if a.kind == AxisKind::Rotary { "deg" } else { "mm" });
        for (direction, report) in &reports {
            let path = if reports.len() > 1 { plot_path_of_direction(path, direction.map(direction_symbol)) } else { path.clone() };
            let svg = report.plot_svg(unit).map_err(Failure::computation)?;
            write_atomically(&path, svg.as_bytes()).map_err(Failure::input)?;
            written.push(path);
        }
    }
    if let Some(path) = &args.errors_out {
        let mut text = if path.exists() {
            std::fs::read_to_string(path).map_err(|e| Failure::input(anyhow::anyhow!("{}: {e}", path.display())))?
        } else {
            String::new()
        };
        for (direction, report) in &reports {
            text = set_error_function(&text, &parameter, *direction, &report.fitted.function)
                .map_err(|m| Failure::input(anyhow::anyhow!("{}: {m}", path.display())))?;
        }
        if let Some(m) = &machine {
            ErrorModel::from_toml_str(&text, &path.display().to_string(), m).map_err(|e| {
                let hint = if directions.len() == 1 && directions[0].is_some() {
                    " (fit the other direction into the same file too, or use --direction both)"
                } else {
                    ""
                };
                Failure::input(anyhow::anyhow!("{e}{hint}"))
            })?;
        }
        write_atomically(path, text.as_bytes()).map_err(Failure::input)?;
        written.insert(0, path.clone());
    }
    if args.json {
        let docs: Vec<_> = reports.iter().map(|(_, r)| r.to_json()).collect();
        match docs.as_slice() {
            [one] => println!("{one}"),
            _ => println!("{}", serde_json::json!({ "plus": docs[0], "minus": docs[1] })),
        }
        return Ok(());
    }
    for (direction, report) in &reports {
        print_fit(&parameter, *direction, report);
    }
    for path in written {
        println!("  wrote {}", path.display());
    }
    Ok(())
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
fn print_fit(parameter: &ParameterId, direction: Option<Direction>, report: &DirectFitReport) {
    let f = &report.fitted;
    let unit = parameter.unit();
    let suffix = direction.map(|d| direction_symbol(d).to_string()).unwrap_or_default();
    println!(
        "{parameter}{suffix}: {} observations, {} functions kept ({} removed by stepwise selection)",
        report.positions.len(),
        f.names.len(),
        f.removed.len()
    );
    for ((n, c), u) in f.names.iter().zip(&f.coefficients).zip(&f.std_uncertainties) {
        println!("  {n:<40} {c:>14.6e} +- {u:.2e}");
    }
    println!(
        "  residual standard deviation {:.4} {unit}, RMS {:.4} {unit}, largest |residual| {:.4} {unit}",
        f.fit.sigma, f.rms, f.max_abs_residual
    );
    println!("  95 % prediction interval: +- {:.4} {unit} at most", f.max_prediction_half_width);
    println!("  largest Cook's distance {:.3} (observation {})", f.max_cooks_distance.1, f.max_cooks_distance.0 + 1);
    for w in &report.wavelengths {
        println!("  periodic wavelength {w}");
    }
    if let Some((p, a)) = report.residual_period {
        println!("  strongest periodic residual: period {p:.4}, amplitude {a:.4} {unit}");
    }
}
