//! Compensation tables sampled from the pose correction: own-axis and cross-axis tables,
//! bidirectional (the lead-screw and cross-axis tables of NISTIR 5236 section 4), and a volumetric grid
//! over the work volume with trilinear interpolation (the Fanuc 3D lattice of specs/anchors.md §3).
//!
//! Tables are taken along the axis lines through a reference pose (default: home, all axes at 0,
//! clamped into the travel). The own-axis table of axis i holds the correction of axis i with axis i
//! moved and all others at the reference; the cross-axis table (i -> j) holds the correction of axis
//! j along the same line minus its value at the reference pose, so that the sum of all tables at a
//! pose on an axis line equals the correction there (the constant part is counted once, in the
//! own-axis tables). Corrections of poses off the axis lines that depend on two axes at once (Abbe
//! terms such as EBX times z) need the volumetric grid.

use super::batch_correction::correct_batch;
use super::correction::{Correction, Corrector};
use super::CompensateError;
use crate::error_model::Direction;
use crate::machine::{AxisKind, Machine};

/// One table: the correction of axis `corrected` as a function of the position of axis `driver`.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisTable {
    /// Index (canonical order) of the axis whose position is the argument.
    pub driver: usize,
    /// Index of the axis whose set-point is corrected.
    pub corrected: usize,
    /// Equally spaced positions of `driver`, increasing (mm or deg).
    pub positions: Vec<f64>,
    /// Correction while `driver` moves in the positive direction (mm or deg of `corrected`).
    pub forward: Vec<f64>,
    /// Correction while `driver` moves in the negative direction (mm or deg of `corrected`).
    pub reverse: Vec<f64>,
}

impl AxisTable {
    pub fn is_own_axis(&self) -> bool {
        self.driver == self.corrected
    }

    /// Largest absolute value of either direction.
    pub fn max_abs(&self) -> f64 {
        self.forward.iter().chain(&self.reverse).fold(0.0, |m, v| m.max(v.abs()))
    }

    /// Linear interpolation of the mean of both directions at `x` (ends held).
    pub fn mean_at(&self, x: f64) -> f64 {
        let n = self.positions.len();
        let i = self.positions.partition_point(|&p| p <= x).clamp(1, n - 1) - 1;
        let t = ((x - self.positions[i]) / (self.positions[i + 1] - self.positions[i])).clamp(0.0, 1.0);
        let mean = |k: usize| 0.5 * (self.forward[k] + self.reverse[k]);
        mean(i) + t * (mean(i + 1) - mean(i))
    }
}

/// What to sample.
#[derive(Clone, Debug, PartialEq)]
pub struct TableSpec {
    /// Points per table (equally spaced over the travel; a rotary axis without travel: 0..360 deg,
    /// both ends included).
    pub points: usize,
    /// Reference pose (mm, deg), one value per axis; `None`: home clamped into the travel.
    pub reference: Option<Vec<f64>>,
    /// Temperatures of the error model's sensors (degC); empty: 20 degC.
    pub temperatures: Vec<f64>,
}

/// Own-axis and cross-axis tables of a machine.
#[derive(Clone, Debug, PartialEq)]
pub struct TableSet {
    /// The reference pose (mm, deg).
    pub reference: Vec<f64>,
    /// The sensor temperatures the tables were sampled at (degC; empty: 20 degC).
    pub temperatures: Vec<f64>,
    /// Every (driver, corrected) pair, own-axis tables first for each driver.
    pub tables: Vec<AxisTable>,
    /// The largest position and orientation residual of any sampled correction (mm, rad).
    pub worst_residual_position: f64,
    pub worst_uncorrectable_orientation: f64,
}

impl TableSet {
    /// The table of `corrected` as a function of `driver`.
    pub fn table(&self, driver: usize, corrected: usize) -> Option<&AxisTable> {
        self.tables.iter().find(|t| t.driver == driver && t.corrected == corrected)
    }

    /// These tables minus `other`'s, table by table and point by point (both sampled along the same
    /// lines through the same reference pose): what tables must add to the corrections `other`
    /// describes, e.g. on top of a controller's corrected kinematics. The residuals are this set's.
    pub fn minus(&self, other: &TableSet) -> TableSet {
        let tables = self
            .tables
            .iter()
            .map(|t| {
                let o = other.table(t.driver, t.corrected).expect("both sets sample every pair of axes");
                debug_assert_eq!(t.positions, o.positions);
                let diff = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x - y).collect();
                AxisTable { forward: diff(&t.forward, &o.forward), reverse: diff(&t.reverse, &o.reverse), ..t.clone() }
            })
            .collect();
        TableSet { tables, ..self.clone() }
    }
}

/// The travel used for tables and grids of `axis` (mm or deg).
pub fn table_range(machine: &Machine, axis: usize) -> Result<[f64; 2], CompensateError> {
    let a = &machine.axes()[axis];
    match (a.range, a.kind) {
        (Some(r), _) => Ok(r),
        (None, AxisKind::Rotary) => Ok([0.0, 360.0]),
        (None, AxisKind::Linear) => {
            Err(CompensateError::Input(format!("axis {} has no range; give `range = [min, max]` in the machine file", a.letter)))
        }
    }
}

/// The reference pose: the given one (checked) or home clamped into each travel (mm, deg).
pub fn reference_pose(machine: &Machine, given: Option<&[f64]>) -> Result<Vec<f64>, CompensateError> {
    match given {
        Some(r) => {
            if r.len() != machine.axis_count() {
                return Err(CompensateError::Input(format!(
                    "the reference pose has {} values but machine `{}` has {} axes ({})",
                    r.len(),
                    machine.name,
                    machine.axis_count(),
                    machine.axis_letters()
                )));
            }
            machine.check_range(r).map_err(|m| CompensateError::Input(format!("reference pose: {m}")))?;
            Ok(r.to_vec())
        }
        None => (0..machine.axis_count()).map(|k| Ok(machine.axes()[k].range.map_or(0.0, |[lo, hi]| 0.0f64.clamp(lo, hi)))).collect(),
    }
}

/// `points` equally spaced positions over `[lo, hi]`, both ends included.
pub fn equally_spaced(lo: f64, hi: f64, points: usize) -> Vec<f64> {
    (0..points).map(|i| if i + 1 == points { hi } else { lo + (hi - lo) * i as f64 / (points - 1) as f64 }).collect()
}

/// Corrections (user units) of the poses `poses_user` (`axis_count` each), with the direction of
/// axis `moving` set to `direction` (others at rest), by [`correct_batch`] (parallel, the batch
/// kernel).
fn corrections(corrector: &Corrector, poses_user: &[f64], moving: Option<(usize, Direction)>, temperatures: &[f64]) -> Vec<Correction> {
    let m = corrector.machine;
    let n = m.axis_count();
    let mut poses = vec![0.0; poses_user.len()];
    for (user, q) in poses_user.chunks(n).zip(poses.chunks_mut(n)) {
        m.pose_to_internal(user, q);
    }
    let mut directions = vec![None; n];
    if let Some((k, d)) = moving {
        directions[k] = Some(d);
    }
    correct_batch(corrector, &poses, Some(&directions), temperatures)
}

fn check_converged(machine: &Machine, poses_user: &[f64], results: &[Correction]) -> Result<(), CompensateError> {
    let n = machine.axis_count();
    match results.iter().position(|c| !c.converged || c.dq.iter().any(|v| !v.is_finite())) {
        Some(i) => Err(CompensateError::Computation(format!(
            "the correction did not converge at pose {:?} (residual {:.4} um)",
            &poses_user[i * n..(i + 1) * n],
            results[i].residual_position.norm() * 1e3
        ))),
        None => Ok(()),
    }
}

/// Most points per table: more than any controller's compensation table holds (LinuxCNC 256,
/// Fanuc 128 per axis by default, Siemens as configured in MD38000), 1 um spacing over 100 mm;
/// checked before anything is allocated (a bound on memory and time, docs/limits.md).
pub const MAX_TABLE_POINTS: usize = 100_000;
/// Most nodes of a volumetric grid (about 100^3): one exact-chain correction per node, some
/// seconds; checked before anything is allocated.
pub const MAX_GRID_NODES: usize = 1_000_000;

/// Own-axis and cross-axis tables, both directions, for every axis of the machine; at most
/// [`MAX_TABLE_POINTS`] points per table.
pub fn axis_tables(corrector: &Corrector, spec: &TableSpec) -> Result<TableSet, CompensateError> {
    let m = corrector.machine;
    if spec.points < 2 {
        return Err(CompensateError::Input("a table needs at least 2 points".into()));
    }
    if spec.points > MAX_TABLE_POINTS {
        return Err(CompensateError::Input(format!(
            "{} points per table: at most {MAX_TABLE_POINTS} are computed (more than any controller's table holds)",
            spec.points
        )));
    }
    let reference = reference_pose(m, spec.reference.as_deref())?;
    let mut tables = Vec::new();
    let (mut worst_p, mut worst_o) = (0.0f64, 0.0f64);
    let covered = super::coverage::table_ranges(m, corrector.errors);
    for driver in 0..m.axis_count() {
        let [lo, hi] = table_range(m, driver)?;
        let travel = || format!("the travel of {}", m.axes()[driver].letter);
        super::coverage::check_covered(m, &covered, driver, lo, hi, &travel)?;
        let line = line_tables(corrector, &reference, &spec.temperatures, driver, &equally_spaced(lo, hi, spec.points))?;
        worst_p = worst_p.max(line.worst_residual_position);
        worst_o = worst_o.max(line.worst_uncorrectable_orientation);
        tables.extend(line.tables);
    }
    Ok(TableSet {
        reference,
        temperatures: spec.temperatures.clone(),
        tables,
        worst_residual_position: worst_p,
        worst_uncorrectable_orientation: worst_o,
    })
}

/// The tables of one driving axis sampled at `positions` (mm or deg, increasing) along the line
/// through `reference` (mm, deg): the own-axis table first, then the cross-axis tables of every
/// other axis (their value at the reference pose subtracted), both directions of motion of `driver`,
/// at the sensor temperatures `temperatures` (degC). The returned set's `reference` and
/// `temperatures` are those given. Used by [`axis_tables`] and by exporters whose controller fixes
/// its own sampling (the Fanuc pitch-error grid through the reference position).
pub fn line_tables(
    corrector: &Corrector,
    reference: &[f64],
    temperatures: &[f64],
    driver: usize,
    positions: &[f64],
) -> Result<TableSet, CompensateError> {
    let m = corrector.machine;
    let n = m.axis_count();
    let at_rest = corrections(corrector, reference, None, temperatures);
    check_converged(m, reference, &at_rest)?;
    let reference_dq = at_rest[0].dq_user(m);
    let poses: Vec<f64> = positions
        .iter()
        .flat_map(|&x| {
            let mut p = reference.to_vec();
            p[driver] = x;
            p
        })
        .collect();
    let forward = corrections(corrector, &poses, Some((driver, Direction::Positive)), temperatures);
    let reverse = corrections(corrector, &poses, Some((driver, Direction::Negative)), temperatures);
    check_converged(m, &poses, &forward)?;
    check_converged(m, &poses, &reverse)?;
    let (mut worst_p, mut worst_o) = (0.0f64, 0.0f64);
    for c in forward.iter().chain(&reverse) {
        worst_p = worst_p.max(c.residual_position.norm());
        worst_o = worst_o.max(c.uncorrectable_orientation.norm());
    }
    let mut order: Vec<usize> = vec![driver];
    order.extend((0..n).filter(|&j| j != driver));
    let tables = order
        .into_iter()
        .map(|corrected| {
            let axis = &m.axes()[corrected];
            let offset = if corrected == driver { 0.0 } else { reference_dq[corrected] };
            let column = |cs: &[Correction]| cs.iter().map(|c| axis.position_to_user(c.dq[corrected]) - offset).collect::<Vec<f64>>();
            AxisTable { driver, corrected, positions: positions.to_vec(), forward: column(&forward), reverse: column(&reverse) }
        })
        .collect();
    Ok(TableSet {
        reference: reference.to_vec(),
        temperatures: temperatures.to_vec(),
        tables,
        worst_residual_position: worst_p,
        worst_uncorrectable_orientation: worst_o,
    })
}

/// Corrections on a regular grid over the three linear axes X, Y, Z (other axes at the reference
/// pose), at rest: the volumetric map a controller interpolates trilinearly.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumetricGrid {
    /// Indices of the X, Y, Z axes.
    pub axes: [usize; 3],
    /// First node (mm) and spacing (mm) along each grid axis; counts of nodes.
    pub start: [f64; 3],
    pub step: [f64; 3],
    pub counts: [usize; 3],
    /// The pose of the other axes (mm, deg); the grid axes' entries are ignored.
    pub reference: Vec<f64>,
    /// Corrections of every machine axis (mm, deg), `axis_count` per node; node `(i, j, k)` at
    /// `((k * ny + j) * nx + i) * axis_count`.
    pub values: Vec<f64>,
    pub axis_count: usize,
    /// The largest position residual and uncorrected orientation of any node (mm, rad).
    pub worst_residual_position: f64,
    pub worst_uncorrectable_orientation: f64,
}

impl VolumetricGrid {
    /// Index of node `(i, j, k)`.
    pub fn node(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.counts[1] + j) * self.counts[0] + i
    }

    /// Position (mm) of node `(i, j, k)`.
    pub fn node_position(&self, i: usize, j: usize, k: usize) -> [f64; 3] {
        let idx = [i, j, k];
        std::array::from_fn(|d| self.start[d] + self.step[d] * idx[d] as f64)
    }

    /// This grid minus `other` (same nodes), node by node.
    pub fn minus(&self, other: &VolumetricGrid) -> VolumetricGrid {
        debug_assert_eq!((self.start, self.step, self.counts), (other.start, other.step, other.counts));
        VolumetricGrid { values: self.values.iter().zip(&other.values).map(|(a, b)| a - b).collect(), ..self.clone() }
    }

    /// Trilinear interpolation of the correction of axis `axis` at `p` (mm; clamped into the grid):
    /// the weighted sum over the 8 vertices of the cell containing `p` (Fanuc 30i three-dimensional
    /// error compensation, specs/anchors.md §3).
    pub fn interpolate(&self, p: [f64; 3], axis: usize) -> f64 {
        let mut cell = [0usize; 3];
        let mut t = [0.0; 3];
        for d in 0..3 {
            let last = self.counts[d] - 1;
            let u = ((p[d] - self.start[d]) / self.step[d]).clamp(0.0, last as f64);
            cell[d] = (u.floor() as usize).min(last.saturating_sub(1));
            t[d] = if last == 0 { 0.0 } else { u - cell[d] as f64 };
        }
        let mut sum = 0.0;
        for corner in 0..8 {
            let o = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
            let mut w = 1.0;
            let mut idx = [0usize; 3];
            for d in 0..3 {
                w *= if o[d] == 1 { t[d] } else { 1.0 - t[d] };
                idx[d] = (cell[d] + o[d]).min(self.counts[d] - 1);
            }
            if w != 0.0 {
                sum += w * self.values[self.node(idx[0], idx[1], idx[2]) * self.axis_count + axis];
            }
        }
        sum
    }
}

/// Samples the correction on a grid of `counts` nodes spanning the travel of X, Y and Z (at most
/// [`MAX_GRID_NODES`] nodes).
pub fn volumetric_grid(corrector: &Corrector, counts: [usize; 3], spec: &TableSpec) -> Result<VolumetricGrid, CompensateError> {
    let m = corrector.machine;
    let n = m.axis_count();
    let mut axes = [0usize; 3];
    for (d, letter) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        axes[d] = m.axis_index(letter).ok_or_else(|| {
            CompensateError::Input(format!("a volumetric grid needs the axes X, Y and Z; machine `{}` has {}", m.name, m.axis_letters()))
        })?;
    }
    if counts.iter().any(|&c| c < 2) {
        return Err(CompensateError::Input(format!("grid counts must be at least 2 per axis, got {counts:?}")));
    }
    let nodes = counts.iter().try_fold(1usize, |a, &c| a.checked_mul(c)).unwrap_or(usize::MAX);
    if nodes > MAX_GRID_NODES {
        return Err(CompensateError::Input(format!(
            "a grid of {}x{}x{} nodes has {nodes} nodes: at most {MAX_GRID_NODES} are computed (e.g. 100,100,100)",
            counts[0], counts[1], counts[2]
        )));
    }
    let reference = reference_pose(m, spec.reference.as_deref())?;
    let mut start = [0.0; 3];
    let mut step = [0.0; 3];
    let covered = super::coverage::table_ranges(m, corrector.errors);
    for d in 0..3 {
        let [lo, hi] = table_range(m, axes[d])?;
        super::coverage::check_covered(m, &covered, axes[d], lo, hi, &|| "the grid".to_string())?;
        start[d] = lo;
        step[d] = (hi - lo) / (counts[d] - 1) as f64;
    }
    let mut poses = Vec::with_capacity(counts.iter().product::<usize>() * n);
    for k in 0..counts[2] {
        for j in 0..counts[1] {
            for i in 0..counts[0] {
                let mut p = reference.clone();
                for (d, idx) in [i, j, k].into_iter().enumerate() {
                    p[axes[d]] = start[d] + step[d] * idx as f64;
                }
                poses.extend(p);
            }
        }
    }
    let results = corrections(corrector, &poses, None, &spec.temperatures);
    check_converged(m, &poses, &results)?;
    let values = results.iter().flat_map(|c| m.axes().iter().zip(&c.dq).map(|(a, &d)| a.position_to_user(d))).collect();
    let worst = |f: &dyn Fn(&Correction) -> f64| results.iter().map(f).fold(0.0, f64::max);
    Ok(VolumetricGrid {
        axes,
        start,
        step,
        counts,
        reference,
        values,
        axis_count: n,
        worst_residual_position: worst(&|c| c.residual_position.norm()),
        worst_uncorrectable_orientation: worst(&|c| c.uncorrectable_orientation.norm()),
    })
}
