//! Ballbar (double ball bar, DBB) tests: the two ball centres, the poses the machine visits, and the
//! bar readings simulated on the exact kinematic chain.
//!
//! A test is a [`Setup`] (spindle ball = tool-side point, pivot ball = workpiece-side point, in M at
//! home, mm) and a list of poses. The bar reading is `dL = |actual| - |nominal|` of the vector from
//! the pivot to the spindle ball (docs/design.md, Conventions), so any machine description works.
//!
//! Presets:
//! - [`circle_test`]: planar circle of ISO 230-4 with two linear axes (CW or CCW);
//! - [`rotary_test`]: one rotary axis swept with the pivot at a radius from it and the spindle ball
//!   on the nominal axis, possibly displaced along it (Jiang 2014): the steps A1 A2 C1 C2 of
//!   ch. 5 ([`jiang_step`]), the two-pivot method of ch. 4 and the four-setup method of ch. 6
//!   (Lee & Yang 2013) are instances with different axial positions of the balls.

use crate::data::{CsvTable, DataError};
use crate::error_model::{Direction, ErrorModel, MachineState};
use crate::geometry::Vec3;
use crate::io::ballbar::BallbarHeader;
use crate::io::plausibility::{self, Finding, Place, Severity};
use crate::io::ranges::READING_UM;
use crate::io::units::Dimension;
use crate::machine::{AxisKind, Machine};
use crate::model::{jacobian, nominal_chain, volumetric_error, Frame, JacobianWorkspace, Setup, JACOBIAN_ROWS};
use thiserror::Error;

#[derive(Debug, Error, PartialEq)]
pub enum BallbarError {
    /// A setup that the machine cannot carry out (unknown axis, wrong kind, out of range).
    #[error("{0}")]
    Setup(String),
}

crate::error::error_of_kind!(BallbarError, Input);

/// Sense of a circular path seen from the positive normal of its plane (right-handed plane basis).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rotation {
    /// Counter-clockwise: increasing angle.
    Ccw,
    /// Clockwise: decreasing angle.
    Cw,
}

impl Rotation {
    /// `ccw` or `cw`.
    pub fn name(self) -> &'static str {
        match self {
            Rotation::Ccw => "ccw",
            Rotation::Cw => "cw",
        }
    }

    pub fn parse(text: &str) -> Option<Rotation> {
        match text.to_ascii_lowercase().as_str() {
            "ccw" | "+" => Some(Rotation::Ccw),
            "cw" | "-" => Some(Rotation::Cw),
            other => match crate::io::ballbar::sense_of(other) {
                Some(crate::io::ballbar::Sense::Ccw) => Some(Rotation::Ccw),
                Some(crate::io::ballbar::Sense::Cw) => Some(Rotation::Cw),
                _ => None,
            },
        }
    }

    /// +1 for CCW, -1 for CW.
    pub fn sign(self) -> f64 {
        match self {
            Rotation::Ccw => 1.0,
            Rotation::Cw => -1.0,
        }
    }
}

/// Geometry of a rotary-axis test (Jiang 2014): which axis turns, where the balls are along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotaryGeometry {
    /// Index of the swept rotary axis in the machine's canonical order.
    pub axis: usize,
    /// In-plane basis of the pivot circle: `u1` = direction of the pivot from the axis at angle 0,
    /// `u2 = d x u1` (the angle grows from `u1` toward `u2`).
    pub u1: Vec3,
    pub u2: Vec3,
    /// Position of the spindle ball along the nominal axis direction `d`, from the axis reference
    /// point (mm). Ch. 5 A2: `-D`; C2: `+D`; ch. 4: the pivot's offset; ch. 6: `±D_A`, `0`, `D_C`.
    pub spindle_position: f64,
    /// Distance from the spindle ball to the plane of the pivot circle, along the axis (mm):
    /// `D = sqrt(L_e^2 - R^2)` for an extended-bar step, 0 for a radial bar.
    pub axial_separation: f64,
    /// Radius of the pivot circle (mm).
    pub radius: f64,
}

/// A ballbar test: the two ball centres and the poses visited.
#[derive(Clone, Debug)]
pub struct BallbarTest {
    pub name: String,
    pub setup: Setup,
    /// `axis_count` positions per sample, internal units (mm, rad), canonical axis order.
    pub poses: Vec<f64>,
    /// Direction of motion per axis and sample (`axis_count` per sample), for bidirectional errors.
    pub directions: Vec<Option<Direction>>,
    /// Polar angle of each sample in the plane of the test (rad): for a circle, the angle of the
    /// programmed position about the centre; for a rotary test, the axis position.
    pub angles: Vec<f64>,
    /// Nominal distance between the ball centres (mm), the same at every sample.
    pub nominal_length: f64,
    /// Set for rotary-axis tests.
    pub rotary: Option<RotaryGeometry>,
    axis_count: usize,
}

impl BallbarTest {
    pub fn len(&self) -> usize {
        self.angles.len()
    }

    pub fn is_empty(&self) -> bool {
        self.angles.is_empty()
    }

    /// Positions (mm, rad) of sample `i`.
    pub fn pose(&self, i: usize) -> &[f64] {
        &self.poses[i * self.axis_count..(i + 1) * self.axis_count]
    }

    /// Exact bar readings `dL` (mm) for the parameter vector `params` (mm, rad).
    pub fn simulate_params(&self, machine: &Machine, params: &[f64]) -> Vec<f64> {
        (0..self.len()).map(|i| volumetric_error(machine, self.pose(i), params, &self.setup, Frame::Workpiece).length).collect()
    }

    /// Exact bar readings `dL` (mm) with an error model, at the directions of motion of the path
    /// (bidirectional errors such as `EXX+` / `EXX-` act).
    pub fn simulate(&self, machine: &Machine, errors: &ErrorModel) -> Vec<f64> {
        let mut values = vec![0.0; machine.parameter_count()];
        (0..self.len())
            .map(|i| {
                let directions = &self.directions[i * self.axis_count..(i + 1) * self.axis_count];
                let state = MachineState { directions: Some(directions), temperatures: &[] };
                errors.values_at_state(machine, self.pose(i), &state, &mut values);
                volumetric_error(machine, self.pose(i), &values, &self.setup, Frame::Workpiece).length
            })
            .collect()
    }

    /// The `dL` row of the first-order model (Soons 1993 eq. 2.24) at every sample: `len()` rows of
    /// `machine.parameter_count()` (mm of bar length per mm or rad of parameter), row-major.
    pub fn dl_jacobian(&self, machine: &Machine) -> Vec<f64> {
        let n = machine.parameter_count();
        let mut ws = JacobianWorkspace::default();
        let mut block = vec![0.0; JACOBIAN_ROWS * n];
        let mut out = Vec::with_capacity(self.len() * n);
        for i in 0..self.len() {
            jacobian(machine, self.pose(i), &self.setup, Frame::Workpiece, &mut ws, &mut block);
            out.extend_from_slice(&block[6 * n..7 * n]);
        }
        out
    }
}

/// Plane of a circular test, named by its two linear axes in right-handed order: `xy` (angle from
/// +X toward +Y), `yz` (from +Y toward +Z), `zx` (from +Z toward +X).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    Xy,
    Yz,
    Zx,
}

impl Plane {
    pub fn parse(text: &str) -> Option<Plane> {
        match text.to_ascii_lowercase().as_str() {
            "xy" => Some(Plane::Xy),
            "yz" => Some(Plane::Yz),
            "zx" | "xz" => Some(Plane::Zx),
            _ => None,
        }
    }

    /// Letters of the first and second in-plane axes and of the normal axis.
    pub fn letters(self) -> (char, char, char) {
        match self {
            Plane::Xy => ('X', 'Y', 'Z'),
            Plane::Yz => ('Y', 'Z', 'X'),
            Plane::Zx => ('Z', 'X', 'Y'),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Plane::Xy => "xy",
            Plane::Yz => "yz",
            Plane::Zx => "zx",
        }
    }
}

/// A planar circular test (ISO 230-4): the programmed centre and radius, the plane, and the angles.
#[derive(Clone, Debug)]
pub struct CircleSpec {
    pub plane: Plane,
    /// Programmed centre: position of every machine axis (user units, mm and deg), canonical order.
    pub centre: Vec<f64>,
    pub radius: f64,
    /// Polar angles of the samples (rad), in the order the path visits them.
    pub angles: Vec<f64>,
    pub rotation: Rotation,
}

fn axis_of(machine: &Machine, letter: char) -> Result<usize, BallbarError> {
    machine
        .axis_index(letter)
        .ok_or_else(|| BallbarError::Setup(format!("machine `{}` has no axis {letter} (axes: {})", machine.name, machine.axis_letters())))
}

/// A planar circular test on `machine`: the pivot ball sits where the nominal tool point is at the
/// programmed centre (so the bar is radial in the plane), and the poses run over
/// `centre + R (cos t, sin t)` in the plane's two axes. Directions of motion follow the tangent of
/// the path. Errors name an axis the machine lacks or a pose outside the travel.
pub fn circle_test(machine: &Machine, spec: &CircleSpec) -> Result<BallbarTest, BallbarError> {
    let (a_letter, b_letter, _) = spec.plane.letters();
    let (a, b) = (axis_of(machine, a_letter)?, axis_of(machine, b_letter)?);
    for k in [a, b] {
        if machine.axes()[k].kind != AxisKind::Linear {
            return Err(BallbarError::Setup(format!("axis {} is not linear", machine.axes()[k].letter)));
        }
    }
    let n_axes = machine.axis_count();
    if spec.centre.len() != n_axes {
        return Err(BallbarError::Setup(format!("the centre needs {n_axes} axis positions ({})", machine.axis_letters())));
    }
    let mut centre_q = vec![0.0; n_axes];
    machine.pose_to_internal(&spec.centre, &mut centre_q);
    // The pivot: the nominal tool point at the centre pose, in the workpiece frame (= M at home).
    let tool = nominal_chain(machine, machine.tool_chain(), &centre_q, None).transform_point(&machine.tool_point);
    let work = nominal_chain(machine, machine.work_chain(), &centre_q, None);
    let pivot = work.inverse().transform_point(&tool);
    let setup = Setup { tool_point: machine.tool_point, work_point: pivot };

    let mut poses = Vec::with_capacity(spec.angles.len() * n_axes);
    let mut directions = Vec::with_capacity(spec.angles.len() * n_axes);
    let mut user = spec.centre.clone();
    let sign = spec.rotation.sign();
    for &t in &spec.angles {
        user[a] = spec.centre[a] + spec.radius * t.cos();
        user[b] = spec.centre[b] + spec.radius * t.sin();
        machine.check_range(&user).map_err(|e| BallbarError::Setup(format!("circle of radius {} mm: {e}", spec.radius)))?;
        let mut q = vec![0.0; n_axes];
        machine.pose_to_internal(&user, &mut q);
        poses.extend_from_slice(&q);
        // velocity along the path: sign * (-sin t, cos t)
        let velocity = [(a, -sign * t.sin()), (b, sign * t.cos())];
        for k in 0..n_axes {
            let v = velocity.iter().find(|(i, _)| *i == k).map(|(_, v)| *v);
            directions.push(match v {
                Some(v) if v > 1e-12 => Some(Direction::Positive),
                Some(v) if v < -1e-12 => Some(Direction::Negative),
                _ => None,
            });
        }
    }
    let nominal_length = nominal_distance(machine, &setup, &poses[..n_axes.min(poses.len())]);
    Ok(BallbarTest {
        name: format!("{} circle R{} {}", spec.plane.name(), spec.radius, spec.rotation.name()),
        setup,
        poses,
        directions,
        angles: spec.angles.clone(),
        nominal_length,
        rotary: None,
        axis_count: n_axes,
    })
}

fn nominal_distance(machine: &Machine, setup: &Setup, q: &[f64]) -> f64 {
    if q.is_empty() {
        return 0.0;
    }
    let tool = nominal_chain(machine, machine.tool_chain(), q, None).transform_point(&setup.tool_point);
    let work = nominal_chain(machine, machine.work_chain(), q, None).transform_point(&setup.work_point);
    (tool - work).norm()
}

/// Where the balls of a rotary-axis test are (Jiang 2014 ch. 4-6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotarySpec {
    /// Letter of the swept rotary axis.
    pub axis: char,
    /// Unit direction of the pivot from the axis at axis position 0 (perpendicular to the axis).
    pub radial: Vec3,
    /// Pivot radius from the axis (mm).
    pub radius: f64,
    /// Position of the pivot plane along the axis direction, from the axis point (mm).
    pub pivot_position: f64,
    /// Position of the spindle ball along the axis direction, from the axis point (mm).
    pub spindle_position: f64,
}

/// A rotary-axis test: only `spec.axis` moves, over `angles_deg` (deg); every other axis stays at
/// `base` (user units). The ball carried by the axis at `p + pivot_position d + radius radial`, the
/// other on the axis at `p + spindle_position d` (`p`, `d`: the axis point and direction at home).
/// For a workpiece-side axis (a table) the carried ball is the pivot and the spindle ball is on the
/// axis, as in Jiang 2014; for a tool-side axis (a head) the roles swap: the spindle ball is carried at
/// the radius and the table ball sits on the axis. The bar reading depends only on the distance, so
/// the identification of [`crate::identify::pige`] is the same for both.
pub fn rotary_test(machine: &Machine, spec: &RotarySpec, angles_deg: &[f64], base: &[f64]) -> Result<BallbarTest, BallbarError> {
    let k = axis_of(machine, spec.axis)?;
    let axis = &machine.axes()[k];
    if axis.kind != AxisKind::Rotary {
        return Err(BallbarError::Setup(format!("axis {} is not rotary", spec.axis)));
    }
    let n_axes = machine.axis_count();
    if base.len() != n_axes {
        return Err(BallbarError::Setup(format!("the base pose needs {n_axes} axis positions ({})", machine.axis_letters())));
    }
    let d = axis.direction;
    let radial = spec.radial - d * spec.radial.dot(&d);
    if radial.norm() < 1e-9 || spec.radius.is_nan() || spec.radius <= 0.0 {
        return Err(BallbarError::Setup(format!("the pivot must lie at a positive radius off the {} axis", spec.axis)));
    }
    let u1 = radial.normalize();
    let u2 = d.cross(&u1);
    let on_axis = axis.point + d * spec.spindle_position;
    let carried = axis.point + d * spec.pivot_position + u1 * spec.radius;
    // The ball at the radius rides on the swept axis: the pivot on the table for a workpiece-side
    // axis, the spindle ball for a tool-side (head) axis; the other ball stays on the axis.
    let setup = if machine.tool_chain().contains(&k) {
        Setup { tool_point: carried, work_point: on_axis }
    } else {
        Setup { tool_point: on_axis, work_point: carried }
    };
    let mut poses = Vec::with_capacity(angles_deg.len() * n_axes);
    let mut user = base.to_vec();
    let mut q = vec![0.0; n_axes];
    for &a in angles_deg {
        user[k] = a;
        machine.check_range(&user).map_err(|e| BallbarError::Setup(e.to_string()))?;
        machine.pose_to_internal(&user, &mut q);
        poses.extend_from_slice(&q);
    }
    let sweep = if angles_deg.last() >= angles_deg.first() { Direction::Positive } else { Direction::Negative };
    let directions = (0..angles_deg.len()).flat_map(|_| (0..n_axes).map(move |j| (j == k).then_some(sweep))).collect();
    let nominal_length = nominal_distance(machine, &setup, &poses[..n_axes.min(poses.len())]);
    Ok(BallbarTest {
        name: format!("{} axis, pivot R{} at {}, spindle at {}", spec.axis, spec.radius, spec.pivot_position, spec.spindle_position),
        setup,
        poses,
        directions,
        angles: angles_deg.iter().map(|a| a.to_radians()).collect(),
        nominal_length,
        rotary: Some(RotaryGeometry {
            axis: k,
            u1,
            u2,
            spindle_position: spec.spindle_position,
            axial_separation: spec.spindle_position - spec.pivot_position,
            radius: spec.radius,
        }),
        axis_count: n_axes,
    })
}

/// The four steps of the one-pivot method of Jiang 2014 ch. 5 (Fig. 5.1 / 3.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JiangStep {
    /// Outer axis (A), normal bar: pivot on the inner table at radius R, spindle ball at the axis point.
    A1,
    /// Outer axis, extended bar: spindle ball moved by `-D` along the outer axis.
    A2,
    /// Inner axis (C), normal bar.
    C1,
    /// Inner axis, extended bar: spindle ball moved by `+D` along the inner axis.
    C2,
}

impl JiangStep {
    pub const ALL: [JiangStep; 4] = [JiangStep::A1, JiangStep::A2, JiangStep::C1, JiangStep::C2];

    pub fn name(self) -> &'static str {
        match self {
            JiangStep::A1 => "A1",
            JiangStep::A2 => "A2",
            JiangStep::C1 => "C1",
            JiangStep::C2 => "C2",
        }
    }

    pub fn parse(text: &str) -> Option<JiangStep> {
        JiangStep::ALL.into_iter().find(|s| s.name().eq_ignore_ascii_case(text))
    }

    pub fn is_outer(self) -> bool {
        matches!(self, JiangStep::A1 | JiangStep::A2)
    }

    pub fn is_extended(self) -> bool {
        matches!(self, JiangStep::A2 | JiangStep::C2)
    }
}

/// Bar lengths of the Jiang 2014 tests (Table 3.1): normal `R` and extended `L_e` (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarLengths {
    pub normal: f64,
    pub extended: f64,
}

impl BarLengths {
    /// Table 3.1: 100 mm and 150 mm.
    pub const TABLE_3_1: BarLengths = BarLengths { normal: 100.0, extended: 150.0 };

    /// Axial offset of the spindle ball for the extended step, `D = sqrt(L_e^2 - R^2)` (Jiang 2014
    /// Eq. 7.1; the printed Eq. 3.13, `D = 50 sqrt 2`, is an arithmetic erratum).
    pub fn extended_offset(&self) -> f64 {
        (self.extended * self.extended - self.normal * self.normal).max(0.0).sqrt()
    }
}

/// The two rotary axes of a five-axis machine, tested as Jiang 2014 tests A (`outer`) and C
/// (`inner`). On a table-tilting machine (`wCAbYXZt`) or a spindle-tilting one (`wXYbZCBt`) both
/// are on one side and `outer` (the one nearer the base) carries `inner`; on a machine with one
/// rotary axis on each side (`wCXYbZAt`) neither carries the other and `outer` is the tool-side one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RotaryPair {
    pub outer: char,
    pub inner: char,
}

impl RotaryPair {
    /// The two rotary axes of `machine`: both workpiece-side, both tool-side (base first), or one
    /// on each side (tool side first). Errors name the rotary axes the machine has.
    pub fn of_machine(machine: &Machine) -> Result<RotaryPair, BallbarError> {
        let rotary = |chain: &[usize]| -> Vec<char> {
            chain.iter().map(|&k| &machine.axes()[k]).filter(|a| a.kind == AxisKind::Rotary).map(|a| a.letter).collect()
        };
        let (work, tool) = (rotary(machine.work_chain()), rotary(machine.tool_chain()));
        match (work.as_slice(), tool.as_slice()) {
            ([outer, inner], []) | ([], [outer, inner]) | ([inner], [outer]) => Ok(RotaryPair { outer: *outer, inner: *inner }),
            _ => Err(BallbarError::Setup(format!(
                "machine `{}` has {} rotary axes ({}); the 5-axis ballbar tests need exactly two",
                machine.name,
                work.len() + tool.len(),
                work.iter().chain(&tool).collect::<String>()
            ))),
        }
    }

    /// True when `outer` carries `inner` (both on the same side of the chain): then the inner axis
    /// is seen through the outer's location errors (Jiang 2014 Table 5.1).
    pub fn inner_carried_by_outer(&self, machine: &Machine) -> bool {
        let side = |letter: char| machine.axis_index(letter).map(|k| machine.tool_chain().contains(&k));
        side(self.outer) == side(self.inner)
    }
}

/// Which four steps measure the PIGEs (Jiang 2014): the steps are always called A1 A2 (the outer
/// axis) and C1 C2 (the inner axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Ch. 5, one pivot setup: normal bar (A1, C1) and extended bar (A2, C2), [`jiang_spec`].
    ExtendedBar,
    /// Ch. 4, two pivot placements: as ch. 5 with both balls of the outer-axis steps moved by
    /// `outer_offset` (mm) along the outer axis (the pivot off the inner table centre).
    TwoPivot { outer_offset: f64 },
    /// Ch. 6 (Lee & Yang 2013), normal bar only: the outer axis at two positions along it
    /// (A1, A2; mm from the outer axis point) and the inner axis at two (C1, C2; mm from the plane
    /// through the outer axis point).
    FourSetup { outer: [f64; 2], inner: [f64; 2] },
}

impl Method {
    pub fn name(&self) -> &'static str {
        match self {
            Method::ExtendedBar => "extended-bar",
            Method::TwoPivot { .. } => "two-pivot",
            Method::FourSetup { .. } => "four-setup",
        }
    }
}

/// The placement of one step of `method` (see [`Method`]; built on [`jiang_spec`]).
pub fn method_spec(
    machine: &Machine,
    pair: RotaryPair,
    method: Method,
    step: JiangStep,
    bars: BarLengths,
) -> Result<RotarySpec, BallbarError> {
    let bad = |what: &str, v: f64| -> Result<(), BallbarError> {
        if v.is_finite() {
            Ok(())
        } else {
            Err(BallbarError::Setup(format!("{what} {v} is not a finite number of mm")))
        }
    };
    match method {
        Method::ExtendedBar => jiang_spec(machine, pair, step, bars, 0.0),
        Method::TwoPivot { outer_offset } => {
            bad("the outer-axis pivot offset", outer_offset)?;
            jiang_spec(machine, pair, step, bars, if step.is_outer() { outer_offset } else { 0.0 })
        }
        Method::FourSetup { outer, inner } => {
            let normal = if step.is_outer() { JiangStep::A1 } else { JiangStep::C1 };
            let positions = if step.is_outer() { outer } else { inner };
            for v in positions {
                bad("a four-setup position", v)?;
            }
            if (positions[0] - positions[1]).abs() < 1.0 {
                return Err(BallbarError::Setup(format!(
                    "the two positions along the {} axis must differ by at least 1 mm (the tilt is their centres' difference over their distance), got {} and {}",
                    if step.is_outer() { pair.outer } else { pair.inner },
                    positions[0],
                    positions[1]
                )));
            }
            let mut spec = jiang_spec(machine, pair, normal, bars, 0.0)?;
            let at = positions[usize::from(step.is_extended())];
            spec.pivot_position += at;
            spec.spindle_position += at;
            Ok(spec)
        }
    }
}

/// The ballbar placement of one step of Jiang 2014 ch. 5: the pivot on the inner table in the plane
/// through the outer axis point, `R` from the axis under test: for the outer axis along
/// `d_inner x d_outer` (A test: +Y), for the inner axis along `d_outer` (C test: +X); the spindle
/// ball on the axis under test, moved by `-D` (outer) or `+D` (inner) for the extended steps.
/// `outer_offset` moves both balls of the outer-axis steps along the outer axis (ch. 4: the pivot
/// away from the inner table centre; 0 for ch. 5).
pub fn jiang_spec(
    machine: &Machine,
    pair: RotaryPair,
    step: JiangStep,
    bars: BarLengths,
    outer_offset: f64,
) -> Result<RotarySpec, BallbarError> {
    let outer = &machine.axes()[axis_of(machine, pair.outer)?];
    let inner = &machine.axes()[axis_of(machine, pair.inner)?];
    let d = bars.extended_offset();
    let (axis, radial, shift, spindle) = match step {
        JiangStep::A1 => (pair.outer, inner.direction.cross(&outer.direction), outer_offset, 0.0),
        JiangStep::A2 => (pair.outer, inner.direction.cross(&outer.direction), outer_offset, -d),
        JiangStep::C1 => (pair.inner, outer.direction, 0.0, 0.0),
        JiangStep::C2 => (pair.inner, outer.direction, 0.0, d),
    };
    // Positions along the tested axis are counted from its point; the inner test uses the point of
    // the inner axis nearest to the outer axis point.
    let along = if step.is_outer() { 0.0 } else { (outer.point - inner.point).dot(&inner.direction) };
    Ok(RotarySpec { axis, radial, radius: bars.normal, pivot_position: along + shift, spindle_position: along + shift + spindle })
}

/// `n` equally spaced angles (deg) from `start` over `span`: a full circle (`|span| = 360`) leaves
/// out the end point, which repeats the start; an arc includes both ends.
pub fn sweep_angles(start: f64, span: f64, step: f64) -> Vec<f64> {
    let steps = (span.abs() / step.abs()).round().max(1.0) as usize;
    let full = (span.abs() - 360.0).abs() < 1e-9;
    let count = if full { steps } else { steps + 1 };
    (0..count).map(|i| start + span * i as f64 / steps as f64).collect()
}

/// A step of Jiang 2014 ch. 5 on `machine` (all other axes at 0), swept every `step_deg`: the outer
/// axis over its range (-20 ... 70 deg on the C600U), the inner axis over 0 ... 360 deg.
pub fn jiang_step(
    machine: &Machine,
    pair: RotaryPair,
    step: JiangStep,
    bars: BarLengths,
    step_deg: f64,
) -> Result<BallbarTest, BallbarError> {
    method_step(machine, pair, Method::ExtendedBar, step, bars, step_deg)
}

/// A step of `method` on `machine` (all other axes at 0), swept every `step_deg` over the axis
/// range, or one turn (0 ... 360 deg, or from the range start) when the range is a turn or more.
pub fn method_step(
    machine: &Machine,
    pair: RotaryPair,
    method: Method,
    step: JiangStep,
    bars: BarLengths,
    step_deg: f64,
) -> Result<BallbarTest, BallbarError> {
    let spec = method_spec(machine, pair, method, step, bars)?;
    let axis = &machine.axes()[axis_of(machine, spec.axis)?];
    let angles = match axis.range {
        Some([lo, hi]) if hi - lo < 360.0 => sweep_angles(lo, hi - lo, step_deg),
        Some([lo, hi]) if lo > 0.0 || hi < 360.0 => sweep_angles(lo, 360.0, step_deg),
        _ => sweep_angles(0.0, 360.0, step_deg),
    };
    let mut test = rotary_test(machine, &spec, &angles, &vec![0.0; machine.axis_count()])?;
    test.name = format!("{} ({})", step.name(), test.name);
    Ok(test)
}

/// Bar readings read from a file: the swept angle (deg), `dL` (um) and the run number of each row,
/// with the file's metadata, the ballbar test's header and warnings of the plausibility checks.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceFile {
    pub angles_deg: Vec<f64>,
    pub dl_um: Vec<f64>,
    /// `run` column, or 1 for every row.
    pub runs: Vec<i64>,
    pub metadata: crate::io::Metadata,
    pub header: BallbarHeader,
    /// Suspicious but usable content, each naming the file and column.
    pub warnings: Vec<String>,
}

impl TraceFile {
    /// The distinct run numbers, in order of first appearance.
    pub fn run_numbers(&self) -> Vec<i64> {
        let mut out: Vec<i64> = Vec::new();
        for r in &self.runs {
            if !out.contains(r) {
                out.push(*r);
            }
        }
        out
    }

    /// Angles (rad) and readings (mm) of run `run`.
    pub fn run(&self, run: i64) -> (Vec<f64>, Vec<f64>) {
        let rows = (0..self.runs.len()).filter(|&i| self.runs[i] == run);
        rows.map(|i| (self.angles_deg[i].to_radians(), self.dl_um[i] * 1e-3)).unzip()
    }
}

/// The finding of a plausibility check as an error of `table` (refusal) or a warning line.
fn sort_finding(table: &CsvTable, f: Option<Finding>, warnings: &mut Vec<String>) -> Result<(), DataError> {
    match f {
        Some(Finding { severity: Severity::Refuse, message }) => Err(DataError::Invalid {
            origin: table.origin().to_string(),
            message: message.strip_prefix(&format!("{}: ", table.origin())).unwrap_or(&message).to_string(),
        }),
        Some(Finding { severity: Severity::Warn, message }) => {
            warnings.push(message);
            Ok(())
        }
        None => Ok(()),
    }
}

/// The test parameters in the header of a ballbar file (`io::ballbar`); an unreadable value is an
/// error naming the file.
pub fn ballbar_header(table: &CsvTable) -> Result<BallbarHeader, DataError> {
    BallbarHeader::from_metadata(table.metadata())
        .map_err(|m| DataError::Invalid { origin: table.origin().to_string(), message: m.to_string() })
}

/// The bar deviations (um, actual minus nominal length) of a ballbar table: the `dL` column (or a
/// synonym: `deviation`, `dr` ...; unit from the header, um by default), or a length column
/// (`radius`, `length`, mm by default) from which `radius_mm` is subtracted. Checked by
/// [`check_bar_deviations`]; warnings are pushed.
pub fn bar_deviations(table: &CsvTable, radius_mm: Option<f64>, warnings: &mut Vec<String>) -> Result<Vec<f64>, DataError> {
    let dl = bar_readings(table, radius_mm, warnings)?;
    check_bar_deviations(table, radius_mm, &dl, warnings)?;
    Ok(dl)
}

/// The length column of a ballbar table, if its readings are bar lengths.
fn length_column(table: &CsvTable) -> Option<&'static str> {
    ["radius", "length", "barlength", "actualradius", "measuredradius"].into_iter().find(|c| table.has_column(c))
}

/// The bar deviations (um) of a ballbar table as [`bar_deviations`] reads them, before the checks
/// of their size (a raw capture is checked on its capture arc only).
pub fn bar_readings(table: &CsvTable, radius_mm: Option<f64>, warnings: &mut Vec<String>) -> Result<Vec<f64>, DataError> {
    match (table.has_column("dL"), length_column(table)) {
        (false, Some(c)) => {
            let r = radius_mm.ok_or_else(|| DataError::Invalid {
                origin: table.origin().to_string(),
                message: format!(
                    "the readings are bar lengths (column {}); give the nominal radius (--radius, or `Radius:` in the header)",
                    table.column_text(c).unwrap_or(c)
                ),
            })?;
            let lengths = table.numbers_in(c, crate::io::Unit::MM)?;
            let text = table.column_text(c).unwrap_or(c).to_string();
            sort_finding(table, plausibility::bar_lengths(&lengths, r, Place { file: table.origin(), column: &text }), warnings)?;
            Ok(lengths.iter().map(|l| (l - r) * 1e3).collect())
        }
        _ => table.numbers_as("dL", Dimension::Length),
    }
}

/// The checks of bar deviations `dl` (um) read from `table`: against the radius
/// (`io::plausibility::ballbar_readings`) and for their size; refusals are errors, warnings pushed.
pub fn check_bar_deviations(table: &CsvTable, radius_mm: Option<f64>, dl: &[f64], warnings: &mut Vec<String>) -> Result<(), DataError> {
    let length_column = length_column(table);
    let column = table.column_text("dL").or_else(|| length_column.and_then(|c| table.column_text(c))).unwrap_or("dL").to_string();
    crate::data::checks::physical_range(table, if table.has_column("dL") { "dL" } else { length_column.unwrap_or("dL") }, dl, &READING_UM)?;
    if let Some(r) = radius_mm {
        let place = Place { file: table.origin(), column: &column };
        sort_finding(table, plausibility::ballbar_readings(dl, r, place), warnings)?;
    }
    let finding = if table.has_column("dL") {
        crate::data::checks::deviation_finding(table, "dL", dl)
    } else {
        let place = Place { file: table.origin(), column: &column };
        plausibility::deviation_scale(dl, None, place, "label the header `radius [mm]`", "label the header with the unit of the values")
    };
    sort_finding(table, finding, warnings)
}

/// An angle column (deg; the header's unit honoured), refused when the values look like radians.
pub fn angle_column(table: &CsvTable, name: &str) -> Result<Vec<f64>, DataError> {
    let angles = table.numbers_as(name, Dimension::Angle)?;
    if table.unit_of(name).is_none() {
        let text = table.column_text(name).unwrap_or(name).to_string();
        let fix = format!(
            "label the header `{} [rad]` (or convert the values to degrees)",
            table.headers().iter().find(|h| h.text == text).map_or(name, |h| h.name.as_str())
        );
        sort_finding(
            table,
            plausibility::angles_in_radians(&angles, Place { file: table.origin(), column: &text }, &fix),
            &mut Vec::new(),
        )?;
    }
    Ok(angles)
}

/// Checks that the angles of each run (rows in file order) cover the arc the header claims.
pub fn check_arc(
    table: &CsvTable,
    header: &BallbarHeader,
    angles_deg: &[f64],
    runs: &[i64],
    warnings: &mut Vec<String>,
) -> Result<(), DataError> {
    let Some(arc) = header.arc_deg else { return Ok(()) };
    let mut seen: Vec<i64> = Vec::new();
    for &r in runs {
        if seen.contains(&r) {
            continue;
        }
        seen.push(r);
        let a: Vec<f64> = (0..runs.len()).filter(|&i| runs[i] == r).map(|i| angles_deg[i]).collect();
        sort_finding(table, plausibility::arc_coverage(&a, arc, Place { file: table.origin(), column: "angles" }), warnings)?;
    }
    Ok(())
}

/// Angles (deg) of rows sampled at a fixed rate (no angle column): the `sample` column (or the
/// row's place within its run) times the step that the header's radius, feed rate and sample rate
/// give, counter-clockwise or clockwise per row.
pub fn sample_angles(table: &CsvTable, header: &BallbarHeader, runs: &[i64], ccw: &[bool]) -> Result<Vec<f64>, DataError> {
    let index: Vec<f64> = match ["sample", "index", "point", "samplenumber", "n"].into_iter().find(|c| table.has_column(c)) {
        Some(c) => table.numbers(c)?,
        None => {
            let mut count: Vec<(i64, f64)> = Vec::new();
            runs.iter()
                .map(|r| match count.iter_mut().find(|c| c.0 == *r) {
                    Some(c) => {
                        c.1 += 1.0;
                        c.1
                    }
                    None => {
                        count.push((*r, 0.0));
                        0.0
                    }
                })
                .collect()
        }
    };
    let bad = |m: crate::Error| DataError::Invalid { origin: table.origin().to_string(), message: m.to_string() };
    let unit_ccw = header.sample_angles(2, true).map_err(bad)?;
    let unit_cw = header.sample_angles(2, false).map_err(bad)?;
    let start = header.start_deg.unwrap_or(0.0);
    Ok(index
        .iter()
        .zip(ccw)
        .map(|(k, &c)| {
            let step = if c { unit_ccw[1] - unit_ccw[0] } else { unit_cw[1] - unit_cw[0] };
            start + step * k
        })
        .collect())
}

/// Reads a bar trace forgivingly (`data::CsvTable`): the first of `angle_columns` present (e.g.
/// `C`, then `angle`; deg), or sample numbers with the radius, feed rate and sample rate in the
/// header; `dL` (um) or bar lengths; optional integer `run`. Errors name the file, line and column;
/// the plausibility checks (radians, size of the readings, radius, arc) refuse or warn.
pub fn read_trace(path: impl AsRef<std::path::Path>, angle_columns: &[&str]) -> Result<TraceFile, DataError> {
    trace_of(&CsvTable::read(path)?, angle_columns)
}

/// As [`read_trace`] from a table already read.
pub fn trace_of(table: &CsvTable, angle_columns: &[&str]) -> Result<TraceFile, DataError> {
    let header = ballbar_header(table)?;
    let mut warnings: Vec<String> = table.warnings().to_vec();
    let dl_um = bar_readings(table, header.radius_mm, &mut warnings)?;
    let runs: Vec<i64> = if table.has_column("run") {
        table
            .numbers("run")?
            .iter()
            .enumerate()
            .map(|(i, v)| {
                if v.fract() == 0.0 && v.abs() < 1e15 {
                    Ok(*v as i64)
                } else {
                    Err(table.row_error(i, &format!("column run: `{v}` is not an integer")))
                }
            })
            .collect::<Result<_, _>>()?
    } else {
        vec![1; dl_um.len()]
    };
    let (rows, angles_deg) = match angle_columns.iter().find(|c| table.has_column(c)) {
        Some(c) => ((0..dl_um.len()).collect(), angle_column(table, c)?),
        None if header.feed_mm_per_min.is_some() || header.sample_rate_hz.is_some() => {
            // the sense of each row: a `dir` column, else the header's direction
            let ccw: Vec<bool> = if table.has_column("dir") {
                let texts = table.texts("dir")?;
                texts
                    .iter()
                    .enumerate()
                    .map(|(i, t)| {
                        Rotation::parse(t)
                            .map(|r| r == Rotation::Ccw)
                            .ok_or_else(|| table.row_error(i, &format!("column dir: `{t}` is not `ccw` or `cw`")))
                    })
                    .collect::<Result<_, _>>()?
            } else {
                vec![header.sense != Some(crate::io::ballbar::Sense::Cw); runs.len()]
            };
            let sense_runs: Vec<i64> = runs.iter().zip(&ccw).map(|(r, c)| 2 * r + i64::from(*c)).collect();
            super::ballbar_raw::sampled_rows(table, &header, &sense_runs, &ccw, &dl_um, &mut warnings)?
        }
        None => {
            return Err(DataError::Invalid {
                origin: table.origin().to_string(),
                message: format!(
                    "needs an angle column ({}, deg) and `dL` (um), or sample numbers with `Radius`, `Feed rate` and `Sample rate` in the header",
                    angle_columns.iter().map(|c| format!("`{c}`")).collect::<Vec<_>>().join(" or ")
                ),
            })
        }
    };
    // a raw capture keeps the rows of its capture arcs only
    let dl_um: Vec<f64> = rows.iter().map(|&i| dl_um[i]).collect();
    let runs: Vec<i64> = rows.iter().map(|&i| runs[i]).collect();
    check_bar_deviations(table, header.radius_mm, &dl_um, &mut warnings)?;
    check_arc(table, &header, &angles_deg, &runs, &mut warnings)?;
    Ok(TraceFile { angles_deg, dl_um, runs, metadata: table.metadata().clone(), header, warnings })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c600u() -> Machine {
        Machine::from_toml_str(include_str!("../../../../examples/machines/c600u.toml"), "c600u").unwrap()
    }

    #[test]
    fn jiang_steps_place_the_balls_as_the_thesis() {
        // Jiang 2014 ch. 5 (digest 2.4): A1 pivot (0,R,0) spindle O; A2 spindle (-D,0,0);
        // C1 pivot (R,0,0) spindle O; C2 spindle (0,0,D).
        let m = c600u();
        let pair = RotaryPair::of_machine(&m).unwrap();
        assert_eq!(pair, RotaryPair { outer: 'A', inner: 'C' });
        let bars = BarLengths::TABLE_3_1;
        let d = bars.extended_offset();
        let expect = [
            (JiangStep::A1, Vec3::new(0.0, 100.0, 0.0), Vec3::zeros(), 100.0),
            (JiangStep::A2, Vec3::new(0.0, 100.0, 0.0), Vec3::new(-d, 0.0, 0.0), 150.0),
            (JiangStep::C1, Vec3::new(100.0, 0.0, 0.0), Vec3::zeros(), 100.0),
            (JiangStep::C2, Vec3::new(100.0, 0.0, 0.0), Vec3::new(0.0, 0.0, d), 150.0),
        ];
        for (step, pivot, spindle, length) in expect {
            let t = jiang_step(&m, pair, step, bars, 5.0).unwrap();
            assert!((t.setup.work_point - pivot).norm() < 1e-12, "{step:?}");
            assert!((t.setup.tool_point - spindle).norm() < 1e-12, "{step:?}");
            assert!((t.nominal_length - length).abs() < 1e-9, "{step:?}: {}", t.nominal_length);
            let n = if step.is_outer() { 19 } else { 72 };
            assert_eq!(t.len(), n);
        }
    }

    #[test]
    fn sweeps_leave_out_the_repeated_end_of_a_full_circle() {
        assert_eq!(sweep_angles(0.0, 360.0, 90.0), vec![0.0, 90.0, 180.0, 270.0]);
        assert_eq!(sweep_angles(-20.0, 90.0, 45.0), vec![-20.0, 25.0, 70.0]);
        assert_eq!(sweep_angles(0.0, -360.0, 180.0), vec![0.0, -180.0]);
    }

    #[test]
    fn circle_pivot_is_at_the_programmed_centre() {
        let m = Machine::from_toml_str(include_str!("../../../../examples/machines/vmc3.toml"), "vmc3").unwrap();
        let spec = CircleSpec {
            plane: Plane::Xy,
            centre: vec![10.0, 20.0, -100.0],
            radius: 100.0,
            angles: sweep_angles(0.0, 360.0, 90.0).iter().map(|a: &f64| a.to_radians()).collect(),
            rotation: Rotation::Ccw,
        };
        let t = circle_test(&m, &spec).unwrap();
        // vmc3: tool at (0,0,400) at home, X and Y move the table by -X, -Y: the tool relative to the
        // table is at (X, Y, 400 + Z).
        assert!((t.setup.work_point - Vec3::new(10.0, 20.0, 300.0)).norm() < 1e-9);
        assert!((t.nominal_length - 100.0).abs() < 1e-9);
        // at t = 0 (CCW) X is at rest, Y moves +
        assert_eq!(&t.directions[..3], &[None, Some(Direction::Positive), None]);
        let err = circle_test(&m, &CircleSpec { radius: 500.0, ..spec }).unwrap_err();
        assert!(err.to_string().contains("outside its range"), "{err}");
    }
}
