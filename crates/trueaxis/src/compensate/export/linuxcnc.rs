//! LinuxCNC joint compensation files (`[JOINT_n] COMP_FILE`, `COMP_FILE_TYPE`; specs/anchors.md §2):
//! one file per joint of `nominal forward reverse` triplets in machine units (mm, deg), ascending
//! nominal positions, at most 256 triplets per joint. LinuxCNC reads triplets until the first line
//! that is not one, so the files carry no comments; the INI snippet says what they hold.
//!
//! Semantics (LinuxCNC `usrmotLoadComp` and the motion controller): the trim interpolated at the
//! commanded joint position is *added* to the motor command, the forward trim while the joint moves
//! up, the reverse trim while it moves down. Type 1 files hold the trims directly, so they are the
//! corrections of trueaxis. Type 0 files hold the positions the joint actually reaches, and LinuxCNC
//! takes `trim = nominal - actual`; trueaxis writes `actual = nominal - correction`.
//!
//! Joint compensation is one-dimensional: only the own-axis tables are exported; the cross-axis
//! corrections that are left out are listed in the INI snippet and in [`Export::left_out`]. The HAL
//! component of [`super::linuxcnc_hal`] carries them.

use super::residual::{Branch, Interpolation, TableSum};
use super::{
    check_count, check_equal_spacing, check_rotary_closure, check_user_limits, closure_tolerance, cross_axis_left_out, Export, ExportInput,
    ExportedFile,
};
use crate::compensate::CompensateError;
use std::fmt::Write;

/// Most triplets LinuxCNC accepts per joint.
pub const MAX_TRIPLETS: usize = 256;

/// `COMP_FILE_TYPE` 0 (positions) or 1 (trims).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompType {
    Positions = 0,
    Trims = 1,
}

/// One `<letter>.comp` file per axis and `linuxcnc-comp.ini` (the INI lines that load them). Joint
/// numbers follow the machine's canonical axis order (trivkins: X=0, Y=1, ...).
pub fn export<'a>(input: &ExportInput<'a>, comp_type: CompType) -> Result<Export<'a>, CompensateError> {
    check_user_limits(input)?;
    let m = input.machine;
    let mut files = Vec::new();
    let mut ini = String::from("# trueaxis: joint compensation files for LinuxCNC; add these lines to the machine's INI file\n");
    let _ = writeln!(ini, "# machine: {}; corrections in machine units (mm, deg), added to the joint command", m.name);
    for (joint, axis) in m.axes().iter().enumerate() {
        let table = input.tables.table(joint, joint).expect("own-axis table of every axis");
        let what = format!("LinuxCNC compensation table of joint {joint} ({})", axis.letter);
        check_count(table.positions.len(), MAX_TRIPLETS, &what)?;
        check_equal_spacing(&table.positions, &what)?;
        check_rotary_closure(m, table, closure_tolerance(m, joint))?;
        let mut text = String::new();
        for ((&nominal, &f), &r) in table.positions.iter().zip(&table.forward).zip(&table.reverse) {
            let (second, third) = match comp_type {
                CompType::Trims => (f, r),
                CompType::Positions => (nominal - f, nominal - r),
            };
            let _ = writeln!(text, "{nominal:.6} {second:.6} {third:.6}");
        }
        let name = format!("{}.comp", axis.letter);
        let _ = writeln!(ini, "\n[JOINT_{joint}]\nCOMP_FILE = {name}\nCOMP_FILE_TYPE = {}", comp_type as i32);
        files.push(ExportedFile { name, contents: text });
    }
    let left_out = cross_axis_left_out(input);
    if !left_out.is_empty() {
        let _ = writeln!(ini, "\n# not representable in joint compensation (use --format linuxcnc-hal for these):");
        for d in &left_out {
            let _ = writeln!(ini, "#   {d}");
        }
    }
    files.push(ExportedFile { name: "linuxcnc-comp.ini".into(), contents: ini });
    let own = input.tables.tables.iter().filter(|t| t.is_own_axis()).map(|t| (t.clone(), Branch::Directional)).collect();
    Ok(Export { files, applied: Box::new(TableSum { machine: m, tables: own, interpolation: Interpolation::Linear }), left_out })
}
