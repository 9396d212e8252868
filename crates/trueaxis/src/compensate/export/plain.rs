//! Plain CSV and JSON: every own-axis and cross-axis table (both directions) and the volumetric grid,
//! corrections in um (linear axes) and urad (rotary axes), positions in mm and deg.
//!
//! `tables.csv`: `driver,position,corrected,forward,reverse,unit` (one row per table point);
//! `grid.csv`: one column per grid axis (mm) then `d<axis>` per machine axis (um or urad).
//! JSON: `{"machine":..,"reference":{..},"tables":[{"driver":"X","corrected":"Y","unit":"um",
//! "positions":[..],"forward":[..],"reverse":[..]}],"grid":{"axes":[..],"start":[..],"step":[..],
//! "counts":[..],"units":{..},"values":[[..], ..]}}`.

use super::{check_user_limits, micro_unit, to_micro, ExportInput, ExportedFile};
use crate::compensate::CompensateError;
use std::fmt::Write;

/// `tables.csv` and, with a grid, `grid.csv`.
pub fn export_csv(input: &ExportInput) -> Result<Vec<ExportedFile>, CompensateError> {
    check_user_limits(input)?;
    let m = input.machine;
    let mut text = String::from("driver,position,corrected,forward,reverse,unit\n");
    for t in &input.tables.tables {
        for (i, x) in t.positions.iter().enumerate() {
            let _ = writeln!(
                text,
                "{},{x},{},{:.4},{:.4},{}",
                m.axes()[t.driver].letter,
                m.axes()[t.corrected].letter,
                to_micro(m, t.corrected, t.forward[i]),
                to_micro(m, t.corrected, t.reverse[i]),
                micro_unit(m, t.corrected)
            );
        }
    }
    let mut files = vec![ExportedFile { name: "tables.csv".into(), contents: text }];
    if let Some(g) = input.grid {
        let mut header: Vec<String> = g.axes.iter().map(|&a| m.axes()[a].letter.to_string()).collect();
        header.extend(m.axes().iter().map(|a| format!("d{}", a.letter)));
        let mut text = header.join(",") + "\n";
        for (node, values) in g.values.chunks(g.axis_count).enumerate() {
            let (i, j, k) = (node % g.counts[0], (node / g.counts[0]) % g.counts[1], node / (g.counts[0] * g.counts[1]));
            let mut row: Vec<String> = g.node_position(i, j, k).iter().map(|p| format!("{p}")).collect();
            row.extend(values.iter().enumerate().map(|(a, v)| format!("{:.4}", to_micro(m, a, *v))));
            let _ = writeln!(text, "{}", row.join(","));
        }
        files.push(ExportedFile { name: "grid.csv".into(), contents: text });
    }
    Ok(files)
}

/// The JSON document (also written as `compensation.json`).
pub fn to_json(input: &ExportInput) -> Result<serde_json::Value, CompensateError> {
    check_user_limits(input)?;
    let m = input.machine;
    let round = |v: f64| (v * 1e4).round() / 1e4;
    let reference: serde_json::Map<String, serde_json::Value> =
        m.axes().iter().zip(&input.tables.reference).map(|(a, v)| (a.letter.to_string(), (*v).into())).collect();
    let tables: Vec<serde_json::Value> = input
        .tables
        .tables
        .iter()
        .map(|t| {
            serde_json::json!({
                "driver": m.axes()[t.driver].letter.to_string(),
                "corrected": m.axes()[t.corrected].letter.to_string(),
                "position_unit": m.axes()[t.driver].position_unit(),
                "unit": micro_unit(m, t.corrected),
                "positions": t.positions,
                "forward": t.forward.iter().map(|v| round(to_micro(m, t.corrected, *v))).collect::<Vec<_>>(),
                "reverse": t.reverse.iter().map(|v| round(to_micro(m, t.corrected, *v))).collect::<Vec<_>>(),
            })
        })
        .collect();
    let grid = input.grid.map(|g| {
        let units: serde_json::Map<String, serde_json::Value> =
            (0..m.axis_count()).map(|a| (format!("d{}", m.axes()[a].letter), micro_unit(m, a).into())).collect();
        serde_json::json!({
            "axes": g.axes.iter().map(|&a| m.axes()[a].letter.to_string()).collect::<Vec<_>>(),
            "start": g.start, "step": g.step, "counts": g.counts, "units": units,
            "values": g.values.chunks(g.axis_count).map(|v| v.iter().enumerate().map(|(a, x)| round(to_micro(m, a, *x))).collect::<Vec<_>>()).collect::<Vec<_>>(),
        })
    });
    Ok(serde_json::json!({ "machine": m.name, "reference": reference, "tables": tables, "grid": grid }))
}
