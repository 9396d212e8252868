//! The `[[fit]]` tables of report.toml (`calibration::fit_arguments`) parsed by the definition of
//! `trueaxis fit` and fitted by its code, so that the report has the numbers of `trueaxis fit --json`.

use crate::fit::{compute, FitArgs};
use crate::Failure;
use std::path::Path;
use trueaxis_report::calibration::{fit_arguments, CertificateFile, FitPart};

#[derive(clap::Parser)]
#[command(name = "fit")]
struct FitCommand {
    #[command(flatten)]
    args: FitArgs,
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
        let run = compute(&args.args).map_err(|f| match f {
            Failure::Input(e) => Failure::input(anyhow::anyhow!("{place}: {e}")),
            Failure::Computation(e) => Failure::computation(anyhow::anyhow!("{place}: {e}")),
            other => other,
        })?;
        let unit = run.position_unit();
        let notes: Vec<String> = run.warnings.iter().chain(&run.applied.notes).cloned().collect();
        for (direction, report) in run.reports {
            let symbol = direction.map(|d| if d == trueaxis::error_model::Direction::Positive { '+' } else { '-' });
            let part = FitPart::new(args.args.data.clone(), symbol, unit, report, notes.clone());
            parts.push(part.map_err(|e| Failure::computation(anyhow::anyhow!("{place}: {e}")))?);
        }
    }
    Ok(parts)
}
