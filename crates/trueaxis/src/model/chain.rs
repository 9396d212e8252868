//! Nominal and actual forward kinematics of the two serial chains (docs/design.md, Conventions):
//! `A_k(q) = L_k S_k(q) J_k(q)`, products taken from the base outward.

use crate::geometry::{Pose, Vec3};
use crate::machine::{Axis, AxisKind, Component, Machine};

/// Nominal pose of the end of `chain` (axis indices, base outward) at pose `q` (mm, rad), the
/// product of the `J_k(q_k)`. `parents`, when given, receives the nominal pose of each axis's
/// parent body (the frame its errors are stated in).
pub fn nominal_chain(machine: &Machine, chain: &[usize], q: &[f64], mut parents: Option<&mut Vec<Pose>>) -> Pose {
    if let Some(p) = parents.as_deref_mut() {
        p.clear();
    }
    let mut t = Pose::IDENTITY;
    for &k in chain {
        if let Some(p) = parents.as_deref_mut() {
            p.push(t);
        }
        t = t.then(&machine.axes()[k].nominal_motion(q[k]));
    }
    t
}

/// Actual pose of the end of `chain` at pose `q` with the error parameter vector `params`
/// (internal units, the layout of [`Machine::parameter_index`]): the exact product of
/// `L_k S_k(q_k) J_k(q_k)`, each small transform applied exactly (rotation by `exp([eps]x)`).
pub fn actual_chain(machine: &Machine, chain: &[usize], q: &[f64], params: &[f64]) -> Pose {
    nominal_and_actual_chain(machine, chain, q, params).1
}

/// The nominal and the actual pose of the end of `chain` in one pass (the hot path of the exact
/// volumetric error): each `J_k(q_k)` is computed once for both products, a linear axis's `J_k` is
/// applied as a pure translation, and an `L_k` or `S_k` whose six components are all zero is the
/// identity exactly and is skipped.
pub(crate) fn nominal_and_actual_chain(machine: &Machine, chain: &[usize], q: &[f64], params: &[f64]) -> (Pose, Pose) {
    let (mut nominal, mut actual) = (Pose::IDENTITY, Pose::IDENTITY);
    for &k in chain {
        let axis = &machine.axes()[k];
        for (start, centre) in [
            (machine.location_index(k, Component::X), axis.location_error_centre()),
            (machine.motion_index(k, Component::X), axis.motion_error_centre(q[k])),
        ] {
            if params[start..start + 6].iter().any(|v| *v != 0.0) {
                let (eps, e) = small_displacement(params, start);
                actual = actual.then(&Pose::small_transform(&eps, &e, &centre));
            }
        }
        match axis.kind {
            AxisKind::Linear => {
                let t = axis.direction * q[k];
                nominal = nominal.then_translation(&t);
                actual = actual.then_translation(&t);
            }
            AxisKind::Rotary => {
                let motion = axis.nominal_motion(q[k]);
                nominal = nominal.then(&motion);
                actual = actual.then(&motion);
            }
        }
    }
    (nominal, actual)
}

/// The rotation vector `eps` and translation `e` stored as the six consecutive components
/// `X Y Z A B C` at `start` of a parameter vector.
#[inline]
pub(crate) fn small_displacement(params: &[f64], start: usize) -> (Vec3, Vec3) {
    let p = &params[start..start + 6];
    (Vec3::new(p[3], p[4], p[5]), Vec3::new(p[0], p[1], p[2]))
}

/// Centre (in the parent frame) of the location error or the motion error of `axis` at `q`.
#[inline]
pub(crate) fn error_centre(axis: &Axis, motion: bool, q: f64) -> Vec3 {
    if motion {
        axis.motion_error_centre(q)
    } else {
        axis.location_error_centre()
    }
}
