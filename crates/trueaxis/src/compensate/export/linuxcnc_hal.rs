//! A LinuxCNC 2.9 HAL component that applies the corrections of every axis, cross-axis and
//! volumetric ones included, through external offsets (LinuxCNC "External Axis Offsets": the pins
//! `axis.L.eoffset-enable`, `-scale`, `-counts` and the applied `axis.L.eoffset`, the INI key
//! `[AXIS_L] OFFSET_AV_RATIO`; specs/anchors.md §2).
//!
//! The component (`<name>.comp`, built and installed by `halcompile --install` from the Debian
//! package linuxcnc-uspace-dev) carries the volumetric grid over X, Y, Z (trilinear, the
//! corrections of every axis at the nodes, other axes at the reference pose) plus, for each other
//! axis, its table of the corrections of every axis as the change from the reference pose (linear,
//! wrapped over a turn for a continuous rotary axis). A machine without X, Y and Z gets the
//! own-axis and cross-axis tables instead of the grid. Every servo period it reads the joint
//! positions (`pos-L`, from `joint.N.pos-cmd`), subtracts the external offsets already applied
//! (`applied-L`, from `axis.L.eoffset`) so that the lookup is at the nominal position, and outputs the
//! corrections as `offset-L` (mm, deg) and as counts of [`COUNT`] (`counts-L`, to
//! `axis.L.eoffset-counts`, with `axis.L.eoffset-scale` = [`COUNT`]). Directions of motion are not
//! known to it: the tables hold the mean of both directions.
//!
//! Each axis also has an input `thermal-L` (mm, deg; default 0) added to its correction: the live
//! thermal offset that `trueaxis live --sink hal` sets through halcmd, so that the geometric
//! corrections and the thermal drift reach the one `axis.L.eoffset-counts` input of each axis.
//!
//! External offsets are added in world (axis) coordinates before the kinematics; they equal joint
//! corrections only with identity kinematics (trivkins): the HAL file assumes joint n = axis n of the
//! machine file.

use super::residual::{Branch, GridSum, Interpolation, TableSum};
use super::{
    check_count, check_equal_spacing, check_rotary_closure, check_user_limits, closure_tolerance, direction_left_out, Export, ExportInput,
    ExportedFile,
};
use crate::compensate::tables::AxisTable;
use crate::compensate::CompensateError;
use crate::machine::{AxisKind, Machine};
use std::fmt::Write;

/// One count of `axis.L.eoffset-counts` (mm or deg): 1 nm, so an s32 spans +-2147 mm.
pub const COUNT: f64 = 1e-6;

/// Most table points and grid nodes the component carries (its size is static memory).
pub const MAX_NODES: usize = 200_000;

/// `<name>.comp`, `<name>.hal` and `<name>.ini` (the lines for the machine's INI file).
pub fn export<'a>(input: &ExportInput<'a>, name: &str) -> Result<Export<'a>, CompensateError> {
    check_user_limits(input)?;
    if name.is_empty()
        || !name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        || name.starts_with(|c: char| c.is_ascii_digit())
    {
        return Err(CompensateError::Input(format!(
            "--hal-component `{name}`: a HAL component name is lower-case letters, digits and `_`, not starting with a digit"
        )));
    }
    let m = input.machine;
    let grid = input.grid;
    // tables: with a grid, those of the axes outside it as changes from the reference; else all
    let mut tables: Vec<AxisTable> = Vec::new();
    for t in &input.tables.tables {
        if grid.is_some_and(|g| g.axes.contains(&t.driver)) {
            continue;
        }
        let what = format!("the HAL component's table {} -> {}", m.axes()[t.driver].letter, m.axes()[t.corrected].letter);
        check_equal_spacing(&t.positions, &what)?;
        check_rotary_closure(m, t, closure_tolerance(m, t.corrected))?;
        let mut mean = t.clone();
        for (f, r) in mean.forward.iter_mut().zip(mean.reverse.iter_mut()) {
            *f = 0.5 * (*f + *r);
            *r = *f;
        }
        if grid.is_some() {
            // the change from the reference pose as the table interpolates it, so that the grid
            // alone holds at the reference
            let at_reference = t.mean_at(input.tables.reference[t.driver]);
            mean.forward.iter_mut().chain(mean.reverse.iter_mut()).for_each(|v| *v -= at_reference);
        }
        tables.push(mean);
    }
    let nodes =
        grid.map_or(0, |g| g.counts.iter().product::<usize>() * g.axis_count) + tables.iter().map(|t| t.positions.len()).sum::<usize>();
    check_count(nodes, MAX_NODES, "the HAL component's tables and grid")?;
    let files = vec![
        ExportedFile { name: format!("{name}.comp"), contents: component(input, name, &tables) },
        ExportedFile { name: format!("{name}.hal"), contents: hal_file(m, name) },
        ExportedFile { name: format!("{name}.ini"), contents: ini_lines(m, name) },
    ];
    let sum =
        TableSum { machine: m, tables: tables.into_iter().map(|t| (t, Branch::Mean)).collect(), interpolation: Interpolation::Linear };
    let applied: Box<dyn super::residual::Applied> = match grid {
        Some(g) => Box::new(GridSum { grid: g, grid_columns: (0..m.axis_count()).collect(), tables: sum }),
        None => Box::new(sum),
    };
    Ok(Export { files, applied, left_out: direction_left_out(input, |_| true) })
}

/// HAL pin name suffix of axis `k`: its letter in lower case.
fn pin(m: &Machine, k: usize) -> String {
    m.axes()[k].letter.to_ascii_lowercase().to_string()
}

/// A C array of doubles, 6 per line.
fn c_array(values: impl Iterator<Item = f64>) -> String {
    let v: Vec<String> = values.map(|x| format!("{x:.12e}")).collect();
    v.chunks(6).map(|c| format!("    {}", c.join(", "))).collect::<Vec<_>>().join(",\n")
}

/// The `.comp` source.
fn component(input: &ExportInput, name: &str, tables: &[AxisTable]) -> String {
    let m = input.machine;
    let n = m.axis_count();
    let mut c = String::new();
    let _ = writeln!(c, "component {name} \"trueaxis compensation of machine {}: external offsets from joint positions\";", m.name);
    let _ = writeln!(
        c,
        "description \"\"\"Generated by trueaxis. Corrections (added to the set-points; mm, deg) of every axis from a volumetric \
         grid over X, Y, Z and tables of the other axes, as external offsets. Build: halcompile --install {name}.comp\"\"\";"
    );
    for k in 0..n {
        let (l, u) = (pin(m, k), m.axes()[k].position_unit());
        let _ = writeln!(c, "pin in float pos_{l} \"position of {} ({u}): net from joint.{k}.pos-cmd\";", m.axes()[k].letter);
        let _ =
            writeln!(c, "pin in float applied_{l} \"external offset applied to {} ({u}): net from axis.{l}.eoffset\";", m.axes()[k].letter);
        let _ = writeln!(
            c,
            "pin in float thermal_{l} \"thermal offset of {} ({u}), added to the correction: set by trueaxis live --sink hal\";",
            m.axes()[k].letter
        );
        let _ = writeln!(c, "pin out float offset_{l} \"correction of {} ({u})\";", m.axes()[k].letter);
        let _ = writeln!(
            c,
            "pin out s32 counts_{l} \"correction of {} in counts of {COUNT:e} {u}: net to axis.{l}.eoffset-counts\";",
            m.axes()[k].letter
        );
    }
    c.push_str("function _;\nlicense \"GPL\";\n;;\n#include <rtapi_math.h>\n\n");
    let _ = writeln!(c, "#define AXES {n}\n#define COUNT {COUNT:e}\n");
    match input.grid {
        Some(g) => {
            let _ = writeln!(c, "static const int grid_axis[3] = {{{}, {}, {}}};", g.axes[0], g.axes[1], g.axes[2]);
            let _ = writeln!(c, "static const double grid_start[3] = {{{:.12e}, {:.12e}, {:.12e}}};", g.start[0], g.start[1], g.start[2]);
            let _ = writeln!(c, "static const double grid_step[3] = {{{:.12e}, {:.12e}, {:.12e}}};", g.step[0], g.step[1], g.step[2]);
            let _ = writeln!(c, "static const int grid_count[3] = {{{}, {}, {}}};", g.counts[0], g.counts[1], g.counts[2]);
            let _ = writeln!(c, "/* node (i, j, k) at ((k * ny + j) * nx + i) * AXES */");
            let _ = writeln!(c, "static const double grid_value[] = {{\n{}\n}};", c_array(g.values.iter().copied()));
        }
        None => c.push_str("static const int grid_count[3] = {0, 0, 0};\nstatic const int grid_axis[3] = {0, 0, 0};\nstatic const double grid_start[3], grid_step[3], grid_value[1];\n"),
    }
    let _ = writeln!(c, "\n#define TABLES {}", tables.len());
    let points = |f: &dyn Fn(&AxisTable) -> String| tables.iter().map(f).collect::<Vec<_>>().join(", ");
    let _ = writeln!(
        c,
        "static const int table_driver[TABLES + 1] = {{{}}};",
        points(&|t| t.driver.to_string()) + if tables.is_empty() { "0" } else { "" }
    );
    let _ = writeln!(
        c,
        "static const int table_corrected[TABLES + 1] = {{{}}};",
        points(&|t| t.corrected.to_string()) + if tables.is_empty() { "0" } else { "" }
    );
    let _ = writeln!(
        c,
        "static const int table_points[TABLES + 1] = {{{}}};",
        points(&|t| t.positions.len().to_string()) + if tables.is_empty() { "0" } else { "" }
    );
    let _ = writeln!(
        c,
        "static const double table_first[TABLES + 1] = {{{}}};",
        points(&|t| format!("{:.12e}", t.positions[0])) + if tables.is_empty() { "0" } else { "" }
    );
    let _ = writeln!(
        c,
        "static const double table_step[TABLES + 1] = {{{}}};",
        points(&|t| format!("{:.12e}", (t.positions[t.positions.len() - 1] - t.positions[0]) / (t.positions.len() - 1) as f64))
            + if tables.is_empty() { "0" } else { "" }
    );
    let _ = writeln!(
        c,
        "static const int table_turn[TABLES + 1] = {{{}}}; /* 1: over one turn of a rotary axis, wrapped */",
        points(&|t| {
            let span = t.positions[t.positions.len() - 1] - t.positions[0];
            i32::from(m.axes()[t.driver].kind == AxisKind::Rotary && (span - 360.0).abs() < 1e-9).to_string()
        }) + if tables.is_empty() { "0" } else { "" }
    );
    let values: Vec<f64> = tables.iter().flat_map(|t| t.forward.iter().copied()).collect();
    let _ = writeln!(
        c,
        "static const double table_value[] = {{\n{}\n}};",
        if values.is_empty() { "    0".into() } else { c_array(values.into_iter()) }
    );
    c.push_str(LOOKUP);
    c.push_str("\nFUNCTION(_) {\n    double q[AXES], out[AXES];\n    int k;\n");
    for k in 0..n {
        let l = pin(m, k);
        let _ = writeln!(c, "    q[{k}] = pos_{l} - applied_{l};");
    }
    c.push_str("    correct(q, out);\n");
    for k in 0..n {
        let l = pin(m, k);
        let _ = writeln!(c, "    offset_{l} = out[{k}] + thermal_{l};\n    counts_{l} = to_counts(out[{k}] + thermal_{l});");
    }
    c.push_str("    (void)k;\n}\n");
    c
}

/// The lookup of the component: trilinear grid plus linear tables, ends held.
const LOOKUP: &str = r#"
static int to_counts(double v) {
    double c = v / COUNT;
    return c >= 0 ? (int)(c + 0.5) : -(int)(-c + 0.5);
}

static void correct(const double *q, double *out) {
    int a, d, t, base = 0;
    for (a = 0; a < AXES; a++) out[a] = 0;
    if (grid_count[0] > 1) {
        int cell[3];
        double w[3];
        for (d = 0; d < 3; d++) {
            int last = grid_count[d] - 1;
            double u = (q[grid_axis[d]] - grid_start[d]) / grid_step[d];
            if (u < 0) u = 0;
            if (u > last) u = last;
            cell[d] = (int)floor(u);
            if (cell[d] > last - 1) cell[d] = last - 1;
            w[d] = u - cell[d];
        }
        for (d = 0; d < 8; d++) {
            int o0 = d & 1, o1 = (d >> 1) & 1, o2 = (d >> 2) & 1;
            double weight = (o0 ? w[0] : 1 - w[0]) * (o1 ? w[1] : 1 - w[1]) * (o2 ? w[2] : 1 - w[2]);
            int node = ((cell[2] + o2) * grid_count[1] + cell[1] + o1) * grid_count[0] + cell[0] + o0;
            if (weight == 0) continue;
            for (a = 0; a < AXES; a++) out[a] += weight * grid_value[node * AXES + a];
        }
    }
    for (t = 0; t < TABLES; t++) {
        int n = table_points[t], i;
        double x = q[table_driver[t]], u, s;
        if (table_turn[t]) x = table_first[t] + fmod(fmod(x - table_first[t], 360.0) + 360.0, 360.0);
        u = (x - table_first[t]) / table_step[t];
        if (u < 0) u = 0;
        if (u > n - 1) u = n - 1;
        i = (int)floor(u);
        if (i > n - 2) i = n - 2;
        s = u - i;
        out[table_corrected[t]] += table_value[base + i] + s * (table_value[base + i + 1] - table_value[base + i]);
        base += n;
    }
}
"#;

/// The HAL lines that load the component and wire it to the external offsets (trivkins: joint n =
/// axis n).
fn hal_file(m: &Machine, name: &str) -> String {
    let hal_name = name.replace('_', "-");
    let mut h = format!("# trueaxis: external-offset compensation of machine `{}` (LinuxCNC 2.9)\n", m.name);
    let _ = writeln!(h, "# build and install the component first: halcompile --install {name}.comp (package linuxcnc-uspace-dev)");
    let _ = writeln!(h, "loadrt {name}\naddf {hal_name}.0 servo-thread");
    for k in 0..m.axis_count() {
        let l = pin(m, k);
        let _ = writeln!(h, "net ta-{l}-pos joint.{k}.pos-cmd => {hal_name}.0.pos-{l}");
        let _ = writeln!(h, "net ta-{l}-applied axis.{l}.eoffset => {hal_name}.0.applied-{l}");
        let _ = writeln!(h, "net ta-{l}-counts {hal_name}.0.counts-{l} => axis.{l}.eoffset-counts");
        let _ = writeln!(h, "setp axis.{l}.eoffset-scale {COUNT:.6}");
        let _ = writeln!(h, "setp axis.{l}.eoffset-enable 1");
    }
    h
}

/// The lines for the machine's INI file.
fn ini_lines(m: &Machine, name: &str) -> String {
    let mut t =
        format!("# trueaxis: add to the machine's INI file (LinuxCNC 2.9 external offsets, trivkins)\n[HAL]\nHALFILE = {name}.hal\n");
    for a in m.axes() {
        let _ = writeln!(
            t,
            "\n[AXIS_{}]\n# share of the axis' velocity and acceleration kept for external offsets\nOFFSET_AV_RATIO = 0.1",
            a.letter
        );
    }
    t
}
