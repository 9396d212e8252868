//! The data of the thermal figures from the thermal library's results (shared by
//! `trueaxis thermal ... --plot` and an HTML report): mode shapes along a line of the structure,
//! time constants with weights, and drift against prediction per run of a campaign.

use super::{DriftPlot, DriftRun, ModeBar, ModeShapeCurve, ModeShapesPlot, RunRole, TimeConstantsPlot};
use trueaxis::thermal::model_file::ThermalModel;
use trueaxis::thermal::time_constants::{Series, TimeConstantFit};
use trueaxis::thermal::validation::{Evaluated, Role};
use trueaxis::thermal::{ModalBasis, ModeWeight};

/// At most this many mode shapes in one plot.
pub const MAX_SHAPES: usize = 6;
/// At most this many sample points along the abscissa of a mode-shape plot.
const MAX_POINTS: usize = 2000;

/// The sample points of a mode-shape plot as `(abscissa, node)` and the abscissa's label: on a
/// mesh, the grid line along the longest dimension through the (first) heat source, in m; for
/// imported matrices, the nodes by number (at most 2000, evenly spaced).
pub fn profile_line(model: &ThermalModel) -> (String, Vec<(f64, usize)>) {
    let source = model.flux_nodes.first().copied().unwrap_or(0);
    match &model.mesh {
        Some(mesh) => {
            let d = (0..mesh.dimensions()).max_by(|&a, &b| mesh.size_m()[a].total_cmp(&mesh.size_m()[b])).unwrap_or(0);
            let mut grid = mesh.node_grid(source);
            let points = (0..=mesh.cells()[d])
                .map(|i| {
                    grid[d] = i;
                    (i as f64 * mesh.spacing(d), mesh.node_index(&grid[..mesh.dimensions()]))
                })
                .collect();
            let axis = ["x", "y", "z"][d];
            let label = if mesh.dimensions() == 1 {
                format!("{axis} (m) along the bar")
            } else {
                format!("{axis} (m) on the grid line through node {source} (heat source)")
            };
            (label, points)
        }
        None => {
            let n = model.system.node_count();
            let step = n.div_ceil(MAX_POINTS).max(1);
            ("node".into(), (0..n).step_by(step).map(|i| (i as f64, i)).collect())
        }
    }
}

/// Mode shapes of `modes` (indices into `basis`, at most [`MAX_SHAPES`] drawn) along
/// [`profile_line`], with the `sensors` (nodes) on that line as markers.
pub fn mode_shapes_plot(model: &ThermalModel, basis: &ModalBasis, modes: &[usize], sensors: &[usize]) -> ModeShapesPlot {
    let (x_label, line) = profile_line(model);
    let curves = modes
        .iter()
        .take(MAX_SHAPES)
        .map(|&i| ModeShapeCurve {
            label: format!("mode {}, tau {:.2} min", i + 1, basis.tau_s(i) / 60.0),
            values: line.iter().map(|&(_, node)| basis.shape(node, i)).collect(),
        })
        .collect();
    let markers: Vec<(f64, String)> =
        sensors.iter().filter_map(|s| line.iter().find(|(_, node)| node == s).map(|(x, _)| (*x, format!("sensor, node {s}")))).collect();
    let off: Vec<String> = sensors.iter().filter(|s| !line.iter().any(|(_, node)| node == *s)).map(|s| s.to_string()).collect();
    let mut title = format!("mode shapes of {}", model.name);
    if !off.is_empty() {
        title += &format!(" (sensors off this line: nodes {})", off.join(", "));
    }
    ModeShapesPlot { title, x_label, positions: line.iter().map(|p| p.0).collect(), modes: curves, markers }
}

/// Time constants and weight shares of the computed modes; `dominant` are the kept modes.
pub fn time_constants_plot(model_name: &str, weights: &[ModeWeight], dominant: &[usize], share: f64) -> TimeConstantsPlot {
    TimeConstantsPlot {
        title: format!("time constants and weights |xi tau| of {}", model_name),
        modes: weights
            .iter()
            .map(|w| ModeBar { mode: w.mode + 1, tau_min: w.tau_s / 60.0, share: w.share, dominant: dominant.contains(&w.mode) })
            .collect(),
        share,
    }
}

/// The drift plot of a thermal error model `error` (the column name) on evaluated segments of a
/// campaign ([`evaluate_segments`](trueaxis::thermal::validation::evaluate_segments)).
pub fn drift_plot(error: &str, evaluated: &[Evaluated]) -> DriftPlot {
    let runs = evaluated
        .iter()
        .map(|e| DriftRun {
            name: e.segment.name.clone(),
            role: match e.segment.role {
                Role::Training => RunRole::Training,
                Role::Validation => RunRole::Validation,
                Role::Prediction => RunRole::Prediction,
            },
            times_s: e.times_s.clone(),
            measured: e.measured.clone(),
            predicted: e.predicted.clone(),
        })
        .collect();
    DriftPlot {
        title: format!("thermal error `{error}`: measured and predicted, residual band (measured - predicted)"),
        quantity: format!("{error} (um)"),
        model_label: "predicted".into(),
        runs,
    }
}

/// Each temperature record of an eq. 3.17 fit (Zhu 2008 §3.5) and its fitted curve
/// `b + sum_j A_j (1 - exp(-t / tau_j))`; `names` label the records.
pub fn step_fit_plot(names: &[String], series: &[Series], fit: &TimeConstantFit) -> DriftPlot {
    let taus: Vec<String> = fit.tau_s.iter().map(|t| format!("{:.2}", t / 60.0)).collect();
    DriftPlot {
        title: format!("temperature records and the eq. 3.17 fit with shared time constants {} min", taus.join(", ")),
        quantity: "T (degC)".into(),
        model_label: "eq. 3.17 fit".into(),
        runs: names
            .iter()
            .zip(series)
            .enumerate()
            .map(|(k, (name, s))| DriftRun {
                name: name.clone(),
                role: RunRole::Training,
                times_s: s.times_s.clone(),
                measured: Some(s.values.clone()),
                predicted: s.times_s.iter().map(|&t| fit.evaluate(k, t)).collect(),
            })
            .collect(),
    }
}
