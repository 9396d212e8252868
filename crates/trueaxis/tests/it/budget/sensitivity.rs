//! The sensitivity matrix of the error budget against central differences of the exact chain, the
//! stack-ups against direct sums (every sign combination for the worst case), and the singular
//! values against an SVD of the homogenised matrix (Zhu 2008 eqs. B.1-B.4, B.12-B.13).

use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use trueaxis::budget::sensitivity::sensitivity;
use trueaxis::budget::spec::{BudgetSpec, KindValues};
use trueaxis::budget::stackup::stack_up;
use trueaxis::budget::{analyse, ErrorKind};
use trueaxis::geometry::Vec3;
use trueaxis::machine::{AxisKind, Machine};
use trueaxis::model::{volumetric_error, Frame, Setup};

const MACHINES: [&str; 5] = ["vmc3", "c600u", "kx8five", "head5", "lathe2"];

fn machine(name: &str) -> Machine {
    Machine::load(format!("{}/../../examples/machines/{name}.toml", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// Random poses within the travel (rotary axes over +-180 deg or their range), internal units.
fn random_poses(m: &Machine, count: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let mut out = Vec::new();
    for _ in 0..count {
        for axis in m.axes() {
            let [lo, hi] = axis.range.unwrap_or([-180.0, 180.0]);
            out.push(axis.position_to_internal(rng.gen_range(lo..=hi)));
        }
    }
    out
}

#[test]
fn sensitivity_equals_central_differences_of_the_exact_chain() {
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    for name in MACHINES {
        let m = machine(name);
        let spec = BudgetSpec::standard(&m, KindValues::DEFAULT);
        for frame in [Frame::Workpiece, Frame::Machine] {
            let setup = Setup { tool_point: m.tool_point + Vec3::new(12.0, -7.0, 30.0), work_point: Vec3::new(40.0, 25.0, -10.0) };
            let poses = random_poses(&m, 4, &mut rng);
            let s = sensitivity(&m, &spec.components, &poses, &setup, frame);
            for (p, q) in poses.chunks(m.axis_count()).enumerate() {
                for (j, c) in spec.components.iter().enumerate() {
                    // a step of 0.01 um or 0.01 urad: second-order terms below 1e-9 of the gain
                    let h = 0.01 * c.id.component().to_internal();
                    let error = |sign: f64| {
                        let mut params = vec![0.0; m.parameter_count()];
                        params[c.index] = sign * h;
                        volumetric_error(&m, q, &params, &setup, frame).position * 1e3
                        // um
                    };
                    let difference = (error(1.0) - error(-1.0)) / (2.0 * 0.01); // um per um or urad
                    let column = s.column(p, j);
                    let scale = column.norm().max(1e-3);
                    assert!(
                        (column - difference).norm() <= 1e-6 * scale,
                        "{name} {frame:?} pose {p} {}: {column:?} vs {difference:?}",
                        c.id
                    );
                }
            }
        }
    }
}

#[test]
fn abbe_lever_of_a_pitch_error_on_vmc3() {
    // vmc3: X carries the table; its pitch EBX tilts the workpiece about y through the X carriage
    // reference point (the origin, moving with x); the tool tip 400 + z mm above it: the error along x
    // is -EBX * (400 + z) in the workpiece frame (1 urad x 1 m = 1 um)
    let m = machine("vmc3");
    let spec = BudgetSpec::standard(&m, KindValues::DEFAULT);
    let j = spec.components.iter().position(|c| c.id.to_string() == "EBX").unwrap();
    for z in [0.0, -150.0, -400.0] {
        let s = sensitivity(&m, &spec.components, &[100.0, 50.0, z], &Setup::of_machine(&m), Frame::Workpiece);
        let g = s.column(0, j);
        assert!((g.x.abs() - (400.0 + z) * 1e-3).abs() < 1e-12, "z {z}: {g:?}");
        assert!(g.y.abs() < 1e-12);
    }
}

#[test]
fn stack_up_equals_direct_sums() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let m = machine("c600u");
    let spec = BudgetSpec::standard(&m, KindValues::DEFAULT);
    let poses = random_poses(&m, 6, &mut rng);
    let s = sensitivity(&m, &spec.components, &poses, &Setup::of_machine(&m), Frame::Workpiece);
    let n = spec.components.len();
    for p in 0..6 {
        // a small case: 11 components picked at random, the others with zero tolerance
        let mut t = vec![0.0; n];
        let picked: Vec<usize> = (0..11).map(|_| rng.gen_range(0..n)).collect();
        for &j in &picked {
            t[j] = rng.gen_range(0.5..20.0);
        }
        let result = stack_up(s.pose(p), &t);
        for d in 0..3 {
            let mut rss = 0.0;
            let mut worst = 0.0;
            for (g, e) in s.row(p, d).iter().zip(&t) {
                rss += (g * e).powi(2);
                worst += g.abs() * e;
            }
            assert!((result.rss[d] - rss.sqrt()).abs() <= 1e-12 * rss.sqrt().max(1.0));
            assert!((result.worst[d] - worst).abs() <= 1e-12 * worst.max(1.0));
        }
        let total: f64 = (0..n).map(|j| (s.column(p, j) * t[j]).norm_squared()).sum();
        assert!((result.rss_total - total.sqrt()).abs() <= 1e-12 * total.sqrt());
        // every one of the 2^k sign combinations of the non-zero components
        let active: Vec<usize> = (0..n).filter(|&j| t[j] > 0.0).collect();
        let mut largest: f64 = 0.0;
        for mask in 0..1u32 << active.len() {
            let v: Vec3 =
                active.iter().enumerate().map(|(b, &j)| s.column(p, j) * t[j] * if mask >> b & 1 == 1 { 1.0 } else { -1.0 }).sum();
            largest = largest.max(v.norm());
        }
        assert!((result.worst_total - largest).abs() <= 1e-9 * largest, "pose {p}: {} vs {largest}", result.worst_total);
    }
}

#[test]
fn singular_values_equal_an_svd_of_the_homogenised_matrix() {
    let m = machine("kx8five");
    let spec = BudgetSpec::standard(&m, KindValues::DEFAULT);
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let poses = random_poses(&m, 3, &mut rng);
    let analysis = analyse(&m, &spec, &poses, &Setup::of_machine(&m), Frame::Workpiece).unwrap();
    let s = &analysis.sensitivity;
    let n = spec.components.len();
    let mut stacked = DMatrix::zeros(9, n);
    for p in 0..3 {
        let h = DMatrix::from_fn(3, n, |d, j| {
            let c = &spec.components[j];
            // homogenised: linear errors per um/m (x axis length in m), angular per urad; in mm
            let factor = if c.kind == ErrorKind::Linear { c.length_mm } else { 1000.0 };
            s.row(p, d)[j] * factor
        });
        let sv = h.clone().svd(false, false).singular_values;
        let mut sv: Vec<f64> = sv.iter().copied().collect();
        sv.sort_by(|a, b| b.total_cmp(a));
        for k in 0..3 {
            assert!((analysis.poses[p].singular_values[k] - sv[k]).abs() <= 1e-9 * sv[0], "pose {p}");
        }
        assert!((analysis.poses[p].condition.unwrap() - sv[0] / sv[2]).abs() <= 1e-8 * sv[0] / sv[2]);
        stacked.view_mut((3 * p, 0), (3, n)).copy_from(&(h / 3f64.sqrt()));
    }
    // over the poses: the square roots of the eigenvalues of the mean of the per-pose Gram matrices
    let mut gram = nalgebra::Matrix3::<f64>::zeros();
    for p in 0..3 {
        for a in 0..3 {
            for b in 0..3 {
                gram[(a, b)] += (0..n).map(|j| stacked[(3 * p + a, j)] * stacked[(3 * p + b, j)]).sum::<f64>();
            }
        }
    }
    let mut eig: Vec<f64> = gram.symmetric_eigenvalues().iter().map(|l| l.sqrt()).collect();
    eig.sort_by(|a, b| b.total_cmp(a));
    for k in 0..3 {
        assert!((analysis.singular_values[k] - eig[k]).abs() <= 1e-9 * eig[0]);
    }
    // homogenisation: a linear axis's length is its travel
    let x = spec.components.iter().find(|c| c.id.to_string() == "EXX").unwrap();
    assert_eq!(x.length_mm, 650.0);
    assert!(m.axes().iter().any(|a| a.kind == AxisKind::Rotary));
}

#[test]
fn exact_chain_confirms_the_linear_worst_case_to_second_order() {
    for name in MACHINES {
        let m = machine(name);
        let spec = BudgetSpec::standard(&m, KindValues::DEFAULT);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let poses = random_poses(&m, 5, &mut rng);
        let a = analyse(&m, &spec, &poses, &Setup::of_machine(&m), Frame::Workpiece).unwrap();
        let check = &a.exact_check;
        // second order: (tolerances ~ 1e-5 rad) x (error ~ 10 um): well under 0.1 %
        assert!((check.exact_um - check.linear_um).abs() <= 1e-3 * check.linear_um, "{name}: {check:?}");
        // halving the tolerances divides the relative difference by two (a second-order remainder)
        let half = spec.with_tolerances(spec.tolerances.iter().map(|t| t / 2.0).collect());
        let b = analyse(&m, &half, &poses, &Setup::of_machine(&m), Frame::Workpiece).unwrap();
        let r1 = (check.exact_um - check.linear_um).abs();
        let r2 = (b.exact_check.exact_um - b.exact_check.linear_um).abs();
        if r1 > 1e-9 {
            assert!((r2 / r1 - 0.25).abs() < 0.05, "{name}: remainder ratio {}", r2 / r1);
        }
    }
}
