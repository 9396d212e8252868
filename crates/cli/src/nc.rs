//! `trueaxis nc`.

use crate::compensate::{failure, parse_axis_values, parse_temperatures};
use crate::Failure;
use std::path::PathBuf;
use trueaxis::compensate::nc::{correct_program, NcOptions};
use trueaxis::compensate::{nc_json, Corrector};
use trueaxis::data::write_atomically;
use trueaxis::errors::ErrorModel;
use trueaxis::machine::Machine;

/// Corrects an RS274/NGC program (LinuxCNC dialect): every programmed point moves by the correction
/// that cancels the predicted error there (exact chain), moves along which the correction varies
/// more than the tolerance are split, and only the numbers that must change are rewritten.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis nc --machine examples/machines/vmc3.toml --errors examples/errors/vmc3.toml \\\n      examples/nc/pocket.ngc --limit-um 50 --out pocket_corrected.ngc\n\n\
Supported: G0 G1 G2 G3 (IJK or R), G17-G19, G20/G21, G90/G91, G53, G54-G59 (offsets from --offset),\n\
comments, line numbers, F S T M words. Refused with a message naming the line: parameters and\n\
expressions, O-word subroutines, cutter and tool-length compensation (G41/G42/G43), G10, G28, G92,\n\
canned cycles, G93. Machine position = program coordinate + work offset (mm, deg)."
)]
pub struct NcArgs {
    /// Machine description (TOML).
    #[arg(long)]
    machine: PathBuf,
    /// Error values (TOML).
    #[arg(long)]
    errors: PathBuf,
    /// The program to correct.
    program: PathBuf,
    /// Write the corrected program here (atomically) instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Split a move where the correction departs from a straight blend by more than this (um;
    /// rotary axes: urad).
    #[arg(long, default_value_t = 1.0)]
    tolerance_um: f64,
    /// Decimals of written numbers in mm and deg (inch: one more).
    #[arg(long, default_value_t = 4)]
    decimals: usize,
    /// A work offset, e.g. `G54=X100,Y50,Z-300` (machine position of the program zero, mm and deg;
    /// repeatable).
    #[arg(long = "offset")]
    offsets: Vec<String>,
    /// Machine position before the first move, e.g. `X0,Y0,Z0` (default all 0, like rs274).
    #[arg(long)]
    start: Option<String>,
    /// Temperature of a sensor of the error model, `T:name=degC` (repeatable).
    #[arg(long = "temperature")]
    temperatures: Vec<String>,
    /// Refuse the program (exit 2, nothing written) when a correction of a linear axis exceeds this (um).
    #[arg(long)]
    limit_um: Option<f64>,
    /// The same for a rotary axis (urad).
    #[arg(long)]
    limit_urad: Option<f64>,
    /// Print a JSON summary (with the program text when --out is not given).
    #[arg(long)]
    json: bool,
}

/// `X100,Y50` into `X=100,Y=50`.
fn letter_values(text: &str) -> String {
    text.split(',')
        .map(|p| {
            let p = p.trim();
            match p.char_indices().nth(1) {
                Some((i, _)) if !p.contains('=') => format!("{}={}", &p[..i], &p[i..]),
                _ => p.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join(",")
}

pub fn run(args: NcArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let errors = ErrorModel::load(&args.errors, &machine).map_err(Failure::input)?;
    let temperatures = parse_temperatures(&errors, &args.temperatures)?;
    let text = std::fs::read_to_string(&args.program)
        .map_err(|e| Failure::input(anyhow::anyhow!("{}: cannot read: {e}", args.program.display())))?;
    if !(args.tolerance_um.is_finite() && args.tolerance_um > 0.0) {
        return Err(Failure::input(anyhow::anyhow!("--tolerance-um must be a positive number")));
    }
    if args.decimals > 9 {
        return Err(Failure::input(anyhow::anyhow!("--decimals must be at most 9")));
    }
    let limits = crate::compensate::limits(args.limit_um, args.limit_urad)?;
    let mut options = NcOptions::new(&machine);
    options.limits = limits;
    options.tolerance_mm = args.tolerance_um * 1e-3;
    options.rotary_tolerance_deg = (args.tolerance_um * 1e-6).to_degrees();
    options.decimals = args.decimals;
    options.decimals_inch = args.decimals + 1;
    for o in &args.offsets {
        let (code, values) = o.split_once('=').ok_or_else(|| Failure::input(anyhow::anyhow!("--offset `{o}` is not G54=X..,Y..")))?;
        let index = match code.trim().to_ascii_uppercase().as_str() {
            "G54" => 0,
            "G55" => 1,
            "G56" => 2,
            "G57" => 3,
            "G58" => 4,
            "G59" => 5,
            other => return Err(Failure::input(anyhow::anyhow!("--offset: `{other}` is not one of G54 ... G59"))),
        };
        options.setup.work_offsets[index] = parse_axis_values(&machine, &letter_values(values), "--offset")?;
    }
    if let Some(s) = &args.start {
        options.setup.start = parse_axis_values(&machine, &letter_values(s), "--start")?;
        machine
            .check_range(&options.setup.start)
            .map_err(|m| Failure::input(anyhow::anyhow!("--start: the start point leaves the machine's travel: {m}")))?;
    }
    let corrector = Corrector::new(&machine, &errors);
    let origin = args.program.display().to_string();
    let result = correct_program(&corrector, &text, &origin, &options, &temperatures).map_err(failure)?;
    if let Some(path) = &args.out {
        write_atomically(path, result.text.as_bytes()).map_err(Failure::input)?;
    }
    let summary = format!(
        "{origin}: {} moves corrected, {} lines changed, {} lines added; largest correction {:.3} um, {:.3} urad; \
         residual <= {:.4} um; uncorrectable orientation <= {:.3} urad",
        result.moves,
        result.changed_lines,
        result.inserted_lines,
        result.max_correction_um,
        result.max_correction_urad,
        result.max_residual_um,
        result.max_uncorrectable_urad
    );
    if args.json {
        let doc = nc_json(&result, args.out.as_ref().map(|p| p.display().to_string()).as_deref());
        println!("{doc}");
    } else if args.out.is_some() {
        println!("{summary}");
    } else {
        print!("{}", result.text);
        eprintln!("{summary}");
    }
    Ok(())
}
