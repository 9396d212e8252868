//! `trueaxis iso230-2`.

use crate::output::{data_quality_text, json, print, warn};
use crate::Failure;
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::evaluate::iso230_2::Iso2302Result;
use trueaxis::evaluate::positioning_test::evaluate_file;

/// Accuracy and repeatability of positioning of an axis after ISO 230-2:2014 (A, R, E, M, B and
/// their unidirectional values, coverage factor 2) from bidirectional runs, e.g. laser readings.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  trueaxis iso230-2 examples/data/iso230_2_x.csv --plot x_positioning.svg\n  \
trueaxis iso230-2 examples/data/laser_x.rtl --json\n\n\
The CSV has the columns target (mm), dev (um, actual minus target), dir (+ or -) and run (integer);\n\
other columns are ignored, `#` starts a comment line. Read forgivingly: `;` or tab separators, decimal\n\
commas, units in the headers (`dev [mm]`), one column per run and direction (`Run 1 +`), a Renishaw\n\
.rtl file. Every target needs at least 2 runs in each direction (ISO 230-2 tests use 5). Results are in\n\
um (urad for a rotary axis, targets in deg). With --scale-temperature and --scale-expansion the\n\
deviations are first corrected to 20 degC (e.g. --scale-temperature 23.4 --scale-expansion 11.5); a\n\
file that records the material temperature and expansion coefficient is corrected with those.")]
pub struct Iso2302Args {
    /// Readings: a table with the columns target, dev, dir, run (or one column per run and
    /// direction), or a Renishaw .rtl laser file.
    file: PathBuf,
    /// Print one JSON document instead of the table.
    #[arg(long)]
    json: bool,
    /// Write an SVG plot of the readings, the mean deviations and the 2s bands (atomically).
    #[arg(long, value_parser = crate::output::file)]
    plot: Option<crate::output::OutputPath>,
    #[command(flatten)]
    temperature: crate::temperature::TemperatureArgs,
}

pub fn run(args: Iso2302Args) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let test = evaluate_file(&args.file, &args.temperature.options()).map_err(Failure::of)?;
    warn(&test.warnings);
    for note in &test.notes {
        eprintln!("trueaxis: {note}");
    }
    if let Some(path) = &args.plot {
        let svg = trueaxis_report::iso230_2_svg(&test.result, &test.data, &format!("ISO 230-2 positioning test: {name}"))
            .map_err(Failure::computation)?;
        write_atomically(path, svg.as_bytes()).map_err(Failure::input)?;
    }
    if args.json {
        return json(&test.to_json());
    }
    let mut text = table_text(&name, &test.result, &test.data.metadata);
    text += &data_quality_text(&test.findings);
    if let Some(path) = &args.plot {
        text += &format!("\nwrote {}\n", path.display());
    }
    print(&text)
}

/// The readable report: the file's metadata, per-position values and the axis results, with units.
fn table_text(name: &str, result: &Iso2302Result, metadata: &trueaxis::io::Metadata) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let uniform = result.positions.iter().all(|p| p.n_plus == result.runs && p.n_minus == result.runs);
    let runs = if uniform { format!("{} runs", result.runs) } else { format!("at least {} runs", result.runs) };
    let (first, last) = (result.positions.first().map_or(0.0, |p| p.target), result.positions.last().map_or(0.0, |p| p.target));
    let _ = writeln!(out, "ISO 230-2:2014 accuracy and repeatability of positioning: {name}");
    for line in metadata.lines() {
        let _ = writeln!(out, "  {line}");
    }
    let (u, pu) = (result.unit, result.position_unit);
    let _ = writeln!(
        out,
        "{} target positions from {first:.3} to {last:.3} {pu}, {runs} in each direction, coverage factor 2",
        result.positions.len()
    );
    let _ = writeln!(out, "positional deviations: actual minus target, in {u}\n");
    let _ = writeln!(
        out,
        "{:>12} {:>5} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8}",
        format!("target ({pu})"),
        "runs",
        "mean+",
        "mean-",
        "mean",
        "s+",
        "s-",
        "B_i",
        "R_i+",
        "R_i-",
        "R_i"
    );
    for p in &result.positions {
        let runs = if p.n_plus == p.n_minus { p.n_plus.to_string() } else { format!("{}/{}", p.n_plus, p.n_minus) };
        let _ = writeln!(
            out,
            "{:>12.3} {:>5} {:>9.3} {:>9.3} {:>9.3} {:>8.3} {:>8.3} {:>8.3} {:>8.3} {:>8.3} {:>8.3}",
            p.target, runs, p.mean_plus, p.mean_minus, p.mean, p.s_plus, p.s_minus, p.reversal, p.r_plus, p.r_minus, p.r
        );
    }
    let _ = writeln!(out, "\naxis results:");
    for (symbol, description, value) in result.axis_table() {
        let _ = writeln!(out, "  {symbol:<7} {value:>9.3} {u}   {description}");
    }
    if result.runs < 5 {
        let _ = writeln!(out, "\nnote: the ISO 230-2 test cycle approaches each target 5 times in each direction; here {} were used", runs);
    }
    out
}
