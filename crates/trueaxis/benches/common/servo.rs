//! Shared by the compensation benchmarks (`benches/compensate.rs` here, `crates/ffi/benches/realtime.rs`):
//! the CPU-time measurement of the benchmark thread, the benchmarked machines and smooth servo paths.
#![allow(dead_code)]

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::{AxisKind, Machine};

/// The workspace root (examples/ and bench/ live there).
pub const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// CPU time of the calling thread (ns), or wall time with `TRUEAXIS_BENCH_WALL=1` or off Linux.
pub struct ThreadCpuTime {
    wall: bool,
}

#[path = "cpu_clock.rs"]
mod cpu_clock;

fn thread_cpu_ns() -> Option<f64> {
    cpu_clock::cpu_ns(cpu_clock::THREAD)
}

static EPOCH: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
static WALL: WallTime = WallTime;

impl ThreadCpuTime {
    pub fn new() -> ThreadCpuTime {
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
pub const CASES: [(&str, &str, &str); 4] = [
    ("vmc3", "examples/machines/vmc3.toml", "examples/errors/vmc3.toml"),
    ("c600u", "examples/machines/c600u.toml", "examples/errors/c600u.toml"),
    ("kx8five", "examples/machines/kx8five.toml", "examples/errors/kx8five.toml"),
    ("kx8five_tables", "examples/machines/kx8five.toml", "bench/kx8five_tables.toml"),
];

pub fn load(machine: &str, errors: &str) -> (Machine, ErrorModel) {
    let m = Machine::load(format!("{ROOT}/{machine}")).expect("machine");
    let e = ErrorModel::load(format!("{ROOT}/{errors}"), &m).expect("errors");
    (m, e)
}

/// The travel of an axis for generated paths (mm, deg): its range, 0..360 deg for a continuous
/// rotary axis, kept 5 % inside the ends.
pub fn travel(machine: &Machine, k: usize) -> (f64, f64) {
    let [lo, hi] = machine.axes()[k].range.unwrap_or([0.0, 360.0]);
    let margin = 0.05 * (hi - lo);
    (lo + margin, hi - margin)
}

/// `count` servo-cycle poses (mm, deg, one after the other): each axis follows a triangle wave over
/// its travel at 100 mm/s (linear) or 30 deg/s (rotary), sampled every 1 ms, with a different phase
/// per axis.
pub fn servo_path(machine: &Machine, count: usize) -> Vec<f64> {
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

/// 0 -> 1 -> 0 over one period of `s`.
pub fn triangle(s: f64) -> f64 {
    let s = s.rem_euclid(2.0);
    if s < 1.0 {
        s
    } else {
        2.0 - s
    }
}
