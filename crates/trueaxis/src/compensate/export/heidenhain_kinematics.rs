//! Heidenhain kinematics changes, as the touch-probe cycle 451 MEASURE KINEMATICS (KinematicsOpt,
//! TNC 640 / iTNC 530 cycle programming manuals) makes them: for each rotary axis the change of its
//! position (the shift of the axis line) and of its orientation (the tilt of the axis), which the
//! control saves in the transformations of its kinematics description, and the rotary axis's zero
//! offset, which cycle 452 PRESET COMPENSATION and the preset table's rotary-axis columns hold.
//!
//! The kinematics description itself is edited by the machine tool builder (its transformation
//! lines are machine-specific and not public), so trueaxis writes the changes as a log in the terms
//! of the cycle 451 log (TCHPR451.TXT: "compensation values in all axes"), one block per rotary
//! axis, with the nominal and identified axis line so that the integrator can enter them, or compare
//! them with what cycle 451 finds. Positions in mm, angles in deg, in the machine frame of the
//! machine file (its axes are the machine's X, Y, Z).

use super::ExportedFile;
use crate::compensate::kinematic::{smallest_rotation, KinematicDescription, RotaryLayout};
use crate::geometry::{rotation_log, Vec3};
use crate::machine::Machine;
use std::fmt::Write;

/// The change of one rotary axis line: its point's shift (mm), the rotation vector of its direction
/// (rad, perpendicular to the nominal direction), its zero offset (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisChange {
    pub shift: Vec3,
    pub tilt: Vec3,
    pub zero_offset: f64,
}

/// The change of rotary axis `k` from `nominal` to `written`.
pub fn axis_change(nominal: &KinematicDescription, written: &KinematicDescription, k: usize) -> AxisChange {
    let (n, w) = (&nominal.axes[k], &written.axes[k]);
    AxisChange { shift: w.point - n.point, tilt: rotation_log(&smallest_rotation(&n.direction, &w.direction)), zero_offset: w.zero_offset }
}

fn vector(v: &Vec3, decimals: usize) -> String {
    format!("X {}  Y {}  Z {}", super::signed(v.x, decimals), super::signed(v.y, decimals), super::signed(v.z, decimals))
}

/// `KINEMATICS.TXT`: the changes of the rotary axes of `layout`.
pub fn export(machine: &Machine, layout: &RotaryLayout, nominal: &KinematicDescription, written: &KinematicDescription) -> ExportedFile {
    let mut text = format!("KINEMATICS CHANGES - trueaxis - {}\n", machine.name);
    text.push_str(
        "Changes of the rotary axes in the kinematics description, in the terms of cycle 451 MEASURE KINEMATICS\n\
         (position = shift of the axis line; orientation = tilt of the axis; zero offset = preset of the rotary axis).\n\
         Machine frame of the machine file; positions in mm, angles in deg. After loading them, set the presets of the\n\
         workpieces again by probing (as after cycle 451).\n",
    );
    for (i, &k) in layout.axes().iter().enumerate() {
        let axis = &machine.axes()[k];
        let c = axis_change(nominal, written, k);
        let (n, w) = (&nominal.axes[k], &written.axes[k]);
        let _ = writeln!(
            text,
            "\nROTARY AXIS {} ({} rotary axis, on the {})",
            axis.letter,
            ["first", "second"][i],
            match axis.side {
                crate::machine::Side::Workpiece => "table",
                crate::machine::Side::Tool => "head",
            }
        );
        let _ = writeln!(text, "  nominal position     {}", vector(&n.point, 6));
        let _ = writeln!(text, "  nominal direction    {}", vector(&n.direction, 9));
        let _ = writeln!(text, "  position change      {}", vector(&c.shift, 6));
        let _ = writeln!(text, "  orientation change   {}", vector(&(c.tilt * 1f64.to_degrees()), 7));
        let _ = writeln!(text, "  zero offset          {} {}", axis.letter, super::signed(c.zero_offset.to_degrees(), 7));
        let _ = writeln!(text, "  identified position  {}", vector(&w.point, 6));
        let _ = writeln!(text, "  identified direction {}", vector(&w.direction, 9));
        let across = c.shift - n.direction * n.direction.dot(&c.shift);
        let _ = writeln!(
            text,
            "  ({:.1} um across the axis, {:.1} urad of tilt; the zero offset: at a commanded position q the axis stands at q {} {:.1} urad)",
            across.norm() * 1e3,
            c.tilt.norm() * 1e6,
            if c.zero_offset < 0.0 { "-" } else { "+" },
            c.zero_offset.abs() * 1e6
        );
    }
    ExportedFile { name: "KINEMATICS.TXT".into(), contents: text }
}
