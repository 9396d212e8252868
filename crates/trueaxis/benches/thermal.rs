//! Thermal modal analysis (BENCHMARKS.md (targets): the first 20 modes of a 1e5-node conduction model
//! in < 10 s; issue 23: <= 4 s) on steel blocks of about 1e3, 1e4 and 1e5 nodes (trilinear
//! hexahedra, four convective faces), the model of `bench/baseline_thermal.py`, which times SciPy on
//! the same K, C (shift-invert `eigsh` on a SuperLU factor, and `lobpcg` with a pyamg multigrid
//! preconditioner):
//! - `first_20/<nodes>`: the solver `thermal modes` chooses (dense at 1e3 nodes, shift-invert block
//!   Lanczos on a nested-dissection sparse Cholesky factor at 1e4, LOBPCG with a smoothed-aggregation
//!   multigrid preconditioner at 1e5);
//! - `lanczos_first_20/103823`: the shift-invert Lanczos at 1e5 nodes, for comparison.
//!
//! The 10^6-node run (not a benchmark: about a minute and 6 GB, see BENCHMARKS.md) is
//! `cargo run --release -p trueaxis --example thermal_cost -- lobpcg 99`.
//! Assembly (0.2 s at 1e5 nodes) is outside the timing, as in the baseline.
//!
//! Run: `cargo bench --bench thermal` (about 5 min; the 1e5-node cases run 10 samples).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use std::time::Duration;
use trueaxis::thermal::{modal_analysis, ModalOptions, SpectrumMethod};

#[path = "common/thermal_block.rs"]
mod thermal_block;
use thermal_block::block;

fn modes(c: &mut Criterion) {
    let auto = ModalOptions { count: Some(20), ..Default::default() };
    let lanczos = ModalOptions { method: SpectrumMethod::Lanczos, ..auto };
    let mut group = c.benchmark_group("thermal_modes");
    for cells in [9usize, 21, 46] {
        let system = block(cells);
        let nodes = system.node_count();
        if nodes > 50_000 {
            group.sample_size(10).measurement_time(Duration::from_secs(90)).warm_up_time(Duration::from_secs(1));
        } else if nodes > 5_000 {
            group.sample_size(10).measurement_time(Duration::from_secs(15));
        }
        group.bench_with_input(BenchmarkId::new("first_20", nodes), &system, |b, s| {
            b.iter(|| modal_analysis(black_box(s), &auto).expect("modes"))
        });
        if nodes > 50_000 {
            group.bench_with_input(BenchmarkId::new("lanczos_first_20", nodes), &system, |b, s| {
                b.iter(|| modal_analysis(black_box(s), &lanczos).expect("modes"))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, modes);
criterion_main!(benches);
