//! `trueaxis convert`: an instrument file into trueaxis's own files.

use crate::output::print;
use crate::Failure;
use anyhow::anyhow;
use std::path::PathBuf;
use trueaxis::data::{write_atomically, CsvTable};
use trueaxis::error_model::from_etalon;
use trueaxis::io::{etalon, read_text, Format};
use trueaxis::machine::Machine;

/// Convert an instrument file into trueaxis's canonical CSV (any table or a Renishaw .rtl laser
/// file: units converted to mm / deg and um / urad, `,` separated, metadata as `# Key: value`
/// comments), or an Etalon exchange file (LaserTRACER / TRAC-CAL results) into an error-values file
/// for a machine.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  trueaxis convert examples/data/laser_x.rtl --to csv --out laser_x_from_rtl.csv\n  \
trueaxis convert examples/data/vmc3_etalon.exc --to errors --machine examples/machines/vmc3.toml --out vmc3_etalon.toml\n\n\
--to csv writes the columns as the other commands read them (target in mm, dev in um, dir, run for a\n\
laser file); --to errors writes [constant] and [table.NAME] entries in um and urad (the Etalon file\n\
holds mm and rad), checked against the machine. Without --out the result goes to stdout.")]
pub struct ConvertArgs {
    /// The file to convert.
    file: PathBuf,
    /// What to write: csv (readings) or errors (an error-values TOML, from an Etalon file).
    #[arg(long, value_parser = ["csv", "errors"])]
    to: String,
    /// Machine description (TOML), for --to errors: the parameters are checked against it.
    #[arg(long)]
    machine: Option<PathBuf>,
    /// Write here (atomically) instead of stdout.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
}

pub fn run(args: ConvertArgs) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let text = read_text(&args.file).map_err(Failure::input)?;
    let format = trueaxis::io::detect(&text);
    let output = match (args.to.as_str(), format) {
        ("errors", Format::Etalon) => {
            let machine_path = args.machine.as_ref().ok_or_else(|| {
                Failure::input(anyhow!("--to errors needs --machine M.toml: the error parameters are checked against the machine"))
            })?;
            let machine = Machine::load(machine_path).map_err(Failure::of)?;
            let file = etalon::parse(&text, &name).map_err(Failure::of)?;
            let conversion = from_etalon(&file, &machine, &name).map_err(Failure::of)?;
            for w in &conversion.warnings {
                eprintln!("trueaxis: warning: {name}: {w}");
            }
            eprintln!("trueaxis: {name}: {} parameters converted: {}", conversion.written.len(), conversion.written.join(" "));
            conversion.toml
        }
        ("errors", other) => {
            return Err(Failure::input(anyhow!(
                "{name}: --to errors converts an Etalon exchange file (error parameters); this is a {}",
                other.name()
            )))
        }
        (_, Format::Etalon) => {
            return Err(Failure::input(anyhow!(
                "{name}: an Etalon exchange file holds error parameters, not readings: use --to errors --machine M.toml"
            )))
        }
        _ => {
            let table = CsvTable::from_text(&text, &name).map_err(Failure::input)?;
            crate::output::warn(table.warnings());
            table.to_canonical_csv().map_err(Failure::input)?
        }
    };
    match &args.out {
        Some(path) => {
            write_atomically(path, output.as_bytes()).map_err(Failure::input)?;
            eprintln!("trueaxis: wrote {}", path.display());
            Ok(())
        }
        None => print(&output),
    }
}
