//! Cost of the first 20 thermal modes of the benchmark block (`benches/common/thermal_block.rs`)
//! by phase, for BENCHMARKS.md: ordering and factorisation, then the Lanczos block steps; wall and
//! process CPU time (all threads), the factor's nonzeros, the 20 time constants.
//! Also the 10^6-node feasibility run (`/usr/bin/time -v` for the peak memory):
//!
//! `cargo run --release -p trueaxis --example thermal_cost -- [lanczos|lobpcg] 99` (10^6 nodes; default
//! 46, 103 823 nodes; default method lanczos; also dense); optional further arguments: the Lanczos block size
//! and the largest basis. With lobpcg the "factorisation" line is the multigrid setup.

use std::time::Instant;
use trueaxis::thermal::lanczos::LanczosProgress;
use trueaxis::thermal::sparse_cholesky::factorisation_work;
use trueaxis::thermal::{modal_analysis_with_progress, ModalOptions, SpectrumMethod};

#[path = "../benches/common/cpu_clock.rs"]
mod cpu_clock;
#[path = "../benches/common/thermal_block.rs"]
mod thermal_block;

fn process_cpu_seconds() -> f64 {
    1e-9 * cpu_clock::cpu_ns(cpu_clock::PROCESS).expect("a CPU-time clock (Linux)")
}

fn main() {
    let mut words: Vec<String> = std::env::args().skip(1).collect();
    let method = match words.first().map(String::as_str) {
        Some("lobpcg") => Some(SpectrumMethod::Lobpcg),
        Some("lanczos") => Some(SpectrumMethod::Lanczos),
        Some("dense") => Some(SpectrumMethod::Dense),
        _ => None,
    };
    if method.is_some() {
        words.remove(0);
    }
    let args: Vec<usize> = words.iter().map(|a| a.parse().expect("a whole number")).collect();
    let cells = args.first().copied().unwrap_or(46);
    let mut options = ModalOptions { count: Some(20), method: method.unwrap_or(SpectrumMethod::Lanczos), ..Default::default() };
    if let Some(&block) = args.get(1) {
        options.lanczos.block = block;
    }
    if let Some(&basis) = args.get(2) {
        options.lanczos.max_basis = Some(basis);
    }
    let t0 = Instant::now();
    let system = thermal_block::block(cells);
    println!("assembly: {} nodes, {:.2} s", system.node_count(), t0.elapsed().as_secs_f64());
    let flops = if options.method != SpectrumMethod::Lanczos {
        0.0
    } else {
        let (nonzeros, flops) = factorisation_work(&system.conductivity, system.coordinates.as_deref()).expect("symbolic analysis");
        println!("factor: {nonzeros:.3e} nonzeros ({:.2} GB), {flops:.3e} flops to factorise", nonzeros as f64 * 8e-9);
        flops
    };
    let (t0, c0) = (Instant::now(), process_cpu_seconds());
    let mut last = (0.0, 0.0);
    let mut steps = 0;
    let show_steps = std::env::var_os("THERMAL_COST_STEPS").is_some();
    let mut progress = |p: LanczosProgress| {
        let (wall, cpu) = (t0.elapsed().as_secs_f64(), process_cpu_seconds() - c0);
        match p {
            LanczosProgress::Factorised { nonzeros } => {
                println!(
                    "ordering + factorisation: {wall:.2} s wall, {cpu:.2} s CPU, {nonzeros:.3e} nonzeros ({:.1} GFLOP/s per CPU second)",
                    flops / cpu * 1e-9
                );
                last = (wall, cpu);
            }
            LanczosProgress::Preconditioned { levels } => {
                println!("multigrid setup: {wall:.2} s wall, {cpu:.2} s CPU, {levels} levels");
                last = (wall, cpu);
            }
            LanczosProgress::Iterating { converged, .. } | LanczosProgress::Refining { converged, .. } => {
                steps += 1;
                if show_steps {
                    println!("  step {steps}: converged {converged}, {wall:.2} s");
                }
            }
            LanczosProgress::Factorising { .. } | LanczosProgress::Preconditioning { .. } => {}
        }
    };
    let modes = modal_analysis_with_progress(&system, &options, &mut progress).expect("modes");
    let (wall, cpu) = (t0.elapsed().as_secs_f64(), process_cpu_seconds() - c0);
    let (name, unit) = match options.method {
        SpectrumMethod::Lobpcg => ("LOBPCG", "iterations"),
        SpectrumMethod::Dense => ("dense", "steps"),
        _ => ("Lanczos", "Ritz steps"),
    };
    println!("{name}: {:.2} s wall, {:.2} s CPU ({steps} {unit})", wall - last.0, cpu - last.1);
    println!("total: {wall:.2} s wall, {cpu:.2} s CPU");
    let tau: Vec<String> = (0..modes.len()).map(|i| format!("{:.6e}", modes.tau_s(i))).collect();
    println!("tau_s: {}", tau.join(" "));
}
