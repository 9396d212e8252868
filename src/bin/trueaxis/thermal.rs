//! `trueaxis thermal modes|place|fit|predict`.

use crate::iso230_2::print;
use crate::Failure;
use serde_json::{json, Value};
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::errors::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::thermal::campaign::Campaign;
use trueaxis::thermal::links::{add_terms, model_terms, terms_toml};
use trueaxis::thermal::model_file::{load_model, ThermalModel};
use trueaxis::thermal::placement::{condition_number, effective_independence, exhaustive, log_det_information, modal_rule};
use trueaxis::thermal::regression::{fit_regression, fit_stepwise, select_by_correlation, RegressionModel};
use trueaxis::thermal::time_constants::{fit_time_constants, Series};
use trueaxis::thermal::validation::residual_stats;
use trueaxis::thermal::{
    dominant_modes, modal_analysis, mode_weights, ModalBasis, ModalOptions, SpectrumMethod, ThermalError, DEFAULT_SHARE,
};

/// Thermal modal analysis, sensor placement and thermal error models (seed 002 ch. 3-4).
#[derive(clap::Args)]
#[command(after_help = "Examples (see `trueaxis thermal <command> --help`):\n  \
trueaxis thermal modes --model examples/thermal/fin.toml --count 6\n  \
trueaxis thermal place --model examples/thermal/elongation.toml --count 3 --share 1\n  \
trueaxis thermal fit --data examples/thermal/campaign.csv --error dz --train-runs warmup --out dz_model.toml\n  \
trueaxis thermal predict --model dz_model.toml --data examples/thermal/campaign.csv")]
pub struct ThermalArgs {
    #[command(subcommand)]
    command: ThermalCommand,
}

#[derive(clap::Subcommand)]
enum ThermalCommand {
    Modes(ModesArgs),
    Place(PlaceArgs),
    Fit(Box<FitArgs>),
    Predict(PredictArgs),
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum MethodArg {
    Auto,
    Dense,
    Lanczos,
}

/// Modes of a thermal model: time constants (min) and weights |xi tau| under the model's step
/// flux, sorted by decreasing time constant; the dominant modes carry the `--share` of the weight.
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis thermal modes --model examples/thermal/fin.toml --count 6 --json")]
struct ModesArgs {
    /// Thermal model (TOML): kind = bar1d | grid2d | grid3d | matrix_market.
    #[arg(long)]
    model: PathBuf,
    /// Number of modes (the lowest).
    #[arg(long, default_value_t = 10)]
    count: usize,
    /// Cumulative weight share kept by truncation.
    #[arg(long, default_value_t = DEFAULT_SHARE)]
    share: f64,
    /// Eigensolver: dense up to 1500 nodes and shift-invert Lanczos above (auto), or forced.
    #[arg(long, value_enum, default_value = "auto")]
    method: MethodArg,
    /// Print one JSON document.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum PlaceMethod {
    Modal,
    Efi,
    Exhaustive,
}

/// Temperature sensor placement for the dominant modes: the modal rule of seed 002 §3.3.1
/// (extremes of each dominant mode, reuse, ties to the heat source), effective independence, or
/// exhaustive search for the largest det(Phi_s^T Phi_s).
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis thermal place --model examples/thermal/fin.toml --method modal --json")]
struct PlaceArgs {
    #[arg(long)]
    model: PathBuf,
    /// Modes computed before truncation.
    #[arg(long, default_value_t = 20)]
    count: usize,
    #[arg(long, default_value_t = DEFAULT_SHARE)]
    share: f64,
    #[arg(long, value_enum, default_value = "modal")]
    method: PlaceMethod,
    /// Number of sensors (efi, exhaustive; default: one per dominant mode).
    #[arg(long)]
    sensors: Option<usize>,
    /// Modal rule: reuse a placed sensor reaching this fraction of a mode's extreme.
    #[arg(long, default_value_t = 0.8)]
    reuse: f64,
    #[arg(long)]
    json: bool,
}

/// Fits a thermal error model to a campaign CSV (columns t, run, T:<sensor>, the error in um):
/// PITE/PDTE regression (seed 002 eqs. 3.12-3.15 with intercepts as eqs. 4.3-4.5), validated on
/// the runs not trained on; or, with --time-constants N, the eq. 3.17 fit of shared time constants
/// to the temperature records of every run.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  trueaxis thermal fit --data examples/thermal/campaign.csv --error dz --train-runs warmup --out dz_model.toml\n  \
trueaxis thermal fit --data examples/thermal/campaign.csv --time-constants 2 --train-runs warmup --until 14400 --json"
)]
struct FitArgs {
    /// Campaign (CSV).
    #[arg(long)]
    data: PathBuf,
    /// Error column (um) to model.
    #[arg(long, required_unless_present = "time_constants")]
    error: Option<String>,
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
    #[arg(long)]
    json: bool,
}

/// Evaluates a fitted thermal error model on a campaign CSV; with the measured error column
/// present, also the residual band, RMS, max and range.
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis thermal predict --model dz_model.toml --data examples/thermal/campaign.csv --json")]
struct PredictArgs {
    /// Fitted model (TOML, kind = "regression").
    #[arg(long)]
    model: PathBuf,
    #[arg(long)]
    data: PathBuf,
    #[arg(long)]
    json: bool,
    /// Write the result here (atomically) instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
}

fn failure(e: ThermalError) -> Failure {
    match e {
        ThermalError::Computation(_) => Failure::computation(e),
        _ => Failure::input(e),
    }
}

pub fn run(args: ThermalArgs) -> Result<(), Failure> {
    match args.command {
        ThermalCommand::Modes(a) => modes(a),
        ThermalCommand::Place(a) => place(a),
        ThermalCommand::Fit(a) => fit(*a),
        ThermalCommand::Predict(a) => predict(a),
    }
}

fn check_share(share: f64) -> Result<(), Failure> {
    if share > 0.0 && share <= 1.0 {
        Ok(())
    } else {
        Err(Failure::input(anyhow::anyhow!("--share {share} must lie in (0, 1]")))
    }
}

fn analyse(model: &ThermalModel, count: usize, method: MethodArg) -> Result<ModalBasis, Failure> {
    if count == 0 {
        return Err(Failure::input(anyhow::anyhow!("--count must be at least 1")));
    }
    let method = match method {
        MethodArg::Auto => SpectrumMethod::Auto,
        MethodArg::Dense => SpectrumMethod::Dense,
        MethodArg::Lanczos => SpectrumMethod::Lanczos,
    };
    let count = count.min(model.system.node_count());
    modal_analysis(&model.system, &ModalOptions { count: Some(count), method, ..Default::default() }).map_err(failure)
}

fn modes(args: ModesArgs) -> Result<(), Failure> {
    check_share(args.share)?;
    let model = load_model(&args.model).map_err(failure)?;
    let basis = analyse(&model, args.count, args.method)?;
    let weights = mode_weights(&basis, &model.system.load);
    let dominant = dominant_modes(&weights, args.share);
    if args.json {
        let modes: Vec<Value> = weights
            .iter()
            .map(|w| {
                json!({"mode": w.mode + 1, "tau_min": w.tau_s / 60.0, "tau_s": w.tau_s, "weight": w.weight, "share": w.share,
                       "dominant": dominant.contains(&w.mode)})
            })
            .collect();
        let doc = json!({"model": model.name, "nodes": model.system.node_count(), "share": args.share,
                         "dominant": dominant.iter().map(|m| m + 1).collect::<Vec<_>>(), "modes": modes});
        return print(&format!("{doc}\n"));
    }
    let mut out = format!(
        "thermal modes of {} ({} nodes), weights |xi tau| under the step flux, sorted by decreasing time constant\n{:>5} {:>12} {:>12} {:>8}  dominant\n",
        model.name,
        model.system.node_count(),
        "mode",
        "tau (min)",
        "weight",
        "share"
    );
    for w in &weights {
        out += &format!(
            "{:>5} {:>12.3} {:>12.4e} {:>7.1}%  {}\n",
            w.mode + 1,
            w.tau_s / 60.0,
            w.weight,
            100.0 * w.share,
            if dominant.contains(&w.mode) { "yes" } else { "" }
        );
    }
    out +=
        &format!("{} dominant modes carry {:.0} % of the weight of the {} computed\n", dominant.len(), 100.0 * args.share, weights.len());
    print(&out)
}

fn place(args: PlaceArgs) -> Result<(), Failure> {
    check_share(args.share)?;
    let model = load_model(&args.model).map_err(failure)?;
    let basis = analyse(&model, args.count, MethodArg::Auto)?;
    let weights = mode_weights(&basis, &model.system.load);
    let dominant = dominant_modes(&weights, args.share);
    let coordinates = model.system.coordinates.clone();
    let distance = |node: usize| -> f64 {
        model
            .flux_nodes
            .iter()
            .map(|&f| match &coordinates {
                Some(c) => (0..3).map(|d| (c[node][d] - c[f][d]).powi(2)).sum::<f64>().sqrt(),
                None => (node as f64 - f as f64).abs(),
            })
            .fold(f64::INFINITY, f64::min)
    };
    let count = args.sensors.unwrap_or(dominant.len());
    let (sensors, served): (Vec<usize>, Vec<Vec<usize>>) = match args.method {
        PlaceMethod::Modal => {
            let placed = modal_rule(&basis, &dominant, &model.candidates, args.reuse, distance).map_err(failure)?;
            placed.into_iter().map(|p| (p.node, p.modes)).unzip()
        }
        PlaceMethod::Efi => {
            let s = effective_independence(&basis, &dominant, &model.candidates, count).map_err(failure)?;
            let n = s.len();
            (s, vec![Vec::new(); n])
        }
        PlaceMethod::Exhaustive => {
            if count < dominant.len() {
                return Err(Failure::input(anyhow::anyhow!(
                    "exhaustive search maximises det(Phi_s^T Phi_s): it needs at least {} sensors (one per dominant mode)",
                    dominant.len()
                )));
            }
            let (s, _) = exhaustive(&model.candidates, count, |s| log_det_information(&basis, &dominant, s)).map_err(failure)?;
            let n = s.len();
            (s, vec![Vec::new(); n])
        }
    };
    let cond = condition_number(&basis, &dominant, &sensors);
    let method = match args.method {
        PlaceMethod::Modal => "modal",
        PlaceMethod::Efi => "efi",
        PlaceMethod::Exhaustive => "exhaustive",
    };
    let position = |n: usize| coordinates.as_ref().map(|c| c[n].to_vec());
    if args.json {
        let list: Vec<Value> = sensors
            .iter()
            .zip(&served)
            .map(|(n, m)| json!({"node": n, "position_m": position(*n), "modes": m.iter().map(|i| i + 1).collect::<Vec<_>>()}))
            .collect();
        let doc = json!({"model": model.name, "method": method, "dominant_modes": dominant.iter().map(|m| m + 1).collect::<Vec<_>>(),
                         "sensors": list, "condition_number": if cond.is_finite() { json!(cond) } else { Value::Null }});
        return print(&format!("{doc}\n"));
    }
    let mut out = format!(
        "sensor placement ({method}) for the dominant modes {:?} of {}\n",
        dominant.iter().map(|m| m + 1).collect::<Vec<_>>(),
        model.name
    );
    for (n, m) in sensors.iter().zip(&served) {
        let at =
            position(*n).map_or(String::new(), |p| format!(" at {:?} m", p.iter().map(|v| (v * 1e4).round() / 1e4).collect::<Vec<_>>()));
        let modes = if m.is_empty() { String::new() } else { format!(", serves modes {:?}", m.iter().map(|i| i + 1).collect::<Vec<_>>()) };
        out += &format!("  node {n}{at}{modes}\n");
    }
    out += &format!("condition number of Phi_s: {cond:.3e}\n");
    print(&out)
}

fn fit(args: FitArgs) -> Result<(), Failure> {
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
        return fit_taus(&campaign, &rows, &sensors, n, args.until, args.json);
    }
    let error = args.error.clone().expect("clap requires --error");
    let temps = campaign.select(&sensors, &rows).map_err(failure)?;
    let measured = campaign.select(std::slice::from_ref(&error), &rows).map_err(failure)?.remove(0);
    let positions = match &args.position {
        Some(p) => Some(campaign.select(std::slice::from_ref(p), &rows).map_err(failure)?.remove(0)),
        None => None,
    };
    let position = args.position.as_deref().zip(positions.as_deref());
    let intercept = !args.no_intercept;
    let (model, fit, kept) = match args.select.as_deref() {
        None => {
            let (m, f) = fit_regression(&error, &sensors, &temps, position, args.degree, intercept, &measured).map_err(failure)?;
            (m, f, None)
        }
        Some("stepwise") => {
            let (m, f, k) = fit_stepwise(&error, &sensors, &temps, position, args.degree, intercept, &measured, 0.9999).map_err(failure)?;
            (m, f, Some(k))
        }
        Some(s) if s.starts_with("correlation:") => {
            let n: usize =
                s["correlation:".len()..].parse().map_err(|_| Failure::input(anyhow::anyhow!("--select {s}: expected correlation:N")))?;
            let chosen = select_by_correlation(&temps, &measured, n, 0.0);
            let names: Vec<String> = chosen.iter().map(|&i| sensors[i].clone()).collect();
            let t: Vec<Vec<f64>> = chosen.iter().map(|&i| temps[i].clone()).collect();
            let (m, f) = fit_regression(&error, &names, &t, position, args.degree, intercept, &measured).map_err(failure)?;
            (m, f, Some(names))
        }
        Some(other) => return Err(Failure::input(anyhow::anyhow!("--select {other}: expected correlation:N or stepwise"))),
    };
    let training = residual_stats(&measured, &measured.iter().zip(&fit.residuals).map(|(m, r)| m - r).collect::<Vec<_>>());
    let mut validation = Vec::new();
    if args.train_runs.is_some() {
        for run in campaign.run_names().into_iter().filter(|r| !args.train_runs.as_ref().is_some_and(|t| t.contains(r))) {
            let rows = campaign.rows_of(std::slice::from_ref(&run)).map_err(failure)?;
            let (m, p) = evaluate(&campaign, &model, &rows).map_err(failure)?;
            if let Some(m) = m {
                validation.push((run, residual_stats(&m, &p)));
            }
        }
    }
    if let Some(path) = &args.out {
        write_atomically(path, model.to_toml().as_bytes()).map_err(Failure::input)?;
    }
    if let (Some(path), Some(parameter)) = (&args.terms_out, &args.parameter) {
        let terms = model_terms(parameter, &model, 1.0).map_err(failure)?;
        if let Some(machine) = &args.machine {
            let machine = Machine::load(machine).map_err(Failure::input)?;
            add_terms(&mut ErrorModel::zero(&machine), &machine, &terms).map_err(failure)?;
        }
        let text = format!(
            "# thermal error model of `{error}` as error terms (factors T - 20 degC), from trueaxis thermal fit\n{}",
            terms_toml(&terms)
        );
        write_atomically(path, text.as_bytes()).map_err(Failure::input)?;
    }
    if args.json {
        let doc = json!({"model": model, "kept": kept, "training": training,
                         "validation": validation.iter().map(|(r, s)| (r.clone(), json!(s))).collect::<serde_json::Map<_, _>>()});
        return print(&format!("{doc}\n"));
    }
    let mut out = format!("thermal error model of `{error}` (um) from {} rows of {}\n", rows.len(), args.data.display());
    for (k, row) in model.coefficients.iter().enumerate() {
        let p = match (k, &model.position) {
            (0, _) | (_, None) => String::new(),
            (1, Some(a)) => format!(" * {a}"),
            (k, Some(a)) => format!(" * {a}^{k}"),
        };
        let terms: Vec<String> = std::iter::once(format!("{:+.5}", row[0]))
            .chain(model.sensors.iter().zip(&row[1..]).map(|(s, c)| format!("{c:+.5} {s}")))
            .collect();
        out += &format!("  [{}]{p}\n", terms.join(" "));
    }
    let line = |name: &str, s: &Option<trueaxis::thermal::validation::ResidualStats>| {
        s.map_or(String::new(), |s| {
            format!(
                "  {name:<12} RMS {:.3}  max {:.3}  range {:.3}  band [{:.3}, {:.3}] um ({} samples)\n",
                s.rms, s.max_abs, s.range, s.min, s.max, s.samples
            )
        })
    };
    out += "residuals (measured - predicted):\n";
    out += &line("training", &training);
    for (run, s) in &validation {
        out += &line(run, s);
    }
    print(&out)
}

fn fit_taus(campaign: &Campaign, rows: &[usize], sensors: &[String], n: usize, until: Option<f64>, json_out: bool) -> Result<(), Failure> {
    let t = campaign.column("t").map_err(failure)?;
    let mut series = Vec::new();
    let mut labels = Vec::new();
    let runs: Vec<String> = campaign.run_names().into_iter().filter(|r| rows.iter().any(|&i| &campaign.runs[i] == r)).collect();
    for run in &runs {
        let run_rows: Vec<usize> = rows.iter().copied().filter(|&i| &campaign.runs[i] == run).collect();
        let t0 = run_rows.iter().map(|&i| t[i]).fold(f64::INFINITY, f64::min);
        let run_rows: Vec<usize> = run_rows.into_iter().filter(|&i| until.is_none_or(|u| t[i] - t0 <= u)).collect();
        for s in sensors {
            let v = campaign.column(s).map_err(failure)?;
            series
                .push(Series { times_s: run_rows.iter().map(|&i| t[i] - t0).collect(), values: run_rows.iter().map(|&i| v[i]).collect() });
            labels.push((run.clone(), s.clone()));
        }
    }
    let fit = fit_time_constants(&series, n, true).map_err(failure)?;
    if json_out {
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

/// Measured (when the column exists) and predicted error at `rows`.
fn evaluate(campaign: &Campaign, model: &RegressionModel, rows: &[usize]) -> Result<(Option<Vec<f64>>, Vec<f64>), ThermalError> {
    let temps = campaign.select(&model.sensors, rows)?;
    let positions = match &model.position {
        Some(p) => Some(campaign.select(std::slice::from_ref(p), rows)?.remove(0)),
        None => None,
    };
    let mut t = vec![0.0; model.sensors.len()];
    let predicted = (0..rows.len())
        .map(|i| {
            t.iter_mut().zip(&temps).for_each(|(x, col)| *x = col[i]);
            model.evaluate(positions.as_ref().map_or(0.0, |p| p[i]), &t)
        })
        .collect();
    let measured = if campaign.names.contains(&model.error) {
        Some(campaign.select(std::slice::from_ref(&model.error), rows)?.remove(0))
    } else {
        None
    };
    Ok((measured, predicted))
}

fn predict(args: PredictArgs) -> Result<(), Failure> {
    let text =
        std::fs::read_to_string(&args.model).map_err(|e| Failure::input(anyhow::anyhow!("{}: cannot read: {e}", args.model.display())))?;
    let model = RegressionModel::from_toml_str(&text, &args.model.display().to_string()).map_err(failure)?;
    let campaign = Campaign::read(&args.data).map_err(failure)?;
    let rows: Vec<usize> = (0..campaign.len()).collect();
    let (measured, predicted) = evaluate(&campaign, &model, &rows).map_err(failure)?;
    let times = campaign.column("t").ok();
    let mut per_run = Vec::new();
    if let Some(m) = &measured {
        for run in campaign.run_names() {
            let idx: Vec<usize> = rows.iter().copied().filter(|&i| campaign.runs[i] == run).collect();
            let (a, b): (Vec<f64>, Vec<f64>) = idx.iter().map(|&i| (m[i], predicted[i])).unzip();
            per_run.push((run, residual_stats(&a, &b)));
        }
    }
    let text = if args.json {
        let samples: Vec<Value> = rows
            .iter()
            .map(|&i| {
                let mut s = json!({"run": campaign.runs[i], "predicted": predicted[i]});
                if let Some(t) = times {
                    s["t"] = json!(t[i]);
                }
                if let Some(m) = &measured {
                    s["measured"] = json!(m[i]);
                    s["residual"] = json!(m[i] - predicted[i]);
                }
                s
            })
            .collect();
        let stats: serde_json::Map<String, Value> = per_run.iter().map(|(r, s)| (r.clone(), json!(s))).collect();
        format!("{}\n", json!({"error": model.error, "unit": "um", "samples": samples, "residuals": stats}))
    } else {
        let mut out = format!(
            "run,t,{}_predicted{}\n",
            model.error,
            if measured.is_some() { format!(",{0},{0}_residual", model.error) } else { String::new() }
        );
        for &i in &rows {
            let t = times.map_or(String::new(), |t| t[i].to_string());
            out += &format!("{},{t},{:.4}", campaign.runs[i], predicted[i]);
            if let Some(m) = &measured {
                out += &format!(",{},{:.4}", m[i], m[i] - predicted[i]);
            }
            out.push('\n');
        }
        for (run, s) in &per_run {
            if let Some(s) = s {
                out += &format!(
                    "# {run}: residual RMS {:.3} max {:.3} range {:.3} band [{:.3}, {:.3}] um\n",
                    s.rms, s.max_abs, s.range, s.min, s.max
                );
            }
        }
        out
    };
    match &args.out {
        Some(p) => write_atomically(p, text.as_bytes()).map_err(Failure::input),
        None => print(&text),
    }
}
