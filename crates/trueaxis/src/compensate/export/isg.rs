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
//!
//! Beside the parameter file the controller needs the compensation's list file (TF5280 "General
//! configuration", P-VOLC parameters): the logical axis number of each participating axis (`X 1`
//! ...), the kinematic chain (`chain`, the axis names in order, P-VOLC-00007), the number of
//! workpiece axes (`workpiece_axes`), and the parameter files with their format (`file[0]`,
//! `file_format[0] ISG_CSV`); the startup list points to it (`vol_comp[0].file_name`,
//! P-STUP-00101) and bounds the records (`vol_comp[0].max_records`). `volcomp1.lis` is that list
//! file; the startup-list lines are in its head comment. The chain is written in the order of the
//! TF5240 universal kinematics (from the workpiece to the machine origin, then to the tool tip),
//! the logical axis numbers as 1, 2, ... in the machine's axis order: both must be checked against
//! the controller's configuration.

use super::residual::ModelCorrection;
use super::{check_equal_spacing, check_user_limits, direction_left_out, Export, ExportInput, ExportedFile};
use crate::compensate::CompensateError;
use crate::error_model::{ErrorFunction, ErrorModel};
use crate::machine::{Component, ParameterId, SetupSide};
use std::fmt::Write;

/// `volcomp.csv`, one block per axis and one of constants, and its list file `volcomp1.lis`.
pub fn export<'a>(input: &ExportInput<'a>) -> Result<Export<'a>, CompensateError> {
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
    // the parameters as written, for the correction the controller computes from them (a table of
    // the program's own sampling that does not build is a failed computation)
    let failed = |e: crate::Error| CompensateError::Computation(e.to_string());
    let mut written = ErrorModel::zero(m);
    let mut records = 0;
    for (k, axis) in m.axes().iter().enumerate() {
        let table = input.tables.table(k, k).expect("own-axis table of every axis");
        check_equal_spacing(&table.positions, &format!("ISG GRID block of axis {}", axis.letter))?;
        let names: Vec<String> =
            Component::ALL.iter().map(|c| ParameterId::Motion { axis: axis.letter, component: *c }.to_string()).collect();
        let _ = writeln!(text, "#\n{} {}", axis.letter, names.join(" "));
        let mut columns = vec![Vec::new(); Component::ALL.len()];
        for &x in &table.positions {
            let mut pose = reference.clone();
            pose[k] = x;
            m.pose_to_internal(&pose, &mut q);
            input.errors.values_at(m, &q, &mut values);
            let row: Vec<String> = Component::ALL.iter().map(|c| format!("{:.9e}", values[m.motion_index(k, *c)])).collect();
            let _ = writeln!(text, "{x:.6} {}", row.join(" "));
            for (column, c) in columns.iter_mut().zip(Component::ALL) {
                column.push(row_value(&values, m.motion_index(k, c), c));
            }
            records += 1;
        }
        for (column, c) in columns.into_iter().zip(Component::ALL) {
            let id = ParameterId::Motion { axis: axis.letter, component: c };
            let f = ErrorFunction::table(table.positions.clone(), column, None).map_err(failed)?;
            written.set(m, id, f).map_err(failed)?;
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
        records += 1;
    }
    for (k, axis) in m.axes().iter().enumerate() {
        for c in Component::ALL {
            let v = values[m.location_index(k, c)];
            if v != 0.0 {
                let id = ParameterId::Location { axis: axis.letter, component: c };
                written.set(m, id, ErrorFunction::Constant(v / c.to_internal())).map_err(failed)?;
            }
        }
    }
    let mut left_out = direction_left_out(input, |_| true);
    if !input.errors.sensors().is_empty() {
        left_out.push(format!("temperature terms (sensors {}): the file holds the errors at 20 degC", input.errors.sensors().join(", ")));
    }
    for side in [SetupSide::Tool, SetupSide::Workpiece] {
        let i = m.setup_index(side, Component::X);
        if values[i..i + 3].iter().any(|v| *v != 0.0) {
            left_out.push(format!("the {side:?} setup errors (not machine errors)").to_lowercase());
        }
    }
    left_out.push("the orientation of the tool (the controller compensates the tool position only)".into());
    let files = vec![
        ExportedFile { name: "volcomp.csv".into(), contents: text },
        ExportedFile { name: "volcomp1.lis".into(), contents: list_file(m, records) },
    ];
    Ok(Export { files, applied: Box::new(ModelCorrection { machine: m, errors: written }), left_out })
}

/// A parameter value (mm, rad) in the unit of an error-values file (um, urad).
fn row_value(values: &[f64], index: usize, c: Component) -> f64 {
    values[index] / c.to_internal()
}

/// The list file of the compensation (TF5280 "General configuration"): axis assignment, chain,
/// workpiece axes, parameter file and format; the startup-list lines in its head comment.
fn list_file(m: &crate::machine::Machine, records: usize) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "# trueaxis: list file of the volumetric compensation of `{}` (ISG kernel / TwinCAT TF5280)", m.name);
    let _ = writeln!(text, "# startup list (hochlauf.lis) lines that load it:");
    let _ = writeln!(text, "#   vol_comp[0].file_name    volcomp1.lis");
    let _ = writeln!(text, "#   vol_comp[0].max_records  {}", records.max(1));
    let _ = writeln!(text, "# logical axis numbers: 1, 2, ... in the machine file's axis order; check them against the channel");
    for (k, a) in m.axes().iter().enumerate() {
        let _ = writeln!(text, "{}    {}", a.letter, k + 1);
    }
    let letters = |chain: &[usize]| chain.iter().map(|&k| m.axes()[k].letter).collect::<String>();
    // workpiece to machine origin (the workpiece chain from its far end), then out to the tool tip
    let mut work: Vec<usize> = m.work_chain().to_vec();
    work.reverse();
    let _ = writeln!(text, "chain    {}{}", letters(&work), letters(m.tool_chain()));
    let _ = writeln!(text, "workpiece_axes    {}", work.len());
    let _ = writeln!(text, "file[0]    volcomp.csv");
    let _ = writeln!(text, "file_format[0]    ISG_CSV");
    text
}
