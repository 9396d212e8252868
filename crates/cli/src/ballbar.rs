//! `trueaxis ballbar simulate|identify|sensitivity|iso230-4|tmbb|tmbb-setup`.

mod sensitivity;
mod tmbb_setup;

use crate::output::{self, print, text_or_file};
use crate::{parse, Failure};
use anyhow::anyhow;
use std::path::{Path, PathBuf};
use tmbb_setup::SetupDimensions;
use trueaxis::data::{write_atomically, OutputSet};
use trueaxis::error_model::ErrorModel;
use trueaxis::evaluate::circular_test::{cartesian_machine, centre_pose, circular_test_file, CircularTestOptions};
use trueaxis::identify::pige_report::{bar_lengths, identify_pige_files, method_of, pige_user_value, PigeRequest};
use trueaxis::identify::tmbb::{observability, UNIDENTIFIABLE};
use trueaxis::identify::tmbb_report::tmbb_files;
use trueaxis::instruments::ballbar::{method_step, BarLengths, JiangStep, Method, Plane, RotaryPair, Rotation};
use trueaxis::instruments::ballbar_simulation::{circle_runs, noise_stream, readings_csv, SimulationSettings};
use trueaxis::machine::{Component, Machine};
use trueaxis_report::{circular_runs_svg, polar_svg, PolarPlot, PolarSeries};

/// Ballbar tests: simulated readings, the PIGEs of two rotary axes (Jiang (2014)), ISO 230-4 circular
/// tests with diagnostics, the two-length rotary-table test (Zhu (2008)).
#[derive(clap::Args)]
#[command(after_help = "Examples (see `trueaxis ballbar <command> --help`):\n  \
trueaxis ballbar iso230-4 examples/ballbar/vmc3_xy.csv --machine examples/machines/vmc3.toml --radius 100 --centre 0,0,-200\n  \
trueaxis ballbar identify --machine examples/machines/c600u.toml --a1 examples/ballbar/A1.csv --a2 examples/ballbar/A2.csv \\\n      \
--c1 examples/ballbar/C1.csv --c2 examples/ballbar/C2.csv\n  \
trueaxis ballbar tmbb --short examples/ballbar/tmbb_L1.csv --long examples/ballbar/tmbb_L2.csv")]
pub struct BallbarArgs {
    #[command(subcommand)]
    command: BallbarCommand,
}

#[derive(clap::Subcommand)]
enum BallbarCommand {
    Simulate(SimulateArgs),
    Identify(IdentifyArgs),
    #[command(name = "iso230-4")]
    Iso2304(Iso2304Args),
    Sensitivity(sensitivity::SensitivityArgs),
    Tmbb(TmbbArgs),
    #[command(name = "tmbb-setup")]
    TmbbSetup(tmbb_setup::TmbbSetupArgs),
}

pub fn run(args: BallbarArgs) -> Result<(), Failure> {
    match args.command {
        BallbarCommand::Simulate(a) => simulate(a),
        BallbarCommand::Identify(a) => identify(a),
        BallbarCommand::Iso2304(a) => iso230_4(a),
        BallbarCommand::Sensitivity(a) => sensitivity::run(a),
        BallbarCommand::Tmbb(a) => tmbb(a),
        BallbarCommand::TmbbSetup(a) => tmbb_setup::run(a),
    }
}

/// Bar lengths of the 5-axis tests (the defaults of Jiang (2014)).
#[derive(clap::Args, Clone, Copy)]
struct BarArgs {
    /// Normal bar length R (mm).
    #[arg(long, default_value_t = 100.0)]
    normal_length: f64,
    /// Extended bar length L_e (mm); the spindle ball moves by D = sqrt(L_e^2 - R^2) along the axis.
    #[arg(long, default_value_t = 150.0)]
    extended_length: f64,
}

impl BarArgs {
    fn lengths(self) -> Result<BarLengths, Failure> {
        bar_lengths(self.normal_length, self.extended_length).map_err(Failure::input)
    }
}

#[derive(Clone, Copy, clap::ValueEnum, PartialEq)]
enum MethodKind {
    /// Jiang (2014), extended bar: one pivot setup, normal and extended bar on each axis.
    ExtendedBar,
    /// Jiang (2014), two pivots: as the extended-bar method with the outer-axis pivot moved along the outer axis (--outer-offset).
    TwoPivot,
    /// Lee & Yang, as in Jiang (2014): normal bar only, each axis at two positions (--outer-positions, --inner-positions).
    FourSetup,
}

/// The method of the four rotary-axis steps and its geometry.
#[derive(clap::Args, Clone, Copy)]
struct MethodArgs {
    /// Which four steps: A1 A2 (outer axis) and C1 C2 (inner axis) of the method of Jiang (2014).
    #[arg(long, value_enum, default_value = "extended-bar")]
    method: MethodKind,
    /// two-pivot: both balls of the outer-axis steps moved this far along the outer axis (mm).
    #[arg(long, allow_hyphen_values = true)]
    outer_offset: Option<f64>,
    /// four-setup: positions p1,p2 along the outer axis of steps A1 and A2 (mm from its point).
    #[arg(long, value_parser = parse::pair, allow_hyphen_values = true)]
    outer_positions: Option<[f64; 2]>,
    /// four-setup: positions p1,p2 along the inner axis of steps C1 and C2 (mm).
    #[arg(long, value_parser = parse::pair, allow_hyphen_values = true)]
    inner_positions: Option<[f64; 2]>,
}

impl MethodArgs {
    fn method(self) -> Result<Method, Failure> {
        use clap::ValueEnum;
        let name = self.method.to_possible_value().map(|v| v.get_name().to_string()).unwrap_or_default();
        method_of(&name, self.outer_offset, self.outer_positions, self.inner_positions).map_err(Failure::input)
    }
}

#[derive(Clone, Copy, clap::ValueEnum, PartialEq)]
enum TestKind {
    A1,
    A2,
    C1,
    C2,
    Circle,
}

#[derive(Clone, Copy, clap::ValueEnum, PartialEq)]
enum DirArg {
    Ccw,
    Cw,
    Both,
}

/// Simulated bar readings on the exact kinematic chain: a step of the 5-axis test of Jiang (2014) (A1 A2
/// C1 C2 on the machine's two rotary axes: table, head or one of each) or an ISO 230-4 circle.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  trueaxis ballbar simulate --machine examples/machines/c600u.toml --errors examples/ballbar/c600u_piges.toml --test c2 --out c2.csv\n  \
trueaxis ballbar simulate --machine examples/machines/c600u.toml --errors examples/ballbar/c600u_piges.toml --test a1 \\\n      \
--method four-setup --outer-positions -200,250 --inner-positions 0,78 --out a1.csv\n  \
trueaxis ballbar simulate --machine examples/machines/vmc3.toml --errors examples/ballbar/vmc3_circle.toml --test circle --plane xy --radius 100 --centre 0,0,-200 --dir both\n\n\
Output CSV: the axis columns (mm, deg), angle (deg, in the plane of the test), dir (ccw/cw), dL (um)."
)]
pub struct SimulateArgs {
    #[arg(long)]
    machine: PathBuf,
    /// Error values (TOML); none: an error-free machine.
    #[arg(long)]
    errors: Option<PathBuf>,
    #[arg(long, value_enum)]
    test: TestKind,
    #[command(flatten)]
    bars: BarArgs,
    #[command(flatten)]
    method: MethodArgs,
    /// Circle: plane (xy, yz, zx).
    #[arg(long, default_value = "xy", value_parser = parse::plane)]
    plane: Plane,
    /// Circle: radius (mm).
    #[arg(long, default_value_t = 100.0)]
    radius: f64,
    /// Circle: programmed centre x,y,z (mm); other axes at 0.
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    centre: Option<trueaxis::geometry::Vec3>,
    /// Circle: sense of the run(s).
    #[arg(long, value_enum, default_value = "both")]
    dir: DirArg,
    /// Angle step (deg).
    #[arg(long, default_value_t = 1.0)]
    step: f64,
    /// Circle: start angle (deg).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    start: f64,
    /// Gaussian noise added to every reading (um, standard deviation), with --seed.
    #[arg(long, default_value_t = 0.0)]
    noise: f64,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Write the CSV here (atomically) instead of stdout.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
}

fn load(machine: &Path, errors: Option<&Path>) -> Result<(Machine, ErrorModel), Failure> {
    let m = Machine::load(machine).map_err(Failure::input)?;
    let e = match errors {
        Some(p) => ErrorModel::load(p, &m).map_err(Failure::input)?,
        None => ErrorModel::zero(&m),
    };
    Ok((m, e))
}

impl TestKind {
    /// The step of Jiang (2014) (`None`: the circle).
    fn step(self) -> Option<JiangStep> {
        match self {
            TestKind::A1 => Some(JiangStep::A1),
            TestKind::A2 => Some(JiangStep::A2),
            TestKind::C1 => Some(JiangStep::C1),
            TestKind::C2 => Some(JiangStep::C2),
            TestKind::Circle => None,
        }
    }
}

impl DirArg {
    fn rotations(self) -> Vec<Rotation> {
        match self {
            DirArg::Ccw => vec![Rotation::Ccw],
            DirArg::Cw => vec![Rotation::Cw],
            DirArg::Both => vec![Rotation::Ccw, Rotation::Cw],
        }
    }
}

/// The readings of the test (`instruments::ballbar_simulation`), written as CSV.
fn simulate(a: SimulateArgs) -> Result<(), Failure> {
    let (m, e) = load(&a.machine, a.errors.as_deref())?;
    let settings = SimulationSettings { step_deg: a.step, noise_um: a.noise, seed: a.seed, radius_mm: a.radius, start_deg: a.start };
    settings.check().map_err(Failure::of)?;
    let runs = match a.test.step() {
        None => circle_runs(&m, a.plane, &centre_pose(&m, a.centre), &settings, &a.dir.rotations()).map_err(Failure::input)?,
        Some(step) => {
            let pair = RotaryPair::of_machine(&m).map_err(Failure::input)?;
            let method = a.method.method()?;
            vec![(Rotation::Ccw, method_step(&m, pair, method, step, a.bars.lengths()?, a.step).map_err(Failure::input)?)]
        }
    };
    let csv = readings_csv(&m, &e, &runs, &settings, noise_stream(a.test.step())).map_err(Failure::of)?;
    text_or_file(a.out.as_deref(), &csv)
}

/// The 8 PIGEs of the two rotary axes from the four steps of Jiang (2014) (one pivot setup by
/// default, ch. 4 two pivots, ch. 6 four setups): algebraic circle fits, the axis lines, the
/// start-angle correction (Eq. 4.1), repeatability over runs, and the simulated compensation residual.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  trueaxis ballbar identify --machine examples/machines/c600u.toml --a1 examples/ballbar/A1.csv \\\n      \
--a2 examples/ballbar/A2.csv --c1 examples/ballbar/C1.csv --c2 examples/ballbar/C2.csv --plot-dir out --out piges.toml\n  \
trueaxis ballbar identify --machine examples/machines/c600u.toml --method four-setup --outer-positions -200,250 \\\n      \
--inner-positions 0,78 --a1 A1.csv --a2 A2.csv --c1 C1.csv --c2 C2.csv\n\n\
Each CSV holds the swept axis position (column A or C, or angle; deg) and dL (um, the bar reading\n\
relative to the bar length); an optional integer column `run` holds repeated runs (mean and standard\n\
deviation are then reported). Each step needs at least 8 readings over at least 45 deg. Results:\n\
EY0A EZ0A EX0C EY0C in um, EB0A EC0A EA0C EB0C in urad and arcsec (an axis not along X, Y or Z gets\n\
all three translations and rotations, their components along the axis zero)."
)]
pub struct IdentifyArgs {
    #[arg(long)]
    machine: PathBuf,
    #[arg(long)]
    a1: PathBuf,
    #[arg(long)]
    a2: PathBuf,
    #[arg(long)]
    c1: PathBuf,
    #[arg(long)]
    c2: PathBuf,
    #[command(flatten)]
    bars: BarArgs,
    #[command(flatten)]
    method: MethodArgs,
    /// Misplacement of the outer-axis pivot from a centring test: radial,tangential (mm), Eq. 4.1.
    #[arg(long, value_parser = parse::pair, allow_hyphen_values = true)]
    pivot_offset_a: Option<[f64; 2]>,
    /// Misplacement of the inner-axis pivot: radial,tangential (mm), Eq. 4.1.
    #[arg(long, value_parser = parse::pair, allow_hyphen_values = true)]
    pivot_offset_c: Option<[f64; 2]>,
    /// Expected noise of the bar readings (um, standard deviation): a step whose compensation
    /// residual RMS exceeds 3 times it is reported with a warning. Default: 1 um, the accuracy of a
    /// QC20-W (Jiang (2014)).
    #[arg(long, default_value_t = 1.0)]
    noise: f64,
    /// Write polar plots (raw vs compensated) of the four steps into this directory.
    #[arg(long, value_parser = crate::output::figures)]
    plot_dir: Option<crate::output::OutputPath>,
    /// Write the identified PIGEs as an error-values file (TOML: `[constant]` values and their
    /// standard uncertainties in `[uncertainty]`), which `compensate`, `predict` and `report` read.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// Scale of the plots (um per division); default: automatic.
    #[arg(long)]
    scale: Option<f64>,
    #[arg(long)]
    json: bool,
}

fn identify(a: IdentifyArgs) -> Result<(), Failure> {
    let (m, _) = load(&a.machine, None)?;
    let bars = a.bars.lengths()?;
    let method = a.method.method()?;
    if let Some(s) = a.scale.filter(|s| !(*s > 0.0 && s.is_finite())) {
        return Err(Failure::input(anyhow!("--scale must be a positive number of um per division, got {s}")));
    }
    let request = PigeRequest {
        files: [a.a1.clone(), a.a2.clone(), a.c1.clone(), a.c2.clone()],
        method,
        bars,
        pivot_offset_outer: a.pivot_offset_a,
        pivot_offset_inner: a.pivot_offset_c,
        noise_um: a.noise,
    };
    let report = identify_pige_files(&m, &request).map_err(Failure::of)?;
    let last = report.last();
    if let Some(dir) = &a.plot_dir {
        // the plots of every step, or none (docs/reliability.md)
        let mut plots = OutputSet::new();
        plots.create_directory(dir);
        for s in &report.steps {
            let raw: Vec<f64> = s.dl.iter().map(|v| v * 1e3).collect();
            let comp: Vec<f64> = s.residual.iter().map(|v| v * 1e3).collect();
            let lines: Vec<String> = last
                .values
                .iter()
                .map(|(id, v)| {
                    let (u, unit) = pige_user_value(id, *v);
                    format!("{id} = {u:+.3} {unit}")
                })
                .chain([format!("compensated: RMS {:.3} um, band {:.3} um", s.rms_um, s.band_um)])
                .collect();
            let (u1, u2) = plane_labels(&s.geometry);
            let svg = polar_svg(&PolarPlot {
                title: &format!("step {} of Jiang (2014): {}", s.step.name(), s.path.display()),
                axes: (&u1, &u2),
                series: vec![
                    PolarSeries { label: "raw".into(), angles: &s.angles, dl_um: &raw },
                    PolarSeries { label: "compensated (identified PIGEs removed)".into(), angles: &s.angles, dl_um: &comp },
                ],
                um_per_division: a.scale,
                lines: &lines,
                conditions: &[],
            })
            .map_err(Failure::computation)?;
            plots.file(dir.join(format!("{}.svg", s.step.name())), svg);
        }
        plots.commit().map_err(Failure::input)?;
    }
    output::warn(&report.warnings);
    if let Some(path) = &a.out {
        let origin = [&a.a1, &a.a2, &a.c1, &a.c2].iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ");
        let text = report.error_values_text(&origin).map_err(Failure::of)?;
        write_atomically(path, text.as_bytes()).map_err(Failure::input)?;
    }
    if a.json {
        return output::json(&report.to_json());
    }
    let repeated = report.repeated();
    let single_u = &report.single_u;
    let mut out = format!(
        "PIGEs of {} (Jiang (2014), {} method, {} run(s)); D = {:.3} mm\n",
        m.name,
        method.name(),
        report.runs.len(),
        bars.extended_offset()
    );
    for (k, (id, mean, sd)) in report.stats.parameters.iter().enumerate() {
        let (u, unit) = pige_user_value(id, *mean);
        let (s, _) = pige_user_value(id, *sd);
        let arcsec = if unit == "urad" { format!("  ({:+.2}\")", u / 1e6 * 180.0 / std::f64::consts::PI * 3600.0) } else { String::new() };
        let spread = match (repeated, single_u) {
            (true, _) => format!(" ± {s:.3} (sd of the runs)"),
            (false, Some(su)) => format!(" ± {:.3} (u)", pige_user_value(id, su[k]).0),
            (false, None) => String::new(),
        };
        out.push_str(&format!("  {id}  {u:+10.3} {unit}{spread}{arcsec}\n"));
    }
    if repeated {
        out.push_str(&format!("repeatability within 1 um / 1 arcsec: {}\n", if report.stats.within_tolerance { "yes" } else { "no" }));
    } else if single_u.is_some() {
        out.push_str("u: standard uncertainty from the scatter of each trace about its circle, propagated to the PIGEs (one run)\n");
    }
    out.push_str("simulated compensation residual (last run):\n");
    for s in &report.steps {
        out.push_str(&format!("  {}: RMS {:.3} um, band {:.3} um\n", s.step.name(), s.rms_um, s.band_um));
    }
    print(&out)
}

fn plane_labels(g: &trueaxis::instruments::ballbar::RotaryGeometry) -> (String, String) {
    let name = |v: &trueaxis::geometry::Vec3| {
        let k = (0..3).max_by(|&i, &j| v[i].abs().total_cmp(&v[j].abs())).unwrap_or(0);
        format!("{}{}", if v[k] < 0.0 { '-' } else { '+' }, Component::from_index(k).letter())
    };
    (name(&g.u1), name(&g.u2))
}

/// ISO 230-4 circular test: least-squares centre, circular deviation G, radial deviation F,
/// hysteresis H, and diagnostics fitted on the machine's kinematic model.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis ballbar iso230-4 examples/ballbar/vmc3_xy.csv --machine examples/machines/vmc3.toml \\\n      \
--radius 100 --centre 0,0,-200 --feed 1000 --pitch 10 --plot xy.svg\n\n\
The CSV has `angle` (deg, from the plane's first axis toward its second) or the plane's two axis\n\
columns (mm), `dL` (um) and optionally `dir` (ccw/cw) to hold both runs. Without --machine a plain\n\
Cartesian machine (all three slides carry the tool) is used."
)]
pub struct Iso2304Args {
    /// Readings: a table (read forgivingly) or a ballbar text export with a `Key: value` header.
    file: PathBuf,
    #[arg(long)]
    machine: Option<PathBuf>,
    /// Plane of the circle: xy, yz or zx (default: the file's `Plane:`, else xy).
    #[arg(long, value_parser = parse::plane)]
    plane: Option<Plane>,
    /// Nominal radius (mm): the bar length (default: the file's `Radius:`).
    #[arg(long)]
    radius: Option<f64>,
    /// Programmed centre x,y,z (mm).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    centre: Option<trueaxis::geometry::Vec3>,
    /// Feed rate (mm/min), to state the servo mismatch in ms.
    #[arg(long)]
    feed: Option<f64>,
    /// Ball-screw pitch (mm), to fit cyclic errors.
    #[arg(long)]
    pitch: Option<f64>,
    /// Decay angle of reversal spikes (deg).
    #[arg(long, default_value_t = 3.0)]
    spike_width: f64,
    /// Scale of the plot (um per division); default: automatic.
    #[arg(long)]
    scale: Option<f64>,
    #[arg(long, value_parser = crate::output::file)]
    plot: Option<crate::output::OutputPath>,
    #[arg(long)]
    json: bool,
}

fn iso230_4(a: Iso2304Args) -> Result<(), Failure> {
    let m = match &a.machine {
        Some(p) => Machine::load(p).map_err(Failure::input)?,
        None => cartesian_machine(),
    };
    let options = CircularTestOptions {
        plane: a.plane,
        radius_mm: a.radius,
        centre_mm: a.centre,
        feed_mm_per_min: a.feed,
        pitch_mm: a.pitch,
        spike_width_deg: a.spike_width,
    };
    let test = circular_test_file(&a.file, &m, &options).map_err(Failure::of)?;
    let (plane, radius, file, result) = (test.plane, test.radius_mm, &test.file, &test.result);
    let runs = &file.runs;
    let (ia, ib, _) = plane.letters();
    output::warn(&file.warnings);
    let lines = result.summary_lines();
    if let Some(path) = &a.plot {
        let title = format!("ISO 230-4 circular test, {} plane, R {} mm: {}", plane.name(), radius, a.file.display());
        let svg = circular_runs_svg(&title, (&format!("+{ia}"), &format!("+{ib}")), runs, a.scale, &lines).map_err(Failure::input)?;
        write_atomically(path, svg.as_bytes()).map_err(Failure::input)?;
    }
    if a.json {
        return output::json(&test.to_json());
    }
    let mut out = format!("ISO 230-4 circular test: {} ({} plane, R = {} mm, {})\n", a.file.display(), plane.name(), radius, m.name);
    for l in file.metadata.lines() {
        out.push_str(&format!("  {l}\n"));
    }
    for l in &lines {
        out.push_str(&format!("  {l}\n"));
    }
    for o in &result.diagnostics.omitted {
        out.push_str(&format!("  not fitted: {o}\n"));
    }
    out += &crate::output::data_quality_text(&test.findings);
    if let Some(p) = &a.plot {
        out.push_str(&format!("wrote {}\n", p.display()));
    }
    print(&out)
}

/// Two-length telescopic ballbar test of a rotary table (Zhu (2008)): the tilts E_x, E_y and
/// the axial error D_z by l2 and l-infinity, with the condition number under explicit unit scalings.
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis ballbar tmbb --short examples/ballbar/tmbb_L1.csv --long examples/ballbar/tmbb_L2.csv\n\n\
Each CSV has the table angle (column C or angle, deg) and dL (um) at the same angles. Defaults: the\n\
setup of Zhu (2008) (R_x = 71.842, L1 = 90.850, L2 = 217.952 mm, R_z = 0). E_x, E_y are the\n\
table tilts EAC, EBC (arcsec and urad), D_z its axial error EZC (um); residuals of the differenced\n\
squared lengths in mm^2. D_x, D_y (coupled with the eccentricity) and E_z are not identifiable.")]
pub struct TmbbArgs {
    #[arg(long)]
    short: PathBuf,
    #[arg(long)]
    long: PathBuf,
    #[command(flatten)]
    dimensions: SetupDimensions,
    #[arg(long)]
    json: bool,
}

fn tmbb(a: TmbbArgs) -> Result<(), Failure> {
    let setup = a.dimensions.setup();
    let report = tmbb_files(&setup, &a.short, &a.long).map_err(Failure::of)?;
    output::warn(&report.warnings());
    if a.json {
        return output::json(&report.to_json());
    }
    let obs = observability(&setup, &report.angles).map_err(Failure::computation)?;
    let (l2, linf, cond, angles) = (&report.l2, &report.linf, &report.conditioning, &report.angles);
    let arcsec = |r: f64| r * 180.0 / std::f64::consts::PI * 3600.0;
    let (h1, h2) = setup.heights().map_err(Failure::input)?;
    let mut out = format!(
        "Two-length TMBB test of a rotary table (Zhu (2008)): R_x = {} mm, L1 = {} mm, L2 = {} mm, H2 - H1 = {:.3} mm, {} angles\n",
        a.dimensions.rx,
        a.dimensions.l1,
        a.dimensions.l2,
        h2 - h1,
        angles.len()
    );
    out.push_str(&format!("{:>16} {:>12} {:>12}\n", "", "l2", "l-infinity"));
    out.push_str(&format!("{:>16} {:>12.3} {:>12.3}\n", "E_x (arcsec)", arcsec(l2.ex), arcsec(linf.ex)));
    out.push_str(&format!("{:>16} {:>12.3} {:>12.3}\n", "E_y (arcsec)", arcsec(l2.ey), arcsec(linf.ey)));
    out.push_str(&format!("{:>16} {:>12.3} {:>12.3}\n", "D_z (um)", l2.dz * 1e3, linf.dz * 1e3));
    out.push_str(&format!("{:>16} {:>12.5} {:>12.5}\n", "max|e| (mm^2)", l2.max_abs, linf.max_abs));
    out.push_str(&format!("{:>16} {:>12.5} {:>12.5}\n", "range e (mm^2)", l2.range, linf.range));
    out.push_str(&format!("{:>16} {:>12.5} {:>12.5}\n", "RMS e (mm^2)", l2.rms, linf.rms));
    let [ux, uy, uz] = report.std_uncertainty;
    out.push_str(&format!(
        "standard uncertainty of the l2 estimate (residual scatter): E_x {:.4}\", E_y {:.4}\", D_z {:.4} um\n",
        arcsec(ux),
        arcsec(uy),
        uz * 1e3
    ));
    for b in &report.bars {
        out.push_str(&format!(
            "left of the {} mm bar ({}) without the identified errors and the centring: RMS {:.3} um, band {:.3} um\n",
            b.length_mm,
            b.path.display(),
            b.rms_um,
            b.band_um
        ));
    }
    out.push_str(&format!(
        "cond(J): {:.2} (lengths in mm, angles in rad), {:.2} (m, rad), {:.3} (unit-length columns)\n",
        cond.mm_rad, cond.m_rad, cond.unit_columns
    ));
    out.push_str("not identifiable from the differenced data:\n");
    for (n, p, why) in UNIDENTIFIABLE {
        let norm = obs.iter().find(|o| o.0 == n).map_or(0.0, |o| o.2);
        out.push_str(&format!("  {n} ({p}): {why} [differenced column norm {norm:.1e}]\n"));
    }
    print(&out)
}
