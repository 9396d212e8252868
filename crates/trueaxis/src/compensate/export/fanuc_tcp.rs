//! Fanuc tool centre point control for 5-axis machining (Series 30i-MODEL A additional manual
//! A-79348E; Series 16i/18i-MB tilted working plane, A-78712E): the positions of the rotary axes
//! that the control's five-axis functions compute with, as programmable parameter input (`G10 L52`).
//!
//! Parameters (real, mm, in the machine coordinate system with the rotary axes at 0 deg):
//! 19700-19702 rotary table position (from the origin of the machine coordinate system to a point on
//! the first rotary axis of the table), 19703-19705 intersection offset vector from that point to a
//! point on the second rotary axis of the table, 19709-19711 intersection offset vector from the tool
//! axis to the (second) rotary axis of the tool, 19712-19714 from the second to the first rotary
//! axis of the tool. Parameter 19680 (mechanical unit type: 2 tool, 12 table, 21 mixed) is the
//! builder's and stays. The zero offset of a rotary axis is a shift of its reference position
//! (parameter 1240, coordinate of the reference position in the machine coordinate system, deg).
//!
//! What these parameters cannot hold: the direction of a rotary axis is one of the machine axes (or
//! an inclination in one plane, parameters 19682/19683), so a tilt of a rotary axis has no place; it
//! is left out and its effect is in the error the files leave.

use super::ExportedFile;
use crate::compensate::kinematic::{KinematicCorrection, RotaryKind, RotaryLayout};
use crate::compensate::CompensateError;
use crate::geometry::Vec3;
use crate::machine::Machine;
use std::fmt::Write;

/// `tcp_parameters.nc` and the lines of what the parameters leave out (the rotary axes' tilts).
pub fn export(
    machine: &Machine,
    layout: &RotaryLayout,
    kinematics: &KinematicCorrection,
) -> Result<(Vec<ExportedFile>, Vec<String>), CompensateError> {
    let written = &kinematics.written;
    let point = |k: usize| written.axes[k].point;
    let mut vectors: Vec<(usize, &str, Vec3)> = Vec::new();
    match layout.kind {
        RotaryKind::Table => {
            vectors.push((19700, "rotary table position (to the first rotary axis of the table)", point(layout.first)));
            if let Some(second) = layout.second {
                vectors.push((19703, "intersection offset, first to second rotary axis of the table", point(second) - point(layout.first)));
            }
        }
        RotaryKind::Head | RotaryKind::Mixed => {
            let tool_axis = layout.second.filter(|_| layout.kind == RotaryKind::Head).unwrap_or(layout.first);
            let tool_point = written.tool_end.transform_point(&machine.tool_point);
            vectors.push((
                19709,
                "intersection offset, tool axis to the rotary axis of the tool next to it",
                point(tool_axis) - tool_point,
            ));
            if layout.kind == RotaryKind::Head {
                vectors.push((
                    19712,
                    "intersection offset, second to first rotary axis of the tool",
                    point(layout.first) - point(tool_axis),
                ));
            } else if let Some(table) = layout.second {
                vectors.push((19700, "rotary table position", point(table)));
            }
        }
    }
    let mut text = String::from("%\n");
    let _ = writeln!(text, "(TOOL CENTRE POINT PARAMETERS - TRUEAXIS - {})", machine.name.to_uppercase().replace(['(', ')'], ""));
    text.push_str(
        "(VECTORS IN MM IN THE MACHINE FRAME OF THE MACHINE FILE, ROTARY AXES AT 0 DEG; ITS ORIGIN MUST BE THE)\n\
         (ORIGIN OF THE MACHINE COORDINATE SYSTEM. PARAMETER WRITE ENABLE (PWE) ON; POWER OFF AND ON AFTER.)\n\
         G10 L52\n",
    );
    for (number, what, v) in &vectors {
        let _ = writeln!(text, "({})", what.to_uppercase());
        for (c, value) in v.iter().enumerate() {
            let _ = writeln!(text, "N{} R{:.4}", number + c, value);
        }
    }
    for &k in &layout.axes() {
        let delta = written.axes[k].zero_offset.to_degrees();
        let _ = writeln!(
            text,
            "(ZERO OFFSET OF {}: ADD {:.6} DEG TO PARAMETER 1240 OF THE AXIS, THE REFERENCE POSITION)",
            machine.axes()[k].letter,
            -delta
        );
    }
    text.push_str("G11\nM30\n%\n");
    let left_out = layout
        .axes()
        .iter()
        .filter_map(|&k| {
            let tilt = crate::compensate::kinematic::smallest_rotation(&machine.axes()[k].direction, &kinematics.actual.axes[k].direction);
            let urad = crate::geometry::rotation_log(&tilt).norm() * 1e6;
            (urad >= 0.05).then(|| {
                format!(
                    "tilt of rotary axis {} ({urad:.1} urad): the Fanuc tool centre point parameters hold axis positions, not directions",
                    machine.axes()[k].letter
                )
            })
        })
        .collect();
    Ok((vec![ExportedFile { name: "tcp_parameters.nc".into(), contents: text }], left_out))
}
