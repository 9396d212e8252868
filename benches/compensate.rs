//! Compensation hot paths (DESIGN.md section 5: one pose for a real-time corrector < 1 us).
//!
//! - `realtime/<machine>/servo`: one call of the real-time corrector through the C ABI
//!   (`trueaxis_correct`, as a controller calls it) per servo cycle of 1 ms along a smooth 5-axis
//!   (3-axis) path at 6 m/min and 30 deg/s: consecutive calls are close, as in a controller.
//! - `realtime/<machine>/jump`: every call at a pose far from the previous one (the poses of
//!   `benches/common`), the worst case: no warm start helps.
//! - `nc/<machine>`: NC-program correction throughput of a generated program of 10^4 G1 moves
//!   (elements = lines; the points corrected per line are printed once).
//!
//! Machines: vmc3, c600u, kx8five with their example errors, and kx8five with all 30 motion-error
//! tables of `bench/kx8five_tables.toml`.
//!
//! Times are the CPU time of the benchmark thread (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`): on the
//! shared 2-core reference machine, under a load average of 5-15, wall time measures the load and
//! the thread's CPU time measures the code. `TRUEAXIS_BENCH_WALL=1` times wall clock instead.
//!
//! Run: `cargo bench --bench compensate`.

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::ffi::CString;
use trueaxis::compensate::ffi::{trueaxis_correct, trueaxis_corrector_free, trueaxis_corrector_new};
use trueaxis::compensate::nc::{correct_program, NcOptions};
use trueaxis::compensate::Corrector;
use trueaxis::errors::ErrorModel;
use trueaxis::machine::{AxisKind, Machine};

#[allow(dead_code)] // the kinematics bench uses the rest
mod common;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// CPU time of the calling thread (ns), or wall time with `TRUEAXIS_BENCH_WALL=1` or off Linux.
struct ThreadCpuTime {
    wall: bool,
}

#[cfg(target_os = "linux")]
fn thread_cpu_ns() -> Option<f64> {
    #[repr(C)]
    struct Timespec {
        tv_sec: std::ffi::c_long,
        tv_nsec: std::ffi::c_long,
    }
    extern "C" {
        fn clock_gettime(clock: std::ffi::c_int, tp: *mut Timespec) -> std::ffi::c_int;
    }
    const CLOCK_THREAD_CPUTIME_ID: std::ffi::c_int = 3;
    let mut t = Timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes one timespec into `t`
    let status = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut t) };
    (status == 0).then_some(t.tv_sec as f64 * 1e9 + t.tv_nsec as f64)
}

#[cfg(not(target_os = "linux"))]
fn thread_cpu_ns() -> Option<f64> {
    None
}

static EPOCH: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
static WALL: WallTime = WallTime;

impl ThreadCpuTime {
    fn new() -> ThreadCpuTime {
        ThreadCpuTime { wall: std::env::var_os("TRUEAXIS_BENCH_WALL").is_some() || thread_cpu_ns().is_none() }
    }

    fn now(&self) -> f64 {
        match self.wall {
            true => EPOCH.get_or_init(std::time::Instant::now).elapsed().as_nanos() as f64,
            false => thread_cpu_ns().unwrap_or(0.0),
        }
    }
}

impl Measurement for ThreadCpuTime {
    type Intermediate = f64;
    type Value = f64;
    fn start(&self) -> f64 {
        self.now()
    }
    fn end(&self, start: f64) -> f64 {
        self.now() - start
    }
    fn add(&self, a: &f64, b: &f64) -> f64 {
        a + b
    }
    fn zero(&self) -> f64 {
        0.0
    }
    fn to_f64(&self, value: &f64) -> f64 {
        *value
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        // nanoseconds, as criterion's wall time
        WALL.formatter()
    }
}

/// (label, machine file, error file) of the benchmarked corrections.
const CASES: [(&str, &str, &str); 4] = [
    ("vmc3", "examples/machines/vmc3.toml", "examples/errors/vmc3.toml"),
    ("c600u", "examples/machines/c600u.toml", "examples/errors/c600u.toml"),
    ("kx8five", "examples/machines/kx8five.toml", "examples/errors/kx8five.toml"),
    ("kx8five_tables", "examples/machines/kx8five.toml", "bench/kx8five_tables.toml"),
];

fn load(machine: &str, errors: &str) -> (Machine, ErrorModel) {
    let m = Machine::load(format!("{ROOT}/{machine}")).expect("machine");
    let e = ErrorModel::load(format!("{ROOT}/{errors}"), &m).expect("errors");
    (m, e)
}

/// The travel of an axis for generated paths (mm, deg): its range, 0..360 deg for a continuous
/// rotary axis, kept 5 % inside the ends.
fn travel(machine: &Machine, k: usize) -> (f64, f64) {
    let [lo, hi] = machine.axes()[k].range.unwrap_or([0.0, 360.0]);
    let margin = 0.05 * (hi - lo);
    (lo + margin, hi - margin)
}

/// `count` servo-cycle poses (mm, deg, one after the other): each axis follows a triangle wave over
/// its travel at 100 mm/s (linear) or 30 deg/s (rotary), sampled every 1 ms, with a different phase
/// per axis.
fn servo_path(machine: &Machine, count: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(count * machine.axis_count());
    for i in 0..count {
        for (k, axis) in machine.axes().iter().enumerate() {
            let (lo, hi) = travel(machine, k);
            let speed = if axis.kind == AxisKind::Rotary { 0.030 } else { 0.100 }; // per ms
            out.push(lo + triangle(i as f64 * speed / (hi - lo) + 0.37 * k as f64) * (hi - lo));
        }
    }
    out
}

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
        let mut out = [0.0f64; 9];
        for (kind, poses) in [("servo", &servo), ("jump", &jumps)] {
            // every pose is corrected (status 0) before timing
            for p in poses.chunks(n) {
                let rc = unsafe { trueaxis_correct(corrector, p.as_ptr(), std::ptr::null(), std::ptr::null(), out.as_mut_ptr()) };
                assert_eq!(rc, 0, "{label} {kind}: status {rc} at {p:?}");
            }
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

/// A program of `moves` G1 moves: a raster of 5 mm steps over the XY travel at three depths, and for
/// a machine with A and C every move also turns the table (A over its travel, C continuously).
fn generated_program(machine: &Machine, moves: usize) -> String {
    let letters: Vec<char> = machine.axes().iter().map(|a| a.letter).collect();
    let mut text = String::from("(generated benchmark program)\nG21 G90 G17 G94\n");
    for i in 0..moves {
        let mut words = Vec::new();
        for (k, &letter) in letters.iter().enumerate() {
            let (lo, hi) = travel(machine, k);
            // X back and forth in 200 steps, Y one step per pass, Z three levels, A and C slow waves
            let u = match letter {
                'X' => triangle(i as f64 / 200.0),
                'Y' => (i / 200 % 100) as f64 / 99.0,
                'Z' => 0.3 + 0.2 * (i / 200 % 3) as f64,
                _ => triangle(i as f64 / (700.0 + 300.0 * k as f64)),
            };
            words.push(format!("{letter}{:.3}", lo + u * (hi - lo)));
        }
        text += &format!("G1 {} F3000\n", words.join(" "));
    }
    text + "M2\n"
}

/// 0 -> 1 -> 0 over one period of `s`.
fn triangle(s: f64) -> f64 {
    let s = s.rem_euclid(2.0);
    if s < 1.0 {
        s
    } else {
        2.0 - s
    }
}

fn nc(c: &mut Criterion<ThreadCpuTime>) {
    let mut group = c.benchmark_group("nc");
    group.sample_size(10);
    for (label, machine_file, errors_file) in [CASES[0], CASES[1]] {
        let (machine, errors) = load(machine_file, errors_file);
        let program = generated_program(&machine, 10_000);
        let lines = program.lines().count();
        let corrector = Corrector::new(&machine, &errors);
        let options = NcOptions::new(&machine);
        let r = correct_program(&corrector, &program, label, &options, &[]).expect("program corrected");
        println!(
            "nc/{label}: {lines} lines, {} moves, {} points corrected ({:.1} per line), {} lines added",
            r.moves,
            r.corrected_points,
            r.corrected_points as f64 / lines as f64,
            r.inserted_lines
        );
        group.throughput(Throughput::Elements(lines as u64));
        group.bench_function(BenchmarkId::new(label, lines), |b| {
            b.iter(|| correct_program(&corrector, black_box(&program), label, &options, &[]).unwrap())
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(ThreadCpuTime::new());
    targets = realtime, nc
}
criterion_main!(benches);
