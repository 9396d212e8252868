//! `trueaxis nc`.

use crate::inputs::temperatures;
use crate::parse::{axis_values, correction_limits};
use crate::Failure;
use std::path::{Path, PathBuf};
use trueaxis::compensate::nc::params::read_parameter_file;
use trueaxis::compensate::nc::{correct_file, Controller, FileId, Header, NcOptions, NcResult, SearchPath, ToolTable, UnknownTools};
use trueaxis::compensate::{nc_json, Corrector};
use trueaxis::data::write_streamed;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// Corrects an NC program, RS274/NGC (LinuxCNC 2.9) or Fanuc: every point the program moves to is
/// moved by the correction that cancels the predicted error there (exact chain); moves along which
/// the correction varies more than the tolerance are split; only the numbers that must change are
/// rewritten, and what the correction cannot stay inside (loops, subroutines called from several
/// places, canned cycles) is expanded into plain moves and noted at the top.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis nc --machine examples/machines/vmc3.toml --errors examples/errors/vmc3.toml \\\n      examples/nc/pocket.ngc --limit-um 50 --out pocket_corrected.ngc\n\n\
Runs the program as the controller does: parameters and expressions, O-word subroutines and\n\
loops (LinuxCNC), macro variables, IF/GOTO/WHILE and M98/M99/G65 (Fanuc, Haas, Mach3/Mach4),\n\
Haas M97, grbl $J= jogs, the SINUMERIK 840D's R parameters and DEF variables, CR=/AR= arcs,\n\
TRANS/ATRANS, GOTOF/GOTOB, IF, WHILE, FOR, LOOP, REPEAT, L subprograms and CYCLE81-CYCLE83\n\
(called directly or with MCALL), Fadal E fixture offsets, R0+ planes and # macro statements (V\n\
and R variables, IF/GOTO to labels), tool length offsets (G43 H or D from --tool-table), work\n\
offsets (G54-G59.3, Fadal E1-E48, from --parameters or --offset, G10 L2/L20), G92, G28/G30,\n\
G53, canned cycles G73 G81-G89 and CYCLE81-CYCLE83 (kept as cycles in G90), arcs in\n\
G17/G18/G19, G20/G21, G93/G94/G95.\n\
Refused with the line and the reason: probing (G38.x, G31), spindle-synchronised motion (G33,\n\
LinuxCNC G76), tapping in G91, cutter radius compensation (G41/G42). The corrected program\n\
starts with a header naming the machine and error files and their SHA-256; a program with that\n\
header is refused (it would be corrected twice) unless --force. See docs/nc.md."
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
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// The program's dialect: linuxcnc, fanuc, haas, mach3, mach4, grbl, fadal or siemens (default:
    /// detected from the program; docs/nc.md has each dialect's codes).
    #[arg(long)]
    dialect: Option<String>,
    /// Tool table in LinuxCNC's format (`T1 P1 Z50.5 D6 ;comment`), machine units; a Fanuc H
    /// number is looked up as a tool number.
    #[arg(long)]
    tool_table: Option<PathBuf>,
    /// The length offset (Z, machine units) of a tool the tool table lacks, or of every tool when
    /// no table is given: 0 (default) puts the tool tip at the machine file's tool point. The
    /// header then states how far a real tool's length from it moves the corrected points.
    #[arg(long)]
    tool_length: Option<f64>,
    /// Refuse a tool that is not in the tool table instead (the line named).
    #[arg(long)]
    strict_tools: bool,
    /// Write drilling and boring cycles (G73 G81-G83 G85 G86 G89, SINUMERIK CYCLE81-CYCLE83) as plain moves, each point
    /// corrected, instead of keeping them as cycles with the hole position, the bottom and R
    /// corrected at the hole (the default; see docs/nc.md). Tapping stays a cycle.
    #[arg(long)]
    expand_cycles: bool,
    /// LinuxCNC parameter file (`.var`: work offsets #5221..., G28/G30 positions #5161/#5181...),
    /// machine units.
    #[arg(long)]
    parameters: Option<PathBuf>,
    /// Units of the tool table and the parameter file: mm or inch.
    #[arg(long, default_value = "mm")]
    machine_units: String,
    /// A directory where subroutine files (`o<name> call` -> name.ngc, Fanuc O1234) are looked for
    /// (repeatable; default: the program's directory).
    #[arg(long = "search-path")]
    search_path: Vec<PathBuf>,
    /// Split a move where the correction departs from a straight blend by more than this (um;
    /// rotary axes: urad).
    #[arg(long, default_value_t = 1.0)]
    tolerance_um: f64,
    /// Decimals of written numbers in mm and deg (default: LinuxCNC 5, Fanuc 3, the IS-B
    /// increment; inch: one more).
    #[arg(long)]
    decimals: Option<usize>,
    /// A work offset, e.g. `G54=X100,Y50,Z-300` (machine position of the program zero, mm and deg;
    /// G54 ... G59.3, or a Fadal fixture offset E1 ... E48 (E1-E6 are G54-G59); repeatable;
    /// applied after --parameters).
    #[arg(long = "offset")]
    offsets: Vec<String>,
    /// Machine position before the first move, e.g. `X0,Y0,Z0` (default all 0, like rs274).
    #[arg(long)]
    start: Option<String>,
    /// Fanuc G73/G83: retraction and clearance of a peck (parameters 5114/5115 of the control), mm.
    #[arg(long, default_value_t = 0.254)]
    peck_clearance_mm: f64,
    /// Temperature of a sensor of the error model, `T:name=degC` (repeatable).
    #[arg(long = "temperature")]
    temperatures: Vec<String>,
    /// Refuse the program (exit 2, nothing written) when a correction of a linear axis exceeds this
    /// (um; default: the machine file's `[limits] correction_um`, else 1000).
    #[arg(long)]
    limit_um: Option<f64>,
    /// The same for a rotary axis (urad; default `[limits] correction_urad`, else 10000).
    #[arg(long)]
    limit_urad: Option<f64>,
    /// Print a JSON summary (with the program text when --out is not given).
    #[arg(long)]
    json: bool,
    /// Correct a program that says it was corrected already (its header names trueaxis): the
    /// correction is then applied twice.
    #[arg(long)]
    force: bool,
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

fn bad(message: String) -> Failure {
    Failure::input(anyhow::anyhow!(message))
}

fn read(path: &PathBuf) -> Result<String, Failure> {
    std::fs::read_to_string(path).map_err(|e| bad(format!("{}: cannot read: {e}", path.display())))
}

/// The options of the command line.
fn options(args: &NcArgs, machine: &Machine) -> Result<NcOptions, Failure> {
    let mut options = NcOptions::new(machine);
    options.limits = correction_limits(machine, args.limit_um, args.limit_urad)?;
    if !(args.tolerance_um.is_finite() && args.tolerance_um > 0.0) {
        return Err(bad("--tolerance-um must be a positive number".into()));
    }
    options.tolerance_mm = args.tolerance_um * 1e-3;
    options.rotary_tolerance_deg = (args.tolerance_um * 1e-6).to_degrees();
    if let Some(d) = args.decimals {
        if d > 9 {
            return Err(bad("--decimals must be at most 9".into()));
        }
        options.decimals = Some(d);
    }
    options.dialect = match &args.dialect {
        None => None,
        Some(d) => Some(Controller::parse(d).ok_or_else(|| bad(format!("--dialect `{d}` is not one of {}", Controller::names())))?),
    };
    let setup = &mut options.setup;
    setup.machine_inch = match args.machine_units.to_ascii_lowercase().as_str() {
        "mm" => false,
        "inch" | "in" => true,
        other => return Err(bad(format!("--machine-units `{other}` is not mm or inch"))),
    };
    if let Some(path) = &args.tool_table {
        setup.tools = ToolTable::parse(&read(path)?, &path.display().to_string()).map_err(Failure::of)?;
    }
    if let Some(path) = &args.parameters {
        setup.parameters = read_parameter_file(&read(path)?, &path.display().to_string()).map_err(Failure::of)?;
    }
    for o in &args.offsets {
        let (code, values) = o.split_once('=').ok_or_else(|| bad(format!("--offset `{o}` is not G54=X..,Y..")))?;
        let code = code.trim().to_ascii_uppercase();
        let system = trueaxis::compensate::nc::fadal::fixture::offset_system(&code)
            .ok_or_else(|| bad(format!("--offset: `{code}` is not one of G54 ... G59.3 or a Fadal fixture offset E1 ... E48")))?;
        let values = axis_values(machine, &letter_values(values), "--offset")?;
        setup.set_work_offset(&trueaxis::compensate::nc::machine_axes(machine), system, &values);
    }
    if let Some(s) = &args.start {
        setup.start = axis_values(machine, &letter_values(s), "--start")?;
        machine.check_range(&setup.start).map_err(|m| bad(format!("--start: the start point leaves the machine's travel: {m}")))?;
    }
    setup.unknown_tools = match (args.strict_tools, args.tool_length) {
        (true, Some(_)) => return Err(bad("--strict-tools and --tool-length exclude each other".into())),
        (true, None) => UnknownTools::Refuse,
        (false, Some(l)) if !l.is_finite() || l.abs() > 10_000.0 => return Err(bad(format!("--tool-length {l}: not a length (mm)"))),
        (false, l) => UnknownTools::Assume(l.unwrap_or(0.0)),
    };
    if !(args.peck_clearance_mm.is_finite() && args.peck_clearance_mm >= 0.0) {
        return Err(bad("--peck-clearance-mm must be a non-negative number".into()));
    }
    setup.fanuc.peck_clearance_mm = args.peck_clearance_mm;
    setup.expand_cycles = args.expand_cycles;
    let mut dirs = args.search_path.clone();
    if dirs.is_empty() {
        dirs.push(
            args.program
                .parent()
                .map_or_else(|| PathBuf::from("."), |p| if p.as_os_str().is_empty() { PathBuf::from(".") } else { p.to_path_buf() }),
        );
    }
    setup.search_path = SearchPath(dirs);
    Ok(options)
}

pub fn run(args: NcArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let errors = ErrorModel::load(&args.errors, &machine).map_err(Failure::input)?;
    let temperatures = temperatures(&errors, &args.temperatures)?;
    let mut options = options(&args, &machine)?;
    let id = |path: &PathBuf| -> Result<FileId, Failure> {
        let bytes = std::fs::read(path).map_err(|e| bad(format!("{}: cannot read: {e}", path.display())))?;
        Ok(FileId::of(&path.display().to_string(), &bytes))
    };
    options.header = Some(Header { machine: id(&args.machine)?, errors: id(&args.errors)? });
    options.force = args.force;
    let corrector = Corrector::new(&machine, &errors);
    let origin = args.program.display().to_string();
    // the program streams from its file to the output (or standard output), in parts; with
    // --json and no --out its text goes into the JSON document
    let correct = |w: &mut dyn std::io::Write| correct_file(&corrector, &args.program, &origin, &options, &temperatures, w);
    let result = match (&args.out, args.json) {
        (None, true) => {
            let mut text = Vec::new();
            let r = correct(&mut text).map_err(Failure::of)?;
            NcResult { program: text, ..r }
        }
        (out, _) => {
            let out = out.as_deref().unwrap_or(Path::new(trueaxis::data::STANDARD_OUTPUT));
            let mut result = None;
            write_streamed(out, |w| correct(w).map(|r| result = Some(r))).map_err(Failure::of)?;
            result.expect("written")
        }
    };
    if !args.json {
        crate::output::warn(&result.warnings);
    }
    let expanded =
        if result.expanded.is_empty() { String::new() } else { format!("; {} parts expanded into plain moves", result.expanded.len()) };
    let summary = format!(
        "{origin} ({}): {} moves corrected, {} lines changed, {} lines added{expanded}; largest correction {:.3} um, {:.3} urad; \
         residual <= {:.4} um (the rounding of the written numbers included); uncorrectable orientation <= {:.3} urad",
        result.dialect,
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
        eprintln!("{summary}");
    }
    Ok(())
}
