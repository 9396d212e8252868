//! Corrections of many poses at once (`correct_batch`: the batch kernel, blocks of 8 poses in lock
//! step) against the scalar solve pose by pose (`Corrector::correct_state`): the same corrections to
//! 1e-9 mm (linear axes) and 1e-12 rad (rotary axes), the same residuals to 1e-9 mm and the same
//! number of iterations, over random poses of every example machine with its example errors
//! (5-axis, lathe, tables, backlash with directions of motion, thermal terms with sensor inputs),
//! the benchmark's 30-table model and errors a hundred times the examples' (several iterations per
//! pose); states per pose and shared; the three orientation targets; block remainders. A
//! volumetric grid (which calls it) checked node by node against `correct_state`.

use std::path::Path;
use trueaxis::compensate::{correct_batch, volumetric_grid, Correction, CorrectionWorkspace, Corrector, OrientationTarget, TableSpec};
use trueaxis::error_model::{Direction, ErrorModel, MachineState};
use trueaxis::geometry::Vec3;
use trueaxis::machine::{AxisKind, Machine};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

fn load(machine: &str, errors: &str) -> (Machine, ErrorModel) {
    let root = Path::new(ROOT);
    let m = Machine::load(root.join(format!("examples/machines/{machine}.toml"))).unwrap();
    let e = ErrorModel::load(root.join(errors), &m).unwrap();
    (m, e)
}

/// Every example machine with its example error model, and the benchmark's table model.
fn models() -> Vec<(String, Machine, ErrorModel)> {
    let mut out: Vec<(String, Machine, ErrorModel)> =
        [("c600u", "c600u"), ("head5", "head5"), ("kx8five", "kx8five"), ("lathe2", "lathe2"), ("vmc3", "vmc3"), ("vmc3", "vmc3_backlash")]
            .into_iter()
            .map(|(m, e)| {
                let (machine, errors) = load(m, &format!("examples/errors/{e}.toml"));
                (format!("{m} with {e}"), machine, errors)
            })
            .collect();
    let (machine, errors) = load("kx8five", "bench/kx8five_tables.toml");
    out.push(("kx8five with the 30 benchmark tables".into(), machine, errors));
    out
}

/// `count` poses (internal units) spread over the travel by a low-discrepancy sequence.
fn poses(machine: &Machine, count: usize, phase: f64) -> Vec<f64> {
    let n = machine.axis_count();
    (0..count * n)
        .map(|i| {
            let axis = &machine.axes()[i % n];
            let u = (phase + i as f64 * 0.618_033_988_749_895).fract();
            let [lo, hi] = axis.range.unwrap_or([0.0, 360.0]);
            axis.position_to_internal(lo + u * (hi - lo))
        })
        .collect()
}

fn assert_same(machine: &Machine, got: &Correction, want: &Correction, what: &str) {
    assert_eq!(got.converged, want.converged, "{what}: converged");
    assert_eq!(got.iterations, want.iterations, "{what}: iterations");
    for (k, axis) in machine.axes().iter().enumerate() {
        let tolerance = if axis.kind == AxisKind::Rotary { 1e-12 } else { 1e-9 };
        assert!((got.dq[k] - want.dq[k]).abs() <= tolerance, "{what}: axis {} {} vs {}", axis.letter, got.dq[k], want.dq[k]);
    }
    for (a, b, name) in [
        (got.residual_position, want.residual_position, "residual position"),
        (got.original_position, want.original_position, "original position"),
    ] {
        assert!((a - b).amax() <= 1e-9, "{what}: {name} {a} vs {b}");
    }
    for (a, b, name) in [
        (got.residual_orientation, want.residual_orientation, "residual orientation"),
        (got.uncorrectable_orientation, want.uncorrectable_orientation, "uncorrectable orientation"),
    ] {
        assert!((a - b).amax() <= 1e-12, "{what}: {name} {a} vs {b}");
    }
}

/// `correct_batch` against `correct_state` pose by pose; returns the most iterations of a pose.
fn check(what: &str, corrector: &Corrector, q: &[f64], directions: Option<&[Option<Direction>]>, inputs: &[f64]) -> usize {
    let machine = corrector.machine;
    let (n_axes, n_inputs) = (machine.axis_count(), corrector.errors.sensors().len());
    let count = q.len() / n_axes;
    let batch = correct_batch(corrector, q, directions, inputs);
    assert_eq!(batch.len(), count);
    let mut ws = CorrectionWorkspace::new(machine);
    let mut most = 0;
    for (i, got) in batch.iter().enumerate() {
        let pose_directions = directions.map(|d| if d.len() == n_axes { d } else { &d[i * n_axes..(i + 1) * n_axes] });
        let temperatures = if inputs.is_empty() || inputs.len() == n_inputs { inputs } else { &inputs[i * n_inputs..(i + 1) * n_inputs] };
        let state = MachineState { directions: pose_directions, temperatures };
        let want = corrector.correct_state(&q[i * n_axes..(i + 1) * n_axes], &state, &mut ws);
        assert_same(machine, got, &want, &format!("{what}, pose {i}"));
        most = most.max(want.iterations);
    }
    most
}

#[test]
fn batch_corrections_equal_the_scalar_solve_on_every_example_machine() {
    for (name, machine, errors) in models() {
        let n_axes = machine.axis_count();
        let n_inputs = errors.sensors().len();
        // 61 poses: seven full blocks of 8 and a remainder of 5
        let q = poses(&machine, 61, 0.1);
        let directions: Vec<Option<Direction>> = (0..61 * n_axes)
            .map(|i| match (i + i / n_axes) % 3 {
                0 => None,
                1 => Some(Direction::Positive),
                _ => Some(Direction::Negative),
            })
            .collect();
        let inputs: Vec<f64> = (0..61 * n_inputs).map(|i| 15.0 + (i as f64 * 0.37).fract() * 20.0).collect();
        let mut corrector = Corrector::new(&machine, &errors);
        for orientation in [OrientationTarget::ToolAxis(Vec3::z()), OrientationTarget::Full, OrientationTarget::None] {
            corrector.options.orientation = orientation;
            let what = format!("{name}, {orientation:?}");
            check(&format!("{what}, at rest"), &corrector, &q, None, &[]);
            check(&format!("{what}, states per pose"), &corrector, &q, Some(&directions), &inputs);
            check(&format!("{what}, one state for all"), &corrector, &q, Some(&directions[..n_axes]), &inputs[..n_inputs]);
            check(&format!("{what}, one pose"), &corrector, &q[..n_axes], Some(&directions[..n_axes]), &inputs[..n_inputs]);
        }
    }
}

#[test]
fn batch_corrections_equal_the_scalar_solve_for_large_errors() {
    // every constant error of kx8five's example model a hundred times larger (hundreds of um and
    // urad): the first-order correction is off by more than the tolerance, the solve iterates
    let (machine, errors) = load("kx8five", "examples/errors/kx8five.toml");
    let n = machine.parameter_count();
    let mut values = vec![0.0; n];
    errors.values_at(&machine, &vec![0.0; machine.axis_count()], &mut values);
    let large: Vec<f64> = values.iter().enumerate().map(|(i, v)| 100.0 * v + if i % 6 < 3 { 0.01 } else { 2e-5 }).collect();
    let large = ErrorModel::from_parameter_vector(&machine, &large);
    let corrector = Corrector::new(&machine, &large);
    let q = poses(&machine, 101, 0.3);
    let most = check("kx8five, large errors", &corrector, &q, None, &[]);
    assert!(most >= 2, "the large errors need at least two linear steps somewhere, took {most}");
}

#[test]
fn volumetric_grid_nodes_equal_the_scalar_solve() {
    let (machine, errors) = load("c600u", "examples/errors/c600u.toml");
    let corrector = Corrector::new(&machine, &errors);
    let spec = TableSpec { points: 2, reference: None, temperatures: vec![] };
    let grid = volumetric_grid(&corrector, [7, 5, 4], &spec).unwrap();
    let mut ws = CorrectionWorkspace::new(&machine);
    let n = machine.axis_count();
    let mut q = vec![0.0; n];
    for k in 0..4 {
        for j in 0..5 {
            for i in 0..7 {
                let mut pose = grid.reference.clone();
                let p = grid.node_position(i, j, k);
                for d in 0..3 {
                    pose[grid.axes[d]] = p[d];
                }
                machine.pose_to_internal(&pose, &mut q);
                let directions = vec![None; n];
                let want = corrector.correct_state(&q, &MachineState { directions: Some(&directions), temperatures: &[] }, &mut ws);
                let node = grid.node(i, j, k);
                for (a, want) in want.dq_user(&machine).iter().enumerate() {
                    let got = grid.values[node * n + a];
                    assert!((got - want).abs() <= 1e-9, "node ({i}, {j}, {k}) axis {a}: {got} vs {want}");
                }
            }
        }
    }
}
