//! Plots (SVG) and, later, the HTML report.

mod fit_plot;
mod heatmap;
mod positioning;
mod histogram;

pub use fit_plot::{fit_plot_svg, FitPlot};
pub use heatmap::{heatmap_svg, MapSlice};
pub use positioning::{positioning_svg, PositionBand, PositioningPlot};
pub use histogram::{convergence_svg, histograms_svg, ConvergenceSeries, HistogramPanel};

use thiserror::Error;

#[derive(Debug, Error)]
pub enum ReportError {
    #[error("cannot draw plot: {0}")]
    Draw(String),
    #[error("cannot draw plot: {0}")]
    Input(String),
}
