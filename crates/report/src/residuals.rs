//! Residuals of an identification per channel against the observation index, as SVG: what is left
//! of each reading once the identified model is subtracted (a drift or an unmodelled error shows as
//! a pattern, noise as a band).

use super::profiles::{profiles_svg, Profiles};
use super::ReportError;

/// One line per channel: `(name, residuals in um)`, plotted against the record index.
pub fn residuals_svg(title: &str, channels: &[(String, Vec<f64>)]) -> Result<String, ReportError> {
    if channels.is_empty() || channels.iter().any(|(_, v)| v.is_empty()) || channels.iter().flat_map(|(_, v)| v).any(|v| !v.is_finite()) {
        return Err(ReportError::Input("a residual plot needs finite residuals for each channel".into()));
    }
    let series: Vec<(String, Vec<(f64, f64)>)> =
        channels.iter().map(|(name, v)| (name.clone(), v.iter().enumerate().map(|(i, r)| (i as f64, *r)).collect())).collect();
    profiles_svg(&Profiles { title, x_label: "point", y_label: "residual (um)", series: &series, symmetric: true, markers: false })
}
