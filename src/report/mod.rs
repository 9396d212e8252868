//! Plots (SVG) and, later, the HTML report.

mod heatmap;

pub use heatmap::{heatmap_svg, MapSlice};

use thiserror::Error;

#[derive(Debug, Error)]
pub enum ReportError {
    #[error("cannot draw plot: {0}")]
    Draw(String),
    #[error("cannot draw plot: {0}")]
    Input(String),
}
