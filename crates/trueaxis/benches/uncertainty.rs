//! The adaptive Monte Carlo of the Andolfatto et al. 2011 identification (BENCHMARKS.md (targets): 807 poses, 14
//! parameters, 3 sources with the cyclic drift, tolerance 0.05; target < 0.5 s, issue 23:
//! <= 5 ms; the NumPy implementation of the same reduced form is bench/baseline_mc.py): one sequence of 10^4 trials and the
//! whole adaptive run with the settings of examples/uncertainty/kx8five_cyclic.toml.
//!
//! Run: `cargo bench --bench uncertainty`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use trueaxis::uncertainty::{run_adaptive, run_sequences, DesignMatrix, Evaluation, IdentificationMap, Sources};

fn monte_carlo(c: &mut Criterion) {
    let root = env!("CARGO_MANIFEST_DIR");
    let design = DesignMatrix::read_csv(format!("{root}/../../examples/uncertainty/kx8five_design.csv")).expect("design");
    let sources = Sources::load(format!("{root}/../../examples/uncertainty/kx8five_cyclic.toml")).expect("sources");
    let map = IdentificationMap::new(design).expect("identifiable");
    let all: Vec<_> = sources.sources.iter().collect();
    let model = map.model(&all, Evaluation::Reduced).expect("model");
    let mut group = c.benchmark_group("uncertainty/seed004_cyclic");
    group.sample_size(10);
    group.bench_function("one_sequence", |b| b.iter(|| run_sequences(black_box(&model), &sources.settings, 1).expect("run")));
    group.bench_function("adaptive", |b| b.iter(|| run_adaptive(black_box(&model), &sources.settings, &mut |_, _| {}).expect("run")));
    group.finish();
}

criterion_group!(benches, monte_carlo);
criterion_main!(benches);
