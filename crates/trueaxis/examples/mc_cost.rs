//! CPU time of the adaptive Monte Carlo of the Andolfatto et al. 2011 problem, for BENCHMARKS.md: the design
//! and sources of `examples/uncertainty/kx8five_design.csv` / `kx8five_cyclic.toml` (as
//! `benches/uncertainty.rs`), `runs` whole adaptive runs. Prints the wall time and the CPU time of
//! the process (all threads) per run: on a machine shared with other processes the CPU time is
//! what the run costs, the wall time what it waited.
//!
//! Run: `cargo run --release -p trueaxis --example mc_cost [runs]` (`RAYON_NUM_THREADS=1` for one core).

use std::time::Instant;
use trueaxis::uncertainty::{run_adaptive, DesignMatrix, Evaluation, IdentificationMap, Sources};

#[path = "../benches/common/cpu_clock.rs"]
mod cpu_clock;

fn process_cpu_seconds() -> f64 {
    1e-9 * cpu_clock::cpu_ns(cpu_clock::PROCESS).expect("a CPU-time clock (Linux)")
}

fn main() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let design = DesignMatrix::read_csv(format!("{root}/examples/uncertainty/kx8five_design.csv")).expect("design");
    let sources = Sources::load(format!("{root}/examples/uncertainty/kx8five_cyclic.toml")).expect("sources");
    let map = IdentificationMap::new(design).expect("identifiable");
    let all: Vec<_> = sources.sources.iter().collect();
    let model = map.model(&all, Evaluation::Reduced).expect("model");
    let runs: usize = std::env::args().nth(1).map_or(50, |r| r.parse().expect("runs: a number"));
    let first = run_adaptive(&model, &sources.settings, &mut |_, _| {}).expect("run");
    for c in &first.history {
        println!(
            "after sequence {}: 2 x max [s_y, s_u, s_low, s_high] = {:.4?} (tolerance {})",
            c.sequence,
            c.max.map(|s| 2.0 * s),
            sources.settings.tolerance
        );
    }
    let (wall, cpu) = (Instant::now(), process_cpu_seconds());
    for _ in 0..runs {
        std::hint::black_box(run_adaptive(&model, &sources.settings, &mut |_, _| {}).expect("run"));
    }
    let cpu = process_cpu_seconds() - cpu;
    let wall = wall.elapsed().as_secs_f64();
    println!(
        "{} sequences of {} trials, {} outputs: {:.2} ms CPU per run, {:.2} ms wall per run ({} threads)",
        first.sequences,
        sources.settings.trials_per_sequence,
        first.outputs.len(),
        1e3 * cpu / runs as f64,
        1e3 * wall / runs as f64,
        rayon::current_num_threads()
    );
}
