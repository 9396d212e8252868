//! `trueaxis report`: a self-contained HTML calibration report from a user's own files.

mod fits;

use crate::parse::point as parse_point;
use crate::Failure;
use std::path::{Path, PathBuf};
use trueaxis::data::write_atomically;
use trueaxis::geometry::Vec3;
use trueaxis::instruments::ballbar::Plane;
use trueaxis::machine::Machine;
use trueaxis::thermal::DEFAULT_SHARE;
use trueaxis_report::calibration::{assemble, summary_json, CalibrationError, CalibrationReport, CertificateFile, ReportRequest, POINTS};

/// A calibration report (HTML with inline figures, no network access; and the same as a PDF with
/// --pdf) from your own files: the certificate particulars, instruments and tolerances of a small
/// report.toml (--certificate) and what the files record; the conformity of each toleranced item
/// (simple acceptance or a guard band of the uncertainty, ISO 14253-1); the identification of a
/// measurement campaign, each parameter with one expanded uncertainty (k = 2) and its budget;
/// ISO 230-4 ballbar circles; the volumetric error before and after compensation with the
/// controller tables you choose (--controller); thermal modes and drift. A section appears only
/// when its input is given; the last one lists the input files with their size and SHA-256.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
trueaxis report --machine examples/machines/kx8five.toml --campaign examples/campaigns/kx8five/campaign.toml \\\n      \
--sources examples/uncertainty/kx8five_cyclic.toml --out kx8five-report.html\n  \
trueaxis report --machine examples/machines/vmc3.toml --errors examples/errors/vmc3.toml \\\n      \
--ballbar examples/ballbar/vmc3_xy.csv --ballbar-radius 100 --ballbar-centre 0,0,-200 --out vmc3-report.html\n\n\
  trueaxis report --machine examples/machines/vmc3.toml --errors examples/errors/vmc3.toml \\\n      \
--ballbar examples/ballbar/export_xy.txt --ballbar-radius 100 --ballbar-centre 0,0,-200 \\\n      \
--certificate examples/report/vmc3.toml --controller heidenhain --out vmc3.html --pdf vmc3.pdf\n  \
trueaxis report --machine examples/machines/vmc3.toml --errors examples/errors/vmc3.toml \\\n      \
--positioning examples/data/laser_x.rtl --certificate examples/report/vmc3_laser.toml --out x.html\n\n\
Sections: certificate (always; particulars from --certificate and the files); conformity (tolerances\n\
in --certificate); machine (always); campaign and identification (--campaign); uncertainty budget\n\
(--sources); volumetric and compensation (--errors, or the values identified from --campaign);\n\
positioning (--positioning, ISO 230-2 with its uncertainty); ballbar (--ballbar); rotary-axis location\n\
errors (--rotary-ballbar A1,A2,C1,C2 with --rotary-method, with U); rotary table (--tmbb SHORT,LONG,\n\
the two-length test of Zhu (2008), with U); direct measurements (the [[fit]] tables of --certificate:\n\
the options of `trueaxis fit`); thermal modes (--thermal-model); thermal drift vs prediction\n\
(--thermal-error with --thermal-data); inputs (always). Each part is computed as the command that does it alone:\n\
identify, uncertainty, ballbar iso230-4, predict --frame machine, compensate. The --ballbar-plane,\n\
--ballbar-radius and --ballbar-centre options are given once for all circles or once per --ballbar,\n\
in order. The report.toml keys are described in docs/report.md.")]
pub struct ReportArgs {
    /// Machine description (TOML).
    #[arg(long)]
    machine: PathBuf,
    /// Error values (TOML), identified or measured: the volumetric error maps and the compensation.
    /// Default: the values identified from --campaign.
    #[arg(long, required_unless_present = "campaign")]
    errors: Option<PathBuf>,
    /// Measurement campaign (TOML): identification with uncertainties, identifiability, residuals.
    #[arg(long)]
    campaign: Option<PathBuf>,
    /// Solve a campaign whose parameters the measurements cannot separate anyway (as `identify`).
    #[arg(long, requires = "campaign")]
    allow_rank_deficient: bool,
    /// Uncertainty sources and Monte Carlo settings (TOML), with --campaign: budget and histograms.
    #[arg(long, requires = "campaign")]
    sources: Option<PathBuf>,
    /// Time per measured point of the campaign (s), for the drift sources.
    #[arg(long, default_value_t = assemble::POINT_TIME_S)]
    point_time: f64,
    /// An ISO 230-4 circle (CSV as `ballbar iso230-4` reads it); repeatable.
    #[arg(long = "ballbar")]
    ballbar: Vec<PathBuf>,
    /// An ISO 230-2 positioning test (a table as `iso230-2` reads it, or a Renishaw `.rtl`);
    /// repeatable.
    #[arg(long = "positioning", value_name = "FILE")]
    positioning: Vec<PathBuf>,
    /// Plane of the circles: xy, yz or zx (default xy).
    #[arg(long, value_parser = parse_plane)]
    ballbar_plane: Vec<Plane>,
    /// Nominal radius of the circles: the bar length (mm).
    #[arg(long)]
    ballbar_radius: Vec<f64>,
    /// Programmed centre x,y,z of the circles (mm; default 0,0,0).
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    ballbar_centre: Vec<Vec3>,
    /// The four steps of a rotary-axis ballbar test of a five-axis machine, A1,A2,C1,C2 in this
    /// order (CSV as `ballbar identify` reads them; Jiang (2014)): the location errors of the two
    /// rotary axes, each with U, and the traces.
    #[arg(long, value_name = "A1,A2,C1,C2", value_delimiter = ',')]
    rotary_ballbar: Vec<PathBuf>,
    /// The method of the four steps, as `ballbar identify --method`: extended-bar (Jiang (2014)
    /// ch. 5), two-pivot (ch. 4, with --rotary-outer-offset) or four-setup (ch. 6, with
    /// --rotary-outer-positions and --rotary-inner-positions).
    #[arg(long, value_name = "METHOD", default_value = "extended-bar", value_parser = ["extended-bar", "two-pivot", "four-setup"], requires = "rotary_ballbar")]
    rotary_method: String,
    /// two-pivot: both balls of the outer-axis steps moved this far along the outer axis (mm).
    #[arg(long, value_name = "MM", allow_hyphen_values = true, requires = "rotary_ballbar")]
    rotary_outer_offset: Option<f64>,
    /// four-setup: positions p1,p2 along the outer axis of steps A1 and A2 (mm).
    #[arg(long, value_name = "P1,P2", value_parser = parse_pair, allow_hyphen_values = true, requires = "rotary_ballbar")]
    rotary_outer_positions: Option<[f64; 2]>,
    /// four-setup: positions p1,p2 along the inner axis of steps C1 and C2 (mm).
    #[arg(long, value_name = "P1,P2", value_parser = parse_pair, allow_hyphen_values = true, requires = "rotary_ballbar")]
    rotary_inner_positions: Option<[f64; 2]>,
    /// Misplacement radial,tangential (mm) of the outer-axis pivot from a centring test (Eq. 4.1).
    #[arg(long, value_name = "R,T", value_parser = parse_pair, allow_hyphen_values = true, requires = "rotary_ballbar")]
    rotary_pivot_offset_a: Option<[f64; 2]>,
    /// Misplacement radial,tangential (mm) of the inner-axis pivot.
    #[arg(long, value_name = "R,T", value_parser = parse_pair, allow_hyphen_values = true, requires = "rotary_ballbar")]
    rotary_pivot_offset_c: Option<[f64; 2]>,
    /// A two-length ballbar test of a rotary table, the short and the long bar's files SHORT,LONG
    /// (CSV as `ballbar tmbb` reads them; Zhu (2008)): the table's tilts and axial error, each with U.
    #[arg(long, value_name = "SHORT,LONG", value_delimiter = ',')]
    tmbb: Vec<PathBuf>,
    /// The setup of the two-length test RX,RZ,L1,L2 (mm): table-ball radius and height, short and
    /// long bar (default: the setup of Zhu (2008)).
    #[arg(long, value_name = "RX,RZ,L1,L2", value_delimiter = ',', allow_hyphen_values = true, default_values_t = assemble::TMBB_SETUP_MM, requires = "tmbb")]
    tmbb_setup: Vec<f64>,
    /// Normal and extended bar lengths R,L_e of the rotary-axis test (mm).
    #[arg(long, value_name = "R,LE", value_delimiter = ',', default_values_t = assemble::ROTARY_BARS_MM, requires = "rotary_ballbar")]
    rotary_bars: Vec<f64>,
    /// Thermal conduction model (TOML or Matrix Market, as `thermal modes` reads it): its modes.
    #[arg(long, value_name = "MODEL.toml")]
    thermal_model: Option<PathBuf>,
    /// Number of thermal modes to compute and plot.
    #[arg(long, default_value_t = assemble::THERMAL_MODES, requires = "thermal_model")]
    thermal_modes: usize,
    /// Cumulative weight share of the dominant thermal modes (0 < share <= 1).
    #[arg(long, default_value_t = DEFAULT_SHARE, requires = "thermal_model")]
    thermal_share: f64,
    /// Thermal error model (written by `thermal fit --out`), with --thermal-data: drift vs prediction.
    #[arg(long, value_name = "FITTED.toml", requires = "thermal_data")]
    thermal_error: Option<PathBuf>,
    /// Thermal campaign (CSV as `thermal fit` reads it) that --thermal-error predicts.
    #[arg(long, value_name = "CAMPAIGN.csv", requires = "thermal_error")]
    thermal_data: Option<PathBuf>,
    /// Points per compensation table (as `compensate --points`).
    #[arg(long, default_value_t = POINTS, value_parser = crate::bounds::count::<2, { trueaxis::compensate::tables::MAX_TABLE_POINTS }>)]
    points: usize,
    /// Certificate particulars, instruments, decision rule and tolerances (report.toml, docs/report.md).
    #[arg(long, value_name = "REPORT.toml")]
    certificate: Option<PathBuf>,
    /// The controller format whose tables the after-compensation map shows, as `compensate
    /// --format` writes them: heidenhain, siemens, fanuc, linuxcnc, linuxcnc-hal, isg or lattice
    /// (default: the exact correction at each pose, as a model-based controller applies it).
    #[arg(long, value_name = "FORMAT")]
    controller: Option<String>,
    /// Title of the report (default: report.toml's title, else "Calibration report: " and the machine's name).
    #[arg(long)]
    title: Option<String>,
    /// The HTML file to write (atomically).
    #[arg(long, value_parser = crate::output::file)]
    out: crate::output::OutputPath,
    /// Also write the report as a PDF (A4), from the same content.
    #[arg(long, value_name = "FILE.pdf", value_parser = crate::output::file)]
    pdf: Option<crate::output::OutputPath>,
    /// Print a JSON summary (sections, inputs, key numbers) instead of text.
    #[arg(long)]
    json: bool,
}

fn parse_plane(text: &str) -> Result<Plane, String> {
    Plane::parse(text).ok_or_else(|| format!("`{text}` is not a plane (xy, yz, zx)"))
}

fn parse_pair(text: &str) -> Result<[f64; 2], String> {
    match text.split(',').map(|v| v.trim().parse::<f64>()).collect::<Result<Vec<_>, _>>().as_deref() {
        Ok([a, b]) if a.is_finite() && b.is_finite() => Ok([*a, *b]),
        _ => Err(format!("`{text}` is not two numbers a,b")),
    }
}

impl From<CalibrationError> for Failure {
    fn from(e: CalibrationError) -> Failure {
        Failure::of(e)
    }
}

/// The command line as typed, for the report.
fn command_line() -> String {
    let quote = |a: String| if a.is_empty() || a.contains(char::is_whitespace) { format!("'{a}'") } else { a };
    std::iter::once("trueaxis".to_string()).chain(std::env::args().skip(1).map(quote)).collect::<Vec<_>>().join(" ")
}

/// The report's description: the options as given.
fn request(args: ReportArgs) -> ReportRequest {
    ReportRequest {
        machine: args.machine,
        errors: args.errors,
        campaign: args.campaign,
        allow_rank_deficient: args.allow_rank_deficient,
        sources: args.sources,
        point_time: args.point_time,
        ballbar: args.ballbar,
        ballbar_plane: args.ballbar_plane,
        ballbar_radius: args.ballbar_radius,
        ballbar_centre: args.ballbar_centre,
        positioning: args.positioning,
        rotary_ballbar: args.rotary_ballbar,
        rotary_method: args.rotary_method,
        rotary_outer_offset: args.rotary_outer_offset,
        rotary_outer_positions: args.rotary_outer_positions,
        rotary_inner_positions: args.rotary_inner_positions,
        rotary_pivot_offset_a: args.rotary_pivot_offset_a,
        rotary_pivot_offset_c: args.rotary_pivot_offset_c,
        rotary_bars: args.rotary_bars,
        tmbb: args.tmbb,
        tmbb_setup: args.tmbb_setup,
        thermal_model: args.thermal_model,
        thermal_modes: args.thermal_modes,
        thermal_share: args.thermal_share,
        thermal_error: args.thermal_error,
        thermal_data: args.thermal_data,
        points: args.points,
        certificate: args.certificate,
        controller: args.controller,
        title: args.title,
        command: Some(command_line()),
    }
}

pub fn run(args: ReportArgs) -> Result<(), Failure> {
    let (out, pdf_path, json) = (args.out.clone(), args.pdf.clone(), args.json);
    let request = request(args);
    let machine = Machine::load(&request.machine).map_err(Failure::input)?;
    let bar = crate::progress::spinner(json);
    let mut progress = |message: &str| {
        bar.set_message(message.to_string());
        bar.tick();
    };
    let mut fits = |certificate: &CertificateFile, path: &Path| fits::fit_parts(certificate, &request.machine, path);
    let result = assemble(&request, &machine, &mut progress, &mut fits);
    bar.finish_and_clear();
    let report = result?;
    let html = report.to_html();
    let pdf = match &pdf_path {
        Some(_) => Some(report.to_pdf().map_err(Failure::of)?),
        None => None,
    };
    write_atomically(&out, html.as_bytes()).map_err(Failure::input)?;
    if let (Some(path), Some(bytes)) = (&pdf_path, &pdf) {
        write_atomically(path, bytes).map_err(Failure::input)?;
    }
    let sections: Vec<String> = report.sections().iter().map(|s| s.id.clone()).collect();
    if json {
        println!("{}", summary_json(&out, &report, &sections, html.len(), pdf_path.as_deref()));
        return Ok(());
    }
    println!("wrote {} ({} bytes): {}", out.display(), html.len(), sections.join(", "));
    if let (Some(path), Some(bytes)) = (&pdf_path, &pdf) {
        println!("wrote {} ({} bytes)", path.display(), bytes.len());
    }
    print_findings(&report);
    Ok(())
}

/// The conformity statement and the volumetric error before and after compensation.
fn print_findings(report: &CalibrationReport) {
    let items = report.conformity_items();
    if !items.is_empty() {
        println!("{}", trueaxis_report::calibration::conformity::statement(&items, report.certificate.decision.rule));
    }
    if let Some(v) = &report.volume {
        println!(
            "volumetric error over {} poses: largest {:.2} um before, {:.2} um after compensation ({}), {:.2} um with the summed tables",
            v.poses,
            v.before_um.0,
            v.after_um.0,
            v.controller.as_deref().map_or("exact correction".to_string(), |c| format!("{c} tables")),
            v.after_tables_um.0
        );
    }
}
