//! Identification hot paths (BENCHMARKS.md (targets)): the linear solve of the Andolfatto et al. 2011 identification
//! (807 poses x 3 channels = 2421 readings, 14 parameters; target < 1 ms), the whole campaign
//! (design matrix from the exact chain and its Jacobians, then the solve), a large dense solve of
//! 10^5 readings x 500 parameters (target < 2 s), and the whole identification of the nine
//! translational error maps of the 3-axis vmc3 as cubic splines with 53 knots (B-splines) from 10^5
//! laser-tracer lengths (501 basis and squareness coefficients, tests/it/support/basis_campaign.rs).
//!
//! Run: `cargo bench --bench identify`. The NumPy/SciPy baselines of the same solves are
//! `identify/lstsq_*` and `identify/qr_*` in bench/baseline.py.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use trueaxis::error_model::ErrorModel;
use trueaxis::identify::{identify, solve, Campaign, DesignMatrix, IndirectOptions};
use trueaxis::machine::Machine;

#[path = "../tests/it/support/basis_campaign.rs"]
mod basis_campaign;
#[path = "common/problems.rs"]
mod problems;
use problems::random_design;

fn root() -> &'static str {
    env!("CARGO_MANIFEST_DIR")
}

/// The Andolfatto et al. 2011 design of examples/uncertainty/kx8five_design.csv as an identification problem.
fn seed004_design() -> DesignMatrix {
    let d =
        trueaxis::uncertainty::DesignMatrix::read_csv(format!("{}/../../examples/uncertainty/kx8five_design.csv", root())).expect("design");
    problems::design_of_file(&d, |i| (0, i / 3))
}

fn solves(c: &mut Criterion) {
    let mut group = c.benchmark_group("identify");
    let options = IndirectOptions::default();
    let design = seed004_design();
    let start = vec![0.0; design.names.len()];
    group.bench_function("solve_2421x14", |b| b.iter(|| solve(black_box(&design), &start, &options).expect("full rank")));

    let machine = Machine::load(format!("{}/../../examples/machines/kx8five.toml", root())).expect("machine");
    let campaign = Campaign::load(format!("{}/../../examples/campaigns/kx8five/campaign.toml", root()), &machine).expect("campaign");
    let nominal = campaign.nominal_errors(&machine).expect("nominal errors");
    group.bench_function("campaign_kx8five_807", |b| {
        b.iter(|| identify(black_box(&campaign), &machine, &nominal, &options).expect("identifiable"))
    });

    let large = random_design(100_000, 500);
    let start = vec![0.0; 500];
    group.sample_size(10);
    group.bench_function("solve_100000x500", |b| b.iter(|| solve(black_box(&large), &start, &options).expect("full rank")));
    drop(large);

    let vmc3 = Machine::load(format!("{}/../../examples/machines/vmc3.toml", root())).expect("machine");
    let dir = tempfile::tempdir().expect("temporary folder");
    let bases = basis_campaign::bspline_bases(&vmc3, 53);
    let poses = basis_campaign::random_poses(&vmc3, 25_000, 1);
    let path = basis_campaign::write_campaign(dir.path(), &vmc3, &basis_campaign::SQUARENESS, &bases, &poses, 0.2);
    let zero = ErrorModel::zero(&vmc3);
    let maps = basis_campaign::simulate_into(&path, &vmc3, &zero, 1);
    group.bench_function("campaign_vmc3_bspline_100000x501", |b| {
        b.iter(|| identify(black_box(&maps), &vmc3, &zero, &options).expect("identifiable"))
    });
    group.finish();
}

criterion_group!(benches, solves);
criterion_main!(benches);
