//! `trueaxis verify`: a re-measurement after compensation against the model's prediction, with the
//! residuals tested against the repeatability (`trueaxis::evaluate::verification`).

use crate::output::{self, print};
use crate::Failure;
use std::fmt::Write;
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::error_model::ErrorModel;
use trueaxis::evaluate::verification::{verify, Verification, VerificationOptions};
use trueaxis::identify::{identify, Campaign, IndirectOptions};
use trueaxis::machine::Machine;

/// Compares a re-measurement (a campaign file: probed hole plates, 3D ball, lengths) with what the
/// compensation with the error model should leave, fits the campaign's unknowns to the residuals
/// (a plate's misalignment, a suspected remaining error), and tests the residuals against the
/// repeatability of the readings (their sigma_um) and, with --calibration, the model's uncertainty.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
trueaxis verify --machine examples/machines/vmc3.toml --errors examples/verification/vmc3/model.toml \\\n      \
--campaign examples/verification/vmc3/plate_yz.toml --compensated --ignore-channel plate_yz:dx\n  \
trueaxis verify --machine examples/machines/vmc3.toml --errors examples/verification/vmc3/model.toml \\\n      \
--campaign examples/verification/vmc3/plate_yz.toml --compensated --ignore-channel plate_yz:dx --repeatability-dof 32 --json\n\n\
sigma_um of each measurement is the repeatability of its readings (one standard deviation; a\n\
repeatability quoted as 2S is twice that). The residual test: chi-square (repeatability taken as exact) or, with\n\
--repeatability-dof, F; the verdict is printed, the exit status is 0 whatever it is. See docs/verification.md.")]
pub struct VerifyArgs {
    /// Machine description (TOML).
    #[arg(long)]
    machine: PathBuf,
    /// The error values the compensation used (TOML).
    #[arg(long)]
    errors: PathBuf,
    /// The re-measurement (campaign TOML with its data files); its parameters are fitted to the
    /// residuals (e.g. plate = true for a hole plate's misalignment, EC0X for a suspected squareness).
    #[arg(long)]
    campaign: PathBuf,
    /// The readings were taken with the compensation active (expected: zero); without this flag
    /// they were taken without it and the model's prediction is subtracted (off-line compensation).
    #[arg(long)]
    compensated: bool,
    /// The campaign the error values were identified from: the model's uncertainty is added to the
    /// expected residuals (g^T Cov g).
    #[arg(long)]
    calibration: Option<PathBuf>,
    /// Degrees of freedom of the repeatability (e.g. 5 repeats of 8 holes: 32); F test instead of chi-square.
    #[arg(long)]
    repeatability_dof: Option<usize>,
    /// Confidence level of the tests.
    #[arg(long, default_value_t = 0.95)]
    level: f64,
    /// Leave out a channel `measurement:column` (e.g. the out-of-plane dz of a plate in XY); repeatable.
    #[arg(long = "ignore-channel")]
    ignored_channels: Vec<String>,
    /// Write the residual of every reading (CSV: measurement, line, channel, residual_um).
    #[arg(long, value_parser = crate::output::file)]
    residuals: Option<crate::output::OutputPath>,
    /// Print one JSON document.
    #[arg(long)]
    json: bool,
}

pub fn run(args: VerifyArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let errors = ErrorModel::load(&args.errors, &machine).map_err(Failure::input)?;
    let campaign = Campaign::load_measurements(&args.campaign, &machine).map_err(Failure::of)?;
    let calibration = match &args.calibration {
        Some(path) => {
            let cal = Campaign::load(path, &machine).map_err(Failure::of)?;
            let nominal = cal.nominal_errors(&machine).map_err(Failure::of)?;
            let id = identify(&cal, &machine, &nominal, &IndirectOptions::default()).map_err(Failure::of)?;
            Some((cal, id))
        }
        None => None,
    };
    let options = VerificationOptions {
        compensated: args.compensated,
        repeatability_dof: args.repeatability_dof,
        level: args.level,
        ignored_channels: args.ignored_channels.clone(),
    };
    let result = verify(&campaign, &machine, &errors, calibration.as_ref().map(|(c, i)| (c, i)), &options).map_err(Failure::of)?;
    if result.residuals.iter().chain([&result.chi2]).any(|v| !v.is_finite()) {
        return Err(Failure::computation(anyhow::anyhow!("the verification produced numbers that are not finite")));
    }
    if let Some(path) = &args.residuals {
        write_atomically(path, residuals_csv(&campaign, &result).as_bytes()).map_err(Failure::input)?;
    }
    if args.json {
        let mut doc = serde_json::to_value(&result).map_err(Failure::computation)?;
        doc["unit"] = serde_json::json!("um");
        doc["residuals"] = serde_json::json!(null);
        return output::json(&doc);
    }
    print(&text(&args, &result))
}

fn residuals_csv(campaign: &Campaign, result: &Verification) -> String {
    let mut text = String::from("measurement,line,channel,residual_um\n");
    let mut row = 0;
    for m in &campaign.measurements {
        for r in 0..m.records() {
            for c in m.instrument.channels() {
                let _ = writeln!(text, "{},{},{},{:.4}", m.name, m.lines[r], c, result.residuals[row]);
                row += 1;
            }
        }
    }
    text
}

fn text(args: &VerifyArgs, r: &Verification) -> String {
    let mut s = format!(
        "verification of {} against {} ({} readings, {})\n",
        args.campaign.display(),
        args.errors.display(),
        r.readings,
        if r.compensated {
            "measured with the compensation active: expected readings 0"
        } else {
            "measured without compensation: the model's prediction subtracted"
        }
    );
    let _ = writeln!(
        s,
        "{:<22} {:>4} {:>21} {:>21} {:>21} {:>16}",
        "channel (um)", "n", "model before rms/max", "measured rms/max", "residual rms/max", "expected rms"
    );
    for c in &r.channels {
        let _ = writeln!(
            s,
            "{:<22} {:>4} {:>10.3} {:>10.3} {:>10.3} {:>10.3} {:>10.3} {:>10.3} {:>16.3}",
            c.name,
            c.count,
            c.predicted_rms,
            c.predicted_max,
            c.measured_rms,
            c.measured_max,
            c.residual_rms,
            c.residual_max,
            c.expected_rms
        );
    }
    let _ = writeln!(
        s,
        "  (expected: the repeatability sigma_um{} of each reading)",
        if r.with_model_uncertainty { " and the model's prediction uncertainty" } else { "" }
    );
    if !r.fitted.is_empty() {
        s += "fitted to the residuals:\n";
        for f in &r.fitted {
            let _ = writeln!(
                s,
                "  {:<20} {:>12.4} +- {:<9.4} {:<6} {}",
                f.name,
                f.value,
                f.std_uncertainty,
                f.unit,
                match (f.significant, f.model) {
                    (true, true) => "significant: the model misses it",
                    (true, false) => "significant (setup)",
                    (false, _) => "",
                }
            );
        }
    }
    if !r.unseen.is_empty() {
        let _ = writeln!(s, "  not seen by the readings kept, left out: {}", r.unseen.join(" "));
    }
    let (name, how) = match r.test {
        "F" => (
            "F",
            format!(
                "F = chi2/dof = {:.3}, critical F({}, {}) at {} %",
                r.statistic,
                r.dof,
                args.repeatability_dof.unwrap_or(0),
                r.level * 100.0
            ),
        ),
        _ => ("chi-square", format!("chi2 = {:.2} on {} dof, critical {:.2} at {} %", r.statistic, r.dof, r.critical, r.level * 100.0)),
    };
    let _ = writeln!(
        s,
        "residual test ({name}): {how}{}; s0 = {:.3}, p = {:.3e}",
        if r.test == "F" { format!(" = {:.3}", r.critical) } else { String::new() },
        r.s0,
        r.p_value
    );
    let _ = writeln!(
        s,
        "{}",
        if r.consistent {
            "CONSISTENT: the residuals are within what the repeatability explains"
        } else {
            "NOT CONSISTENT: the residuals exceed the repeatability; the model misses an error (see the fitted unknowns and --residuals)"
        }
    );
    s
}
