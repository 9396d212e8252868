//! The real-time corrector (BENCHMARKS.md (targets): one pose < 1 us), called through the C ABI
//! (`trueaxis_correct`, as a controller calls it):
//! - `realtime/<machine>/servo`: one call of the real-time corrector through the C ABI
//!   (`trueaxis_correct`, as a controller calls it) per servo cycle of 1 ms along a smooth 5-axis
//!   (3-axis) path at 6 m/min and 30 deg/s: consecutive calls are close, as in a controller.
//! - `realtime/<machine>/jump`: every call at a pose far from the previous one (the poses of
//!   `benches/common`), the worst case: no warm start helps.
//!
//! Machines: vmc3, c600u, kx8five with their example errors, and kx8five with all 30 motion-error
//! tables of `bench/kx8five_tables.toml`. Times are the CPU time of the benchmark thread (see
//! `crates/trueaxis/benches/common/servo.rs`); `TRUEAXIS_BENCH_WALL=1` times wall clock instead.
//!
//! Run: `cargo bench -p trueaxis-ffi --bench realtime`.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::ffi::CString;
use trueaxis::compensate::realtime::RealtimeStatus;
use trueaxis_rt::{trueaxis_correct, trueaxis_corrector_free, trueaxis_corrector_new};

#[path = "../../trueaxis/benches/common/mod.rs"]
#[allow(dead_code)]
mod common;
#[path = "../../trueaxis/benches/common/servo.rs"]
mod servo;
use servo::{load, servo_path, ThreadCpuTime, CASES, ROOT};

fn realtime(c: &mut Criterion<ThreadCpuTime>) {
    let mut group = c.benchmark_group("realtime");
    group.throughput(Throughput::Elements(1));
    for (label, machine_file, errors_file) in CASES {
        let (machine, _) = load(machine_file, errors_file);
        let n = machine.axis_count();
        let path = |p: &str| CString::new(format!("{ROOT}/{p}")).unwrap();
        let (mp, ep) = (path(machine_file), path(errors_file));
        let corrector = unsafe { trueaxis_corrector_new(mp.as_ptr(), ep.as_ptr(), std::ptr::null_mut(), 0) };
        assert!(!corrector.is_null(), "{label}: corrector");
        let servo = servo_path(&machine, 20_000);
        let jumps: Vec<f64> = common::poses(&machine, 20_000)
            .chunks(n)
            .flat_map(|q| q.iter().zip(machine.axes()).map(|(v, a)| a.position_to_user(*v)).collect::<Vec<_>>())
            .collect();
        let mut buffer = [0.0f64; 9];
        let mut correct =
            |p: &[f64]| unsafe { trueaxis_correct(corrector, p.as_ptr(), std::ptr::null(), std::ptr::null(), buffer.as_mut_ptr()) };
        // every pose of the servo path is corrected (status 0); of the jumps over the whole travel,
        // those the corrector refuses as beyond the correction limit (near a 5-axis singularity,
        // e.g. the c600u's C axis parallel to the spindle at A near 0) are left out
        for p in servo.chunks(n) {
            let rc = correct(p);
            assert_eq!(rc, 0, "{label} servo: status {rc} at {p:?}");
        }
        let jumps: Vec<f64> = jumps
            .chunks(n)
            .filter(|p| match correct(p) {
                0 => true,
                rc => {
                    assert_eq!(rc, RealtimeStatus::BeyondLimit as i32, "{label} jump: status {rc} at {p:?}");
                    false
                }
            })
            .flatten()
            .copied()
            .collect();
        assert!(jumps.len() >= 19_000 * n, "{label}: {} of 20,000 jumps corrected", jumps.len() / n);
        let mut out = [0.0f64; 9];
        for (kind, poses) in [("servo", &servo), ("jump", &jumps)] {
            let mut i = 0;
            group.bench_function(BenchmarkId::new(label, kind), |b| {
                b.iter(|| {
                    let p = &poses[i * n..(i + 1) * n];
                    i = (i + 1) % (poses.len() / n);
                    unsafe { trueaxis_correct(corrector, black_box(p.as_ptr()), std::ptr::null(), std::ptr::null(), out.as_mut_ptr()) }
                })
            });
        }
        unsafe { trueaxis_corrector_free(corrector) };
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(ThreadCpuTime::new());
    targets = realtime
}
criterion_main!(benches);
