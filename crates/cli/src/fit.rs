//! `trueaxis fit`: parses the options, runs the direct fit of the library
//! (`trueaxis::identify::direct_job`), writes the error-values file and the plots, prints.

use crate::fit_options::FitOptions;
use crate::{output, Failure};
use std::path::PathBuf;
use trueaxis::data::OutputSet;
use trueaxis::error_model::Direction;
use trueaxis::identify::direct_job::direction_symbol;
use trueaxis::identify::{run_direct_job, DirectFitReport, DirectFitRun, ResidualPeriod};
use trueaxis::machine::ParameterId;

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
    #[command(flatten)]
    pub options: FitOptions,
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

pub fn run(args: FitArgs) -> Result<(), Failure> {
    let errors_out = args.errors_out.as_ref().map(|p| p.to_path_buf());
    let run = run_direct_job(&args.options.job(errors_out)).map_err(Failure::of)?;
    output::warn(&run.warnings);
    for note in &run.applied.notes {
        eprintln!("trueaxis: {note}");
    }
    let written = write_outputs(&args, &run)?;
    if args.json {
        return output::json(&run.to_json());
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
fn write_outputs(args: &FitArgs, run: &DirectFitRun) -> Result<Vec<PathBuf>, Failure> {
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
        outputs.file(path, run.error_values_text(path).map_err(Failure::of)?);
        written.insert(0, path.to_path_buf());
    }
    outputs.commit().map_err(Failure::input)?;
    Ok(written)
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
