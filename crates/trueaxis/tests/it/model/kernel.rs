//! The batch volumetric error kernel (structure-of-arrays blocks, run-time instruction set)
//! against the scalar path (`ErrorModel::values_at_state` + `volumetric_error`, pose by pose):
//! equal to 1e-9 um in position and length and 1e-9 urad in orientation over random poses of every
//! example machine with its example errors (5-axis, lathe, tables, polynomials, backlash, thermal
//! terms), the benchmark's 30-table model, random constant errors, both frames, an offset setup
//! and block remainders.

use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use std::path::Path;
use trueaxis::error_model::{Direction, ErrorModel, MachineState};
use trueaxis::machine::Machine;
use trueaxis::model::{volumetric_error, Frame, Predictor, Setup, VolumetricError, VolumetricKernel, INSTRUCTION_SETS};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// Position and length: 1e-9 um = 1e-12 mm; orientation 1e-9 urad = 1e-15 rad.
fn assert_equal(got: &VolumetricError, want: &VolumetricError, what: &str) {
    assert!((got.position - want.position).amax() <= 1e-12, "{what}: position {} vs {}", got.position, want.position);
    assert!((got.length - want.length).abs() <= 1e-12, "{what}: length {} vs {}", got.length, want.length);
    assert!((got.orientation - want.orientation).amax() <= 1e-15, "{what}: orientation {} vs {}", got.orientation, want.orientation);
    assert!(got.position.iter().chain(got.orientation.iter()).all(|v| v.is_finite()) && got.length.is_finite(), "{what}: not finite");
}

/// Poses (internal units) from draws in [0, 1): each axis over its travel, 0..360 deg (and a
/// little beyond, for the periodic wrap) for a continuous rotary axis.
fn poses(machine: &Machine, draws: &[f64]) -> Vec<f64> {
    let n_axes = machine.axis_count();
    let mut out = Vec::new();
    for pose in draws.chunks_exact(n_axes) {
        for (axis, u) in machine.axes().iter().zip(pose) {
            let [lo, hi] = axis.range.unwrap_or([-30.0, 400.0]);
            out.push(axis.position_to_internal(lo + u * (hi - lo)));
        }
    }
    out
}

/// Every example machine with its example error model (same file stem), the benchmark's table
/// model, and the 2D CMM with random constants.
fn models() -> Vec<(String, Machine, ErrorModel)> {
    let root = Path::new(ROOT);
    let mut out = Vec::new();
    for (machine, errors) in [
        ("c600u", "c600u"),
        ("head5", "head5"),
        ("kx8five", "kx8five"),
        ("kx8five", "kx8five_table1"),
        ("lathe2", "lathe2"),
        ("vmc3", "vmc3"),
        ("vmc3", "vmc3_backlash"),
    ] {
        let m = Machine::load(root.join(format!("examples/machines/{machine}.toml"))).unwrap();
        let e = ErrorModel::load(root.join(format!("examples/errors/{errors}.toml")), &m).unwrap();
        out.push((format!("{machine} with {errors}"), m, e));
    }
    let m = Machine::load(root.join("examples/machines/kx8five.toml")).unwrap();
    let e = ErrorModel::load(root.join("bench/kx8five_tables.toml"), &m).unwrap();
    out.push(("kx8five with the 30 benchmark tables".into(), m, e));
    out
}

fn scalar(p: &Predictor, q: &[f64], state: &MachineState) -> VolumetricError {
    let mut values = vec![0.0; p.machine.parameter_count()];
    p.errors.values_at_state(p.machine, q, state, &mut values);
    volumetric_error(p.machine, q, &values, &p.setup, p.frame)
}

/// The kernel (through `predict_states`, as `predict` and the Python binding call it) against
/// the scalar path, with directions and input values when given.
fn check(what: &str, p: &Predictor, q: &[f64], directions: Option<&[Option<Direction>]>, inputs: &[f64]) {
    let n_axes = p.machine.axis_count();
    let n_inputs = p.errors.sensors().len();
    let batch = p.predict_states(q, directions, inputs);
    assert_eq!(batch.len(), q.len() / n_axes);
    for (i, got) in batch.iter().enumerate() {
        let state = MachineState {
            directions: directions.map(|d| &d[i * n_axes..(i + 1) * n_axes]),
            temperatures: if inputs.is_empty() { &[] } else { &inputs[i * n_inputs..(i + 1) * n_inputs] },
        };
        assert_equal(got, &scalar(p, &q[i * n_axes..(i + 1) * n_axes], &state), &format!("{what}, pose {i}"));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, rng_seed: RngSeed::Fixed(23), ..ProptestConfig::default() })]

    #[test]
    fn kernel_equals_the_scalar_path_on_every_example_machine(
        draws in proptest::collection::vec(0.0f64..1.0, 6 * 37),
        signs in proptest::collection::vec(any::<bool>(), 6 * 37),
        inputs in proptest::collection::vec(10.0f64..40.0, 37 * 4),
        offset in proptest::collection::vec(-200.0f64..200.0, 6),
    ) {
        for (name, machine, errors) in models() {
            let n_axes = machine.axis_count();
            // 37 poses: four full blocks of 8 and a remainder of 5
            let q = poses(&machine, &draws[..37 * n_axes]);
            let directions: Vec<Option<Direction>> = signs[..37 * n_axes]
                .iter()
                .enumerate()
                .map(|(i, s)| if i % 5 == 0 { None } else if *s { Some(Direction::Positive) } else { Some(Direction::Negative) })
                .collect();
            let n_inputs = errors.sensors().len();
            let values = &inputs[..37 * n_inputs];
            for frame in [Frame::Workpiece, Frame::Machine] {
                let mut p = Predictor::new(&machine, &errors);
                p.frame = frame;
                check(&format!("{name}, {frame:?}"), &p, &q, None, &[]);
                check(&format!("{name}, {frame:?}, directions and inputs"), &p, &q, Some(&directions), values);
                p.setup = Setup {
                    tool_point: machine.tool_point + trueaxis::geometry::Vec3::new(offset[0], offset[1], offset[2]),
                    work_point: trueaxis::geometry::Vec3::new(offset[3], offset[4], offset[5]),
                };
                check(&format!("{name}, {frame:?}, offset setup"), &p, &q, None, &[]);
            }
        }
    }

    #[test]
    fn kernel_equals_the_scalar_path_with_every_parameter_constant(
        draws in proptest::collection::vec(0.0f64..1.0, 6 * 11),
        parameters in proptest::collection::vec(-1.0f64..1.0, 12 * 6 + 6),
    ) {
        // all location, motion and setup errors non-zero constants (tens of um and urad, the motion
        // errors of linear axes about a moving centre); plus one large rotation (0.02 rad) beyond
        // the series of the small-angle exponential and logarithm
        for name in ["kx8five", "c600u", "lathe2", "cmm2d", "vmc3"] {
            let machine = Machine::load(Path::new(ROOT).join(format!("examples/machines/{name}.toml"))).unwrap();
            let n = machine.parameter_count();
            let mut values: Vec<f64> = (0..n).map(|i| parameters[i] * if i % 6 < 3 { 0.05 } else { 5e-5 }).collect();
            let q = poses(&machine, &draws[..11 * machine.axis_count()]);
            let errors = ErrorModel::from_parameter_vector(&machine, &values);
            check(&format!("{name}, constants"), &Predictor::new(&machine, &errors), &q, None, &[]);
            values[5] = 0.02;
            let errors = ErrorModel::from_parameter_vector(&machine, &values);
            check(&format!("{name}, a large rotation"), &Predictor::new(&machine, &errors), &q, None, &[]);
        }
    }
}

#[test]
fn every_compiled_instruction_set_equals_the_scalar_path() {
    // the kernel's own loop (one workspace, no threads) over 1000 poses of the table model, with
    // each instruction set this CPU has (the baseline everywhere)
    let (name, machine, errors) = models().pop().unwrap();
    let setup = Setup::of_machine(&machine);
    let best = VolumetricKernel::new(&machine, &errors, &setup, Frame::Workpiece);
    let available =
        |set: &'static str| VolumetricKernel::new(&machine, &errors, &setup, Frame::Workpiece).with_instruction_set(set).is_some();
    assert_eq!(best.instruction_set, INSTRUCTION_SETS.into_iter().find(|s| available(s)).unwrap(), "the best set this CPU has");
    let draws: Vec<f64> = (0..1000 * machine.axis_count()).map(|i| (i as f64 * 0.618_033_988_749_895).fract()).collect();
    let q = poses(&machine, &draws);
    let p = Predictor::new(&machine, &errors);
    let mut tested = Vec::new();
    for set in INSTRUCTION_SETS {
        let Some(kernel) = VolumetricKernel::new(&machine, &errors, &setup, Frame::Workpiece).with_instruction_set(set) else { continue };
        let mut out = vec![VolumetricError::default(); 1000];
        kernel.evaluate(&mut kernel.workspace(), &q, &mut out);
        let mut largest: f64 = 0.0;
        for (i, got) in out.iter().enumerate() {
            let want = scalar(&p, &q[i * machine.axis_count()..(i + 1) * machine.axis_count()], &MachineState::default());
            assert_equal(got, &want, &format!("{name}, {set}, pose {i}"));
            largest = largest.max(want.position.amax());
        }
        // the errors compared are those of a real model: micrometres, not zeros
        assert!(largest > 1e-3, "largest error {largest} mm");
        tested.push(set);
    }
    assert!(tested.contains(&"baseline"), "{tested:?}");
    assert!(VolumetricKernel::new(&machine, &errors, &setup, Frame::Workpiece).with_instruction_set("NEON-9000").is_none());
}
