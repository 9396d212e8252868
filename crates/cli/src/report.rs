//! `trueaxis report`: a self-contained HTML calibration report from a user's own files.

mod fits;

use crate::predict::parse_point;
use crate::Failure;
use indicatif::ProgressBar;
use std::path::{Path, PathBuf};
use trueaxis::data::write_atomically;
use trueaxis::error_model::ErrorModel;
use trueaxis::geometry::Vec3;
use trueaxis::identify::pige_report::{bar_lengths, method_of, PigeRequest};
use trueaxis::identify::tmbb::TmbbSetup;
use trueaxis::instruments::ballbar::Plane;
use trueaxis::machine::Machine;
use trueaxis::screen::thermal::read_screened;
use trueaxis::thermal::error_model::ThermalErrorModel;
use trueaxis::thermal::model_file::load_model;
use trueaxis::thermal::{LanczosProgress, DEFAULT_SHARE};
use trueaxis::uncertainty::Sources;
use trueaxis_report::calibration::CertificateFile;
use trueaxis_report::calibration::{
    CalibrationError, CalibrationReport, CircleInput, CirclePart, CompensationPart, DataQualityPart, FitPart, IdentificationPart,
    InputFile, PositioningPart, RotaryBallbarPart, ThermalDriftPart, ThermalModesPart, TmbbPart, Traceability, UncertaintyPart, VolumePart,
    CONTROLLER_FORMATS, GRID_NODES, POINTS,
};

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
    #[arg(long, default_value_t = 0.75)]
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
    #[arg(long, value_name = "RX,RZ,L1,L2", value_delimiter = ',', allow_hyphen_values = true, default_values_t = [71.842, 0.0, 90.85, 217.952], requires = "tmbb")]
    tmbb_setup: Vec<f64>,
    /// Normal and extended bar lengths R,L_e of the rotary-axis test (mm).
    #[arg(long, value_name = "R,LE", value_delimiter = ',', default_values_t = [100.0, 150.0], requires = "rotary_ballbar")]
    rotary_bars: Vec<f64>,
    /// Thermal conduction model (TOML or Matrix Market, as `thermal modes` reads it): its modes.
    #[arg(long, value_name = "MODEL.toml")]
    thermal_model: Option<PathBuf>,
    /// Number of thermal modes to compute and plot.
    #[arg(long, default_value_t = 6, requires = "thermal_model")]
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
    #[arg(long, value_parser = crate::outputs::file)]
    out: crate::outputs::OutputPath,
    /// Also write the report as a PDF (A4), from the same content.
    #[arg(long, value_name = "FILE.pdf", value_parser = crate::outputs::file)]
    pdf: Option<crate::outputs::OutputPath>,
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

fn bad(message: String) -> Failure {
    Failure::input(anyhow::anyhow!(message))
}

/// The value of a per-circle option for circle `i` of `n`: given once for all or once per circle.
fn per_circle<T: Copy>(values: &[T], option: &str, n: usize, default: Option<T>) -> Result<Vec<T>, Failure> {
    match values.len() {
        0 => default.map(|d| vec![d; n]).ok_or_else(|| bad(format!("--ballbar needs {option} (once for all circles or once per circle)"))),
        1 => Ok(vec![values[0]; n]),
        k if k == n => Ok(values.to_vec()),
        k => Err(bad(format!("{option} is given {k} times for {n} circles: give it once for all or once per --ballbar"))),
    }
}

fn circles(args: &ReportArgs) -> Result<Vec<CircleInput>, Failure> {
    let n = args.ballbar.len();
    if n == 0 {
        if !(args.ballbar_plane.is_empty() && args.ballbar_radius.is_empty() && args.ballbar_centre.is_empty()) {
            return Err(bad("--ballbar-plane, --ballbar-radius and --ballbar-centre need a --ballbar circle".into()));
        }
        return Ok(Vec::new());
    }
    let planes = per_circle(&args.ballbar_plane, "--ballbar-plane", n, Some(Plane::Xy))?;
    let radii = per_circle(&args.ballbar_radius, "--ballbar-radius", n, None)?;
    let centres = per_circle(&args.ballbar_centre, "--ballbar-centre", n, Some(Vec3::zeros()))?;
    Ok((0..n).map(|i| CircleInput { path: args.ballbar[i].clone(), plane: planes[i], radius: radii[i], centre: centres[i] }).collect())
}

/// The input files with their roles: the machine, errors, campaign (and its data and nominal
/// errors), sources, circles.
fn input_files(args: &ReportArgs, identification: Option<&IdentificationPart>, fits: &[FitPart]) -> Result<Vec<InputFile>, Failure> {
    let mut files: Vec<(&str, PathBuf)> = vec![("machine", args.machine.clone())];
    if let Some(e) = &args.errors {
        files.push(("error values", e.clone()));
    }
    if let (Some(c), Some(id)) = (&args.campaign, identification) {
        files.push(("campaign", c.clone()));
        if let Some(n) = &id.campaign.nominal_errors {
            files.push(("campaign nominal errors", n.clone()));
        }
        for m in &id.campaign.measurements {
            files.push(("campaign data", m.data.clone()));
        }
    }
    if let Some(s) = &args.sources {
        files.push(("uncertainty sources", s.clone()));
    }
    if let Some(c) = &args.certificate {
        files.push(("certificate particulars and tolerances", c.clone()));
    }
    for p in &args.positioning {
        files.push(("positioning test", p.clone()));
    }
    for c in &args.ballbar {
        files.push(("ballbar circle", c.clone()));
    }
    for (c, step) in args.rotary_ballbar.iter().zip(["A1", "A2", "C1", "C2"]) {
        files.push((step_role(step), c.clone()));
    }
    for f in fits.iter().filter(|f| f.direction != Some('-')) {
        files.push(("direct measurement (fit)", f.file.clone()));
    }
    for (c, role) in args.tmbb.iter().zip(["two-length ballbar test, short bar", "two-length ballbar test, long bar"]) {
        files.push((role, c.clone()));
    }
    for (role, path) in
        [("thermal model", &args.thermal_model), ("thermal error model", &args.thermal_error), ("thermal campaign", &args.thermal_data)]
    {
        if let Some(p) = path {
            files.push((role, p.clone()));
        }
    }
    files.iter().map(|(role, path)| InputFile::read(role, path).map_err(Failure::input)).collect()
}

fn step_role(step: &str) -> &'static str {
    match step {
        "A1" => "rotary-axis ballbar step A1",
        "A2" => "rotary-axis ballbar step A2",
        "C1" => "rotary-axis ballbar step C1",
        _ => "rotary-axis ballbar step C2",
    }
}

/// The rotary-axis ballbar test of --rotary-ballbar, if given.
fn rotary_ballbar(args: &ReportArgs, machine: &Machine) -> Result<Option<RotaryBallbarPart>, Failure> {
    let files = match args.rotary_ballbar.as_slice() {
        [] => return Ok(None),
        [a1, a2, c1, c2] => [a1.clone(), a2.clone(), c1.clone(), c2.clone()],
        other => return Err(bad(format!("--rotary-ballbar takes the four files A1,A2,C1,C2 in this order, got {}", other.len()))),
    };
    let bars = match args.rotary_bars.as_slice() {
        [normal, extended] => bar_lengths(*normal, *extended).map_err(|_| {
            bad(format!("--rotary-bars {normal},{extended}: the extended length must exceed the normal one, both positive (mm)"))
        })?,
        other => return Err(bad(format!("--rotary-bars takes two lengths R,L_e in mm, got {}", other.len()))),
    };
    let method = method_of(&args.rotary_method, args.rotary_outer_offset, args.rotary_outer_positions, args.rotary_inner_positions)
        .map_err(|e| bad(e.to_string().replace("--", "--rotary-")))?;
    let request = PigeRequest {
        files,
        method,
        bars,
        pivot_offset_outer: args.rotary_pivot_offset_a,
        pivot_offset_inner: args.rotary_pivot_offset_c,
        noise_um: 1.0,
    };
    let part = RotaryBallbarPart::evaluate(machine, request).map_err(|e| match e {
        // the library names the options of `ballbar identify`; here they are --rotary-...
        CalibrationError::Input(m) => CalibrationError::Input(m.replace("--pivot-offset-", "--rotary-pivot-offset-")),
        other => other,
    });
    Ok(Some(part.map_err(Failure::of)?))
}

/// The two-length rotary-table test of --tmbb, if given.
fn tmbb(args: &ReportArgs) -> Result<Option<TmbbPart>, Failure> {
    let (short, long) = match args.tmbb.as_slice() {
        [] => return Ok(None),
        [short, long] => (short, long),
        other => return Err(bad(format!("--tmbb takes the two files SHORT,LONG (short bar first), got {}", other.len()))),
    };
    let setup = match args.tmbb_setup.as_slice() {
        &[rx, rz, l1, l2] => TmbbSetup { rx, rz, l1, l2 },
        other => return Err(bad(format!("--tmbb-setup takes RX,RZ,L1,L2 in mm, got {} numbers", other.len()))),
    };
    Ok(Some(TmbbPart::evaluate(&setup, short, long).map_err(|e| Failure::of(prefixed("--tmbb", e)))?))
}

/// A bad input of an option's files, named by the option.
fn prefixed(option: &str, e: CalibrationError) -> CalibrationError {
    match e {
        CalibrationError::Input(m) => CalibrationError::Input(format!("{option}: {m}")),
        other => other,
    }
}

/// The command line as typed, for the report.
fn command_line() -> String {
    let quote = |a: String| if a.is_empty() || a.contains(char::is_whitespace) { format!("'{a}'") } else { a };
    std::iter::once("trueaxis".to_string()).chain(std::env::args().skip(1).map(quote)).collect::<Vec<_>>().join(" ")
}

pub fn run(args: ReportArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let circle_inputs = circles(&args)?;
    if !(args.point_time.is_finite() && args.point_time >= 0.0) {
        return Err(bad(format!("--point-time must be a non-negative number of seconds, got {}", args.point_time)));
    }
    let bar = crate::progress::spinner(args.json);
    let result = build(&args, &machine, circle_inputs, &bar);
    bar.finish_and_clear();
    let report = result?;
    if let Some(path) = &args.certificate {
        report.check_tolerances(&path.display().to_string()).map_err(Failure::of)?;
    }
    let html = report.to_html();
    let pdf = match &args.pdf {
        Some(_) => Some(report.to_pdf().map_err(Failure::of)?),
        None => None,
    };
    write_atomically(&args.out, html.as_bytes()).map_err(Failure::input)?;
    if let (Some(path), Some(bytes)) = (&args.pdf, &pdf) {
        write_atomically(path, bytes).map_err(Failure::input)?;
    }
    let sections: Vec<String> = report.sections().iter().map(|s| s.id.clone()).collect();
    if args.json {
        println!("{}", summary_json(&args.out, &report, &sections, html.len(), args.pdf.as_deref()));
        return Ok(());
    }
    println!("wrote {} ({} bytes): {}", args.out.display(), html.len(), sections.join(", "));
    if let (Some(path), Some(bytes)) = (&args.pdf, &pdf) {
        println!("wrote {} ({} bytes)", path.display(), bytes.len());
    }
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
    Ok(())
}

/// Computes every part the inputs allow.
fn build<'a>(
    args: &ReportArgs,
    machine: &'a Machine,
    circle_inputs: Vec<CircleInput>,
    bar: &ProgressBar,
) -> Result<CalibrationReport<'a>, Failure> {
    let certificate = match &args.certificate {
        Some(path) => CertificateFile::load(path).map_err(bad)?,
        None => CertificateFile::default(),
    };
    if let Some(c) = &args.controller {
        if !CONTROLLER_FORMATS.contains(&c.as_str()) {
            return Err(bad(format!("--controller `{c}` is not a controller format; give one of {}", CONTROLLER_FORMATS.join(", "))));
        }
    }
    let mut identification = None;
    if let Some(path) = &args.campaign {
        bar.set_message("identification");
        identification = Some(IdentificationPart::identify(machine, path, args.allow_rank_deficient).map_err(Failure::of)?);
    }
    let mut uncertainty = None;
    if let (Some(path), Some(id)) = (&args.sources, &identification) {
        let sources = Sources::load(path).map_err(|e| Failure::of(e))?;
        let origin = path.display().to_string();
        let mut progress = |stage: Option<&str>, sequence: usize| {
            bar.set_message(format!(
                "Monte Carlo, {}: sequence {sequence}",
                stage.map_or("all sources".into(), |s| format!("`{s}` alone"))
            ));
            bar.tick();
        };
        uncertainty = Some(UncertaintyPart::evaluate(id, sources, &origin, args.point_time, &mut progress).map_err(Failure::of)?);
    }
    bar.set_message("positioning tests");
    let positioning =
        args.positioning.iter().map(|p| PositioningPart::evaluate(p, &certificate)).collect::<Result<Vec<_>, _>>().map_err(Failure::of)?;
    bar.set_message("ballbar circles");
    let mut circles =
        circle_inputs.into_iter().map(|c| CirclePart::evaluate(machine, c)).collect::<Result<Vec<_>, _>>().map_err(Failure::of)?;
    for c in &mut circles {
        c.reading_u_um = certificate.reading_uncertainty_um("ballbar");
    }
    bar.set_message("rotary-axis ballbar steps");
    let rotary_ballbar = rotary_ballbar(args, machine)?;
    bar.set_message("two-length rotary-table test");
    let tmbb = tmbb(args)?;
    let loaded;
    let (errors, origin): (&ErrorModel, String) = match (&args.errors, &identification) {
        (Some(path), _) => {
            loaded = ErrorModel::load(path, machine).map_err(Failure::input)?;
            (&loaded, format!("the error values of {}", path.display()))
        }
        (None, Some(id)) => (&id.errors, format!("the errors identified from {}", id.campaign.origin)),
        (None, None) => return Err(bad("give --errors or --campaign".into())),
    };
    bar.set_message("compensation tables and volumetric error");
    let compensation = CompensationPart::compute(machine, errors, &origin, args.points, GRID_NODES).map_err(Failure::of)?;
    let controller = match &args.controller {
        Some(format) => Some(compensation.controller(machine, errors, format, None).map_err(Failure::of)?),
        None => None,
    };
    let volume = {
        VolumePart::compute(machine, errors, errors, &compensation, None).map_err(Failure::of)?.map(|mut v| {
            v.description.push(format!(
                "The machine is taken to have {origin}, and the corrections are computed from them. {} How well the errors themselves are known is the uncertainty of their measurement or identification.",
                match &args.controller {
                    Some(c) => format!(
                        "The map after compensation shows the exact correction at each pose; what the {} files leave is on the compensation page.",
                        trueaxis_report::calibration::controller_name(c)
                    ),
                    None => "The exact correction leaves only the corrector's tolerance; give --controller to see what a controller's files leave.".to_string(),
                }
            ));
            v
        })
    };
    let (thermal_modes, thermal_drift, thermal_findings) = thermal_parts(args, bar)?;
    bar.set_message("direct measurements");
    let fits = match &args.certificate {
        Some(path) => fits::fit_parts(&certificate, &args.machine, path)?,
        None => Vec::new(),
    };
    let mut data_quality = DataQualityPart::of_parts(&positioning, &circles, identification.as_ref()).map_err(Failure::of)?;
    for f in &fits {
        let role = format!("direct measurement ({})", f.name());
        data_quality.add(&f.file.display().to_string(), &role, f.report.findings.clone()).map_err(Failure::of)?;
    }
    if let (Some(path), Some(findings)) = (&args.thermal_data, thermal_findings) {
        data_quality.add(&path.display().to_string(), "thermal campaign", findings).map_err(Failure::of)?;
    }
    let traceability = Traceability::now(input_files(args, identification.as_ref(), &fits)?, Some(command_line()));
    let issued = certificate.issue_date(&traceability.date);
    Ok(CalibrationReport {
        title: args
            .title
            .clone()
            .or_else(|| certificate.certificate.title.clone())
            .unwrap_or_else(|| format!("Calibration report: {}", machine.name)),
        subtitle: format!("Date of issue {issued}; {}", traceability.software),
        machine,
        machine_notes: Vec::new(),
        identification,
        uncertainty,
        volume,
        thermal_modes,
        thermal_drift,
        circles,
        rotary_ballbar,
        tmbb,
        fits,
        positioning,
        data_quality: (!data_quality.files.is_empty()).then_some(data_quality),
        compensation: Some(compensation),
        controller,
        extra: Vec::new(),
        traceability,
        certificate,
    })
}

/// The thermal modes of --thermal-model and the prediction of --thermal-data by --thermal-error,
/// with the screening findings of --thermal-data.
type ThermalParts = (Option<ThermalModesPart>, Option<ThermalDriftPart>, Option<Vec<trueaxis::screen::Finding>>);

fn thermal_parts(args: &ReportArgs, bar: &ProgressBar) -> Result<ThermalParts, Failure> {
    let modes = match &args.thermal_model {
        Some(path) => {
            bar.set_message("thermal modes");
            let model = load_model(path).map_err(|e| Failure::of(e))?;
            let mut progress = |p: LanczosProgress| {
                if let LanczosProgress::Iterating { converged, wanted, .. } | LanczosProgress::Refining { converged, wanted, .. } = p {
                    bar.set_message(format!("thermal modes: {converged} of {wanted} converged"));
                }
            };
            let origin = path.display().to_string();
            Some(ThermalModesPart::compute(&model, &origin, args.thermal_modes, args.thermal_share, &mut progress).map_err(Failure::of)?)
        }
        None => None,
    };
    let drift = match (&args.thermal_error, &args.thermal_data) {
        (Some(model_path), Some(data_path)) => {
            bar.set_message("thermal error model");
            let text = trueaxis::data::inputs::read_to_string(model_path)
                .map_err(|e| bad(format!("{}: cannot read: {e}", model_path.display())))?;
            let model_origin = model_path.display().to_string();
            let model = ThermalErrorModel::from_toml_str(&text, &model_origin).map_err(|e| Failure::of(e))?;
            let (campaign, findings) = read_screened(data_path, false, false).map_err(|e| Failure::of(e))?;
            let part =
                ThermalDriftPart::compute(&model, &model_origin, &campaign, &data_path.display().to_string()).map_err(Failure::of)?;
            Some((part, findings))
        }
        _ => None,
    };
    let (drift, findings) = drift.unzip();
    Ok((modes, drift, findings))
}

fn summary_json(out: &Path, report: &CalibrationReport, sections: &[String], bytes: usize, pdf: Option<&Path>) -> serde_json::Value {
    use serde_json::json;
    let parameters = report.identification.as_ref().map(|id| {
        id.parameter_rows(report.uncertainty.as_ref()).into_iter().map(|p| (p.name.clone(), p.json())).collect::<serde_json::Map<_, _>>()
    });
    let conformity: Vec<_> = report
        .conformity_items()
        .iter()
        .map(|i| json!({"item": i.name, "value": i.value, "expanded_uncertainty": i.expanded, "tolerance": i.tolerance, "unit": i.unit, "decision": i.mark.word()}))
        .collect();
    let volumetric = report.volume.as_ref().map(|v| {
        json!({"poses": v.poses, "max_before_um": v.before_um.0, "rms_before_um": v.before_um.1,
               "max_after_um": v.after_um.0, "rms_after_um": v.after_um.1, "controller": v.controller,
               "max_after_tables_um": v.after_tables_um.0, "rms_after_tables_um": v.after_tables_um.1})
    });
    let ballbar: Vec<_> = report
        .circles
        .iter()
        .map(|c| {
            let diagnostics: serde_json::Map<String, serde_json::Value> = c
                .result
                .diagnostics
                .items
                .iter()
                .map(|d| (d.name.clone(), json!({"value": d.value, "unit": d.unit, "expanded_uncertainty": 2.0 * d.std_uncertainty})))
                .collect();
            json!({"file": c.input.path.display().to_string(), "G_um": c.result.runs.iter().map(|r| r.g_um).collect::<Vec<_>>(),
                   "F_max_um": c.result.runs.iter().map(|r| r.f_max_um).collect::<Vec<_>>(),
                   "F_min_um": c.result.runs.iter().map(|r| r.f_min_um).collect::<Vec<_>>(),
                   "H_um": c.result.hysteresis_um, "reading_expanded_uncertainty_um": c.reading_u_um,
                   "feed_mm_per_min": c.feed_mm_per_min, "diagnostics": diagnostics})
        })
        .collect();
    let positioning: Vec<_> = report
        .positioning
        .iter()
        .map(|p| {
            let results: serde_json::Map<String, serde_json::Value> = p
                .test
                .result
                .axis_table()
                .iter()
                .map(|(symbol, _, value)| (symbol.to_string(), json!({"value": value, "expanded_uncertainty": p.uncertainty.of(symbol)})))
                .collect();
            let budget: serde_json::Map<String, serde_json::Value> =
                p.uncertainty.budget.iter().map(|c| (c.name.to_string(), json!(c.standard_uncertainty))).collect();
            json!({"file": p.path.display().to_string(), "axis": p.axis(), "unit": p.test.result.unit, "coverage_factor": 2,
                   "length": p.uncertainty.length, "results": results, "budget": budget,
                   "temperature_correction": p.test.temperature_correction})
        })
        .collect();
    let rotary_ballbar = report.rotary_ballbar.as_ref().map(|r| {
        let errors: serde_json::Map<String, serde_json::Value> = r.errors().iter().map(|e| (e.name.clone(), e.json())).collect();
        json!({"method": r.report.method.name(), "runs": r.report.runs.len(), "uncertainty_method": r.uncertainty_method(), "errors": errors,
               "residual_rms_um": r.report.steps.iter().map(|s| s.rms_um).collect::<Vec<_>>()})
    });
    let tmbb = report.tmbb.as_ref().map(|t| {
        let errors: serde_json::Map<String, serde_json::Value> = t.errors().iter().map(|e| (e.name.clone(), e.json())).collect();
        json!({"method": "two-length ballbar, Zhu (2008)", "estimator": "least squares (l2)", "errors": errors,
               "left_rms_um": t.report.bars.iter().map(|b| b.rms_um).collect::<Vec<_>>()})
    });
    let inputs: Vec<_> = report
        .traceability
        .inputs
        .iter()
        .map(|f| json!({"role": f.role, "path": f.path, "bytes": f.bytes, "sha256": f.sha256, "recorded": f.recorded}))
        .collect();
    let thermal_modes = report.thermal_modes.as_ref().map(|m| {
        json!({"tau_min": m.weights.iter().map(|w| w.tau_s / 60.0).collect::<Vec<_>>(),
               "share": m.weights.iter().map(|w| w.share).collect::<Vec<_>>(),
               "dominant": m.dominant.iter().map(|d| d + 1).collect::<Vec<_>>()})
    });
    let thermal_drift = report.thermal_drift.as_ref().map(|d| {
        let runs: serde_json::Map<String, serde_json::Value> = d.runs.iter().map(|(run, s)| (run.clone(), json!(s))).collect();
        json!({"error": d.error, "residuals_um": runs})
    });
    json!({
        "out": out.display().to_string(), "bytes": bytes, "pdf": pdf.map(|p| p.display().to_string()), "sections": sections, "inputs": inputs,
        "conformity": conformity, "decision_rule": report.certificate.decision.rule.name(),
        "controller": report.controller.as_ref().map(|c| json!({"format": c.format, "worst_um": c.residual.worst_um, "rms_um": c.residual.rms_um, "worst_error_um": c.residual.worst_error_um, "rms_error_um": c.residual.rms_error_um, "leaves_more_than_it_removes": c.residual.leaves_more_than_it_removes(), "left_out": c.left_out, "kinematics": c.kinematics})),
        "parameters": parameters, "volumetric": volumetric, "positioning": positioning, "ballbar": ballbar, "rotary_ballbar": rotary_ballbar, "tmbb": tmbb,
        "fits": report.fits.iter().map(FitPart::json).collect::<Vec<_>>(),
        "thermal_modes": thermal_modes, "thermal_drift": thermal_drift,
        "data_quality": report.data_quality.as_ref().map(|d| d.to_json()),
        "compensation": report.compensation.as_ref().map(|c| json!({"max_correction_um": c.extent.max_um, "max_correction_urad": c.extent.max_urad})),
    })
}
