//! NC-program correction throughput (BENCHMARKS.md (targets): >= 100,000 lines/s). The real-time
//! corrector through its C ABI is benchmarked in `crates/ffi/benches/realtime.rs`.
//!
//! - `nc/<machine>`: NC-program correction throughput of a generated program of 10^4 G1 moves
//!   (elements = lines; the points corrected per line are printed once).
//! - `nc_loop/vmc3`: a LinuxCNC program whose `while` loop runs 10^4 blocks with expressions, all
//!   expanded into plain moves (elements = executed blocks).
//!
//! - `grid/<machine>` (wall clock, both threads): the volumetric grid of 46 x 46 x 46 = 97,336 nodes
//!   (elements = nodes) by `volumetric_grid` (the batch kernel in blocks of 8 nodes);
//!   `grid_one_thread/<machine>` the same on the calling thread alone (CPU time), and
//!   `grid_scalar_one_thread/<machine>` the same nodes corrected one by one on the scalar chain
//!   (`Corrector::correct_state`, the path the grid took before; CPU time).
//!
//! Machines: vmc3, c600u, kx8five with their example errors, and kx8five with all 30 motion-error
//! tables of `bench/kx8five_tables.toml`.
//!
//! Times are the CPU time of the benchmark thread (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`): on the
//! shared 2-core reference machine, under a load average of 5-15, wall time measures the load and
//! the thread's CPU time measures the code. `TRUEAXIS_BENCH_WALL=1` times wall clock instead.
//!
//! Run: `cargo bench --bench compensate`.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use trueaxis::compensate::nc::{correct_program, NcOptions};
use trueaxis::compensate::{volumetric_grid, CorrectionWorkspace, Corrector, TableSpec, VolumetricGrid};
use trueaxis::error_model::MachineState;
use trueaxis::machine::Machine;

#[allow(dead_code)] // the kinematics bench uses the rest
mod common;

#[path = "common/servo.rs"]
mod servo;
use servo::{load, travel, triangle, ThreadCpuTime, CASES};

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
    let mut group = c.benchmark_group("nc_loop");
    group.sample_size(10);
    let (label, machine_file, errors_file) = CASES[0];
    let (machine, errors) = load(machine_file, errors_file);
    let program = loop_program(10_000);
    let corrector = Corrector::new(&machine, &errors);
    let options = NcOptions::new(&machine);
    let r = correct_program(&corrector, &program, label, &options, &[]).expect("program corrected");
    println!("nc_loop/{label}: {} blocks executed, {} moves, {} lines written", r.blocks, r.moves, r.text().lines().count());
    group.throughput(Throughput::Elements(r.blocks as u64));
    group.bench_function(BenchmarkId::new(label, r.blocks), |b| {
        b.iter(|| correct_program(&corrector, black_box(&program), label, &options, &[]).unwrap())
    });
    group.finish();
}

/// A raster computed by a `while` loop: `moves` G1 blocks with parameters and expressions.
fn loop_program(moves: usize) -> String {
    format!(
        "G21 G90 G17 G94 F3000\nG0 X-350 Y-200 Z-100\n#<i> = 0\no1 while [#<i> LT {moves}]\n  G1 X[-350 + 700 * [#<i> MOD 2]] Y[-200 + 0.04 * #<i>] Z[-100 - 5 * SIN[#<i>]]\n  #<i> = [#<i> + 1]\no1 endwhile\nM2\n"
    )
}

/// The nodes of a `counts` grid over X, Y, Z with the other axes at the grid's reference pose
/// (internal units), in the grid's node order.
fn grid_poses(machine: &Machine, grid: &VolumetricGrid) -> Vec<f64> {
    let n = machine.axis_count();
    let mut poses = vec![0.0; grid.values.len()];
    let mut user = grid.reference.clone();
    for k in 0..grid.counts[2] {
        for j in 0..grid.counts[1] {
            for i in 0..grid.counts[0] {
                let p = grid.node_position(i, j, k);
                for d in 0..3 {
                    user[grid.axes[d]] = p[d];
                }
                machine.pose_to_internal(&user, &mut poses[grid.node(i, j, k) * n..][..n]);
            }
        }
    }
    poses
}

/// The grid's machines, corrector inputs and nodes.
fn grid_cases() -> Vec<(&'static str, Machine, trueaxis::error_model::ErrorModel)> {
    [CASES[0], CASES[2]]
        .into_iter()
        .map(|(label, machine_file, errors_file)| {
            let (machine, errors) = load(machine_file, errors_file);
            (label, machine, errors)
        })
        .collect()
}

const GRID_COUNTS: [usize; 3] = [46, 46, 46];

fn grid_spec() -> TableSpec {
    TableSpec { points: 2, reference: None, temperatures: vec![] }
}

/// Wall clock, both threads.
fn grid(c: &mut Criterion) {
    let nodes = GRID_COUNTS.iter().product::<usize>();
    let spec = grid_spec();
    let mut group = c.benchmark_group("grid");
    group.sample_size(10);
    group.throughput(Throughput::Elements(nodes as u64));
    for (label, machine, errors) in grid_cases() {
        let corrector = Corrector::new(&machine, &errors);
        group.bench_function(BenchmarkId::new(label, nodes), |b| {
            b.iter(|| volumetric_grid(&corrector, black_box(GRID_COUNTS), &spec).unwrap())
        });
    }
    group.finish();
}

/// CPU time of one thread: the grid in a pool of the calling thread alone, and the same nodes
/// corrected one by one on the scalar chain.
fn grid_one_thread(c: &mut Criterion<ThreadCpuTime>) {
    let nodes = GRID_COUNTS.iter().product::<usize>();
    let spec = grid_spec();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).use_current_thread().build().expect("a pool of this thread");
    for (label, machine, errors) in grid_cases() {
        let corrector = Corrector::new(&machine, &errors);
        let grid = volumetric_grid(&corrector, GRID_COUNTS, &spec).expect("grid");
        let poses = grid_poses(&machine, &grid);
        let n = machine.axis_count();
        let mut group = c.benchmark_group("grid_one_thread");
        group.sample_size(10);
        group.throughput(Throughput::Elements(nodes as u64));
        group.bench_function(BenchmarkId::new(label, nodes), |b| {
            b.iter(|| pool.install(|| volumetric_grid(&corrector, black_box(GRID_COUNTS), &spec).unwrap()))
        });
        group.finish();
        let mut group = c.benchmark_group("grid_scalar_one_thread");
        group.sample_size(10);
        group.throughput(Throughput::Elements(nodes as u64));
        let mut ws = CorrectionWorkspace::new(&machine);
        let directions = vec![None; n];
        let state = MachineState { directions: Some(&directions), temperatures: &[] };
        group.bench_function(BenchmarkId::new(label, nodes), |b| {
            b.iter(|| black_box(&poses).chunks(n).map(|q| corrector.correct_state(q, &state, &mut ws)).collect::<Vec<_>>())
        });
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(ThreadCpuTime::new());
    targets = nc, grid_one_thread
}
criterion_group!(wall, grid);
// the wall-clock group first: `grid_one_thread` makes this thread a pool of its own, in which every
// later parallel call would run
criterion_main!(wall, benches);
