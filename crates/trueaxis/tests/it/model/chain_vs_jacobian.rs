//! The first-order model (Jacobian, Soons 1993 eq. 2.24 / Andolfatto et al. 2011 eq. 2) against the exact chain:
//! the difference must scale as the square of the error size (docs/verification.md). And the exact
//! chain against an independent implementation with plain 4x4 homogeneous matrices.

use nalgebra::{Matrix4, Rotation3, Unit, Vector3};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use trueaxis::machine::{AxisKind, Machine, SetupSide};
use trueaxis::model::{jacobian, volumetric_error, Frame, JacobianWorkspace, Setup, VolumetricError, JACOBIAN_ROWS};

const MACHINES: [(&str, &str); 5] = [
    ("vmc3", include_str!("../../../../../examples/machines/vmc3.toml")),
    ("kx8five", include_str!("../../../../../examples/machines/kx8five.toml")),
    ("head5", include_str!("../../../../../examples/machines/head5.toml")),
    ("c600u", include_str!("../../../../../examples/machines/c600u.toml")),
    ("lathe2", include_str!("../../../../../examples/machines/lathe2.toml")),
];

fn machine(i: usize) -> Machine {
    Machine::from_toml_str(MACHINES[i].1, MACHINES[i].0).unwrap()
}

/// A pose inside the travel (rotary axes without a range: any angle), from unit-interval draws.
fn pose_from(machine: &Machine, draws: &[f64]) -> Vec<f64> {
    machine
        .axes()
        .iter()
        .zip(draws)
        .map(|(a, t)| {
            let [lo, hi] = a.range.unwrap_or([-180.0, 180.0]);
            a.position_to_internal(lo + (hi - lo) * t)
        })
        .collect()
}

fn as_rows(e: &VolumetricError) -> [f64; 7] {
    [e.position.x, e.position.y, e.position.z, e.orientation.x, e.orientation.y, e.orientation.z, e.length]
}

/// Largest |exact(s u) - J s u| over the three groups (position mm, orientation rad, dL mm).
fn remainder(machine: &Machine, q: &[f64], setup: &Setup, frame: Frame, u: &[f64], s: f64, jac: &[f64]) -> [f64; 3] {
    let n = machine.parameter_count();
    let params: Vec<f64> = u.iter().map(|v| v * s).collect();
    let exact = as_rows(&volumetric_error(machine, q, &params, setup, frame));
    let mut linear = [0.0; 7];
    for (r, l) in linear.iter_mut().enumerate() {
        *l = (0..n).map(|c| jac[r * n + c] * params[c]).sum();
    }
    let d = |a: usize, b: usize| (a..b).map(|i| (exact[i] - linear[i]).powi(2)).sum::<f64>().sqrt();
    [d(0, 3), d(3, 6), d(6, 7)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, rng_seed: RngSeed::Fixed(2024), ..ProptestConfig::default() })]

    /// Halving the error size divides the first-order remainder by 4 (second-order agreement),
    /// for every row group, every example machine, both frames.
    #[test]
    fn exact_minus_first_order_is_second_order(
        which in 0usize..MACHINES.len(),
        draws in proptest::collection::vec(0.0f64..1.0, 5),
        u in proptest::collection::vec(-1.0f64..1.0, 66),
        tool in proptest::collection::vec(-200.0f64..200.0, 3),
        work in proptest::collection::vec(-200.0f64..200.0, 3),
        machine_frame in any::<bool>(),
    ) {
        let m = machine(which);
        let q = pose_from(&m, &draws);
        let setup = Setup { tool_point: Vector3::new(tool[0], tool[1], tool[2]), work_point: Vector3::new(work[0], work[1], work[2]) };
        let frame = if machine_frame { Frame::Machine } else { Frame::Workpiece };
        let u = &u[..m.parameter_count()];
        let mut jac = vec![0.0; JACOBIAN_ROWS * m.parameter_count()];
        jacobian(&m, &q, &setup, frame, &mut JacobianWorkspace::default(), &mut jac);
        // s = 1e-5: rotations up to 10 urad, translations up to 0.01 um per parameter (66 of them).
        // The remainder is bounded by (lever arm ~1000 mm) * |s u|^2, |u|^2 <= 66. Where it is
        // significant (above 1e-4 of that bound, far above rounding) halving s must divide it by 4.
        let s = 1e-5;
        let bound = 1e3 * 66.0 * s * s;
        let big = remainder(&m, &q, &setup, frame, u, 2.0 * s, &jac);
        let small = remainder(&m, &q, &setup, frame, u, s, &jac);
        for g in 0..3 {
            prop_assert!(small[g] < bound, "group {g}: remainder {} above the second-order bound {bound}", small[g]);
            if small[g] > 1e-4 * bound {
                let ratio = big[g] / small[g];
                prop_assert!((ratio - 4.0).abs() < 0.05, "group {g}: remainder ratio {ratio} (expected 4 for a second-order remainder)");
            }
        }
    }
}

// ---- an independent implementation of the same chain with 4x4 matrices ----

fn trans(v: Vector3<f64>) -> Matrix4<f64> {
    let mut m = Matrix4::identity();
    m.fixed_view_mut::<3, 1>(0, 3).copy_from(&v);
    m
}

fn small(eps: Vector3<f64>, e: Vector3<f64>, c: Vector3<f64>) -> Matrix4<f64> {
    trans(c) * trans(e) * Rotation3::new(eps).to_homogeneous() * trans(-c)
}

fn chain_4x4(m: &Machine, chain: &[usize], q: &[f64], p: &[f64]) -> Matrix4<f64> {
    let mut t = Matrix4::identity();
    for &k in chain {
        let a = &m.axes()[k];
        let l = m.location_index(k, trueaxis::machine::Component::X);
        let s = m.motion_index(k, trueaxis::machine::Component::X);
        let v3 = |i: usize| Vector3::new(p[i], p[i + 1], p[i + 2]);
        let (location_centre, motion_centre, nominal) = match a.kind {
            AxisKind::Linear => (Vector3::zeros(), a.point + a.direction * q[k], trans(a.direction * q[k])),
            AxisKind::Rotary => {
                let r = Rotation3::from_axis_angle(&Unit::new_normalize(a.direction), q[k]).to_homogeneous();
                (a.point, a.point, trans(a.point) * r * trans(-a.point))
            }
        };
        t = t * small(v3(l + 3), v3(l), location_centre) * small(v3(s + 3), v3(s), motion_centre) * nominal;
    }
    t
}

fn relative_4x4(m: &Machine, q: &[f64], p: &[f64], setup: &Setup) -> (Vector3<f64>, Rotation3<f64>) {
    let t = m.setup_index(SetupSide::Tool, trueaxis::machine::Component::X);
    let w = m.setup_index(SetupSide::Workpiece, trueaxis::machine::Component::X);
    let tool = chain_4x4(m, m.tool_chain(), q, p) * trans(setup.tool_point + Vector3::new(p[t], p[t + 1], p[t + 2]));
    let work = chain_4x4(m, m.work_chain(), q, p) * trans(setup.work_point + Vector3::new(p[w], p[w + 1], p[w + 2]));
    let rel = work.try_inverse().unwrap() * tool;
    let rot = Rotation3::from_matrix_unchecked(rel.fixed_view::<3, 3>(0, 0).into_owned());
    (rel.fixed_view::<3, 1>(0, 3).into_owned(), rot)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, rng_seed: RngSeed::Fixed(2025), ..ProptestConfig::default() })]

    /// The exact chain equals a direct product of 4x4 HTMs (nalgebra's own exp map and inverse)
    /// to 1e-9 um, for errors up to 1 mrad / 1 mm per parameter.
    #[test]
    fn exact_chain_matches_plain_homogeneous_matrices(
        which in 0usize..MACHINES.len(),
        draws in proptest::collection::vec(0.0f64..1.0, 5),
        u in proptest::collection::vec(-1e-3f64..1e-3, 66),
        work in proptest::collection::vec(-100.0f64..100.0, 3),
    ) {
        let m = machine(which);
        let q = pose_from(&m, &draws);
        let p = &u[..m.parameter_count()];
        let setup = Setup { tool_point: m.tool_point, work_point: Vector3::new(work[0], work[1], work[2]) };
        let got = volumetric_error(&m, &q, p, &setup, Frame::Workpiece);
        let zero = vec![0.0; m.parameter_count()];
        let (r_act, rot_act) = relative_4x4(&m, &q, p, &setup);
        let (r_nom, rot_nom) = relative_4x4(&m, &q, &zero, &setup);
        prop_assert!((got.position - (r_act - r_nom)).norm() < 1e-12, "position {} vs {}", got.position, r_act - r_nom);
        // compared as rotation matrices: nalgebra's exp map against the relative rotation of the
        // 4x4 chain (its `scaled_axis` goes through acos and loses precision near the identity)
        let relative = rot_act * rot_nom.inverse();
        prop_assert!((Rotation3::new(got.orientation).matrix() - relative.matrix()).norm() < 1e-14);
        prop_assert!((got.length - (r_act.norm() - r_nom.norm())).abs() < 1e-11);
    }
}

/// The parallel batch gives, pose by pose, the same rows as the single-pose Jacobian.
#[test]
fn jacobian_batch_stacks_the_single_pose_jacobians() {
    let m = machine(1);
    let n = m.parameter_count();
    let poses: Vec<f64> = (0..1000).flat_map(|i| pose_from(&m, &[0.1 + 0.0008 * i as f64, 0.5, 0.9, 0.3, (i % 7) as f64 / 7.0])).collect();
    let setup = Setup::of_machine(&m);
    let batch = trueaxis::model::jacobian_batch(&m, &poses, &setup, Frame::Machine);
    assert_eq!(batch.len(), 1000 * JACOBIAN_ROWS * n);
    let mut single = vec![0.0; JACOBIAN_ROWS * n];
    let mut ws = JacobianWorkspace::default();
    for (i, q) in poses.chunks(m.axis_count()).enumerate() {
        jacobian(&m, q, &setup, Frame::Machine, &mut ws, &mut single);
        assert_eq!(&batch[i * JACOBIAN_ROWS * n..(i + 1) * JACOBIAN_ROWS * n], &single[..], "pose {i}");
    }
}

/// The three squareness errors of vmc3 (`wXYbZt`: X rides on Y, Z on the base), each alone at
/// s = 12 urad, against the closed form `s * lever` (docs/design.md, Conventions: the error of the carried
/// body relative to its parent, tool relative to workpiece in the workpiece frame):
/// - `EC0X`: X (with the table) turned by s about z relative to Y. The X motion stays along the
///   table's x; the Y motion is seen turned by -s in the table frame: `dx = s * Y`, `dy = 0`.
/// - `EA0Z`: Z turned about x through the origin (table surface); the tool point is at height
///   `h = 400 + Z` mm: `dy = -s h`, `dx = 0`.
/// - `EB0Z`: Z turned about y: `dx = +s h`, `dy = 0`.
///
/// `EC0Y` turns Y with everything it carries (the whole table stack) and is no squareness: no
/// position error at any pose. Tolerance 1e-4 um (second-order terms are s^2 * 500 mm = 7e-5 um).
#[test]
fn vmc3_squareness_errors_give_s_times_lever() {
    use trueaxis::error_model::{ErrorFunction, ErrorModel};
    use trueaxis::machine::ParameterId;
    use trueaxis::model::Predictor;
    let m = machine(0);
    let s = 12.0; // urad
    let poses = [[0.0, 0.0, 0.0], [300.0, 200.0, -100.0], [-400.0, -250.0, -400.0], [150.0, -120.0, -250.0]];
    for (name, expected) in [
        ("EC0X", (|q: [f64; 3], s: f64| [s * q[1], 0.0, 0.0]) as fn([f64; 3], f64) -> [f64; 3]),
        ("EA0Z", |q, s| [0.0, -s * (400.0 + q[2]), 0.0]),
        ("EB0Z", |q, s| [s * (400.0 + q[2]), 0.0, 0.0]),
        ("EC0Y", |_, _| [0.0; 3]),
    ] {
        let mut errors = ErrorModel::zero(&m);
        errors.set(&m, ParameterId::parse(name).unwrap(), ErrorFunction::Constant(s)).unwrap();
        for frame in [Frame::Workpiece, Frame::Machine] {
            let mut predictor = Predictor::new(&m, &errors);
            predictor.frame = frame;
            for q in poses {
                let got = predictor.predict(&q).to_user_units();
                // urad * mm = 1e-3 um
                let want = expected(q, s * 1e-3);
                for i in 0..3 {
                    assert!(
                        (got[i] - want[i]).abs() < 1e-4,
                        "{name} at {q:?} ({frame:?}): d{} = {} um, expected {}",
                        ["x", "y", "z"][i],
                        got[i],
                        want[i]
                    );
                }
            }
        }
    }
    // and the non-zero ones are visible: 12 urad over a 300 mm lever is 3.6 um
    let mut errors = ErrorModel::zero(&m);
    errors.set(&m, ParameterId::parse("EC0X").unwrap(), ErrorFunction::Constant(s)).unwrap();
    assert!((Predictor::new(&m, &errors).predict(&[0.0, 300.0, 0.0]).to_user_units()[0] - 3.6).abs() < 1e-4);
}
