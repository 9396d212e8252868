//! Cost per pose of the batch volumetric error kernel on one thread, for BENCHMARKS.md: the
//! KX8-Five with the 30 benchmark tables (as `benches/kinematics.rs`), 10^5 poses evaluated 50
//! times on the calling thread. Prints the thread's CPU time per pose (unaffected by other
//! processes waiting for the core) and the instruction set; run under
//! `valgrind --tool=callgrind` (AVX2 at most) for the instructions per pose.
//!
//! Run: `cargo run --release -p trueaxis --example kernel_cost [AVX-512F|AVX2|baseline] [repeats]`.

use std::time::Instant;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::model::{Frame, Setup, VolumetricError, VolumetricKernel, INSTRUCTION_SETS};

#[path = "../benches/common/cpu_clock.rs"]
mod cpu_clock;

fn thread_cpu_seconds() -> f64 {
    1e-9 * cpu_clock::cpu_ns(cpu_clock::THREAD).expect("a CPU-time clock (Linux)")
}

fn main() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let machine = Machine::load(format!("{root}/examples/machines/kx8five.toml")).expect("kx8five machine");
    let errors = ErrorModel::load(format!("{root}/bench/kx8five_tables.toml"), &machine).expect("bench error model");
    let n = 100_000;
    let repeats = 50;
    const PRIMES: [f64; 5] = [2.0, 3.0, 5.0, 7.0, 11.0];
    let mut poses = Vec::with_capacity(n * 5);
    for i in 0..n {
        for (k, axis) in machine.axes().iter().enumerate() {
            let u = (i as f64 * PRIMES[k].sqrt()).fract();
            let [lo, hi] = axis.range.unwrap_or([0.0, 360.0]);
            poses.push(axis.position_to_internal(lo + u * (hi - lo)));
        }
    }
    let args: Vec<String> = std::env::args().collect();
    let kernel = VolumetricKernel::new(&machine, &errors, &Setup::of_machine(&machine), Frame::Workpiece);
    // optional: the instruction set (AVX-512F, AVX2, baseline) and the number of repeats
    let kernel = match args.get(1) {
        Some(set) => {
            let set = INSTRUCTION_SETS.into_iter().find(|s| s == set).expect("instruction set: AVX-512F, AVX2 or baseline");
            kernel.with_instruction_set(set).expect("this CPU lacks the instruction set")
        }
        None => kernel,
    };
    let repeats: usize = args.get(2).map_or(repeats, |r| r.parse().expect("repeats: a number"));
    let mut ws = kernel.workspace();
    let mut out = vec![VolumetricError::default(); n];
    let (wall, cpu) = (Instant::now(), thread_cpu_seconds());
    for _ in 0..repeats {
        kernel.evaluate(&mut ws, std::hint::black_box(&poses), &mut out);
    }
    let cpu = thread_cpu_seconds() - cpu;
    let wall = wall.elapsed().as_secs_f64();
    let total = (n * repeats) as f64;
    println!(
        "{}: {} poses, {:.1} ns CPU per pose ({:.2} M poses/s per core), wall {:.1} ns per pose; checksum {:.6e}",
        kernel.instruction_set,
        n * repeats,
        1e9 * cpu / total,
        total / cpu / 1e6,
        1e9 * wall / total,
        out.iter().map(|e| e.position.x).sum::<f64>()
    );
}
