//! `trueaxis thermal fit`: PITE/PDTE regression models validated on other runs, and the shared
//! time constants of eq. 3.17 (fitted by `trueaxis::thermal::campaign_fit`).

use super::{plot_text, write_plot};
use crate::output::{self, print};
use crate::Failure;
use std::path::PathBuf;
use trueaxis::data::OutputSet;
use trueaxis::machine::Machine;
use trueaxis::screen::irls::Weighting;
use trueaxis::screen::{findings_json, Finding};
use trueaxis::thermal::campaign_fit::{fit_campaign, CampaignFit, FitRequest, ModelForm as FitForm, RobustSummary, TimeConstantsFit};
use trueaxis::thermal::error_model::ThermalErrorModel;
use trueaxis::thermal::regression::RegressionModel;
use trueaxis::thermal::thermal_screening::read_screened;
use trueaxis::thermal::validation::ResidualStats;
use trueaxis_report::{drift_plot, drift_svg, step_fit_plot};

/// Fits a thermal error model to a campaign CSV (columns t, run, T:<sensor>, the error in um):
/// PITE/PDTE regression (Zhu (2008), with intercepts) or the
/// state-space drift model (Soons (1993)), validated on the runs not trained on or on the later
/// part of each training run; or, with --time-constants N, the fit of shared time
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
    /// Model form: regression (static, Zhu (2008)) or state-space (Soons (1993):
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
    /// Fit N shared time constants (a sum of exponential step responses) to the temperature columns instead.
    #[arg(long)]
    time_constants: Option<usize>,
    /// With --time-constants: use only the first SECONDS of each run (the step response; the fit
    /// describes a warm-up from a step, not the cool-down after it).
    #[arg(long)]
    until: Option<f64>,
    /// Sensor columns, comma separated (default: every T:<sensor> column).
    #[arg(long, value_delimiter = ',')]
    sensors: Option<Vec<String>>,
    /// Sensor selection: `correlation:N` (the N best correlated, NISTIR 5236) or `stepwise`.
    #[arg(long)]
    select: Option<String>,
    /// Axis column whose position enters the model (PDTE).
    #[arg(long)]
    position: Option<String>,
    /// Highest power of the position (PDTE).
    #[arg(long, default_value_t = 0)]
    degree: usize,
    /// Drop the intercept terms (as Zhu (2008) prints the model).
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
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// ISO 230 parameter the error is (e.g. EZZ, TZ) for --terms-out.
    #[arg(long)]
    parameter: Option<String>,
    /// Write the model as [[term.NAME]] error terms (T - 20 degC) for `trueaxis predict`.
    #[arg(long, requires = "parameter", value_parser = crate::output::file)]
    terms_out: Option<crate::output::OutputPath>,
    /// Machine (TOML) to check --parameter against.
    #[arg(long)]
    machine: Option<PathBuf>,
    /// Write a figure (SVG): per run the measured values against the model over time and the
    /// residual band, training and validation runs told apart (with --time-constants: each
    /// temperature record and its fit of shared time constants).
    #[arg(long, value_name = "FILE.svg", value_parser = crate::output::file)]
    plot: Option<crate::output::OutputPath>,
    /// Print one JSON document.
    #[arg(long)]
    json: bool,
    /// Leave out the rows with a blank cell (a logger dropout) and list them; without it a blank
    /// cell refuses the file.
    #[arg(long)]
    skip_missing: bool,
    /// Cut each run at its gaps in `t` (over 5 times the median sampling interval): the segment
    /// after a gap is fitted as a run of its own, a state-space model starts again there.
    #[arg(long)]
    split_gaps: bool,
    /// Fit the regression model by M-estimation (robust regression, Huber 1981), Huber weights
    /// (k = 1.345, the default) or Tukey bisquare (c = 4.685) of the residuals in MAD-based
    /// sigmas: gross errors in the error column pull the model by their clipped size only (Huber)
    /// or not at all (Tukey); the samples left with a weight under 0.1 are listed and each
    /// coefficient gets its uncertainty from the M-estimator covariance (docs/screening.md).
    #[arg(long, value_name = "WEIGHTS", num_args = 0..=1, default_missing_value = "huber", value_parser = ["huber", "tukey"])]
    robust: Option<String>,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum ModelForm {
    Regression,
    StateSpace,
}

pub fn fit(args: FitArgs) -> Result<(), Failure> {
    let (campaign, findings) = read_screened(&args.data, args.skip_missing, args.split_gaps).map_err(Failure::of)?;
    let request = FitRequest {
        error: args.error.clone(),
        model: match args.model {
            ModelForm::Regression => FitForm::Regression,
            ModelForm::StateSpace => FitForm::StateSpace,
        },
        rates: args.rates,
        validate: args.validate.clone(),
        time_constants: args.time_constants,
        until: args.until,
        sensors: args.sensors.clone(),
        select: args.select.clone(),
        position: args.position.clone(),
        degree: args.degree,
        no_intercept: args.no_intercept,
        geometric_degree: args.geometric_degree,
        by_direction: args.by_direction,
        ranges: args.ranges.clone(),
        train_runs: args.train_runs.clone(),
        robust: args.robust.as_deref().and_then(Weighting::parse),
        terms: args.terms_out.is_some(),
    };
    let fitted = match fit_campaign(&campaign, &args.data.display().to_string(), &request).map_err(Failure::of)? {
        CampaignFit::Model(m) => m,
        CampaignFit::TimeConstants(t) => return print_taus(&args, &t, &findings),
    };
    let (error, model, rows) = (&fitted.error, &fitted.model, fitted.rows);
    // model, terms and plot together, or none of them (docs/reliability.md)
    let mut outputs = OutputSet::new();
    if let Some(path) = &args.out {
        outputs.file(path, model.to_toml());
    }
    if let (Some(path), Some(parameter)) = (&args.terms_out, &args.parameter) {
        let machine = args.machine.as_ref().map(Machine::load).transpose().map_err(Failure::input)?;
        if let Some(text) = fitted.terms_text(parameter, machine.as_ref()).map_err(Failure::of)? {
            outputs.file(path, text);
        }
    }
    if let Some(path) = &args.plot {
        outputs.file(path, plot_text(path, drift_svg(&drift_plot(error, &fitted.evaluated)))?);
    }
    outputs.commit().map_err(Failure::input)?;
    if args.json {
        let mut doc = fitted.to_json();
        doc["data_quality"] = findings_json(&findings);
        return output::json(&doc);
    }
    let mut out = format!("thermal error model of `{error}` (um) from {rows} rows of {}\n", args.data.display());
    match model {
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
            out += &format!("  state space (Soons (1993)), time constants {} min; gains (um/degC) per time constant:\n", taus.join(", "));
            for (s, g) in m.sensors.iter().zip(&m.gains_um_per_degc) {
                out += &format!("  {s:<10} {}\n", g.iter().map(|v| format!("{v:+.5}")).collect::<Vec<_>>().join(" "));
            }
        }
    }
    if let Some(r) = &fitted.robust {
        out += &robust_text(r);
    }
    out += "residuals (measured - predicted):\n";
    out += &stats_line("training", &fitted.training);
    for (run, s) in &fitted.validation {
        out += &stats_line(run, s);
    }
    out += &crate::output::data_quality_text(&findings);
    print(&out)
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

/// The robust fit's method, coefficients with their uncertainties and the samples it left out in
/// effect.
fn robust_text(r: &RobustSummary) -> String {
    let w = &r.weights;
    let mut out = format!(
        "robust fit: {}, {} iterations{}, scale s = {:.3} um; coefficients with u (k=1) from the M-estimator covariance (Huber 1981 7.6):\n",
        w.weighting.describe(),
        w.iterations,
        if w.converged { "" } else { " (not converged)" },
        w.scale
    );
    for (n, (c, u)) in r.names.iter().zip(r.coefficients.iter().zip(&r.uncertainties)) {
        out += &format!("  {n:<16} {c:+.5} +- {u:.5}\n");
    }
    out += &format!("  {} sample(s) with weight under 0.1 (as good as left out)", r.downweighted.len());
    out += if r.downweighted.is_empty() { "\n" } else { ":\n" };
    for (run, line, e, weight) in r.downweighted.iter().take(40) {
        out += &format!("    line {line} (run {run}): residual {e:+.3} um, weight {weight:.3}\n");
    }
    if r.downweighted.len() > 40 {
        out += &format!("    ... and {} more (all in --json)\n", r.downweighted.len() - 40);
    }
    if let Some(note) = r.systematic_note() {
        out += &format!("  note: {note}\n");
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

fn print_taus(args: &FitArgs, taus: &TimeConstantsFit, findings: &[Finding]) -> Result<(), Failure> {
    let (labels, series, fit) = (&taus.labels, &taus.series, &taus.fit);
    if let Some(path) = &args.plot {
        let names: Vec<String> = labels.iter().map(|(r, s)| format!("{r} {s}")).collect();
        write_plot(path, drift_svg(&step_fit_plot(&names, series, fit)))?;
    }
    if args.json {
        let mut doc = taus.to_json();
        doc["data_quality"] = findings_json(findings);
        return output::json(&doc);
    }
    let mut out = format!(
        "shared time constants of {} records: {} min\nresidual RMS {:.4} degC\n",
        series.len(),
        fit.tau_s.iter().map(|t| format!("{:.2}", t / 60.0)).collect::<Vec<_>>().join(", "),
        fit.residual_rms
    );
    for ((r, s), (a, b)) in labels.iter().zip(fit.amplitudes.iter().zip(&fit.offsets)) {
        out += &format!("  {r:<10} {s:<10} T0 {b:.3}  A {:?}\n", a.iter().map(|v| (v * 1e4).round() / 1e4).collect::<Vec<_>>());
    }
    out += &crate::output::data_quality_text(findings);
    print(&out)
}
