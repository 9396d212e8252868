//! Cost of the large identification solve for BENCHMARKS.md: the dense `n x p` problem of
//! `benches/identify.rs` (`identify/solve_100000x500`: standard normal entries, unit weights),
//! timed as wall clock and as the CPU time of the whole process (all threads), for the weighted
//! Gram product alone ([`weighted_gram`], `n (p + 1)^2` flops for its lower triangle) and for the
//! whole `solve`. On a machine shared with other processes the CPU time is what the computation
//! costs; the flop rate per CPU-second compared with one core's peak is the fraction reached.
//!
//! Run: `cargo run --release -p trueaxis --example ident_cost [n] [p] [repeats]`; with
//! `PEAK_GFLOPS` set to one core's measured peak (`bench/fma_peak.c`) it also prints the fraction
//! of the peak.

use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;
use trueaxis::identify::{solve, weighted_gram, DesignMatrix, IndirectOptions};

#[path = "../benches/common/cpu_clock.rs"]
mod cpu_clock;

fn process_cpu_seconds() -> f64 {
    1e-9 * cpu_clock::cpu_ns(cpu_clock::PROCESS).expect("a CPU-time clock (Linux)")
}

/// Runs `f` `repeats` times; the fastest wall clock and the fastest CPU time (s).
fn best<T>(repeats: usize, mut f: impl FnMut() -> T) -> (f64, f64) {
    let (mut wall, mut cpu) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..repeats {
        let (t, c) = (Instant::now(), process_cpu_seconds());
        std::hint::black_box(f());
        wall = wall.min(t.elapsed().as_secs_f64());
        cpu = cpu.min(process_cpu_seconds() - c);
    }
    (wall, cpu)
}

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).map(|a| a.parse().expect("n p repeats as integers")).collect();
    let (n, p, repeats) =
        (args.first().copied().unwrap_or(100_000), args.get(1).copied().unwrap_or(500), args.get(2).copied().unwrap_or(5));
    let mut rng = ChaCha8Rng::seed_from_u64(500);
    let matrix = DMatrix::from_fn(n, p, |_, _| rng.sample::<f64, _>(rand_distr::StandardNormal));
    let observations: Vec<f64> = (0..n).map(|_| rng.sample::<f64, _>(rand_distr::StandardNormal)).collect();
    let ones = vec![1.0; n];
    let flops = n as f64 * (p + 1) as f64 * (p + 2) as f64; // lower triangle with the diagonal, 2 per multiply-add
    let (wall, cpu) = best(repeats, || weighted_gram(&matrix, &observations, &ones));
    let threads = rayon::current_num_threads();
    let per_cpu_second = 1e-9 * flops / cpu;
    let fraction = match std::env::var("PEAK_GFLOPS").ok().and_then(|v| v.parse::<f64>().ok()) {
        Some(peak) => format!(" = {:.0} % of one core's {peak} GFLOP/s", 100.0 * per_cpu_second / peak),
        None => " (set PEAK_GFLOPS to one core's peak for the fraction)".to_string(),
    };
    println!(
        "weighted Gram {n} x {}: wall {wall:.3} s, CPU {cpu:.3} s; {:.1} GFLOP/s wall on {threads} threads, {per_cpu_second:.1} GFLOP/s per CPU-second{fraction}",
        p + 1,
        1e-9 * flops / wall,
    );
    let design = DesignMatrix {
        names: (0..p).map(|j| format!("c{j}")).collect(),
        units: vec!["um".into(); p],
        matrix,
        observations,
        sigma_um: ones.clone(),
        weights: ones,
        channels: vec![0; n],
        channel_names: vec!["x".into()],
        records: (0..n).map(|i| (0, i)).collect(),
    };
    let start = vec![0.0; p];
    let (wall, cpu) = best(repeats, || solve(&design, &start, &IndirectOptions::default()).expect("full rank"));
    println!("solve {n} x {p}: wall {wall:.3} s, CPU {cpu:.3} s");
}
