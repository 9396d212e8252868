//! Controller exporters (specs/anchors.md §2-§3): LinuxCNC joint compensation files and a HAL
//! component driving external offsets, the ISG / Beckhoff volumetric CSV with its list file,
//! Heidenhain `.COM` / `.CMA` tables, a Siemens 840D sl init program (LEC and sag/angularity
//! compensation), a Fanuc pitch-error compensation program (`G10 L50`), a plain 3D lattice, and
//! plain CSV / JSON. Every exporter checks the controller's limits (point counts, equal spacing,
//! closure of rotary-axis tables over a turn) and the user's correction limit, and refuses rather
//! than writing a table the controller would reject or that would move an axis further than
//! allowed. Each says what its format leaves out, and describes what the controller applies with its
//! files ([`residual::Applied`]), so that [`residual::residual_of_format`] can compute the error that
//! is left on the exact chain.

pub mod fanuc;
pub mod fanuc_tcp;
pub mod heidenhain;
pub mod heidenhain_kinematics;
pub mod isg;
pub mod lattice;
pub mod linuxcnc;
pub mod linuxcnc_hal;
pub mod linuxcnc_kins;
pub mod plain;
pub mod residual;
pub mod rigid_fit;
pub mod siemens;
pub mod siemens_swivel;

use super::tables::{AxisTable, TableSet, VolumetricGrid};
use super::CompensateError;
use crate::error_model::ErrorModel;
use crate::machine::{AxisKind, Machine};

/// One output file: a name (relative to the output directory) and its text.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportedFile {
    pub name: String,
    pub contents: String,
}

/// What an exporter produces.
pub struct Export<'a> {
    /// The files, to be written together (atomically each, all or none).
    pub files: Vec<ExportedFile>,
    /// The corrections the controller applies with these files.
    pub applied: Box<dyn residual::Applied + 'a>,
    /// What the format could not carry, one line each with its size (um, urad).
    pub left_out: Vec<String>,
}

impl std::fmt::Debug for Export<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Export").field("files", &self.files).field("left_out", &self.left_out).finish_non_exhaustive()
    }
}

/// Where a correction limit comes from (for the refusal message).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitSource {
    /// trueaxis's default ([`crate::machine::DEFAULT_CORRECTION_UM`], `_URAD`): the machine file has no `[limits]` value.
    Default,
    /// The machine file's `[limits]`.
    MachineFile,
    /// Given for this run (`--limit-um` / `--limit-urad`, Python `limit_um` / `limit_urad`).
    Given,
}

impl LimitSource {
    fn describe(self, key: &str) -> String {
        match self {
            LimitSource::Default => format!("trueaxis's default, the machine file has no `[limits] {key}`"),
            LimitSource::MachineFile => format!("the machine file's `[limits] {key}`"),
            LimitSource::Given => "given for this run".into(),
        }
    }
}

/// The limits on corrections: a table, NC program or real-time call with a correction beyond them
/// is refused (never clipped). [`Limits::default`] is trueaxis's default (docs/limits.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Largest allowed correction of a linear axis (um).
    pub max_um: f64,
    /// Largest allowed correction of a rotary axis (urad).
    pub max_urad: f64,
    pub source_um: LimitSource,
    pub source_urad: LimitSource,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_um: crate::machine::DEFAULT_CORRECTION_UM,
            max_urad: crate::machine::DEFAULT_CORRECTION_URAD,
            source_um: LimitSource::Default,
            source_urad: LimitSource::Default,
        }
    }
}

impl Limits {
    /// The limits of `machine`: its file's `[limits]`, else the defaults.
    pub fn of_machine(machine: &Machine) -> Limits {
        let l = &machine.correction_limits;
        let source = |v: Option<f64>| if v.is_some() { LimitSource::MachineFile } else { LimitSource::Default };
        Limits {
            max_um: l.linear_um(),
            max_urad: l.rotary_urad(),
            source_um: source(l.correction_um),
            source_urad: source(l.correction_urad),
        }
    }

    /// The limits of `machine` with the values given for this run (um, urad) in place of the
    /// machine file's; an error names a value that is not a positive number or beyond the largest
    /// limit ([`crate::machine::check_limit_value`]).
    pub fn with_overrides(machine: &Machine, max_um: Option<f64>, max_urad: Option<f64>) -> Result<Limits, CompensateError> {
        let mut limits = Limits::of_machine(machine);
        for (name, v, rotary) in [("the linear correction limit", max_um, false), ("the rotary correction limit", max_urad, true)] {
            if let Some(v) = v {
                crate::machine::check_limit_value(name, v, rotary).map_err(|e| CompensateError::Input(e.to_string()))?;
            }
        }
        if let Some(v) = max_um {
            (limits.max_um, limits.source_um) = (v, LimitSource::Given);
        }
        if let Some(v) = max_urad {
            (limits.max_urad, limits.source_urad) = (v, LimitSource::Given);
        }
        Ok(limits)
    }

    /// The limit of an axis of `kind` (um or urad) and where it comes from.
    pub fn of_kind(&self, kind: AxisKind) -> (f64, LimitSource) {
        match kind {
            AxisKind::Rotary => (self.max_urad, self.source_urad),
            AxisKind::Linear => (self.max_um, self.source_um),
        }
    }

    /// Whether a correction of `micro` (um or urad) of an axis of `kind` is within the limit.
    pub fn allows(&self, kind: AxisKind, micro: f64) -> bool {
        micro.abs() <= self.of_kind(kind).0
    }
}

/// Everything an exporter may use.
pub struct ExportInput<'a> {
    pub machine: &'a Machine,
    pub errors: &'a ErrorModel,
    pub tables: &'a TableSet,
    pub grid: Option<&'a VolumetricGrid>,
    pub limits: Limits,
}

/// Which corrections a format writes (for its summary).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Coverage {
    pub own_axis_tables: bool,
    pub cross_axis_tables: bool,
    pub grid: bool,
}

impl Coverage {
    pub const OWN_AXIS_TABLES: Coverage = Coverage { own_axis_tables: true, cross_axis_tables: false, grid: false };
    pub const TABLES: Coverage = Coverage { own_axis_tables: true, cross_axis_tables: true, grid: false };
    pub const GRID: Coverage = Coverage { own_axis_tables: false, cross_axis_tables: false, grid: true };
    pub const TABLES_AND_GRID: Coverage = Coverage { own_axis_tables: true, cross_axis_tables: true, grid: true };
}

/// The extent of what a format writes: the largest |correction| of a linear axis (um) and of a
/// rotary axis (urad), and the largest residual (mm) and uncorrected orientation (rad) of the poses
/// they were sampled at. The residuals of the tables count whenever any table is written.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Extent {
    pub max_um: f64,
    pub max_urad: f64,
    pub worst_residual_mm: f64,
    pub worst_uncorrectable_rad: f64,
}

/// The [`Extent`] of the tables and grid of `input` that `coverage` selects.
pub fn largest_corrections(input: &ExportInput, coverage: Coverage) -> Extent {
    let m = input.machine;
    let mut e = Extent::default();
    let mut add = |axis: usize, value: f64| {
        let micro = to_micro(m, axis, value).abs();
        match m.axes()[axis].kind {
            AxisKind::Rotary => e.max_urad = e.max_urad.max(micro),
            AxisKind::Linear => e.max_um = e.max_um.max(micro),
        }
    };
    for t in &input.tables.tables {
        if (t.is_own_axis() && coverage.own_axis_tables) || (!t.is_own_axis() && coverage.cross_axis_tables) {
            add(t.corrected, t.max_abs());
        }
    }
    if let (true, Some(g)) = (coverage.grid, input.grid) {
        for node in g.values.chunks(g.axis_count) {
            node.iter().enumerate().for_each(|(axis, &v)| add(axis, v));
        }
    }
    let mut worst = |residual: f64, orientation: f64| {
        e.worst_residual_mm = e.worst_residual_mm.max(residual);
        e.worst_uncorrectable_rad = e.worst_uncorrectable_rad.max(orientation);
    };
    if coverage.own_axis_tables || coverage.cross_axis_tables {
        worst(input.tables.worst_residual_position, input.tables.worst_uncorrectable_orientation);
    }
    if let (true, Some(g)) = (coverage.grid, input.grid) {
        worst(g.worst_residual_position, g.worst_uncorrectable_orientation);
    }
    e
}

/// A correction of `axis` in user units (mm, deg) as um or urad.
pub fn to_micro(machine: &Machine, axis: usize, value: f64) -> f64 {
    let a = &machine.axes()[axis];
    a.position_to_internal(value) * if a.kind == AxisKind::Rotary { 1e6 } else { 1e3 }
}

/// Unit of [`to_micro`] for `axis`.
pub fn micro_unit(machine: &Machine, axis: usize) -> &'static str {
    if machine.axes()[axis].kind == AxisKind::Rotary {
        "urad"
    } else {
        "um"
    }
}

/// The refusal of the correction `value` (user units, mm or deg) of `axis` when it exceeds the
/// limit, `None` within it; `place` says where it occurs (for the message).
pub fn limit_refusal(machine: &Machine, limits: &Limits, axis: usize, value: f64, place: &dyn Fn() -> String) -> Option<String> {
    let micro = to_micro(machine, axis, value);
    let a = &machine.axes()[axis];
    if limits.allows(a.kind, micro) && micro.is_finite() {
        return None;
    }
    let (limit, source) = limits.of_kind(a.kind);
    let (key, option) = match a.kind {
        AxisKind::Rotary => ("correction_urad", "--limit-urad"),
        AxisKind::Linear => ("correction_um", "--limit-um"),
    };
    let unit = micro_unit(machine, axis);
    Some(format!(
        "the correction of axis {} is {micro:.3} {unit} at {}, beyond the limit of {limit} {unit} ({}); an error value is likely in the \
         wrong unit (check the error file); if the correction is real, raise `[limits] {key}` in the machine file or pass {option} \
         (docs/limits.md); nothing was written",
        a.letter,
        place(),
        source.describe(key)
    ))
}

/// Refuses the correction `value` (user units, mm or deg) of `axis` when it exceeds the limit
/// ([`limit_refusal`]).
pub fn check_limit(machine: &Machine, limits: &Limits, axis: usize, value: f64, place: &dyn Fn() -> String) -> Result<(), CompensateError> {
    limit_refusal(machine, limits, axis, value, place).map_or(Ok(()), |m| Err(CompensateError::Limit(m)))
}

/// Where a correction is: point `.1` of table `.0` (`Ok`), or a grid node (`Err`).
type At = Result<(usize, usize), usize>;

/// Refuses corrections beyond the limits in any table (both directions) or grid node, naming the
/// worst one (largest ratio to its limit).
pub fn check_user_limits(input: &ExportInput) -> Result<(), CompensateError> {
    let m = input.machine;
    let mut worst: Option<(f64, usize, f64, At)> = None;
    let mut consider = |axis: usize, value: f64, at: At| {
        let micro = to_micro(m, axis, value);
        let ratio = if micro.is_finite() { micro.abs() / input.limits.of_kind(m.axes()[axis].kind).0 } else { f64::INFINITY };
        if ratio > 1.0 && worst.is_none_or(|w| ratio > w.0) {
            worst = Some((ratio, axis, value, at));
        }
    };
    for (ti, t) in input.tables.tables.iter().enumerate() {
        for (i, (&f, &r)) in t.forward.iter().zip(&t.reverse).enumerate() {
            consider(t.corrected, f, Ok((ti, i)));
            consider(t.corrected, r, Ok((ti, i)));
        }
    }
    if let Some(g) = input.grid {
        for (node, values) in g.values.chunks(g.axis_count).enumerate() {
            values.iter().enumerate().for_each(|(axis, &v)| consider(axis, v, Err(node)));
        }
    }
    let Some((_, axis, value, at)) = worst else { return Ok(()) };
    let place = || match at {
        Ok((ti, i)) => {
            let t = &input.tables.tables[ti];
            format!(
                "{} = {} {} (table {} -> {})",
                letter(m, t.driver),
                t.positions[i],
                unit(m, t.driver),
                letter(m, t.driver),
                letter(m, t.corrected)
            )
        }
        Err(node) => {
            let g = input.grid.expect("a grid node comes from the grid");
            let (i, j, k) = (node % g.counts[0], (node / g.counts[0]) % g.counts[1], node / (g.counts[0] * g.counts[1]));
            format!("grid node {:?} mm", g.node_position(i, j, k))
        }
    };
    check_limit(m, &input.limits, axis, value, &place)
}

/// One line per cross-axis table that a format leaves out and that is not zero: `Y as a function of
/// X (cross-axis): up to 12.300 um`.
pub fn cross_axis_left_out(input: &ExportInput) -> Vec<String> {
    let m = input.machine;
    input
        .tables
        .tables
        .iter()
        .filter(|t| !t.is_own_axis() && to_micro(m, t.corrected, t.max_abs()).abs() >= 5e-4)
        .map(|t| {
            format!(
                "{} as a function of {} (cross-axis): up to {:.3} {}",
                letter(m, t.corrected),
                letter(m, t.driver),
                to_micro(m, t.corrected, t.max_abs()),
                micro_unit(m, t.corrected)
            )
        })
        .collect()
}

/// One line per table selected by `which` whose two directions differ (by at least 0.0005 um or
/// urad), for a format that writes only their mean.
pub fn direction_left_out(input: &ExportInput, which: impl Fn(&AxisTable) -> bool) -> Vec<String> {
    let m = input.machine;
    input
        .tables
        .tables
        .iter()
        .filter(|t| which(t))
        .filter_map(|t| {
            let half = t.forward.iter().zip(&t.reverse).map(|(f, r)| 0.5 * (f - r).abs()).fold(0.0, f64::max);
            let micro = to_micro(m, t.corrected, half).abs();
            (micro >= 5e-4).then(|| {
                format!(
                    "direction-dependent part (backlash) of {} as a function of {}: +-{micro:.3} {}",
                    letter(m, t.corrected),
                    letter(m, t.driver),
                    micro_unit(m, t.corrected)
                )
            })
        })
        .collect()
}

fn letter(m: &Machine, axis: usize) -> char {
    m.axes()[axis].letter
}

fn unit(m: &Machine, axis: usize) -> &'static str {
    m.axes()[axis].position_unit()
}

/// Refuses more than `max` points in a table (`what` names it).
pub fn check_count(points: usize, max: usize, what: &str) -> Result<(), CompensateError> {
    if points > max {
        return Err(CompensateError::Limit(format!("{what} has {points} points; the controller accepts at most {max}")));
    }
    Ok(())
}

/// Refuses positions that are not increasing with equal spacing (relative tolerance 1e-9).
pub fn check_equal_spacing(positions: &[f64], what: &str) -> Result<(), CompensateError> {
    if positions.len() < 2 {
        return Err(CompensateError::Limit(format!("{what} needs at least 2 points")));
    }
    let step = (positions[positions.len() - 1] - positions[0]) / (positions.len() - 1) as f64;
    for (i, w) in positions.windows(2).enumerate() {
        if step.is_nan() || step <= 0.0 || ((w[1] - w[0]) - step).abs() > 1e-9 * step.abs().max(1.0) {
            return Err(CompensateError::Limit(format!(
                "{what}: the controller needs equally spaced, increasing points, but points {} and {} are {} apart (expected {step})",
                i + 1,
                i + 2,
                w[1] - w[0]
            )));
        }
    }
    Ok(())
}

/// A table over one full turn of a rotary axis must close: its increments sum to zero over the
/// revolution, i.e. the first value equals the last (Fanuc pitch-error compensation rule,
/// specs/anchors.md §3; the same holds for any controller that wraps the table).
pub fn check_rotary_closure(machine: &Machine, table: &AxisTable, tolerance: f64) -> Result<(), CompensateError> {
    let axis = &machine.axes()[table.driver];
    let span = table.positions[table.positions.len() - 1] - table.positions[0];
    if axis.kind != AxisKind::Rotary || (span - 360.0).abs() > 1e-9 {
        return Ok(());
    }
    for (values, name) in [(&table.forward, "forward"), (&table.reverse, "reverse")] {
        let gap = values[values.len() - 1] - values[0];
        if gap.abs() > tolerance {
            return Err(CompensateError::Limit(format!(
                "table {} -> {} ({name}) over one turn of {} does not close: the increments sum to {} {} instead of 0 \
                 (the error model is not periodic in {})",
                axis.letter,
                machine.axes()[table.corrected].letter,
                axis.letter,
                gap,
                machine.axes()[table.corrected].position_unit(),
                axis.letter
            )));
        }
    }
    Ok(())
}

/// Tolerance of the closure check in user units of the corrected axis: 1 nm or 1 nrad.
pub fn closure_tolerance(machine: &Machine, corrected: usize) -> f64 {
    machine.axes()[corrected].position_to_user(1e-6)
}

/// Fixed-point text of a number with `decimals` digits and an explicit sign.
pub fn signed(value: f64, decimals: usize) -> String {
    let v = if value.abs() < 0.5 * 10f64.powi(-(decimals as i32)) { 0.0 } else { value };
    format!("{v:+.decimals$}")
}
