//! `trueaxis identify`: parameters from indirect measurements (3D ball, lengths, probing).

use crate::Failure;
use std::path::PathBuf;
use trueaxis::data::OutputSet;
use trueaxis::identify::campaign_screening::{identify_screened, ScreenedIdentification};
use trueaxis::identify::robust_campaign::identify_robust;
use trueaxis::identify::{error_values_text, identification_json, Campaign, Identification, IdentifyError, IndirectOptions, Solver};
use trueaxis::machine::Machine;
use trueaxis::screen::irls::Weighting;

#[derive(Clone, Copy, clap::ValueEnum)]
enum SolverArg {
    Qr,
    Svd,
}

/// Identify error parameters from a measurement campaign (3D ball, ballbar / laser lengths, probed
/// points): weighted least squares, identifiability report, uncertainties, residuals per channel.
#[derive(clap::Args)]
#[command(after_help = "Example (Andolfatto et al. (2011): the 14 KX8-Five parameters from 807 CapBall poses):\n  \
trueaxis identify --machine examples/machines/kx8five.toml \\\n      \
--campaign examples/campaigns/kx8five/campaign.toml --out identified.toml\n\n\
Values are in um (translations), urad (rotations) or um per mm^k (polynomial powers, basis\n\
coefficients NAME#l of a campaign [basis.NAME], printed with the function they multiply). A parameter\n\
set the measurements cannot separate is an error (exit 1) naming the inseparable combination,\n\
unless --allow-rank-deficient is given. --out writes an error-values file that predict accepts.")]
pub struct IdentifyArgs {
    /// Machine description (TOML).
    #[arg(long)]
    machine: PathBuf,
    /// Measurement campaign (TOML, docs/design.md, Files).
    #[arg(long)]
    campaign: PathBuf,
    /// Print one JSON document.
    #[arg(long)]
    json: bool,
    /// Solve a rank-deficient set anyway (minimum-norm SVD solution; the unidentifiable
    /// combinations get no uncertainty).
    #[arg(long)]
    allow_rank_deficient: bool,
    /// Linear solver.
    #[arg(long, value_enum, default_value = "qr")]
    solver: SolverArg,
    /// Refine by Levenberg-Marquardt on the exact kinematic chain.
    #[arg(long)]
    refine: bool,
    /// Write the identified values as an error-values TOML (the campaign's nominal errors with the
    /// identified parameters replaced), atomically.
    #[arg(long, value_parser = crate::outputs::file)]
    out: Option<crate::outputs::OutputPath>,
    /// Write the residuals per row (CSV: measurement, line, channel, residual_um), atomically.
    #[arg(long, value_parser = crate::outputs::file)]
    residuals: Option<crate::outputs::OutputPath>,
    /// Leave out the readings screening finds suspect (studentized residual over 5.5 or Cook's
    /// distance over 0.5, stuck sensors, repeated records; docs/screening.md) and report the
    /// result without them, next to the one with every reading. Default: flag them only.
    #[arg(long, conflicts_with = "robust")]
    exclude_outliers: bool,
    /// Robust fit (M-estimation by iteratively reweighted least squares, Huber 1981): each reading
    /// weighted by its residual in MAD-based standard deviations, Huber (k = 1.345) or Tukey
    /// bisquare (c = 4.685); the readings left with a weight under 0.1 are listed, the uncertainty
    /// is the M-estimator's covariance, and the least-squares values are printed beside it.
    #[arg(long, value_enum, conflicts_with = "refine")]
    robust: Option<RobustArg>,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum RobustArg {
    Huber,
    Tukey,
}

impl RobustArg {
    fn weighting(self) -> Weighting {
        match self {
            RobustArg::Huber => Weighting::Huber,
            RobustArg::Tukey => Weighting::Tukey,
        }
    }
}

pub fn failure(e: IdentifyError) -> Failure {
    match e {
        IdentifyError::Input(_) | IdentifyError::Data(_) => Failure::input(e),
        IdentifyError::RankDeficient { .. } => Failure::computation(e),
    }
}

pub fn run(args: IdentifyArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let bar = crate::progress::spinner(args.json);
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    bar.set_message(format!("reading {}", args.campaign.display()));
    let loaded = Campaign::load(&args.campaign, &machine).and_then(|c| c.nominal_errors(&machine).map(|n| (c, n)));
    let (campaign, nominal) = loaded.inspect_err(|_| bar.finish_and_clear()).map_err(failure)?;
    let options = IndirectOptions {
        solver: match args.solver {
            SolverArg::Qr => Solver::Qr,
            SolverArg::Svd => Solver::Svd,
        },
        allow_rank_deficient: args.allow_rank_deficient,
        refine: args.refine,
        ..IndirectOptions::default()
    };
    let records: usize = campaign.measurements.iter().map(|m| m.records()).sum();
    bar.set_message(format!("identifying {} unknowns from {records} records", campaign.unknowns.len()));
    let screened = match args.robust {
        Some(r) => identify_robust(&campaign, &machine, &nominal, &options, r.weighting()),
        None => identify_screened(&campaign, &machine, &nominal, &options, args.exclude_outliers),
    };
    bar.finish_and_clear();
    let screened = screened.map_err(failure)?;
    let (result, campaign) = (&screened.result, &screened.campaign);
    // values, standard uncertainties, residuals and their RMS: all finite before anything is written
    let uncertainties = result.std_uncertainty.iter().flatten();
    if result.values.iter().chain(&result.residuals).chain(uncertainties).chain([&result.residual_rms_um]).any(|v| !v.is_finite()) {
        return Err(Failure::computation(anyhow::anyhow!(
            "{}: the identification produced numbers that are not finite (values, uncertainties or residuals); nothing was written",
            args.campaign.display()
        )));
    }
    let mut outputs = OutputSet::new();
    if let Some(path) = &args.out {
        let nominal_text = match &campaign.nominal_errors {
            Some(p) => trueaxis::files::inputs::read_to_string(p).map_err(|e| Failure::input(anyhow::anyhow!("{}: {e}", p.display())))?,
            None => String::new(),
        };
        let text = error_values_text(result, campaign, &nominal, &nominal_text).map_err(failure)?;
        outputs.file(path, text);
    }
    if let Some(path) = &args.residuals {
        outputs.file(path, residuals_csv(campaign, result));
    }
    // both or neither: a residual path that cannot be written leaves no error file either
    outputs.commit().map_err(Failure::input)?;
    if args.json {
        let mut doc = identification_json(result, campaign);
        screened.add_to_json(&mut doc);
        return print(&format!("{doc}\n"));
    }
    let mut text = table(campaign, result, args.out.as_deref());
    text += &crate::iso230_2::data_quality_text(&screened.findings);
    if let Some(robust) = &screened.robust {
        text += &format!("\n{}", robust.text());
    }
    if let Some(other) = &screened.other {
        text += &comparison_text(result, other, &screened);
    }
    print(&text)
}

/// The parameters of both fits side by side: the result and the other one.
fn comparison_text(result: &Identification, other: &Identification, screened: &ScreenedIdentification) -> String {
    let records = screened.excluded_records;
    let ((this, that), mut s) = if let Some(robust) = &screened.robust {
        let name = robust.weights.weighting.name();
        ((name, "least squares"), format!("\nthe values above are of the robust fit ({name}); least squares beside them:\n"))
    } else if records > 0 {
        (
            ("without suspect", "every reading"),
            format!("\n--exclude-outliers: {records} suspect record(s) left out; the values above are without them\n"),
        )
    } else {
        (("every reading", "without suspect"), "\nsuspect readings are flagged only (--exclude-outliers leaves them out):\n".to_string())
    };
    s += &format!("  {:<16} {:>16} {:>16} {:>9}\n", "parameter", this, that, "change/u");
    for (j, name) in result.names.iter().enumerate() {
        let u = result.std_uncertainty[j].unwrap_or(f64::NAN);
        let change = (other.values[j] - result.values[j]) / u;
        let change = if change.is_finite() { format!("{change:+.1}") } else { "n/a".into() };
        s += &format!("  {name:<16} {:>16.4} {:>16.4} {change:>9}\n", result.values[j], other.values[j]);
    }
    s
}

fn residuals_csv(campaign: &Campaign, result: &Identification) -> String {
    let mut text = String::from("measurement,line,channel,residual_um\n");
    let mut row = 0;
    for m in &campaign.measurements {
        for r in 0..m.records() {
            for c in m.instrument.channels() {
                text += &format!("{},{},{},{:.4}\n", m.name, m.lines[r], c, result.residuals[row]);
                row += 1;
            }
        }
    }
    text
}

/// The readable report.
fn table(campaign: &Campaign, result: &Identification, out: Option<&std::path::Path>) -> String {
    use std::fmt::Write;
    let report = &result.identifiability;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Identification: {} ({} readings, {} unknowns, solver {})",
        campaign.origin,
        result.residuals.len(),
        result.names.len(),
        result.solver.name()
    );
    let _ = writeln!(s, "\n{:<16} {:>12} {:>10} {:<8} {:>11} {:>12}", "parameter", "value", "u (k=1)", "unit", "indep.", "sens. um/u");
    for (j, name) in result.names.iter().enumerate() {
        let (value, u) = value_and_uncertainty(result.values[j], result.std_uncertainty[j]);
        let function = campaign.unknowns[j].function.as_ref().map_or(String::new(), |f| format!("  {f}"));
        let _ = writeln!(
            s,
            "{:<16} {:>12} {:>10} {:<8} {:>11.3} {:>12}{function}",
            name,
            value,
            u,
            result.units[j],
            report.independence[j],
            significant(report.sensitivity[j])
        );
    }
    let _ = writeln!(
        s,
        "\nresidual RMS {:.4} um; s0 = {:.3} (1 when the residuals match the stated noise)",
        result.residual_rms_um, result.sigma0
    );
    for c in &result.channels {
        let _ = writeln!(
            s,
            "  {:<24} n {:>6}  mean {:>8.4}  rms {:>8.4}  max {:>8.4}  sigma {:.3} um",
            c.name,
            c.count,
            // a mean that rounds to zero is printed as 0.0000, whatever the sign of its rounding error
            if c.mean.abs() < 5e-5 { 0.0 } else { c.mean },
            c.rms,
            c.max_abs,
            c.sigma
        );
    }
    let k = report.condition_number.map_or("infinite".to_string(), |k| format!("{k:.4e}"));
    let _ = writeln!(
        s,
        "\nidentifiability: rank {} of {}, condition number {k} (rows / sigma, unit-length columns)",
        report.rank,
        result.names.len()
    );
    let sv: Vec<String> = report.singular_values.iter().map(|v| format!("{v:.3e}")).collect();
    let _ = writeln!(s, "singular values: {}", sv.join(" "));
    for c in &report.unidentifiable {
        let _ = writeln!(s, "NOT IDENTIFIABLE: {}", c.message);
    }
    for (i, j, r) in report.strong_correlations(0.9) {
        let _ = writeln!(s, "strongly correlated: {} and {} (r = {r:+.3})", result.names[i], result.names[j]);
    }
    if let Some(r) = &result.refinement {
        let _ = writeln!(
            s,
            "refined on the exact chain: {} iterations, weighted RMS {:.5} -> {:.5}, largest change {:.3} u",
            r.iterations, r.initial_weighted_rms, r.final_weighted_rms, r.largest_change_in_u
        );
    }
    if let Some(path) = out {
        let _ = writeln!(s, "\nwrote {}", path.display());
    }
    s
}

/// A value and its standard uncertainty with the same decimals: 4, or more so that the uncertainty
/// shows two significant digits (up to 8); in scientific notation when both are below 1e-4 (powers
/// and basis coefficients of high order, um/mm^k).
fn value_and_uncertainty(value: f64, u: Option<f64>) -> (String, String) {
    let size = value.abs().max(u.unwrap_or(0.0));
    if size > 0.0 && size < 1e-4 {
        return (format!("{value:.4e}"), u.map_or("n/a".into(), |u| format!("{u:.3e}")));
    }
    let decimals = u.filter(|u| *u > 0.0).map_or(4, |u| (1 - u.log10().floor() as i32).clamp(4, 8) as usize);
    (format!("{value:.decimals$}"), u.map_or("n/a".into(), |u| format!("{u:.decimals$}")))
}

/// Four decimals between 0.01 and 1e6, else scientific.
fn significant(v: f64) -> String {
    if v == 0.0 || (0.01..1e6).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.4e}")
    }
}

/// Writes to stdout; a closed pipe (`| head`) is not an error.
pub fn print(text: &str) -> Result<(), Failure> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Failure::computation(anyhow::anyhow!("cannot write to stdout: {e}"))),
        _ => Ok(()),
    }
}
