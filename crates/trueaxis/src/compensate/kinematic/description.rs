//! The kinematic description of a machine with its location errors folded in: where each axis
//! actually moves, as a controller's kinematics (Heidenhain's kinematics description, Siemens swivel
//! data, a LinuxCNC kinematics module) describes a machine.
//!
//! The actual chain with constant location errors `L_k` (docs/design.md, "Frames and chain") is
//! `T = Π L_k J_k(q_k)` (base outward). It equals, exactly,
//!
//! ```text
//! T(q) = Π J'_k(q_k + δ_k) · G
//! ```
//!
//! where `J'_k` is the motion of axis k along its *actual* line at home (a rotary axis: rotation
//! about the line through `p'_k` with direction `d'_k`; a linear axis: translation along `d'_k`),
//! `δ_k` the zero offset of a rotary axis (the angle its motion has at the commanded zero), and `G`
//! a constant rigid transform at the end of the chain (the table frame of the workpiece side, the
//! tool frame of the tool side). Derivation: with `H_0 = I` and, axis by axis, `P = H_{k-1} L_k`,
//! the actual line is `P` applied to the nominal line; `M_k` is the smallest rigid motion that takes
//! the nominal line to it (the rotation from `d_k` to `d'_k` about `p_k`, then the shift of `p_k` to
//! `p'_k = P p_k`); `M_k^-1 P` keeps the nominal line and is a rotation about it by `δ_k`, which
//! commutes with `J_k`, so `P J_k(q) = J'_k(q + δ_k) M_k` and `H_k = M_k`. A linear axis has
//! `P Trans(q d) = Trans(q R_P d) P`, so `d'_k = R_P d_k` and `H_k = P`. At the end `G = H_n`.
//!
//! The converse ([`KinematicDescription::to_parameters`]) writes any description, nominal or
//! actual axis by axis, back as location errors of the machine, so that the corrector of
//! `crate::compensate` solves the controller's kinematics exactly (what the controller commands
//! with that description: its inverse kinematics).
//!
//! Units: mm and rad (internal).

use crate::geometry::{rotation_about_axis, rotation_exp, rotation_log, Pose, Vec3};
use crate::machine::{AxisKind, Component, Machine};

/// Where one axis moves at home.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisLine {
    /// Unit direction of motion (linear) or of the rotation (rotary), in M.
    pub direction: Vec3,
    /// Rotary: a point on the line (mm, in M), the image of the nominal axis point. Linear: the
    /// nominal reference point, unused by the motion.
    pub point: Vec3,
    /// Rotary: the angle of the motion at the commanded zero (rad). Linear: 0.
    pub zero_offset: f64,
}

/// Axis lines of every axis (canonical order) and the constant transforms at the ends of the two
/// chains.
#[derive(Clone, Debug, PartialEq)]
pub struct KinematicDescription {
    pub axes: Vec<AxisLine>,
    /// `G` of the tool side: the tool body relative to the last tool-side axis motion.
    pub tool_end: Pose,
    /// `G` of the workpiece side: the table frame relative to the last workpiece-side axis motion.
    pub work_end: Pose,
}

/// The rotation taking unit vector `a` to unit vector `b` about their common normal (the smallest
/// one); the identity when they are equal.
pub fn smallest_rotation(a: &Vec3, b: &Vec3) -> crate::geometry::Mat3 {
    let axis = a.cross(b);
    let angle = axis.norm().atan2(a.dot(b));
    if axis.norm() < 1e-300 {
        return crate::geometry::Mat3::identity();
    }
    rotation_exp(&(axis.normalize() * angle))
}

/// The location error `L_k` of axis `k` in the parameter vector `params` (mm, rad).
fn location(machine: &Machine, params: &[f64], k: usize) -> Pose {
    let start = machine.location_index(k, Component::X);
    let p = &params[start..start + 6];
    let axis = &machine.axes()[k];
    Pose::small_transform(&Vec3::new(p[3], p[4], p[5]), &Vec3::new(p[0], p[1], p[2]), &axis.location_error_centre())
}

/// The rigid motion that takes the nominal line of `axis` (point `p`, direction `d`) to `line`:
/// the smallest rotation of `d` to `line.direction` about `p`, then `p` to `line.point`.
fn alignment(p: &Vec3, d: &Vec3, line: &AxisLine) -> Pose {
    let r = smallest_rotation(d, &line.direction);
    Pose { rotation: r, translation: line.point - r * p }
}

impl KinematicDescription {
    /// The nominal description: every axis on its nominal line, no zero offsets, no end transforms.
    pub fn nominal(machine: &Machine) -> KinematicDescription {
        KinematicDescription {
            axes: machine.axes().iter().map(|a| AxisLine { direction: a.direction, point: a.point, zero_offset: 0.0 }).collect(),
            tool_end: Pose::IDENTITY,
            work_end: Pose::IDENTITY,
        }
    }

    /// The description of the actual machine whose location errors are those of `params` (the
    /// parameter vector of [`Machine::parameter_index`], mm and rad; motion and setup errors are
    /// not read).
    pub fn actual(machine: &Machine, params: &[f64]) -> KinematicDescription {
        let mut d = KinematicDescription::nominal(machine);
        for (chain, end) in [(machine.tool_chain(), &mut d.tool_end), (machine.work_chain(), &mut d.work_end)] {
            let mut h = Pose::IDENTITY;
            for &k in chain {
                let axis = &machine.axes()[k];
                let p = h.then(&location(machine, params, k));
                let direction = (p.rotation * axis.direction).normalize();
                match axis.kind {
                    AxisKind::Linear => {
                        d.axes[k] = AxisLine { direction, point: axis.point, zero_offset: 0.0 };
                        h = p;
                    }
                    AxisKind::Rotary => {
                        let line = AxisLine { direction, point: p.transform_point(&axis.point), zero_offset: 0.0 };
                        let m = alignment(&axis.point, &axis.direction, &line);
                        // M^-1 P keeps the nominal line: a rotation about it by the zero offset
                        let s = m.inverse().then(&p);
                        let zero_offset = rotation_log(&s.rotation).dot(&axis.direction);
                        d.axes[k] = AxisLine { zero_offset, ..line };
                        h = m;
                    }
                }
            }
            *end = h;
        }
        d
    }

    /// The same machine described in the frame of its linear axes, and `Q`: every line and
    /// direction turned by the rotation `Q` that takes the actual directions of the linear axes closest to their
    /// nominal ones (least squares; Kabsch 1976), the workpiece end dropped and the tool end `Q G`.
    ///
    /// A controller's kinematics is stated in the frame its linear axes span, and the relative
    /// motion of tool and workpiece does not change when both chains turn together: with
    /// `Π J'(Q l) = Q Π J'(l) Q^-1`, the tool relative to the workpiece is, up to a constant
    /// transform of the workpiece frame (what setting the workpiece datum absorbs), the chain with
    /// the turned lines, no workpiece end and the tool end `Q G_tool`. A rotation of the linear axes
    /// as a whole (a squareness of one side relative to the other) then shows as turned rotary axis
    /// lines, which the description can hold, and only what is not a common rotation (squareness
    /// proper) is left to the linear axes' tables. The relative position reached on the machine,
    /// `r`, and in this description, `r_Q`, are related by the workpiece datum `r_Q = Q G_work r`.
    pub fn in_frame_of_linear_axes(&self, machine: &Machine) -> (KinematicDescription, crate::geometry::Mat3) {
        let linear: Vec<usize> = (0..machine.axis_count()).filter(|&k| machine.axes()[k].kind == AxisKind::Linear).collect();
        let q = match linear.len() {
            0 => crate::geometry::Mat3::identity(),
            1 => smallest_rotation(&self.axes[linear[0]].direction, &machine.axes()[linear[0]].direction),
            _ => {
                let h = linear
                    .iter()
                    .fold(crate::geometry::Mat3::zeros(), |h, &k| h + machine.axes()[k].direction * self.axes[k].direction.transpose());
                let svd = h.svd(true, true);
                let (u, v_t) = (svd.u.expect("u requested"), svd.v_t.expect("v requested"));
                let mut d = crate::geometry::Mat3::identity();
                if (u * v_t).determinant() < 0.0 {
                    d[(2, 2)] = -1.0;
                }
                u * d * v_t
            }
        };
        let axes = self
            .axes
            .iter()
            .map(|l| AxisLine { direction: (q * l.direction).normalize(), point: q * l.point, zero_offset: l.zero_offset })
            .collect();
        let turn = Pose { rotation: q, translation: Vec3::zeros() };
        (KinematicDescription { axes, tool_end: turn.then(&self.tool_end), work_end: Pose::IDENTITY }, q)
    }

    /// The motion `J'_k(q + δ_k)` of axis `k` at `q` (mm or rad).
    pub fn motion(&self, machine: &Machine, k: usize, q: f64) -> Pose {
        let line = &self.axes[k];
        match machine.axes()[k].kind {
            AxisKind::Linear => Pose::translation(line.direction * q),
            AxisKind::Rotary => {
                let r = rotation_about_axis(&line.direction, q + line.zero_offset);
                Pose { rotation: r, translation: line.point - r * line.point }
            }
        }
    }

    /// The pose of the end of `chain` (axis indices, base outward) at `q` (mm, rad):
    /// `Π J'_k(q_k + δ_k) · end`.
    pub fn chain_pose(&self, machine: &Machine, chain: &[usize], q: &[f64], end: &Pose) -> Pose {
        chain.iter().fold(Pose::IDENTITY, |t, &k| t.then(&self.motion(machine, k, q[k]))).then(end)
    }

    /// Location errors of `machine` (a parameter vector, mm and rad, zero but for the location
    /// errors and, with `tool_end`, the tool setup `TX TY TZ`) whose actual chain is this
    /// description: `Π L_k J_k = Π J'_k(q_k + δ_k) · H` on each side, with `H` the alignment of the
    /// last axis. The workpiece side ends in `H` instead of [`Self::work_end`] (a constant transform
    /// of the table frame, which setting the workpiece datum absorbs); with `tool_end`, the tool
    /// setup puts the machine's tool point where [`Self::tool_end`] puts it.
    pub fn to_parameters(&self, machine: &Machine, tool_end: bool) -> Vec<f64> {
        self.to_parameters_and_ends(machine, tool_end).0
    }

    /// [`Self::to_parameters`], and the constant transforms `H` its chains end in (tool side,
    /// workpiece side): the workpiece side of the parameters is `Π J'_k(q_k + δ_k) · H_work`.
    pub fn to_parameters_and_ends(&self, machine: &Machine, tool_end: bool) -> (Vec<f64>, [Pose; 2]) {
        let mut params = vec![0.0; machine.parameter_count()];
        let mut ends = [Pose::IDENTITY; 2];
        for (side, chain) in [(0, machine.tool_chain()), (1, machine.work_chain())] {
            let mut h = Pose::IDENTITY;
            for &k in chain {
                let axis = &machine.axes()[k];
                let line = &self.axes[k];
                let (p, next) = match axis.kind {
                    AxisKind::Linear => {
                        let p = Pose { rotation: smallest_rotation(&axis.direction, &line.direction), translation: Vec3::zeros() };
                        (p, p)
                    }
                    AxisKind::Rotary => {
                        let m = alignment(&axis.point, &axis.direction, line);
                        (m.then(&Pose::rotation_about_line(&axis.direction, &axis.point, line.zero_offset)), m)
                    }
                };
                let l = h.inverse().then(&p);
                let c = axis.location_error_centre();
                let (eps, e) = (rotation_log(&l.rotation), l.translation - c + l.rotation * c);
                let start = machine.location_index(k, Component::X);
                params[start..start + 3].copy_from_slice(e.as_slice());
                params[start + 3..start + 6].copy_from_slice(eps.as_slice());
                h = next;
            }
            ends[side] = h;
            if side == 0 && tool_end {
                // H (tool_point + T) = tool_end (tool_point)
                let t = h.inverse().transform_point(&self.tool_end.transform_point(&machine.tool_point)) - machine.tool_point;
                for (c, v) in [Component::X, Component::Y, Component::Z].into_iter().zip(t.iter()) {
                    params[machine.setup_index(crate::machine::SetupSide::Tool, c)] = *v;
                }
            }
        }
        (params, ends)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::actual_chain;

    fn machine(name: &str) -> Machine {
        Machine::load(format!("{}/../../examples/machines/{name}.toml", env!("CARGO_MANIFEST_DIR"))).unwrap()
    }

    /// Location errors of every axis (and nothing else) of sizes found on machines: up to 0.05 mm
    /// and 500 urad, all six components.
    fn location_errors(m: &Machine, seed: u64) -> Vec<f64> {
        let mut params = vec![0.0; m.parameter_count()];
        let mut x = seed;
        let mut next = || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for k in 0..m.axis_count() {
            for c in Component::ALL {
                params[m.location_index(k, c)] = next() * if c.is_rotation() { 1e-3 } else { 0.1 };
            }
        }
        params
    }

    fn poses(m: &Machine) -> Vec<Vec<f64>> {
        (0..7)
            .map(|s| {
                m.axes()
                    .iter()
                    .enumerate()
                    .map(|(k, a)| {
                        let [lo, hi] = a.range.unwrap_or([0.0, 360.0]);
                        a.position_to_internal(lo + (hi - lo) * (((s * 5 + k * 3) % 9) as f64 + 0.3) / 9.0)
                    })
                    .collect()
            })
            .collect()
    }

    fn close(a: &Pose, b: &Pose) -> f64 {
        (a.rotation - b.rotation).norm() * 1e3 + (a.translation - b.translation).norm()
    }

    #[test]
    fn the_description_reproduces_the_chain_with_location_errors() {
        for name in ["c600u", "kx8five", "head5", "vmc3"] {
            let m = machine(name);
            let params = location_errors(&m, 7);
            let d = KinematicDescription::actual(&m, &params);
            for q in poses(&m) {
                for (chain, end) in [(m.tool_chain(), &d.tool_end), (m.work_chain(), &d.work_end)] {
                    let exact = actual_chain(&m, chain, &q, &params);
                    let described = d.chain_pose(&m, chain, &q, end);
                    assert!(close(&exact, &described) < 1e-11, "{name}: {exact:?} vs {described:?}");
                }
            }
            for (k, a) in m.axes().iter().enumerate() {
                assert!((d.axes[k].direction.norm() - 1.0).abs() < 1e-15);
                if a.kind == AxisKind::Rotary {
                    // with the location errors of this axis alone, its zero offset is their rotation
                    // about the axis itself (to second order in the errors)
                    let mut only = vec![0.0; m.parameter_count()];
                    let start = m.location_index(k, Component::X);
                    only[start..start + 6].copy_from_slice(&params[start..start + 6]);
                    let eps = Vec3::new(only[start + 3], only[start + 4], only[start + 5]);
                    let alone = KinematicDescription::actual(&m, &only);
                    assert!((alone.axes[k].zero_offset - eps.dot(&a.direction)).abs() < 1e-6, "{name} {}", a.letter);
                    assert!((alone.axes[k].direction - a.direction).norm() <= eps.norm() + 1e-12);
                }
            }
        }
    }

    #[test]
    fn a_description_written_as_location_errors_gives_its_chain_back() {
        for name in ["c600u", "kx8five", "head5"] {
            let m = machine(name);
            let d = KinematicDescription::actual(&m, &location_errors(&m, 11));
            let params = d.to_parameters(&m, true);
            for q in poses(&m) {
                // the workpiece side up to its constant end, the tool side with its tool point
                let exact = actual_chain(&m, m.work_chain(), &q, &params);
                let described = d.chain_pose(&m, m.work_chain(), &q, &Pose::IDENTITY);
                let end = described.inverse().then(&exact);
                let at_home = d.chain_pose(&m, m.work_chain(), &vec![0.0; m.axis_count()], &Pose::IDENTITY).inverse().then(&actual_chain(
                    &m,
                    m.work_chain(),
                    &vec![0.0; m.axis_count()],
                    &params,
                ));
                assert!(close(&end, &at_home) < 1e-11, "{name}: the workpiece end is not constant");
                let tool = actual_chain(&m, m.tool_chain(), &q, &params);
                let setup = m.setup_index(crate::machine::SetupSide::Tool, Component::X);
                let t = Vec3::new(params[setup], params[setup + 1], params[setup + 2]);
                let tool_point = tool.transform_point(&(m.tool_point + t));
                let expected = d.chain_pose(&m, m.tool_chain(), &q, &d.tool_end).transform_point(&m.tool_point);
                assert!((tool_point - expected).norm() < 1e-11, "{name}: {tool_point} vs {expected}");
            }
        }
    }
}
