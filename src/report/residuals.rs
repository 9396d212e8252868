//! Residuals of an identification per channel against the observation index, as SVG: what is left
//! of each reading once the identified model is subtracted (a drift or an unmodelled error shows as
//! a pattern, noise as a band).

use super::ReportError;
use plotters::prelude::*;

const COLOURS: [RGBColor; 4] = [RGBColor(31, 97, 181), RGBColor(204, 60, 40), RGBColor(40, 150, 70), RGBColor(140, 80, 170)];

/// One line per channel: `(name, residuals in um)`, plotted against the record index.
pub fn residuals_svg(title: &str, channels: &[(String, Vec<f64>)]) -> Result<String, ReportError> {
    let values = channels.iter().flat_map(|(_, v)| v.iter().copied());
    if channels.is_empty() || channels.iter().any(|(_, v)| v.is_empty()) || values.clone().any(|v| !v.is_finite()) {
        return Err(ReportError::Input("a residual plot needs finite residuals for each channel".into()));
    }
    let limit = values.fold(0.0f64, |m, v| m.max(v.abs())).max(1e-3) * 1.1;
    let n = channels.iter().map(|(_, v)| v.len()).max().unwrap_or(1);
    let text = |e: &dyn std::fmt::Display| ReportError::Draw(e.to_string());
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 420)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| text(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(65)
            .build_cartesian_2d(0f64..n as f64, -limit..limit)
            .map_err(|e| text(&e))?;
        chart.configure_mesh().x_desc("point").y_desc("residual (um)").draw().map_err(|e| text(&e))?;
        for (k, (name, v)) in channels.iter().enumerate() {
            let colour = COLOURS[k % COLOURS.len()];
            chart
                .draw_series(LineSeries::new(v.iter().enumerate().map(|(i, r)| (i as f64, *r)), colour.stroke_width(1)))
                .map_err(|e| text(&e))?
                .label(name.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour));
        }
        chart.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw().map_err(|e| text(&e))?;
        root.present().map_err(|e| text(&e))?;
    }
    Ok(svg)
}
