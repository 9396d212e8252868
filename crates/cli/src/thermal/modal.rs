//! `trueaxis thermal modes` and `trueaxis thermal place`.

use super::write_plot;
use crate::output::{self, print};
use crate::Failure;
use std::path::PathBuf;
use trueaxis::thermal::model_file::load_model;
use trueaxis::thermal::modes_report::ModesReport;
use trueaxis::thermal::placement_job::{check_fraction, place_sensors, placement_modes, PlaceMethod, PlacementRequest, SensorPlacement};
use trueaxis::thermal::{LanczosProgress, SpectrumMethod, DEFAULT_SHARE};
use trueaxis_report::{mode_shapes_plot, mode_shapes_svg, modes_svg, time_constants_plot};

#[derive(Clone, Copy, clap::ValueEnum)]
enum MethodArg {
    Auto,
    Dense,
    Lanczos,
    Lobpcg,
}

/// Modes of a thermal model: time constants (min) and weights |xi tau| under the model's step
/// flux, sorted by decreasing time constant; the dominant modes carry the `--share` of the weight.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  trueaxis thermal modes --model examples/thermal/fin.toml --count 6 --json\n  \
trueaxis thermal modes --model examples/thermal/plate.toml --count 8 --plot plate_modes.svg")]
pub struct ModesArgs {
    /// Thermal model (TOML): kind = bar1d | grid2d | grid3d | matrix_market.
    #[arg(long)]
    model: PathBuf,
    /// Number of modes (the lowest).
    #[arg(long, default_value_t = 10, value_parser = crate::bounds::count::<1, { crate::bounds::MAX_MODES }>)]
    count: usize,
    /// Cumulative weight share kept by truncation.
    #[arg(long, default_value_t = DEFAULT_SHARE)]
    share: f64,
    /// Eigensolver: dense up to 400 nodes, shift-invert Lanczos (a sparse Cholesky factor) up to
    /// 50,000 nodes and LOBPCG with a multigrid preconditioner above (auto), or forced.
    #[arg(long, value_enum, default_value = "auto")]
    method: MethodArg,
    /// Write a figure (SVG): the first mode shapes along the structure, the time constants with
    /// their weights and the truncation share.
    #[arg(long, value_name = "FILE.svg", value_parser = crate::output::file)]
    plot: Option<crate::output::OutputPath>,
    /// Print one JSON document.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub(super) enum PlaceMethodArg {
    Modal,
    Efi,
    Exhaustive,
    /// Gauss-Legendre points along a bar (the baseline of Zhu (2008)).
    Gauss,
}

/// Temperature sensor placement for the dominant modes: the modal rule of Zhu (2008)
/// (extremes of each dominant mode, reuse, ties to the heat source), effective independence, or
/// exhaustive search for the largest det(Phi_s^T Phi_s).
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  trueaxis thermal place --model examples/thermal/fin.toml --method modal --json\n  \
trueaxis thermal place --model examples/thermal/elongation.toml --count 3 --share 1 --plot sensors.svg")]
pub struct PlaceArgs {
    /// Thermal model (TOML): kind = bar1d | grid2d | grid3d | matrix_market; its `candidates` are
    /// the nodes where a sensor may go (default every node).
    #[arg(long)]
    model: PathBuf,
    /// Modes computed before truncation.
    #[arg(long, default_value_t = 20, value_parser = crate::bounds::count::<1, { crate::bounds::MAX_MODES }>)]
    count: usize,
    /// Cumulative weight share of the dominant modes the sensors must serve (0 < share <= 1).
    #[arg(long, default_value_t = DEFAULT_SHARE)]
    share: f64,
    /// Placement method: modal (Zhu (2008): one sensor at the extreme of each dominant mode,
    /// reused where it serves several), efi (effective independence, Kammer), exhaustive (every
    /// subset of --sensors candidates, largest det(Phi_s^T Phi_s)) or gauss (the candidates nearest
    /// the Gauss-Legendre points of a bar, Gaussian integration).
    #[arg(long, value_enum, default_value = "modal")]
    method: PlaceMethodArg,
    /// Number of sensors (efi, exhaustive; default: one per dominant mode).
    #[arg(long)]
    sensors: Option<usize>,
    /// Modal rule: reuse a placed sensor reaching this fraction of a mode's extreme (0 < reuse <= 1).
    #[arg(long, default_value_t = 0.8)]
    reuse: f64,
    /// Score the placements by the error of the elongation model they lead to (bar1d): trained on a
    /// 20-min on/off cycle of the step flux, validated on 10 and 40 min; every method with the same
    /// number of sensors, Gauss points as the baseline.
    #[arg(long)]
    score: bool,
    /// With --score: expansion coefficient of the bar (um/m/K).
    #[arg(long, default_value_t = 10.8)]
    expansion: f64,
    /// Write a figure (SVG): the dominant mode shapes along the structure with the sensors.
    #[arg(long, value_name = "FILE.svg", value_parser = crate::output::file)]
    plot: Option<crate::output::OutputPath>,
    /// Print one JSON document: the sensors (node, position, modes served), the rank and condition
    /// number of the sensor-mode matrix Phi_s (null when infinite) and an explanation.
    #[arg(long)]
    json: bool,
}

impl From<PlaceMethodArg> for PlaceMethod {
    fn from(m: PlaceMethodArg) -> PlaceMethod {
        match m {
            PlaceMethodArg::Modal => PlaceMethod::Modal,
            PlaceMethodArg::Efi => PlaceMethod::Efi,
            PlaceMethodArg::Exhaustive => PlaceMethod::Exhaustive,
            PlaceMethodArg::Gauss => PlaceMethod::Gauss,
        }
    }
}

impl From<MethodArg> for SpectrumMethod {
    fn from(m: MethodArg) -> SpectrumMethod {
        match m {
            MethodArg::Auto => SpectrumMethod::Auto,
            MethodArg::Dense => SpectrumMethod::Dense,
            MethodArg::Lanczos => SpectrumMethod::Lanczos,
            MethodArg::Lobpcg => SpectrumMethod::Lobpcg,
        }
    }
}

/// Runs `solve` with the eigensolver's progress on a bar of `count` modes (hidden when `quiet`).
fn with_bar<T>(
    count: usize,
    quiet: bool,
    solve: impl FnOnce(&mut dyn FnMut(LanczosProgress)) -> Result<T, trueaxis::Error>,
) -> Result<T, Failure> {
    let bar = crate::progress::steps(count, quiet);
    let mut progress = |p: LanczosProgress| match p {
        LanczosProgress::Factorising { nodes } => bar.set_message(format!("modes converged; factorising K - sigma C ({nodes} nodes)")),
        LanczosProgress::Factorised { nonzeros } => bar.set_message(format!("modes converged; factor with {nonzeros} nonzeros, Lanczos")),
        LanczosProgress::Iterating { converged, basis, max_basis, .. } => {
            bar.set_position(converged as u64);
            bar.set_message(format!("modes converged; Lanczos basis {basis} of at most {max_basis}"));
        }
        LanczosProgress::Preconditioning { nodes } => {
            bar.set_message(format!("modes converged; multigrid preconditioner of K ({nodes} nodes)"))
        }
        LanczosProgress::Preconditioned { levels } => bar.set_message(format!("modes converged; multigrid of {levels} levels, LOBPCG")),
        LanczosProgress::Refining { converged, iteration, max_iterations, .. } => {
            bar.set_position(converged as u64);
            bar.set_message(format!("modes converged; LOBPCG iteration {iteration} of at most {max_iterations}"));
        }
    };
    let result = solve(&mut progress);
    bar.finish_and_clear();
    result.map_err(Failure::of)
}

pub fn modes(args: ModesArgs) -> Result<(), Failure> {
    check_fraction("--share", args.share).map_err(Failure::of)?;
    let model = load_model(&args.model).map_err(Failure::of)?;
    let count = args.count.min(model.system.node_count());
    let report = with_bar(count, args.json, |progress| ModesReport::new(&model, args.count, args.method.into(), args.share, progress))?;
    let (basis, weights, dominant) = (&report.basis, &report.weights, &report.dominant);
    if let Some(path) = &args.plot {
        let first: Vec<usize> = (0..basis.len()).collect();
        let shapes = mode_shapes_plot(&model, basis, &first, &[]);
        write_plot(path, modes_svg(&shapes, &time_constants_plot(&model.name, weights, dominant, args.share)))?;
    }
    if args.json {
        return output::json(&report.to_json());
    }
    let mut out = format!(
        "thermal modes of {} ({} nodes), weights |xi tau| under the step flux, sorted by decreasing time constant\n{:>5} {:>12} {:>12} {:>8}  dominant\n",
        model.name,
        model.system.node_count(),
        "mode",
        "tau (min)",
        "weight",
        "share"
    );
    for w in weights {
        out += &format!(
            "{:>5} {:>12.3} {:>12.4e} {:>7.1}%  {}\n",
            w.mode + 1,
            w.tau_s / 60.0,
            w.weight,
            100.0 * w.share,
            if dominant.contains(&w.mode) { "yes" } else { "" }
        );
    }
    out +=
        &format!("{} dominant modes carry {:.0} % of the weight of the {} computed\n", dominant.len(), 100.0 * args.share, weights.len());
    print(&out)
}

pub fn place(args: PlaceArgs) -> Result<(), Failure> {
    let request = PlacementRequest {
        count: args.count,
        share: args.share,
        method: args.method.into(),
        sensors: args.sensors,
        reuse: args.reuse,
        score: args.score.then_some(args.expansion),
    };
    request.check().map_err(Failure::of)?;
    let model = load_model(&args.model).map_err(Failure::of)?;
    let count = args.count.min(model.system.node_count());
    let basis = with_bar(count, args.json, |progress| placement_modes(&model, args.count, progress))?;
    let placement = place_sensors(&model, basis, &request).map_err(Failure::of)?;
    let (dominant, sensors) = (&placement.dominant, &placement.sensors);
    if let Some(path) = &args.plot {
        write_plot(path, mode_shapes_svg(&mode_shapes_plot(&model, &placement.basis, dominant, sensors)))?;
    }
    if args.json {
        return output::json(&placement.to_json(&model));
    }
    let mut out = format!(
        "sensor placement ({}) for the dominant modes {:?} of {}\n",
        placement.method.name(),
        dominant.iter().map(|m| m + 1).collect::<Vec<_>>(),
        model.name
    );
    for (n, m) in sensors.iter().zip(&placement.served) {
        let at = SensorPlacement::position(&model, *n)
            .map_or(String::new(), |p| format!(" at {:?} m", p.iter().map(|v| (v * 1e4).round() / 1e4).collect::<Vec<_>>()));
        let modes = if m.is_empty() { String::new() } else { format!(", serves modes {:?}", m.iter().map(|i| i + 1).collect::<Vec<_>>()) };
        out += &format!("  node {n}{at}{modes}\n");
    }
    out += &placement.conditioning.explanation();
    out.push('\n');
    if let Some(scores) = &placement.scores {
        out += &super::score::scores_text(scores);
    }
    print(&out)
}
