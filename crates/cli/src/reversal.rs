//! `trueaxis reversal arbor|parallelism|disk`: the reversal techniques of NISTIR 5236 §3.4.

use crate::output::{self, print};
use crate::Failure;
use anyhow::anyhow;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use trueaxis::data::{write_atomically, CsvTable};
use trueaxis::instruments::{flat_face_reversal, parallelism_urad, straightness_reversal, BestFitLine, BestFitRadii, ReversalOptions};
use trueaxis::io::Dimension;
use trueaxis_report::{profiles_svg, Profiles};

/// Reversal techniques (NISTIR 5236): straightness of an axis with an imperfect test
/// arbor, parallelism of an axis to the spindle from best-fit radii, straightness and orthogonality
/// with a flat-face disk. Positions in mm, probe readings in um, slopes in urad.
#[derive(clap::Args)]
#[command(after_help = "Examples (see `trueaxis reversal <method> --help` for the columns):\n  \
trueaxis reversal arbor examples/data/reversal_arbor.csv --remove-line --plot arbor.svg\n  \
trueaxis reversal parallelism examples/data/reversal_parallelism.csv --dz 200\n  \
trueaxis reversal disk examples/data/reversal_disk.csv --json")]
pub struct ReversalArgs {
    #[command(subcommand)]
    method: Method,
}

#[derive(clap::Subcommand)]
enum Method {
    Arbor(ArborArgs),
    Parallelism(ParallelismArgs),
    Disk(DiskArgs),
}

/// Common options: the file, the position column, JSON, plot.
#[derive(clap::Args)]
struct Profile {
    /// Readings: a table (read forgivingly), or a laser file of two runs (a Renishaw .rtl: run 1 is
    /// m1, run 2 is m2).
    file: PathBuf,
    /// Column of the axis positions (mm).
    #[arg(long, default_value = "position")]
    position: String,
    /// Print one JSON document instead of the table.
    #[arg(long)]
    json: bool,
    /// Write an SVG of the profiles (atomically).
    #[arg(long, value_parser = crate::output::file)]
    plot: Option<crate::output::OutputPath>,
}

/// Straightness of an axis with a test arbor by reversal (NISTIR 5236): probe 1 scans the
/// arbor (`m1`), the arbor is turned 180 deg with the spindle and probe 2, mounted 180 deg from probe 1,
/// scans it again at the same positions (`m2`). Straightness s = (m2 - m1)/2, arbor profile
/// a = (m1 + m2)/2 (um).
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis reversal arbor examples/data/reversal_arbor.csv --remove-line --plot arbor.svg\n\n\
Columns: position (mm), m1, m2 (um, readings that grow as the surface approaches the probe).")]
struct ArborArgs {
    #[command(flatten)]
    profile: Profile,
    /// Remove the least-squares line from the straightness and report it (arbor misalignment plus
    /// parallelism).
    #[arg(long)]
    remove_line: bool,
}

/// Parallelism of an axis to the spindle axis average line from best-fit radii (NISTIR
/// 5236): two probes 180 deg apart record one slow spindle revolution at two locations dz
/// apart; alpha_p = [(R21 - R11) - (R22 - R12)] / (2 dz), R_ij the mean reading of probe j at location i.
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis reversal parallelism examples/data/reversal_parallelism.csv --dz 200 --json\n\n\
Columns (um, one row per angular step of the revolution): probe1_location1, probe1_location2,\n\
probe2_location1, probe2_location2.")]
struct ParallelismArgs {
    /// Readings (CSV).
    file: PathBuf,
    /// Distance from location 1 to location 2 along the axis (mm, signed).
    #[arg(long, allow_hyphen_values = true)]
    dz: f64,
    /// Print one JSON document instead of the text.
    #[arg(long)]
    json: bool,
}

/// Straightness and orthogonality with a flat-face disk and a spindle reversal (NISTIR
/// 5236): one probe scans the disk face along x (`m1`), the spindle is turned 180 deg, the
/// same probe scans again (`m2`). delta_z = -(m1 + m2)/2, face error e = (m1 - m2)/2, orthogonality
/// = slope of the least-squares line of delta_z.
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis reversal disk examples/data/reversal_disk.csv --plot disk.svg\n\n\
Columns: position (mm), m1, m2 (um).")]
struct DiskArgs {
    #[command(flatten)]
    profile: Profile,
}

pub fn run(args: ReversalArgs) -> Result<(), Failure> {
    match args.method {
        Method::Arbor(a) => arbor(a),
        Method::Parallelism(a) => parallelism(a),
        Method::Disk(a) => disk(a),
    }
}

/// The two scans of a reversal: positions (mm), first and second readings (um).
struct Scans {
    positions: Vec<f64>,
    m1: Vec<f64>,
    m2: Vec<f64>,
}

/// Reads the position, m1 and m2 columns (positions mm, readings um; units in the headers
/// honoured), or the two runs of a laser file (a Renishaw .rtl, or a table with `target`, `dev`,
/// `run`): run 1 is the first scan, run 2 the second.
fn read_scans(p: &Profile) -> Result<Scans, Failure> {
    let table = CsvTable::read(&p.file).map_err(Failure::input)?;
    if !table.has_column("m1") && table.has_column("dev") && table.has_column("run") {
        return two_runs(&table, &p.file);
    }
    let column = |name: &str, d: Dimension| table.numbers_as(name, d).map_err(Failure::input);
    Ok(Scans {
        positions: column(&p.position, Dimension::Length)?,
        m1: column("m1", Dimension::Length)?,
        m2: column("m2", Dimension::Length)?,
    })
}

/// The two scans of a reversal from the two runs of a laser file, each sorted by position; both
/// runs must read the same positions.
fn two_runs(table: &CsvTable, file: &Path) -> Result<Scans, Failure> {
    let bad = |m: String| Failure::input(anyhow!("{}: {m}", file.display()));
    let positions = table.numbers_as("target", Dimension::Length).map_err(Failure::input)?;
    let devs = table.numbers_as("dev", Dimension::Length).map_err(Failure::input)?;
    let runs = table.texts("run").map_err(Failure::input)?;
    let mut order: Vec<&String> = Vec::new();
    for r in &runs {
        if !order.contains(&r) {
            order.push(r);
        }
    }
    if order.len() != 2 {
        return Err(bad(format!(
            "a reversal needs two scans: columns m1 and m2, or a laser file of exactly two runs; this one has {} runs",
            order.len()
        )));
    }
    let scan = |run: &String| {
        let mut rows: Vec<(f64, f64)> = (0..runs.len()).filter(|&i| &runs[i] == run).map(|i| (positions[i], devs[i])).collect();
        rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        rows
    };
    let (first, second) = (scan(order[0]), scan(order[1]));
    if first.len() != second.len() || first.iter().zip(&second).any(|(a, b)| (a.0 - b.0).abs() > 1e-6) {
        return Err(bad(format!(
            "runs {} and {} do not read the same positions; a reversal compares two scans point by point",
            order[0], order[1]
        )));
    }
    Ok(Scans {
        positions: first.iter().map(|x| x.0).collect(),
        m1: first.iter().map(|x| x.1).collect(),
        m2: second.iter().map(|x| x.1).collect(),
    })
}

/// Refuses a result with a number that is not finite (readings too large): nothing printed or written.
fn check_finite(file: &Path, doc: &Value) -> Result<(), Failure> {
    fn finite(v: &Value) -> bool {
        match v {
            Value::Number(n) => n.as_f64().is_some_and(f64::is_finite),
            Value::Null => false,
            Value::Array(a) => a.iter().all(finite),
            Value::Object(o) => o.values().all(finite),
            _ => true,
        }
    }
    if finite(doc) {
        Ok(())
    } else {
        Err(Failure::computation(anyhow!("{}: the reduction overflowed (readings too large to evaluate in um)", file.display())))
    }
}

fn line_json(line: &BestFitLine) -> Value {
    json!({"slope_urad": line.slope_urad, "intercept_um": line.intercept_um})
}

fn write_plot(p: &Profile, title: &str, series: &[(&str, &[f64])], positions: &[f64]) -> Result<Option<PathBuf>, Failure> {
    let Some(path) = &p.plot else { return Ok(None) };
    let series: Vec<(String, Vec<(f64, f64)>)> =
        series.iter().map(|(n, v)| (n.to_string(), positions.iter().copied().zip(v.iter().copied()).collect())).collect();
    let title = format!("{title}: {}", p.file.display());
    let plot = Profiles { title: &title, x_label: "position (mm)", y_label: "um", series: &series, symmetric: false, markers: true };
    let svg = profiles_svg(&plot).map_err(Failure::computation)?;
    write_atomically(path, svg.as_bytes()).map_err(Failure::input)?;
    Ok(Some(path.to_path_buf()))
}

/// The per-position table and the summary lines, or the JSON document.
fn report(
    json_out: bool,
    doc: &Value,
    header: &[&str],
    columns: &[&[f64]],
    summary: &[String],
    plot: Option<PathBuf>,
) -> Result<(), Failure> {
    use std::fmt::Write;
    if json_out {
        return output::json(&doc);
    }
    let mut out = String::new();
    let _ = writeln!(out, "{}", header.iter().map(|h| format!("{h:>16}")).collect::<String>());
    for i in 0..columns[0].len() {
        let _ = writeln!(out, "{}", columns.iter().map(|c| format!("{:>16.4}", c[i])).collect::<String>());
    }
    for line in summary {
        let _ = writeln!(out, "{line}");
    }
    if let Some(path) = plot {
        let _ = writeln!(out, "wrote {}", path.display());
    }
    print(&out)
}

fn arbor(a: ArborArgs) -> Result<(), Failure> {
    let Scans { positions: z, m1, m2 } = read_scans(&a.profile)?;
    let r = straightness_reversal(&z, &m1, &m2, ReversalOptions { remove_line: a.remove_line })
        .map_err(|e| Failure::input(anyhow!("{}: {e}", a.profile.file.display())))?;
    let doc = json!({
        "method": "arbor",
        "positions_mm": z,
        "straightness_um": r.straightness_um,
        "arbor_form_um": r.arbor_form_um,
        "line": r.line.as_ref().map(line_json),
        "straightness_deviation_um": r.straightness_deviation_um(),
    });
    let mut check = doc.clone();
    check["line"] = r.line.as_ref().map_or(json!(0.0), line_json);
    check_finite(&a.profile.file, &check)?;
    let plot = write_plot(&a.profile, "arbor reversal", &[("straightness s", &r.straightness_um), ("arbor a", &r.arbor_form_um)], &z)?;
    let mut summary = vec![format!("straightness deviation {:.4} um (NISTIR 5236: s = (m2 - m1)/2)", r.straightness_deviation_um())];
    if let Some(line) = &r.line {
        summary.push(format!(
            "least-squares line removed: slope {:.3} urad, {:.4} um at 0 mm (arbor misalignment plus parallelism)",
            line.slope_urad, line.intercept_um
        ));
    }
    report(a.profile.json, &doc, &["position (mm)", "s (um)", "a (um)"], &[&z, &r.straightness_um, &r.arbor_form_um], &summary, plot)
}

fn parallelism(a: ParallelismArgs) -> Result<(), Failure> {
    let table = CsvTable::read(&a.file).map_err(Failure::input)?;
    let names = ["probe1_location1", "probe1_location2", "probe2_location1", "probe2_location2"];
    let columns = names.iter().map(|n| table.numbers_as(n, Dimension::Length).map_err(Failure::input)).collect::<Result<Vec<_>, _>>()?;
    let bad = |e: trueaxis::instruments::ReversalError| Failure::input(anyhow!("{}: {e}", a.file.display()));
    let radii = BestFitRadii::from_readings(&columns[0], &columns[1], &columns[2], &columns[3]).map_err(bad)?;
    let alpha = parallelism_urad(&radii, a.dz).map_err(bad)?;
    let doc = json!({
        "method": "parallelism",
        "dz_mm": a.dz,
        "radii_um": {
            "R11": radii.probe1_location1_um, "R21": radii.probe1_location2_um,
            "R12": radii.probe2_location1_um, "R22": radii.probe2_location2_um,
        },
        "parallelism_urad": alpha,
    });
    check_finite(&a.file, &doc)?;
    if a.json {
        return output::json(&doc);
    }
    print(&format!(
        "best-fit radii (um, mean of each revolution, NISTIR 5236): R11 {:.4}  R21 {:.4}  R12 {:.4}  R22 {:.4}\n\
         parallelism alpha_p = [(R21 - R11) - (R22 - R12)] / (2 dz) = {alpha:.3} urad over dz = {} mm\n",
        radii.probe1_location1_um, radii.probe1_location2_um, radii.probe2_location1_um, radii.probe2_location2_um, a.dz
    ))
}

fn disk(a: DiskArgs) -> Result<(), Failure> {
    let Scans { positions: x, m1, m2 } = read_scans(&a.profile)?;
    let r = flat_face_reversal(&x, &m1, &m2).map_err(|e| Failure::input(anyhow!("{}: {e}", a.profile.file.display())))?;
    let doc = json!({
        "method": "disk",
        "positions_mm": x,
        "delta_z_um": r.delta_z_um,
        "face_error_um": r.face_error_um,
        "straightness_um": r.straightness_um,
        "line": line_json(&r.line),
        "orthogonality_urad": r.orthogonality_urad(),
        "straightness_deviation_um": r.straightness_deviation_um(),
    });
    check_finite(&a.profile.file, &doc)?;
    let plot = write_plot(&a.profile, "flat-face reversal", &[("delta_z", &r.delta_z_um), ("face error e", &r.face_error_um)], &x)?;
    let summary = vec![
        format!("orthogonality alpha_o {:.3} urad (slope of the least-squares line of delta_z, NISTIR 5236)", r.orthogonality_urad()),
        format!("straightness deviation {:.4} um (delta_z without the line)", r.straightness_deviation_um()),
    ];
    report(
        a.profile.json,
        &doc,
        &["position (mm)", "delta_z (um)", "e (um)", "straight. (um)"],
        &[&x, &r.delta_z_um, &r.face_error_um, &r.straightness_um],
        &summary,
        plot,
    )
}
