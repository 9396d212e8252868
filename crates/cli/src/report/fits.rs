//! The `[[fit]]` tables of report.toml (`calibration::fit_arguments`) parsed by the definition of
//! the options of `trueaxis fit` (`fit_options`) and fitted by the library's direct fit
//! (`trueaxis::identify::direct_job`), so that the report has the numbers of `trueaxis fit --json`.

use crate::fit_options::FitOptions;
use crate::Failure;
use std::path::Path;
use trueaxis::identify::direct_job::direction_symbol;
use trueaxis::identify::run_direct_job;
use trueaxis::ErrorKind;
use trueaxis_report::calibration::{fit_arguments, CertificateFile, FitPart};

#[derive(clap::Parser)]
#[command(name = "fit")]
struct FitCommand {
    #[command(flatten)]
    options: FitOptions,
}

/// The fitted error motions of every `[[fit]]` table of the report.toml at `origin`.
pub fn fit_parts(certificate: &CertificateFile, machine: &Path, origin: &Path) -> Result<Vec<FitPart>, Failure> {
    let folder = origin.parent().unwrap_or(Path::new(""));
    let mut parts = Vec::new();
    for (k, table) in certificate.fits.iter().enumerate() {
        let place = format!("{}: [[fit]] {}", origin.display(), k + 1);
        let options = fit_arguments(table, folder).map_err(|e| Failure::of(e.context(&place)))?;
        let argv = ["fit".to_string(), "--machine".into(), machine.display().to_string()].into_iter().chain(options);
        let args = <FitCommand as clap::Parser>::try_parse_from(argv).map_err(|e| {
            let first = e.to_string().lines().next().unwrap_or_default().trim_start_matches("error: ").to_string();
            Failure::input(anyhow::anyhow!("{place}: {first}"))
        })?;
        let run = run_direct_job(&args.options.job(None)).map_err(|e| match e.kind() {
            ErrorKind::Input => Failure::input(anyhow::anyhow!("{place}: {e}")),
            ErrorKind::Computation => Failure::computation(anyhow::anyhow!("{place}: {e}")),
            ErrorKind::Environment => Failure::of(e),
        })?;
        let unit = run.position_unit();
        let notes: Vec<String> = run.warnings.iter().chain(&run.applied.notes).cloned().collect();
        for (direction, report) in run.reports {
            let part = FitPart::new(args.options.data.clone(), direction.map(direction_symbol), unit, report, notes.clone());
            parts.push(part.map_err(|e| Failure::computation(anyhow::anyhow!("{place}: {e}")))?);
        }
    }
    Ok(parts)
}
