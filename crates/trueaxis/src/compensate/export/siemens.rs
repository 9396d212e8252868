//! SINUMERIK 840D sl interpolatory compensation (Function Manual Extended Functions, K3
//! "Compensations": "Measuring system error compensation" and "Sag compensation"; the same system
//! variables on the 828D and 808D).
//!
//! Two init programs, as the manual's examples load them:
//! - `AX_EEC.INI` (`%_N_AX_EEC_INI`): leadscrew / measuring system error compensation (LEC), one
//!   table per axis on its first measuring system: `$AA_ENC_COMP[0,<N>,<axis>]` the compensation
//!   value of interpolation point N, `$AA_ENC_COMP_STEP`, `_MIN`, `_MAX` the point distance, first
//!   and last position, `$AA_ENC_COMP_IS_MODULO` for a rotary axis over a full turn;
//! - `NC_CEC.INI` (`%_N_NC_CEC_INI`): sag / angularity compensation (CEC) tables
//!   `$AN_CEC[<t>,<N>]` with `$AN_CEC_INPUT_AXIS[<t>]` (basic axis), `$AN_CEC_OUTPUT_AXIS[<t>]`
//!   (compensation axis), `$AN_CEC_STEP`, `_MIN`, `_MAX`, `$AN_CEC_DIRECTION` (0 both directions, 1
//!   only positive, -1 only negative traverse of the basic axis), `$AN_CEC_MULT_BY_TABLE` (0: none)
//!   and `$AN_CEC_IS_MODULO`. The own-axis tables' direction-dependent part is a pair of CEC tables
//!   of the axis on itself with directions 1 and -1 (the manual's position-dependent backlash); each
//!   non-zero cross-axis table is one CEC table (two when its directions differ).
//!
//! Sign (K3 "Terms"; 808D function manual, LEC): the compensation value is the difference between
//! the position the encoder measures and the ideal one, and "a positive compensation value causes
//! the corresponding machine axis to move in the negative direction". The values written are
//! therefore minus the trueaxis corrections, in mm (deg for rotary axes), 6 decimals. Linear
//! interpolation between points; outside the table the first / last value holds.
//!
//! Limits: a table holds at most the points configured in MD38000 `$MA_MM_ENC_COMP_MAX_POINTS`
//! (LEC) and MD18342 `$MN_MM_CEC_MAX_POINTS[t]` (CEC), bounded by the static user memory; the 828D
//! offers eight CEC tables of 200 points. The head comment of each program lists the machine data to
//! set; the tables can only be loaded while the compensation is off (MD32700 / MD32710 = 0).
//! Machine axis names are the default ones, `X1 Y1 Z1 A1 ...` (MD10000).

use super::residual::{Branch, Interpolation, TableSum};
use super::{
    check_count, check_equal_spacing, check_rotary_closure, check_user_limits, closure_tolerance, Export, ExportInput, ExportedFile,
};
use crate::compensate::tables::AxisTable;
use crate::compensate::CompensateError;
use crate::machine::{AxisKind, Machine};
use std::fmt::Write;

/// Table sizes the controller is configured for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SiemensLimits {
    /// Most interpolation points per table (MD38000 and MD18342).
    pub max_points: usize,
    /// Most sag-compensation (CEC) tables.
    pub max_cec_tables: usize,
}

impl Default for SiemensLimits {
    /// The SINUMERIK 828D's eight CEC tables of 200 points (K3); an 840D sl is configured for more
    /// through MD18342 / MD38000.
    fn default() -> Self {
        SiemensLimits { max_points: 200, max_cec_tables: 8 }
    }
}

/// Values below half a nanometre (or nano-degree) count as zero.
const ZERO: f64 = 5e-7;

/// Machine axis name of axis `k` (default MD10000 names).
pub fn axis_name(m: &Machine, k: usize) -> String {
    format!("{}1", m.axes()[k].letter)
}

/// A CEC table to write: basic axis, compensation axis, direction, values (corrections, mm or deg).
struct Cec<'t> {
    table: &'t AxisTable,
    direction: i32,
    values: Vec<f64>,
}

/// `AX_EEC.INI` and, when any CEC table is needed, `NC_CEC.INI`.
pub fn export<'a>(input: &ExportInput<'a>, limits: SiemensLimits) -> Result<Export<'a>, CompensateError> {
    check_user_limits(input)?;
    let m = input.machine;
    let mut lec = head(m, "AX_EEC", "leadscrew / measuring system error compensation (LEC)");
    let mut cecs: Vec<Cec> = Vec::new();
    let mut carried = Vec::new();
    let mut machine_data = Vec::new();
    for (k, _) in m.axes().iter().enumerate() {
        let own = input.tables.table(k, k).expect("own-axis table of every axis");
        let what = format!("Siemens compensation table of {}", axis_name(m, k));
        check_count(own.positions.len(), limits.max_points, &what)?;
        check_equal_spacing(&own.positions, &what)?;
        for t in input.tables.tables.iter().filter(|t| t.driver == k) {
            check_rotary_closure(m, t, closure_tolerance(m, t.corrected))?;
        }
        let mean: Vec<f64> = own.forward.iter().zip(&own.reverse).map(|(f, r)| 0.5 * (f + r)).collect();
        let name = axis_name(m, k);
        for (i, v) in mean.iter().enumerate() {
            let _ = writeln!(lec, "$AA_ENC_COMP[0,{i},{name}]={}", super::signed(-v, 6));
        }
        let (min, max, step) = span(own);
        let _ = writeln!(lec, "$AA_ENC_COMP_STEP[0,{name}]={step:.6}");
        let _ = writeln!(lec, "$AA_ENC_COMP_MIN[0,{name}]={min:.6}");
        let _ = writeln!(lec, "$AA_ENC_COMP_MAX[0,{name}]={max:.6}");
        let _ = writeln!(lec, "$AA_ENC_COMP_IS_MODULO[0,{name}]={}", i32::from(is_full_turn(m, own)));
        machine_data.push(format!("MD38000 $MA_MM_ENC_COMP_MAX_POINTS[0,{name}] >= {}", own.positions.len()));
        machine_data.push(format!("MD32700 $MA_ENC_COMP_ENABLE[0,{name}] = 1 (0 while loading AX_EEC.INI)"));
        carried.push((own.clone(), Branch::Directional));
        // the direction-dependent part of the own axis: two CEC tables on itself
        if own.forward.iter().zip(&own.reverse).any(|(f, r)| (f - r).abs() > 2.0 * ZERO) {
            cecs.push(Cec { table: own, direction: 1, values: own.forward.iter().zip(&mean).map(|(f, a)| f - a).collect() });
            cecs.push(Cec { table: own, direction: -1, values: own.reverse.iter().zip(&mean).map(|(r, a)| r - a).collect() });
        }
    }
    lec.push_str("M17\n");
    for t in input.tables.tables.iter().filter(|t| !t.is_own_axis() && t.max_abs() > ZERO) {
        if t.forward.iter().zip(&t.reverse).all(|(f, r)| (f - r).abs() <= ZERO) {
            cecs.push(Cec { table: t, direction: 0, values: t.forward.iter().zip(&t.reverse).map(|(f, r)| 0.5 * (f + r)).collect() });
        } else {
            cecs.push(Cec { table: t, direction: 1, values: t.forward.clone() });
            cecs.push(Cec { table: t, direction: -1, values: t.reverse.clone() });
        }
        carried.push((t.clone(), Branch::Directional));
    }
    if cecs.len() > limits.max_cec_tables {
        return Err(CompensateError::Limit(format!(
            "the Siemens sag compensation needs {} CEC tables but the controller takes {} (the 828D's 8 by default; pass \
             --max-cec-tables for an 840D sl configured with more through MD18342); nothing was written",
            cecs.len(),
            limits.max_cec_tables
        )));
    }
    let mut files = vec![];
    if !cecs.is_empty() {
        files.push(ExportedFile { name: "NC_CEC.INI".into(), contents: cec_program(m, &cecs, &mut machine_data) });
    }
    let lec = lec.replacen("; MACHINE DATA\n", &machine_data_block(&machine_data), 1);
    files.insert(0, ExportedFile { name: "AX_EEC.INI".into(), contents: lec });
    let applied = TableSum { machine: m, tables: carried, interpolation: Interpolation::Linear };
    Ok(Export { files, applied: Box::new(applied), left_out: Vec::new() })
}

/// The head of a program: its name line, what it holds, a placeholder for the machine data, and
/// `CHANDATA(1)`.
fn head(m: &Machine, name: &str, what: &str) -> String {
    let mut text = format!("%_N_{name}_INI\n");
    let _ = writeln!(text, "; trueaxis: {what} of machine `{}`", m.name);
    let _ = writeln!(text, "; compensation values = minus the trueaxis corrections (K3: a positive value moves the axis negative),");
    let _ = writeln!(text, "; mm for linear and deg for rotary axes; machine axis names X1 Y1 Z1 A1 ... (MD10000)");
    text.push_str("; MACHINE DATA\n");
    text.push_str("CHANDATA(1)\n");
    text
}

/// The comment block of the machine data to set (both programs list all of it).
fn machine_data_block(lines: &[String]) -> String {
    let mut text = String::from("; machine and setting data to set (POWER ON after MD38000 / MD18342; load with the compensation off):\n");
    for l in lines {
        let _ = writeln!(text, ";   {l}");
    }
    text
}

/// `NC_CEC.INI`: every CEC table with its parameters; adds its machine data to `machine_data`.
fn cec_program(m: &Machine, cecs: &[Cec], machine_data: &mut Vec<String>) -> String {
    let mut body = String::new();
    let mut sums = vec![0.0f64; m.axis_count()];
    for (t, c) in cecs.iter().enumerate() {
        let (input, output) = (axis_name(m, c.table.driver), axis_name(m, c.table.corrected));
        let _ = writeln!(
            body,
            "; table {t}: {output} as a function of {input}, {}",
            match c.direction {
                0 => "both directions",
                1 => "positive traverse of the basic axis",
                _ => "negative traverse of the basic axis",
            }
        );
        for (i, v) in c.values.iter().enumerate() {
            let _ = writeln!(body, "$AN_CEC[{t},{i}]={}", super::signed(-v, 6));
        }
        let (min, max, step) = span(c.table);
        let _ = writeln!(body, "$AN_CEC_INPUT_AXIS[{t}]=({input})");
        let _ = writeln!(body, "$AN_CEC_OUTPUT_AXIS[{t}]=({output})");
        let _ = writeln!(body, "$AN_CEC_STEP[{t}]={step:.6}");
        let _ = writeln!(body, "$AN_CEC_MIN[{t}]={min:.6}");
        let _ = writeln!(body, "$AN_CEC_MAX[{t}]={max:.6}");
        let _ = writeln!(body, "$AN_CEC_DIRECTION[{t}]={}", c.direction);
        let _ = writeln!(body, "$AN_CEC_MULT_BY_TABLE[{t}]=0");
        let _ = writeln!(body, "$AN_CEC_IS_MODULO[{t}]={}", i32::from(is_full_turn(m, c.table)));
        machine_data.push(format!("MD18342 $MN_MM_CEC_MAX_POINTS[{t}] >= {}", c.values.len()));
        machine_data.push(format!("SD41300 $SN_CEC_TABLE_ENABLE[{t}] = 1, SD41310 $SN_CEC_TABLE_WEIGHT[{t}] = 1.0"));
        sums[c.table.corrected] += c.values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    }
    for (k, s) in sums.iter().enumerate().filter(|(_, s)| **s > 0.0) {
        let unit = if m.axes()[k].kind == AxisKind::Rotary { "deg" } else { "mm" };
        machine_data.push(format!("MD32710 $MA_CEC_ENABLE[{}] = 1 (0 while loading NC_CEC.INI)", axis_name(m, k)));
        machine_data.push(format!("MD32720 $MA_CEC_MAX_SUM[{}] >= {s:.6} {unit} (largest total of its tables)", axis_name(m, k)));
    }
    let mut text = head(m, "NC_CEC", "sag and angularity compensation (CEC)");
    text = text.replacen("; MACHINE DATA\n", &machine_data_block(machine_data), 1);
    text.push_str(&body);
    text.push_str("M17\n");
    text
}

/// First and last position and the distance between points (mm or deg).
fn span(t: &AxisTable) -> (f64, f64, f64) {
    let n = t.positions.len();
    let (min, max) = (t.positions[0], t.positions[n - 1]);
    (min, max, (max - min) / (n - 1) as f64)
}

/// Whether a table spans one turn of a rotary axis (written with the modulo function).
fn is_full_turn(m: &Machine, t: &AxisTable) -> bool {
    let (min, max, _) = span(t);
    m.axes()[t.driver].kind == AxisKind::Rotary && ((max - min) - 360.0).abs() < 1e-9
}
