//! Plots (SVG) and the self-contained HTML report.

pub mod budget;
pub mod calibration;
pub mod html;
pub mod pdf;

mod fit_plot;
mod framed;
mod heatmap;
mod histogram;
mod polar;
mod positioning;
mod profiles;
mod residuals;
pub mod style;
mod thermal;
mod thermal_figures;
mod uncertainty_figures;

pub use fit_plot::{direct_fit_svg, fit_plot_svg, FitPlot};
pub use heatmap::{heatmap_svg, heatmap_svg_scaled, MapSlice};
pub use histogram::{convergence_svg, histograms_svg, ConvergenceSeries, HistogramPanel};
pub use polar::{auto_scale, circle_svg, circular_runs_svg, polar_svg, PolarPlot, PolarSeries};
pub use positioning::{iso230_2_svg, positioning_svg, PositionBand, PositioningPlot};
pub use profiles::{profiles_svg, Profiles};
pub use residuals::residuals_svg;
pub use thermal::{
    drift_svg, mode_shapes_svg, modes_svg, time_constants_svg, DriftPlot, DriftRun, ModeBar, ModeShapeCurve, ModeShapesPlot, RunRole,
    TimeConstantsPlot,
};
pub use thermal_figures::{drift_plot, mode_shapes_plot, profile_line, step_fit_plot, time_constants_plot};
pub use uncertainty_figures::{interval_of, uncertainty_figures};

use thiserror::Error;

/// Why a figure could not be drawn: the data given to it (bad input) or the drawing itself (a
/// failed computation).
#[derive(Debug, Error)]
pub enum ReportError {
    #[error("cannot draw plot: {0}")]
    Draw(String),
    #[error("cannot draw plot: {0}")]
    Input(String),
}

impl From<ReportError> for trueaxis::Error {
    fn from(e: ReportError) -> trueaxis::Error {
        let kind = match e {
            ReportError::Input(_) => trueaxis::ErrorKind::Input,
            ReportError::Draw(_) => trueaxis::ErrorKind::Computation,
        };
        trueaxis::Error::new(kind, e.to_string()).caused_by(e)
    }
}
