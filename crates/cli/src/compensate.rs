//! `trueaxis compensate`.

use crate::inputs::given_temperatures;
use crate::parse::{axis_values, correction_limits};
use crate::Failure;
use std::path::PathBuf;
use trueaxis::compensate::{compensation, CompensateError, CompensationRequest, Corrector, ExportFormat, FormatOptions};
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Format {
    /// LinuxCNC joint compensation files, COMP_FILE_TYPE 1 (trims); `--comp-type 0` for positions.
    Linuxcnc,
    /// LinuxCNC 2.9 HAL component (halcompile) driving external offsets: volumetric grid and tables.
    LinuxcncHal,
    /// ISG / Beckhoff TF5280 volumetric CSV (error parameters with ISO 230-1 names) and its list file.
    Isg,
    /// Heidenhain .COM tables and a .CMA assignment.
    Heidenhain,
    /// Siemens 840D sl init programs: LEC ($AA_ENC_COMP) and sag/angularity compensation ($AN_CEC).
    Siemens,
    /// Fanuc pitch-error compensation as programmable parameter input (G10 L50).
    Fanuc,
    /// A plain 3D lattice over X, Y, Z (data, no controller format; `fanuc3d` is its deprecated name).
    #[value(alias = "fanuc3d")]
    Lattice,
    /// Plain CSV: tables.csv (and grid.csv when the machine has X, Y, Z).
    Csv,
    /// Plain JSON: compensation.json.
    Json,
}

/// The command-line name of a format (`linuxcnc-hal`, ...), as the library parses it.
fn format_name(format: Format) -> String {
    use clap::ValueEnum;
    format.to_possible_value().map(|v| v.get_name().to_string()).unwrap_or_default()
}

/// Compensation tables for a controller: corrections (added to the axis set-points) that cancel the
/// predicted error of the tool point relative to the workpiece, solved on the exact chain (Soons
/// (1993)), sampled as own-axis / cross-axis tables (both directions of motion) and a volumetric grid.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  trueaxis compensate --machine examples/machines/vmc3.toml --errors examples/errors/vmc3.toml \\\n      --format linuxcnc --limit-um 50 --out comp\n  \
trueaxis compensate --machine examples/machines/c600u.toml --errors examples/errors/c600u.toml \\\n      --poses examples/poses/c600u.csv --format csv --out comp5\n\n\
Corrections are in um (linear axes) and urad (rotary axes) in CSV/JSON, in machine units (mm, deg) in\n\
controller files. A correction beyond the machine file's [limits] (default 1000 um, 10000 urad;\n\
--limit-um / --limit-urad override it), a table longer than the controller\n\
accepts, unequal spacing or a rotary table that does not close over a turn refuses the export (exit 2).\n\
--out must not hold files this run does not write (tables of different runs never mix).\n\
--poses: the poses are corrected at the temperatures of the file's T:<sensor> columns (else --temperature)."
)]
pub struct CompensateArgs {
    /// Machine description (TOML).
    #[arg(long)]
    machine: PathBuf,
    /// Error values (TOML).
    #[arg(long)]
    errors: PathBuf,
    /// Output format.
    #[arg(long, value_enum)]
    format: Format,
    /// Output directory (created if missing).
    #[arg(long, value_parser = crate::output::directory)]
    out: crate::output::OutputPath,
    /// Refuse corrections of a linear axis larger than this (um, at most 10000; default: the
    /// machine file's `[limits] correction_um`, else 1000).
    #[arg(long)]
    limit_um: Option<f64>,
    /// Refuse corrections of a rotary axis larger than this (urad, at most 100000; default: the
    /// machine file's `[limits] correction_urad`, else 10000).
    #[arg(long)]
    limit_urad: Option<f64>,
    /// Points per own-axis / cross-axis table (equally spaced over the travel).
    #[arg(long, default_value_t = 41, value_parser = crate::bounds::count::<2, { trueaxis::compensate::tables::MAX_TABLE_POINTS }>)]
    points: usize,
    /// Volumetric grid nodes along X, Y, Z (linuxcnc-hal, lattice, csv, json).
    #[arg(long, value_parser = parse_counts, default_value = "9,9,9")]
    grid: [usize; 3],
    /// Reference pose of the tables, e.g. `X=0,Y=0,Z=-200,A=0,C=0` (default: home clamped into the travel).
    #[arg(long)]
    reference: Option<String>,
    /// LinuxCNC COMP_FILE_TYPE: 1 (trims, default) or 0 (positions).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(0..=1))]
    comp_type: u8,
    /// Largest number of lattice points the controller accepts (lattice).
    #[arg(long)]
    max_lattice_points: Option<usize>,
    /// Most points per table the controller is configured for (siemens: MD38000 / MD18342, default
    /// 200; fanuc: points per axis, default 128).
    #[arg(long)]
    max_table_points: Option<usize>,
    /// Most sag-compensation (CEC) tables (siemens; default 8, the 828D's).
    #[arg(long)]
    max_cec_tables: Option<usize>,
    /// Name of the HAL component (linuxcnc-hal).
    #[arg(long, default_value = "trueaxis_comp")]
    hal_component: String,
    /// Temperature of a sensor of the error model, `T:name=degC` (repeatable; default 20 degC), or
    /// any other input (`--input S:spindle=3000`, `F:workpiece=3500`; default 0).
    #[arg(long = "temperature", visible_alias = "input")]
    temperatures: Vec<String>,
    /// Also correct the poses of this CSV (axis columns; `dir:<axis>` and `T:<sensor>` columns are
    /// used per pose) and write corrections.csv.
    #[arg(long)]
    poses: Option<PathBuf>,
    /// Write the files even when they leave more error than they remove (refused otherwise, exit
    /// status 2; docs/compensation.md).
    #[arg(long)]
    force: bool,
    /// Print one JSON summary instead of text.
    #[arg(long)]
    json: bool,
}

fn parse_counts(text: &str) -> Result<[usize; 3], String> {
    let v: Vec<usize> =
        text.split(',').map(|p| p.trim().parse::<usize>()).collect::<Result<_, _>>().map_err(|_| format!("`{text}` is not NX,NY,NZ"))?;
    <[usize; 3]>::try_from(v).map_err(|_| format!("`{text}` is not three counts NX,NY,NZ"))
}

pub fn run(args: CompensateArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let errors = ErrorModel::load(&args.errors, &machine).map_err(Failure::input)?;
    let temperatures = given_temperatures(&errors, &args.temperatures)?;
    let reference = args.reference.as_deref().map(|r| axis_values(&machine, r, "--reference")).transpose()?;
    let limits = correction_limits(&machine, args.limit_um, args.limit_urad)?;
    let options = FormatOptions {
        comp_type: args.comp_type,
        max_lattice_points: args.max_lattice_points,
        max_table_points: args.max_table_points,
        max_cec_tables: args.max_cec_tables,
        hal_component: args.hal_component.clone(),
    };
    let format = ExportFormat::parse(&format_name(args.format), &options).map_err(Failure::of)?;
    let request = CompensationRequest {
        format,
        points: args.points,
        grid: args.grid,
        reference,
        limits,
        temperatures,
        poses: args.poses.clone(),
        force: args.force,
    };
    let corrector = Corrector::new(&machine, &errors);
    // an error table that does not cover the travel: the message names the error file
    let named = |e: CompensateError| match e {
        CompensateError::Coverage(m) => Failure::of(trueaxis::Error::input(m).in_file(args.errors.display().to_string())),
        e => Failure::of(e),
    };
    let mut job = compensation(&corrector, &request).map_err(named)?;
    job.write(&corrector, &args.out).map_err(Failure::of)?;
    let (names, tables, grid, extent, left_out, residual) =
        (job.file_names(), &job.tables, &job.grid, &job.extent, &job.left_out, &job.residual);
    let largest = |rotary: bool| if rotary { extent.max_urad } else { extent.max_um };
    if args.json {
        println!("{}", job.to_json(&machine, &args.out.display().to_string(), args.points));
    } else {
        println!("wrote {} file(s) to {}: {}", names.len(), args.out.display(), names.join(" "));
        println!(
            "{} tables of {} points{}; largest correction written {:.3} um (linear axes), {:.3} urad (rotary axes)",
            tables.tables.len(),
            args.points,
            grid.as_ref().map_or(String::new(), |g| format!(", grid of {}x{}x{} nodes", g.counts[0], g.counts[1], g.counts[2])),
            largest(false),
            largest(true)
        );
        println!(
            "after correction on the exact chain: position residual <= {:.4} um; orientation not corrected <= {:.3} urad",
            extent.worst_residual_mm * 1e3,
            extent.worst_uncorrectable_rad * 1e6
        );
        if let Some(k) = &job.kinematics {
            println!("kinematic description: {}", k["description"].as_str().unwrap_or_default());
            if let Some(axes) = k["axes"].as_object() {
                for (letter, a) in axes {
                    let triple = |key: &str| {
                        a[key].as_array().map_or(String::new(), |v| {
                            v.iter().map(|x| format!("{:.1}", x.as_f64().unwrap_or(0.0))).collect::<Vec<_>>().join(" ")
                        })
                    };
                    println!(
                        "  rotary axis {letter}: line shifted by ({}) um, tilted by ({}) urad, zero offset {:.1} urad",
                        triple("shift_um"),
                        triple("tilt_urad"),
                        a["zero_offset_urad"].as_f64().unwrap_or(0.0)
                    );
                }
            }
        }
        for l in left_out {
            println!("not carried by this format: {l}");
        }
        if let Some(r) = residual {
            let at: Vec<String> =
                machine.axes().iter().zip(&r.worst_pose).map(|(a, v)| format!("{}={}", a.letter, (v * 1e3).round() / 1e3)).collect();
            let moving =
                if machine.axes().iter().any(|a| a.kind == trueaxis::machine::AxisKind::Rotary) { ", rotary axes moving" } else { "" };
            println!(
                "error before (exact chain, {} poses over the travel{moving}, workpiece placed by its best fit): worst {:.3} um, RMS {:.3} um",
                r.samples, r.worst_error_um, r.rms_error_um
            );
            println!(
                "error left with these files: worst {:.3} um at {} ({}; {:.3} um before), RMS {:.3} um",
                r.worst_um,
                at.join(" "),
                r.worst_state,
                r.error_there_um,
                r.rms_um
            );
            if let Some(u) = &job.left_uncertainty {
                println!(
                    "uncertainty of the error left, from the stated uncertainties of {} error values: U = {:.3} um at most over the travel (k = 2), RMS {:.3} um",
                    u.parameters, u.expanded_um, u.rms_expanded_um
                );
            }
            if r.leaves_more_than_it_removes() {
                println!("WARNING: these files leave more error than they remove (written because of --force)");
            }
        }
        if let Some(s) = &job.poses {
            println!("poses: {s}");
        }
    }
    Ok(())
}
