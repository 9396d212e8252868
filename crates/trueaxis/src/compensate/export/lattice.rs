//! A three-dimensional compensation lattice as plain data: compensation vectors `(CX, CY, CZ)` at
//! the points of a regular lattice over X, Y, Z, to be interpolated trilinearly over the 8 vertices
//! of the cell that contains the position (the scheme of Fanuc 30i "three-dimensional error
//! compensation", specs/anchors.md §3). It is **no file a controller loads**: Fanuc enters its
//! lattice through series-specific parameters that the public documentation does not give. This is
//! the neutral listing to convert: a header with the origin, pitch and number of points per axis,
//! then one line per point `I J K CX CY CZ` (indices from 0, X fastest; corrections in um, added to
//! the position). The corrections of other (rotary) axes are not in it.
//!
//! Checks: equal pitch per axis (a lattice has one pitch), at least 2 points per axis, the user's
//! correction limit, and an optional maximum number of points (the series' limit, which the stored
//! documentation does not give: pass it when known).

use super::residual::{GridSum, Interpolation, TableSum};
use super::{check_count, check_equal_spacing, check_user_limits, micro_unit, to_micro, Export, ExportInput, ExportedFile};
use crate::compensate::CompensateError;
use std::fmt::Write;

/// `lattice3d.txt` from the volumetric grid; `max_points` limits the total number of points.
pub fn export<'a>(input: &ExportInput<'a>, max_points: Option<usize>) -> Result<Export<'a>, CompensateError> {
    check_user_limits(input)?;
    let m = input.machine;
    let g = input.grid.ok_or_else(|| CompensateError::Input("the Fanuc 3D lattice needs a volumetric grid".into()))?;
    let letters = g.axes.map(|a| m.axes()[a].letter);
    for (d, letter) in letters.iter().enumerate() {
        let positions: Vec<f64> = (0..g.counts[d]).map(|i| g.start[d] + g.step[d] * i as f64).collect();
        check_equal_spacing(&positions, &format!("3D lattice along {letter}"))?;
    }
    if let Some(max) = max_points {
        check_count(g.counts.iter().product(), max, "the 3D lattice")?;
    }
    let mut text = String::new();
    let _ = writeln!(text, "; trueaxis three-dimensional compensation lattice (plain data, no controller format), machine `{}`", m.name);
    let _ = writeln!(text, "; corrections in um, added to the position; trilinear interpolation between lattice points");
    let others: Vec<String> = m
        .axes()
        .iter()
        .enumerate()
        .filter(|(k, _)| !g.axes.contains(k))
        .map(|(k, a)| format!("{}={} {}", a.letter, g.reference[k], a.position_unit()))
        .collect();
    if !others.is_empty() {
        let _ = writeln!(text, "; other axes at {}", others.join(" "));
    }
    let _ = writeln!(text, "ORIGIN {:.4} {:.4} {:.4}", g.start[0], g.start[1], g.start[2]);
    let _ = writeln!(text, "PITCH {:.4} {:.4} {:.4}", g.step[0], g.step[1], g.step[2]);
    let _ = writeln!(text, "POINTS {} {} {}", g.counts[0], g.counts[1], g.counts[2]);
    let _ = writeln!(text, "; I J K C{} C{} C{}", letters[0], letters[1], letters[2]);
    for k in 0..g.counts[2] {
        for j in 0..g.counts[1] {
            for i in 0..g.counts[0] {
                let base = g.node(i, j, k) * g.axis_count;
                let c: Vec<String> = g.axes.iter().map(|&a| format!("{:.3}", g.values[base + a] * 1e3)).collect();
                let _ = writeln!(text, "{i} {j} {k} {}", c.join(" "));
            }
        }
    }
    // the corrections of the other axes at the nodes are not written
    let left_out = (0..m.axis_count())
        .filter(|k| !g.axes.contains(k))
        .filter_map(|k| {
            let largest = g.values.chunks(g.axis_count).map(|v| to_micro(m, k, v[k]).abs()).fold(0.0, f64::max);
            (largest >= 5e-4).then(|| format!("corrections of axis {}: up to {largest:.3} {}", m.axes()[k].letter, micro_unit(m, k)))
        })
        .collect();
    let applied = GridSum {
        grid: g,
        grid_columns: g.axes.to_vec(),
        tables: TableSum { machine: m, tables: Vec::new(), interpolation: Interpolation::Linear },
    };
    Ok(Export { files: vec![ExportedFile { name: "lattice3d.txt".into(), contents: text }], applied: Box::new(applied), left_out })
}
