//! SINUMERIK swivel data: the toolholder with orientation capability that CYCLE800 (swiveling)
//! and the orientation transformation of a swivel head or table use, with the fine offsets that
//! the kinematics measurement cycle CYCLE996 (CYCLE9960 on SINUMERIK ONE) writes (Function
//! Manual Basic Functions W1, "Toolholder with orientation capability"; SINUMERIK Operate
//! Commissioning Manual, "Swiveling": offset vectors I1 to I4, rotary axis vectors V1, V2).
//!
//! The data record `m` (`$TC_CARRn[m]`): offset vectors l1 `$TC_CARR1-3`, l2 `4-6`, l3 `15-17`,
//! l4 `18-20` (mm, machine X Y Z components at the basic setting, rotary axes at zero); rotary axis
//! vectors v1 `7-9`, v2 `10-12`; axis names `21`, `22`; kinematic type `23` (`"T"` the tool rotates,
//! `"P"` the part, `"M"` one of each); rotary axis offsets `24`, `25` (deg: the axis position of the
//! basic setting); fine offsets, added to the basic values with the number plus 40: l1 `41-43`, l2
//! `44-46`, l3 `55-57`, l4 `58-60`, axis offsets `64`, `65`. The vectors chain as the manual draws
//! them (I2, I3 from the machine reference point or tool adapter to the pivot of rotary axis 1 and
//! on to rotary axis 2; I1 or I4 the closure):
//!
//! ```text
//! P (table):  x_machine = l2 + R1 (l3 + R2 (l4 + x_table))
//! T (head):   reference - tip = l1 + R1 (l2 + R2 (l3 + T))     T: tool length vector, tip to adapter
//! M (mixed):  reference - tip = l1 + R1 (l2 + T),  x_machine = l3 + R2 (l4 + x_table)
//! ```
//!
//! with `Ri` the rotation about `vi` by the axis position minus its offset (right-hand rule, the
//! direction the axis turns its body; the manual's rule that a rotary axis moving the workpiece has
//! the opposite vector applies to machines whose axis senses follow ISO 841: trueaxis writes the
//! machine file's direction, in which positive motion turns the table). Rotary axis 1 is the one
//! nearer the machine (the second rides on it); with mixed kinematics the head axis.
//!
//! trueaxis writes the whole data record: the basic vectors of the machine file's nominal geometry
//! (in its frame M, whose origin is the reference point of a table; the reference point of a head is
//! where the machine file's tool point is at home, and the tool adapter is taken at the tool point
//! with tool length 0), the rotary axis vectors as identified, and the identified shifts of the axis
//! lines (and, on a head, of the tool point) as fine offsets, so that basic plus fine is the
//! identified geometry. Units: mm, deg.

use super::ExportedFile;
use crate::compensate::kinematic::{KinematicDescription, RotaryKind, RotaryLayout};
use crate::compensate::CompensateError;
use crate::geometry::Vec3;
use crate::machine::Machine;
use std::fmt::Write;

/// The quantities of one swivel data record (mm, unit vectors, deg).
#[derive(Clone, Debug, PartialEq)]
pub struct SwivelData {
    pub kind: char,
    /// l1 .. l4.
    pub offsets: [Vec3; 4],
    /// v1, v2 (v2 zero with one rotary axis).
    pub vectors: [Vec3; 2],
    /// Rotary axis offsets of v1 and v2: the position of the basic setting (deg).
    pub axis_offsets: [f64; 2],
}

/// The swivel data of `description` for the rotary axes of `layout`.
pub fn swivel_data(machine: &Machine, layout: &RotaryLayout, description: &KinematicDescription) -> SwivelData {
    let line = |k: usize| &description.axes[k];
    let p1 = line(layout.first).point;
    let p2 = layout.second.map(|k| line(k).point);
    // the head's reference point: where the machine file's tool point is at home; the tool adapter:
    // where the description puts the tool point (moved with the head's identified geometry)
    let reference = machine.tool_point;
    let adapter = description.tool_end.transform_point(&machine.tool_point);
    let zero = Vec3::zeros();
    let (kind, offsets) = match layout.kind {
        RotaryKind::Table => {
            let p2 = p2.unwrap_or(p1);
            ('P', [zero, p1, p2 - p1, -p2])
        }
        RotaryKind::Head => {
            let p2 = p2.unwrap_or(adapter);
            ('T', [reference - p1, p1 - p2, p2 - adapter, zero])
        }
        RotaryKind::Mixed => {
            let p2 = p2.expect("a mixed layout has two rotary axes");
            ('M', [reference - p1, p1 - adapter, p2, -p2])
        }
    };
    let vectors = [line(layout.first).direction, layout.second.map_or(zero, |k| line(k).direction)];
    let offset = |k: Option<usize>| k.map_or(0.0, |k| -line(k).zero_offset.to_degrees());
    SwivelData { kind, offsets, vectors, axis_offsets: [offset(Some(layout.first)), offset(layout.second)] }
}

/// The numbers of `$TC_CARR` of the x components of l1 .. l4 and their fine offsets.
const OFFSET_NUMBERS: [(usize, usize); 4] = [(1, 41), (4, 44), (15, 55), (18, 58)];

/// `TC_CARR.INI`: swivel data record `record` with basic values from `nominal` and fine offsets
/// taking it to `written` (the identified description), for the rotary axes of `layout`.
pub fn export(
    machine: &Machine,
    layout: &RotaryLayout,
    nominal: &KinematicDescription,
    written: &KinematicDescription,
    record: usize,
) -> Result<ExportedFile, CompensateError> {
    let basic = swivel_data(machine, layout, nominal);
    let actual = swivel_data(machine, layout, written);
    let name = |k: usize| super::siemens::axis_name(machine, k);
    let mut text = String::from("%_N_TC_CARR_INI\n");
    let _ = writeln!(
        text,
        "; swivel data record {record} (toolholder with orientation capability, kinematic type {}) of `{}`",
        basic.kind, machine.name
    );
    text.push_str(
        "; written by trueaxis (docs/compensation.md, Five-axis machines): the machine file's nominal geometry as the basic\n\
         ; offset vectors (frame of the machine file, its origin the reference point, the tool adapter at its tool point),\n\
         ; the identified rotary axis vectors, and the identified shifts of the axis lines and axis zero offsets as fine\n\
         ; offsets ($TC_CARR41-65, added to the basic values: W1, toolholder with orientation capability, fine offset).\n\
         ; If the controller's basic vectors refer to another reference point, keep them and load only the rotary axis\n\
         ; vectors ($TC_CARR7-12) and the fine offsets. Set the workpiece datum again by probing afterwards.\n\
         ; Units: mm, deg.\n",
    );
    text.push_str("CHANDATA(1)\n");
    for (i, (&(number, fine), (b, a))) in OFFSET_NUMBERS.iter().zip(basic.offsets.iter().zip(&actual.offsets)).enumerate() {
        let _ = writeln!(text, "; l{}", i + 1);
        for c in 0..3 {
            let _ = writeln!(text, "$TC_CARR{}[{record}]={}", number + c, super::signed(b[c], 6));
        }
        for c in 0..3 {
            let _ = writeln!(text, "$TC_CARR{}[{record}]={}", fine + c, super::signed(a[c] - b[c], 6));
        }
    }
    for (i, v) in actual.vectors.iter().enumerate() {
        let _ = writeln!(text, "; v{}", i + 1);
        for c in 0..3 {
            let _ = writeln!(text, "$TC_CARR{}[{record}]={}", 7 + 3 * i + c, super::signed(v[c], 9));
        }
    }
    let _ = writeln!(text, "$TC_CARR21[{record}]={}", name(layout.first));
    if let Some(k) = layout.second {
        let _ = writeln!(text, "$TC_CARR22[{record}]={}", name(k));
    }
    let _ = writeln!(text, "$TC_CARR23[{record}]=\"{}\"", basic.kind);
    for (i, (b, a)) in basic.axis_offsets.iter().zip(&actual.axis_offsets).enumerate() {
        let _ = writeln!(text, "$TC_CARR{}[{record}]={}", 24 + i, super::signed(*b, 7));
        let _ = writeln!(text, "$TC_CARR{}[{record}]={}", 64 + i, super::signed(a - b, 7));
    }
    text.push_str("M17\n");
    if text.contains("NaN") || text.contains("inf") {
        return Err(CompensateError::Computation("the swivel data are not finite numbers".into()));
    }
    Ok(ExportedFile { name: "TC_CARR.INI".into(), contents: text })
}
