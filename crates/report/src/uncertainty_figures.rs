//! The figures of an uncertainty budget: histograms of the Monte Carlo output distributions with
//! their coverage intervals and the GUM Gaussians, and the convergence history of the adaptive loop
//! (JCGM 101 §7.9). Shared by `trueaxis uncertainty --plots` and the demo report.

use super::{convergence_svg, histograms_svg, ConvergenceSeries, HistogramPanel, ReportError};
use trueaxis::uncertainty::{Budget, IntervalKind, McSettings, OutputResult};

/// The `[low, high]` interval of `kind` of one output.
pub fn interval_of(kind: IntervalKind, o: &OutputResult) -> (f64, f64) {
    match kind {
        IntervalKind::Symmetric => (o.symmetric.low, o.symmetric.high),
        IntervalKind::Shortest => (o.shortest.low, o.shortest.high),
    }
}

/// `(histograms, convergence)` SVGs of the run with all sources; no convergence plot when the
/// loop stopped after its first sequence.
pub fn uncertainty_figures(budget: &Budget, settings: &McSettings) -> Result<(String, Option<String>), ReportError> {
    let panels: Vec<HistogramPanel> = budget
        .rows
        .iter()
        .enumerate()
        .map(|(j, row)| HistogramPanel {
            title: format!("{} ({})", row.parameter, row.unit),
            values: budget.total.samples[j].clone(),
            interval: interval_of(settings.interval, &budget.total.outputs[j]),
            gaussian: Some((budget.gum_estimate[j], row.gum_total_u)),
        })
        .collect();
    let title =
        format!("Monte Carlo distributions of the {} parameters and their {} % intervals", budget.rows.len(), 100.0 * settings.coverage);
    let histograms = histograms_svg(&title, &panels, 60)?;
    let history = &budget.total.history;
    let convergence = if history.is_empty() {
        None
    } else {
        let names = ["s_y", "s_u", "s_low", "s_high"];
        let series = ConvergenceSeries {
            sequences: history.iter().map(|c| c.sequence).collect(),
            series: names
                .iter()
                .enumerate()
                .map(|(k, n)| (n.to_string(), history.iter().map(|c| c.max[k].max(1e-300)).collect()))
                .collect(),
            tolerance: settings.tolerance,
            unit: "um or urad".into(),
        };
        Some(convergence_svg("Adaptive Monte Carlo: control variables (largest over the parameters)", &series)?)
    };
    Ok((histograms, convergence))
}
