//! `trueaxis thermal fit`: PITE/PDTE regression models validated on other runs, and the shared
//! time constants of eq. 3.17.

use super::{failure, plot_text, write_plot};
use crate::iso230_2::print;
use crate::Failure;
use serde_json::{json, Value};
use std::path::PathBuf;
use trueaxis::data::OutputSet;
use trueaxis::errors::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::thermal::campaign::Campaign;
use trueaxis::thermal::drift_model::{fit_drift_model, record};
use trueaxis::thermal::error_model::ThermalErrorModel;
use trueaxis::thermal::links::{add_terms, model_terms, terms_toml};
use trueaxis::thermal::regression::{fit_regression, fit_split, fit_stepwise, select_by_correlation, RegressionModel};
use trueaxis::thermal::segmented::{fit_segmented, Segmentation};
use trueaxis::thermal::time_constants::{fit_time_constants, Series};
use trueaxis::thermal::validation::{evaluate_segments, residual_stats, segments, ResidualStats, Role, Segment};
use trueaxis_report::{drift_plot, drift_svg, step_fit_plot};

/// Fits a thermal error model to a campaign CSV (columns t, run, T:<sensor>, the error in um):
/// PITE/PDTE regression (seed 002 eqs. 3.12-3.15 with intercepts as eqs. 4.3-4.5) or the
/// state-space drift model (seed 000 §3.4.4), validated on the runs not trained on or on the later
/// part of each training run; or, with --time-constants N, the eq. 3.17 fit of shared time
/// constants to the temperature records of every run.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  trueaxis thermal fit --data examples/thermal/campaign.csv --error dz --train-runs warmup --out dz_model.toml --plot dz_fit.svg\n  \
trueaxis thermal fit --data examples/thermal/campaign.csv --error dz --model state-space --rates 2 --train-runs warmup --out dz_drift.toml\n  \
trueaxis thermal fit --data examples/thermal/campaign.csv --error dz --train-runs long --validate time-split:0.5\n  \
trueaxis thermal fit --data examples/thermal/campaign.csv --time-constants 2 --train-runs warmup --until 14400 --json"
)]
pub struct FitArgs {
    /// Campaign (CSV).
    #[arg(long)]
    data: PathBuf,
    /// Error column (um) to model.
    #[arg(long, required_unless_present = "time_constants")]
    error: Option<String>,
    /// Model form: regression (static, seed 002 eqs. 3.12-3.15) or state-space (seed 000 §3.4.4:
    /// the drift as a sum of first-order lags of the sensors' rises since the start of each run).
    #[arg(long, value_enum, default_value = "regression")]
    model: ModelForm,
    /// State-space model: number of time constants shared by the sensors (1 to 4).
    #[arg(long, default_value_t = 2)]
    rates: usize,
    /// Validation: the runs not in --train-runs (default), or `time-split:F`: each training run
    /// trains on the first fraction F (0 < F < 1) of its time span and verifies on the rest.
    #[arg(long, value_name = "time-split:F")]
    validate: Option<String>,
    /// Fit N shared time constants (eq. 3.17) to the temperature columns instead.
    #[arg(long)]
    time_constants: Option<usize>,
    /// With --time-constants: use only the first SECONDS of each run (the step response; eq. 3.17
    /// describes a warm-up from a step, not the cool-down after it).
    #[arg(long)]
    until: Option<f64>,
    /// Sensor columns, comma separated (default: every T:<sensor> column).
    #[arg(long, value_delimiter = ',')]
    sensors: Option<Vec<String>>,
    /// Sensor selection: `correlation:N` (the N best correlated, seed 003 §3.6) or `stepwise`.
    #[arg(long)]
    select: Option<String>,
    /// Axis column whose position enters the model (PDTE).
    #[arg(long)]
    position: Option<String>,
    /// Highest power of the position (PDTE).
    #[arg(long, default_value_t = 0)]
    degree: usize,
    /// Drop the intercept terms (eqs. 3.12-3.13 as printed).
    #[arg(long)]
    no_intercept: bool,
    /// Geometric/thermal split: the degree of the geometric polynomial in the position (the
    /// intercepts), with --degree the degree of the position multiplying the temperatures.
    #[arg(long, requires = "position")]
    geometric_degree: Option<usize>,
    /// G-T model (NISTIR 5236): one model per direction of motion (column dir, + or -).
    #[arg(long, requires = "position")]
    by_direction: bool,
    /// G-T model: one model per range of the position between these breakpoints (mm or deg,
    /// increasing), e.g. --ranges 0 for [-inf, 0) and [0, inf).
    #[arg(long, value_delimiter = ',', requires = "position", allow_hyphen_values = true)]
    ranges: Option<Vec<f64>>,
    /// Runs to train on, comma separated (default: every row); the others validate.
    #[arg(long, value_delimiter = ',')]
    train_runs: Option<Vec<String>>,
    /// Write the fitted model (TOML) here.
    #[arg(long)]
    out: Option<PathBuf>,
    /// ISO 230 parameter the error is (e.g. EZZ, TZ) for --terms-out.
    #[arg(long)]
    parameter: Option<String>,
    /// Write the model as [[term.NAME]] error terms (T - 20 degC) for `trueaxis predict`.
    #[arg(long, requires = "parameter")]
    terms_out: Option<PathBuf>,
    /// Machine (TOML) to check --parameter against.
    #[arg(long)]
    machine: Option<PathBuf>,
    /// Write a figure (SVG): per run the measured values against the model over time and the
    /// residual band, training and validation runs told apart (with --time-constants: each
    /// temperature record and its eq. 3.17 fit).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Print one JSON document.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum ModelForm {
    Regression,
    StateSpace,
}

pub fn fit(args: FitArgs) -> Result<(), Failure> {
    let campaign = Campaign::read(&args.data).map_err(failure)?;
    let rows: Vec<usize> = match &args.train_runs {
        Some(runs) => campaign.rows_of(runs).map_err(failure)?,
        None => (0..campaign.len()).collect(),
    };
    let sensors = args.sensors.clone().unwrap_or_else(|| campaign.sensors());
    if sensors.is_empty() {
        return Err(Failure::input(anyhow::anyhow!("{}: no temperature columns T:<sensor>", args.data.display())));
    }
    if let Some(n) = args.time_constants {
        return fit_taus(&args, &campaign, &rows, &sensors, n);
    }
    let error = args.error.clone().expect("clap requires --error");
    let split = match args.validate.as_deref() {
        None => None,
        Some(v) => match v.strip_prefix("time-split:").map(str::parse::<f64>) {
            Some(Ok(f)) if f > 0.0 && f < 1.0 => Some(f),
            _ => return Err(Failure::input(anyhow::anyhow!("--validate {v}: expected time-split:F with 0 < F < 1"))),
        },
    };
    let segments = segments(&campaign, args.train_runs.as_deref(), split).map_err(failure)?;
    let training: Vec<&Segment> = segments.iter().filter(|s| s.role == Role::Training).collect();
    let rows: Vec<usize> = training.iter().flat_map(|s| s.rows.iter().copied()).collect();
    let segmented = args.by_direction || args.ranges.is_some();
    let (model, kept) = match args.model {
        ModelForm::Regression if segmented => {
            if args.select.is_some() || args.no_intercept {
                return Err(Failure::input(anyhow::anyhow!(
                    "--select and --no-intercept do not apply to a segmented G-T model (--by-direction, --ranges)"
                )));
            }
            let segmentation = Segmentation {
                by_direction: args.by_direction,
                breakpoints: args.ranges.clone().unwrap_or_default(),
                geometric_degree: args.geometric_degree.unwrap_or(args.degree),
                thermal_degree: args.degree,
            };
            let position = args.position.as_deref().expect("clap requires --position");
            let model = fit_segmented(&campaign, &rows, &error, &sensors, position, &segmentation).map_err(failure)?;
            (ThermalErrorModel::Segmented(model), None)
        }
        ModelForm::Regression => {
            let (model, kept) = fit_regression_model(&args, &campaign, &rows, &sensors, &error)?;
            (ThermalErrorModel::Regression(model), kept)
        }
        ModelForm::StateSpace => {
            if args.select.is_some() || args.position.is_some() || args.no_intercept || args.terms_out.is_some() || segmented {
                return Err(Failure::input(anyhow::anyhow!(
                    "--select, --position, --no-intercept, --by-direction, --ranges and --terms-out apply to regression models, not to --model state-space"
                )));
            }
            let records = training
                .iter()
                .map(|s| record(&campaign, &sensors, Some(&error), &s.rows))
                .collect::<Result<Vec<_>, _>>()
                .map_err(failure)?;
            (ThermalErrorModel::Drift(fit_drift_model(&error, &sensors, &records, args.rates).map_err(failure)?.0), None)
        }
    };
    let evaluated = evaluate_segments(&campaign, &model, &segments).map_err(failure)?;
    let (measured, predicted): (Vec<f64>, Vec<f64>) = evaluated
        .iter()
        .filter(|e| e.segment.role == Role::Training)
        .flat_map(|e| e.measured.clone().unwrap_or_default().into_iter().zip(e.predicted.clone()))
        .unzip();
    let training_stats = residual_stats(&measured, &predicted);
    let validation: Vec<(String, Option<ResidualStats>)> =
        evaluated.iter().filter(|e| e.segment.role == Role::Validation).map(|e| (e.segment.name.clone(), e.stats())).collect();
    // model, terms and plot together, or none of them (docs/reliability.md)
    let mut outputs = OutputSet::new();
    if let Some(path) = &args.out {
        outputs.file(path, model.to_toml());
    }
    if let (Some(path), Some(parameter)) = (&args.terms_out, &args.parameter) {
        let terms = match &model {
            ThermalErrorModel::Regression(regression) => model_terms(parameter, regression, 1.0).map_err(failure)?,
            ThermalErrorModel::Segmented(segmented) => segmented.terms(parameter).map_err(failure)?,
            ThermalErrorModel::Drift(_) => unreachable!("refused above"),
        };
        if let Some(machine) = &args.machine {
            let machine = Machine::load(machine).map_err(Failure::input)?;
            add_terms(&mut ErrorModel::zero(&machine), &machine, &terms).map_err(failure)?;
        }
        let text = format!(
            "# thermal error model of `{error}` as error terms (factors T - 20 degC), from trueaxis thermal fit\n{}",
            terms_toml(&terms)
        );
        outputs.file(path, text);
    }
    if let Some(path) = &args.plot {
        outputs.file(path, plot_text(path, drift_svg(&drift_plot(&error, &evaluated)))?);
    }
    outputs.commit().map_err(Failure::input)?;
    if args.json {
        let doc = json!({"model": model, "kept": kept, "training": training_stats,
                         "validation": validation.iter().map(|(r, s)| (r.clone(), json!(s))).collect::<serde_json::Map<_, _>>()});
        return print(&format!("{doc}\n"));
    }
    let mut out = format!("thermal error model of `{error}` (um) from {} rows of {}\n", rows.len(), args.data.display());
    match &model {
        ThermalErrorModel::Regression(m) => out += &regression_text(m),
        ThermalErrorModel::Segmented(m) => {
            for (k, seg) in m.segments.iter().enumerate() {
                let range = seg.range.map_or(String::new(), |[lo, hi]| format!(" {} in [{lo}, {hi})", m.position));
                out +=
                    &format!("  segment {}:{}{range}\n", k + 1, seg.direction.as_deref().map_or(String::new(), |d| format!(" moving {d}")));
                out += &regression_text(&m.segment_model(k)).lines().map(|l| format!("  {l}\n")).collect::<String>();
            }
        }
        ThermalErrorModel::Drift(m) => {
            let taus: Vec<String> = m.time_constants_s.iter().map(|t| format!("{:.2}", t / 60.0)).collect();
            out +=
                &format!("  state space (seed 000 §3.4.4), time constants {} min; gains (um/degC) per time constant:\n", taus.join(", "));
            for (s, g) in m.sensors.iter().zip(&m.gains_um_per_degc) {
                out += &format!("  {s:<10} {}\n", g.iter().map(|v| format!("{v:+.5}")).collect::<Vec<_>>().join(" "));
            }
        }
    }
    out += "residuals (measured - predicted):\n";
    out += &stats_line("training", &training_stats);
    for (run, s) in &validation {
        out += &stats_line(run, s);
    }
    print(&out)
}

/// The PITE/PDTE regression on the training rows, with the sensor selection of --select; the
/// names of the kept terms or sensors when selected.
fn fit_regression_model(
    args: &FitArgs,
    campaign: &Campaign,
    rows: &[usize],
    sensors: &[String],
    error: &str,
) -> Result<(RegressionModel, Option<Vec<String>>), Failure> {
    let temps = campaign.select(sensors, rows).map_err(failure)?;
    let measured = campaign.select(&[error.to_string()], rows).map_err(failure)?.remove(0);
    let positions = match &args.position {
        Some(p) => Some(campaign.select(std::slice::from_ref(p), rows).map_err(failure)?.remove(0)),
        None => None,
    };
    let position = args.position.as_deref().zip(positions.as_deref());
    let intercept = !args.no_intercept;
    if let (Some(g), Some(position)) = (args.geometric_degree, position) {
        if args.select.is_some() || !intercept {
            return Err(Failure::input(anyhow::anyhow!("--geometric-degree does not combine with --select or --no-intercept")));
        }
        return Ok((fit_split(error, sensors, &temps, position, g, args.degree, &measured).map_err(failure)?.0, None));
    }
    match args.select.as_deref() {
        None => Ok((fit_regression(error, sensors, &temps, position, args.degree, intercept, &measured).map_err(failure)?.0, None)),
        Some("stepwise") => {
            let (m, _, k) = fit_stepwise(error, sensors, &temps, position, args.degree, intercept, &measured, 0.9999).map_err(failure)?;
            Ok((m, Some(k)))
        }
        Some(s) if s.starts_with("correlation:") => {
            let n = match s["correlation:".len()..].parse::<usize>() {
                Ok(n) if n >= 1 => n,
                _ => {
                    return Err(Failure::input(anyhow::anyhow!(
                        "--select {s}: expected correlation:N with N >= 1, the number of sensors to keep (of {})",
                        sensors.len()
                    )))
                }
            };
            let chosen = select_by_correlation(&temps, &measured, n, 0.0);
            let names: Vec<String> = chosen.iter().map(|&i| sensors[i].clone()).collect();
            let t: Vec<Vec<f64>> = chosen.iter().map(|&i| temps[i].clone()).collect();
            let (m, _) = fit_regression(error, &names, &t, position, args.degree, intercept, &measured).map_err(failure)?;
            Ok((m, Some(names)))
        }
        Some(other) => Err(Failure::input(anyhow::anyhow!("--select {other}: expected correlation:N or stepwise"))),
    }
}

/// The coefficients, one line per power of the position.
fn regression_text(model: &RegressionModel) -> String {
    let mut out = String::new();
    for (k, row) in model.coefficients.iter().enumerate() {
        let p = match (k, &model.position) {
            (0, _) | (_, None) => String::new(),
            (1, Some(a)) => format!(" * {a}"),
            (k, Some(a)) => format!(" * {a}^{k}"),
        };
        // small coefficients (per mm^k, per rpm) in scientific notation, so that they do not print as zero
        let number = |v: f64| if v != 0.0 && v.abs() < 1e-3 { format!("{v:+.4e}") } else { format!("{v:+.5}") };
        let terms: Vec<String> = std::iter::once(number(row[0]))
            .chain(model.sensors.iter().zip(&row[1..]).map(|(s, c)| format!("{} {s}", number(*c))))
            .collect();
        out += &format!("  [{}]{p}\n", terms.join(" "));
    }
    out
}

fn stats_line(name: &str, s: &Option<ResidualStats>) -> String {
    s.map_or(String::new(), |s| {
        format!(
            "  {name:<12} RMS {:.3}  max {:.3}  range {:.3}  band [{:.3}, {:.3}] um ({} samples)\n",
            s.rms, s.max_abs, s.range, s.min, s.max, s.samples
        )
    })
}

fn fit_taus(args: &FitArgs, campaign: &Campaign, rows: &[usize], sensors: &[String], n: usize) -> Result<(), Failure> {
    if let Some(u) = args.until.filter(|u| !(u.is_finite() && *u > 0.0)) {
        return Err(Failure::input(anyhow::anyhow!("--until {u}: expected a positive number of seconds from the start of each run")));
    }
    let t = campaign.column("t").map_err(failure)?;
    let mut series = Vec::new();
    let mut labels = Vec::new();
    let runs: Vec<String> = campaign.run_names().into_iter().filter(|r| rows.iter().any(|&i| &campaign.runs[i] == r)).collect();
    for run in &runs {
        let run_rows: Vec<usize> = rows.iter().copied().filter(|&i| &campaign.runs[i] == run).collect();
        let t0 = run_rows.iter().map(|&i| t[i]).fold(f64::INFINITY, f64::min);
        let run_rows: Vec<usize> = run_rows.into_iter().filter(|&i| args.until.is_none_or(|u| t[i] - t0 <= u)).collect();
        for s in sensors {
            let v = campaign.column(s).map_err(failure)?;
            series
                .push(Series { times_s: run_rows.iter().map(|&i| t[i] - t0).collect(), values: run_rows.iter().map(|&i| v[i]).collect() });
            labels.push((run.clone(), s.clone()));
        }
    }
    let fit = fit_time_constants(&series, n, true).map_err(failure)?;
    if let Some(path) = &args.plot {
        let names: Vec<String> = labels.iter().map(|(r, s)| format!("{r} {s}")).collect();
        write_plot(path, drift_svg(&step_fit_plot(&names, &series, &fit)))?;
    }
    if args.json {
        let amplitudes: Vec<Value> = labels
            .iter()
            .zip(fit.amplitudes.iter().zip(&fit.offsets))
            .map(|((r, s), (a, b))| json!({"run": r, "sensor": s, "A": a, "offset": b}))
            .collect();
        let doc = json!({"tau_min": fit.tau_s.iter().map(|t| t / 60.0).collect::<Vec<_>>(), "residual_rms": fit.residual_rms, "amplitudes": amplitudes});
        return print(&format!("{doc}\n"));
    }
    let mut out = format!(
        "shared time constants (eq. 3.17) of {} records: {} min\nresidual RMS {:.4} degC\n",
        series.len(),
        fit.tau_s.iter().map(|t| format!("{:.2}", t / 60.0)).collect::<Vec<_>>().join(", "),
        fit.residual_rms
    );
    for ((r, s), (a, b)) in labels.iter().zip(fit.amplitudes.iter().zip(&fit.offsets)) {
        out += &format!("  {r:<10} {s:<10} T0 {b:.3}  A {:?}\n", a.iter().map(|v| (v * 1e4).round() / 1e4).collect::<Vec<_>>());
    }
    print(&out)
}
