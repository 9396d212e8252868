//! Kinematic hot paths (BENCHMARKS.md (targets)): exact volumetric error of the KX8-Five with all 30
//! motion-error tables and the Andolfatto et al. 2011 location/setup errors, one pose (real-time corrector
//! budget < 1 us) and batches over all cores (target >= 10 M poses/s); first-order Jacobian
//! assembly (7 x 84 per pose), one pose and the 807-pose Andolfatto et al. 2011 test.
//!
//! Run: `cargo bench --bench kinematics`.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use trueaxis::model::{
    jacobian, jacobian_batch, volumetric_error, Frame, JacobianWorkspace, Predictor, Setup, VolumetricError, VolumetricKernel,
    JACOBIAN_ROWS,
};

mod common;

fn volumetric(c: &mut Criterion) {
    let (machine, errors) = common::kx8five_with_tables();
    let predictor = Predictor::new(&machine, &errors);
    let n_axes = machine.axis_count();
    let one = common::poses(&machine, 1);
    let mut values = vec![0.0; machine.parameter_count()];
    let mut group = c.benchmark_group("volumetric_error");
    group.throughput(Throughput::Elements(1));
    group.bench_function("one_pose", |b| b.iter(|| predictor.predict_with(black_box(&one), &mut values)));
    // the two parts of one pose: the 84 parameter values (30 table look-ups) and the exact chain
    group.bench_function("one_pose_error_values", |b| b.iter(|| errors.values_at(&machine, black_box(&one), &mut values)));
    errors.values_at(&machine, &one, &mut values);
    let setup = Setup::of_machine(&machine);
    group.bench_function("one_pose_exact_chain", |b| {
        b.iter(|| volumetric_error(&machine, black_box(&one), black_box(&values), &setup, Frame::Workpiece))
    });
    for n in [10_000usize, 1_000_000] {
        let poses = common::poses(&machine, n);
        assert_eq!(poses.len(), n * n_axes);
        group.throughput(Throughput::Elements(n as u64));
        group.sample_size(if n > 100_000 { 10 } else { 30 });
        group.bench_with_input(BenchmarkId::new("batch", n), &poses, |b, p| b.iter(|| predictor.predict_batch(black_box(p))));
    }
    // the batch kernel on the calling thread (one core), the best instruction set of this CPU
    let kernel = VolumetricKernel::new(&machine, &errors, &setup, Frame::Workpiece);
    let mut ws = kernel.workspace();
    let poses = common::poses(&machine, 10_000);
    let mut out = vec![VolumetricError::default(); 10_000];
    group.throughput(Throughput::Elements(10_000));
    group.sample_size(30);
    group.bench_function(BenchmarkId::new("kernel_one_thread", 10_000), |b| {
        b.iter(|| kernel.evaluate(&mut ws, black_box(&poses), &mut out))
    });
    group.finish();
}

fn jacobians(c: &mut Criterion) {
    let (machine, _) = common::kx8five_with_tables();
    let setup = Setup::of_machine(&machine);
    let one = common::poses(&machine, 1);
    let mut ws = JacobianWorkspace::default();
    let mut rows = vec![0.0; JACOBIAN_ROWS * machine.parameter_count()];
    let mut group = c.benchmark_group("jacobian");
    group.throughput(Throughput::Elements(1));
    group.bench_function("one_pose", |b| b.iter(|| jacobian(&machine, black_box(&one), &setup, Frame::Machine, &mut ws, &mut rows)));
    let poses = common::poses(&machine, 807);
    group.throughput(Throughput::Elements(807));
    group.bench_function("batch_807", |b| b.iter(|| jacobian_batch(&machine, black_box(&poses), &setup, Frame::Machine)));
    group.finish();
}

criterion_group!(benches, volumetric, jacobians);
criterion_main!(benches);
