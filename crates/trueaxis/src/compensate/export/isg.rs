//! The ISG kernel / Beckhoff TwinCAT TF5280 volumetric-compensation CSV (ISG_CSV; specs/anchors.md
//! §3): whitespace-separated columns named in a header line, `//` line comments, `#` a file break
//! followed by a new header. The controller's own kinematic model turns the *error parameters* into
//! corrections, so this exporter writes the errors (not corrections), with ISO 230-1 names: a block
//! per axis with the argument (`X`, mm; `C`, deg) and the component errors `EXX EYX EZX EAX EBX ECX`,
//! and one block of position-independent errors named without the leading `E` (`X0C Y0C A0C B0C`,
//! `C0Y` ...), as in the ISG examples. Values in mm and rad; arguments in mm and deg.
//!
//! The sign convention is ISO 230-1 (actual minus nominal of the carried body relative to its
//! parent), the one of trueaxis; a controller configured otherwise flips it with its `negate` key.
//! Direction-dependent errors are written as the mean of both directions and temperature terms at
//! 20 degC: the file says so when the model has them. Setup errors (tool, workpiece) are not machine
//! errors and are left out.

use super::{check_equal_spacing, check_user_limits, ExportInput, ExportedFile};
use crate::compensate::CompensateError;
use crate::machine::{Component, ParameterId};
use std::fmt::Write;

/// `volcomp.csv`, one block per axis and one of constants.
pub fn export(input: &ExportInput) -> Result<Vec<ExportedFile>, CompensateError> {
    check_user_limits(input)?;
    let m = input.machine;
    let reference = &input.tables.reference;
    let mut values = vec![0.0; m.parameter_count()];
    let mut q = vec![0.0; m.axis_count()];
    let mut text = String::new();
    let _ = writeln!(text, "// trueaxis: volumetric error parameters of `{}` (ISO 230-1 names)", m.name);
    let _ = writeln!(text, "// errors (actual minus nominal) in mm and rad; arguments in mm (linear) and deg (rotary)");
    let directional = input.errors.directional_entries().any(|(_, d, _)| d.is_some());
    if directional {
        let _ = writeln!(text, "// the model has direction-dependent errors: the mean of both directions is written");
    }
    if !input.errors.sensors().is_empty() {
        let _ = writeln!(text, "// the model has temperature terms: values at 20 degC");
    }
    for (k, axis) in m.axes().iter().enumerate() {
        let table = input.tables.table(k, k).expect("own-axis table of every axis");
        check_equal_spacing(&table.positions, &format!("ISG GRID block of axis {}", axis.letter))?;
        let names: Vec<String> =
            Component::ALL.iter().map(|c| ParameterId::Motion { axis: axis.letter, component: *c }.to_string()).collect();
        let _ = writeln!(text, "#\n{} {}", axis.letter, names.join(" "));
        for &x in &table.positions {
            let mut pose = reference.clone();
            pose[k] = x;
            m.pose_to_internal(&pose, &mut q);
            input.errors.values_at(m, &q, &mut values);
            let row: Vec<String> = Component::ALL.iter().map(|c| format!("{:.9e}", values[m.motion_index(k, *c)])).collect();
            let _ = writeln!(text, "{x:.6} {}", row.join(" "));
        }
    }
    m.pose_to_internal(reference, &mut q);
    input.errors.values_at(m, &q, &mut values);
    let constants: Vec<(String, f64)> = m
        .axes()
        .iter()
        .enumerate()
        .flat_map(|(k, axis)| Component::ALL.iter().map(move |c| (k, axis.letter, *c)))
        .map(|(k, letter, c)| (format!("{}0{letter}", c.letter()), values[m.location_index(k, c)]))
        .filter(|(_, v)| *v != 0.0)
        .collect();
    if !constants.is_empty() {
        let names: Vec<&str> = constants.iter().map(|(n, _)| n.as_str()).collect();
        let row: Vec<String> = constants.iter().map(|(_, v)| format!("{v:.9e}")).collect();
        let _ = writeln!(text, "#\n// position-independent (location) errors\n{}\n{}", names.join(" "), row.join(" "));
    }
    Ok(vec![ExportedFile { name: "volcomp.csv".into(), contents: text }])
}
