//! The pose correction (Soons 1993 §2.3.5 iterated on the exact chain): residual after correction on
//! the example machines, checked with the model's own `volumetric_error` (a second code path), the
//! first-order closed form of a 3-axis machine, uncorrectable orientation, bidirectional and
//! thermal terms.

use trueaxis::compensate::{Correction, CorrectionWorkspace, Corrector, OrientationTarget};
use trueaxis::error_model::{Direction, ErrorModel, MachineState};
use trueaxis::geometry::Vec3;
use trueaxis::machine::Machine;
use trueaxis::model::{nominal_chain, volumetric_error, Frame};

fn load(name: &str) -> (Machine, ErrorModel) {
    let m = Machine::load(format!("../../examples/machines/{name}.toml")).unwrap();
    let e = ErrorModel::load(format!("../../examples/errors/{name}.toml"), &m).unwrap();
    (m, e)
}

/// Deterministic quasi-random poses (Halton sequence) inside the travel (rotary without range: 0..360).
fn poses(m: &Machine, count: usize) -> Vec<Vec<f64>> {
    const PRIMES: [u32; 9] = [2, 3, 5, 7, 11, 13, 17, 19, 23];
    let halton = |mut i: u32, b: u32| {
        let (mut f, mut r) = (1.0, 0.0);
        while i > 0 {
            f /= b as f64;
            r += f * (i % b) as f64;
            i /= b;
        }
        r
    };
    (1..=count as u32)
        .map(|i| {
            let user: Vec<f64> = m
                .axes()
                .iter()
                .enumerate()
                .map(|(k, a)| {
                    let [lo, hi] = a.range.unwrap_or([0.0, 360.0]);
                    lo + (hi - lo) * halton(i, PRIMES[k])
                })
                .collect();
            let mut q = vec![0.0; m.axis_count()];
            m.pose_to_internal(&user, &mut q);
            q
        })
        .collect()
}

/// Tool point relative to the workpiece point after the correction, minus the nominal at `q`,
/// computed with `model::volumetric_error` at `q + dq` (independent of the corrector's residual).
fn residual_by_model(m: &Machine, e: &ErrorModel, q: &[f64], c: &Correction, state: &MachineState) -> Vec3 {
    let qc: Vec<f64> = q.iter().zip(&c.dq).map(|(a, b)| a + b).collect();
    let mut values = vec![0.0; m.parameter_count()];
    e.values_at_state(m, &qc, state, &mut values);
    let setup = trueaxis::model::Setup::of_machine(m);
    let error = volumetric_error(m, &qc, &values, &setup, Frame::Workpiece);
    let nominal = |q: &[f64]| {
        let t = nominal_chain(m, m.tool_chain(), q, None);
        let w = nominal_chain(m, m.work_chain(), q, None);
        w.rotation.transpose() * (t.transform_point(&setup.tool_point) - w.transform_point(&setup.work_point))
    };
    error.position + nominal(&qc) - nominal(q)
}

#[test]
fn residual_is_below_a_hundredth_of_a_micrometre_and_one_percent_on_every_example_machine() {
    for name in ["vmc3", "lathe2", "c600u", "kx8five", "head5"] {
        let (m, e) = load(name);
        let corrector = Corrector::new(&m, &e);
        let mut ws = CorrectionWorkspace::new(&m);
        let (mut worst_ratio, mut worst_residual, mut worst_original) = (0.0f64, 0.0f64, 0.0f64);
        for q in poses(&m, 200) {
            let c = corrector.correct(&q, &mut ws);
            assert!(c.converged, "{name}: not converged at {q:?}");
            assert!(c.iterations <= 6, "{name}: {} iterations", c.iterations);
            let residual = residual_by_model(&m, &e, &q, &c, &MachineState::default());
            // the corrector's own residual and the model's agree
            assert!((residual - c.residual_position).norm() < 1e-9, "{name}: {residual} vs {}", c.residual_position);
            assert!(residual.norm() < 1e-5, "{name}: residual {} um at {q:?}", residual.norm() * 1e3);
            worst_ratio = worst_ratio.max(residual.norm() / c.original_position.norm());
            worst_residual = worst_residual.max(residual.norm());
            worst_original = worst_original.max(c.original_position.norm());
        }
        assert!(worst_original > 1e-3, "{name}: the example errors are micrometres, got {worst_original} mm");
        assert!(worst_ratio < 0.01, "{name}: residual/original {worst_ratio}");
        eprintln!("{name}: largest error {:.3} um, largest residual {:.2e} um", worst_original * 1e3, worst_residual * 1e3);
    }
}

#[test]
fn three_axis_correction_is_minus_the_error_to_first_order_and_orientation_is_uncorrectable() {
    // vmc3: X and Y carry the workpiece with directions -x, -y and Z the tool: programmed +X moves
    // the tool +x relative to the workpiece, so the joint Jacobian of the relative position is the
    // identity and the first-order correction is dq = -d (Soons 1993 §2.3.5, linear model).
    let (m, e) = load("vmc3");
    let corrector = Corrector::new(&m, &e);
    let mut ws = CorrectionWorkspace::new(&m);
    for q in poses(&m, 50) {
        let c = corrector.correct(&q, &mut ws);
        for k in 0..3 {
            // second-order remainder: error gradients (~1e-4) times the correction (~1e-2 mm)
            assert!((c.dq[k] + c.original_position[k]).abs() < 5e-6, "axis {k}: {} vs {}", c.dq[k], -c.original_position[k]);
        }
        // no joint turns the tool: the tilt of the tool axis (x, y components) stays as it was
        let o = c.original_orientation;
        let tilt = Vec3::new(o.x, o.y, 0.0);
        assert!((c.uncorrectable_orientation - tilt).norm() < 1e-9, "{} vs {tilt}", c.uncorrectable_orientation);
        assert!(tilt.norm() > 1e-6, "the example has urad-size angular errors");
        assert_eq!(c.uncorrectable(1e-5, 1e-7).len(), 1, "{:?}", c.uncorrectable(1e-5, 1e-7));
    }
}

#[test]
fn five_axis_machines_also_correct_the_tool_axis() {
    for name in ["c600u", "head5", "kx8five"] {
        let (m, e) = load(name);
        let corrector = Corrector::new(&m, &e);
        let mut ws = CorrectionWorkspace::new(&m);
        let mut checked = 0;
        for q in poses(&m, 100) {
            // away from the singular poses where the two rotary axes and the tool axis line up
            let tilt = |letter: char| m.axis_index(letter).map(|k| q[k].to_degrees());
            let singular = match name {
                "c600u" => tilt('A').unwrap().abs() < 6.0,
                "head5" => tilt('B').unwrap().abs() < 6.0,
                // A tilted 45 deg: near A = 0 C is nearly parallel to the tool axis; near A = 180
                // deg C lies along y and both rotary axes tilt the tool about y only
                _ => !(15.0..=165.0).contains(&tilt('A').unwrap()),
            };
            if singular {
                continue;
            }
            let c = corrector.correct(&q, &mut ws);
            assert!(c.converged);
            assert!(
                c.uncorrectable_orientation.norm() < 1e-10,
                "{name}: {} urad left at {:?} deg",
                c.uncorrectable_orientation.norm() * 1e6,
                q.iter().map(|v| v.to_degrees()).collect::<Vec<_>>()
            );
            assert!(c.uncorrectable(1e-5, 1e-9).is_empty());
            checked += 1;
        }
        assert!(checked > 60, "{name}: {checked} poses");
    }
}

#[test]
fn position_only_target_leaves_orientation_alone_and_full_target_is_refused_gracefully() {
    let (m, e) = load("c600u");
    let q = poses(&m, 3)[2].clone();
    let mut ws = CorrectionWorkspace::new(&m);
    let mut corrector = Corrector::new(&m, &e);
    corrector.options.orientation = OrientationTarget::None;
    let c = corrector.correct(&q, &mut ws);
    assert!(c.residual_position.norm() < 1e-5);
    assert_eq!(c.uncorrectable_orientation, Vec3::zeros());
    // all three orientation components on a 5-axis machine: the spin about the tool axis cannot be
    // reached; the position is still corrected first
    corrector.options.orientation = OrientationTarget::Full;
    let c = corrector.correct(&q, &mut ws);
    assert!(c.converged && c.residual_position.norm() < 1e-5);
    assert!(c.uncorrectable_orientation.norm() > 0.0);
}

#[test]
fn bidirectional_and_thermal_terms_enter_the_correction() {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load("../../examples/errors/vmc3_backlash.toml", &m).unwrap();
    assert_eq!(e.sensors(), &["T:column".to_string()]);
    let corrector = Corrector::new(&m, &e);
    let mut ws = CorrectionWorkspace::new(&m);
    let q = [100.0, -50.0, -200.0];
    let at = |dir: Option<Direction>, t: f64, ws: &mut CorrectionWorkspace| {
        let dirs = [dir, None, None];
        corrector.correct_state(&q, &MachineState { directions: Some(&dirs), temperatures: &[t] }, ws)
    };
    let plus = at(Some(Direction::Positive), 20.0, &mut ws);
    let minus = at(Some(Direction::Negative), 20.0, &mut ws);
    // EXX+ - EXX- = 3 um: X carries the workpiece, so the table sits 3 um further along +x when
    // moving up, the tool 3 um further along -x relative to it, and X (which moves the tool +x
    // relative to the workpiece) corrects by +3 um
    assert!((plus.dq[0] - minus.dq[0] - 3e-3).abs() < 1e-7, "{}", (plus.dq[0] - minus.dq[0]) * 1e3);
    // at rest the mean of both directions
    let rest = corrector.correct(&q, &mut ws);
    assert!((rest.dq[0] - 0.5 * (plus.dq[0] + minus.dq[0])).abs() < 1e-8);
    // 5 K warmer: EZZ grows by 0.0115 um/(mm K) * (-200 mm) * 5 K = -11.5 um; Z corrects +11.5 um
    let warm = at(Some(Direction::Positive), 25.0, &mut ws);
    assert!((warm.dq[2] - plus.dq[2] - 11.5e-3).abs() < 1e-6, "{}", (warm.dq[2] - plus.dq[2]) * 1e3);
    for c in [plus, minus, rest, warm] {
        assert!(c.residual_position.norm() < 1e-5);
    }
}

#[test]
fn the_five_axis_correction_is_continuous_through_the_singularity() {
    // c600u at X0 Y0 Z-50 C0 (tool point on the C axis): at A = 0 the C axis is parallel to the tool
    // axis. The tilt of the tool about y that only C can correct is t(A) = EB0C + EB0A cos A
    // (examples/errors/c600u.toml: both 174.533 urad); C corrects it with the gain 1 / sin A, faded
    // out below sin A = eps = 0.1 as g = 2 sin A / (sin^2 A + eps^2), leaving the fraction
    // (eps^2 - sin^2 A) / (eps^2 + sin^2 A) uncorrected (src/compensate/solve.rs). The former hard
    // cut-off made dX jump by 17 um and dC by 3469 urad between A = 5.735 and 5.76 deg.
    let (m, e) = load("c600u");
    let corrector = Corrector::new(&m, &e);
    let mut ws = CorrectionWorkspace::new(&m);
    let eps: f64 = 0.1;
    let at = |a_deg: f64, ws: &mut CorrectionWorkspace| {
        let mut q = vec![0.0; 5];
        m.pose_to_internal(&[0.0, 0.0, -50.0, a_deg, 0.0], &mut q);
        let c = corrector.correct(&q, ws);
        (q, c)
    };
    let step_deg = 0.002;
    let mut previous: Option<Correction> = None;
    let (mut worst_linear, mut worst_rotary, mut worst_left_change) = (0.0f64, 0.0f64, 0.0f64);
    let (mut worst_gain_error, mut worst_left_error) = (0.0f64, 0.0f64);
    for i in 0..=6000 {
        let a = -1.0 + i as f64 * step_deg;
        let (q, c) = at(a, &mut ws);
        assert!(c.converged, "A = {a}");
        let residual = residual_by_model(&m, &e, &q, &c, &MachineState::default());
        assert!(residual.norm() < 1e-5, "A = {a}: residual {} um", residual.norm() * 1e3);
        if let Some(p) = &previous {
            for k in 0..5 {
                let change = (c.dq[k] - p.dq[k]).abs();
                if k < 3 {
                    worst_linear = worst_linear.max(change);
                } else {
                    worst_rotary = worst_rotary.max(change);
                }
            }
            worst_left_change = worst_left_change.max((c.uncorrectable_orientation - p.uncorrectable_orientation).norm());
        }
        // closed forms of the damped solve
        let s = a.to_radians().sin();
        let tilt = 174.533e-6 * (1.0 + a.to_radians().cos());
        let (gain, left) =
            if s.abs() >= eps { (1.0 / s, 0.0) } else { (2.0 * s / (s * s + eps * eps), (eps * eps - s * s) / (eps * eps + s * s)) };
        worst_gain_error = worst_gain_error.max((c.dq[4] - tilt * gain).abs());
        worst_left_error = worst_left_error.max((c.uncorrectable_orientation.norm() - tilt * left).abs());
        previous = Some(c);
    }
    eprintln!(
        "per {step_deg} deg of A: |d dq| <= {:.2e} um, {:.2e} urad, uncorrected orientation changes <= {:.2e} urad; \
         closed forms within {:.2e} urad (dC), {:.2e} urad (left)",
        worst_linear * 1e3,
        worst_rotary * 1e6,
        worst_left_change * 1e6,
        worst_gain_error * 1e6,
        worst_left_error * 1e6
    );
    // continuous: bounded change per 0.002 deg step (the largest slope, dC/dA = 2 t / eps^2 = 0.07,
    // gives 2.4 urad per step)
    assert!(worst_linear < 0.02e-3, "{} um per step", worst_linear * 1e3);
    assert!(worst_rotary < 3e-6, "{} urad per step", worst_rotary * 1e6);
    assert!(worst_left_change < 0.5e-6, "{} urad per step", worst_left_change * 1e6);
    // and equal to the closed forms: exact least squares beyond the fade, the damped gain inside
    assert!(worst_gain_error < 0.05e-6 && worst_left_error < 0.05e-6, "{worst_gain_error} {worst_left_error}");
    // the two poses of the former jump, 0.025 deg apart: changes of the size of 12.5 steps
    let (_, before) = at(5.735, &mut ws);
    let (_, after) = at(5.76, &mut ws);
    let (dx, dc) = ((after.dq[0] - before.dq[0]).abs(), (after.dq[4] - before.dq[4]).abs());
    assert!(dx < 0.2e-3 && dc < 40e-6, "dX changes by {} um, dC by {} urad", dx * 1e3, dc * 1e6);
    // at the singularity the whole C tilt is left uncorrected (and reported), none of it beyond
    let (_, at_zero) = at(0.0, &mut ws);
    assert!((at_zero.uncorrectable_orientation.norm() - 2.0 * 174.533e-6).abs() < 1e-9);
    assert!(at_zero.dq[4].abs() < 1e-12);
}
