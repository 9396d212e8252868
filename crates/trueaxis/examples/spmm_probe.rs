use std::time::Instant;
use trueaxis::thermal::sparse_rows::transpose_times_rows;
#[path = "../benches/common/thermal_block.rs"]
mod thermal_block;
fn main() {
    let cells: usize = std::env::args().nth(1).map_or(46, |a| a.parse().unwrap());
    let p: usize = std::env::args().nth(2).map_or(24, |a| a.parse().unwrap());
    let s = thermal_block::block(cells);
    let k = &s.conductivity;
    let n = k.nrows();
    let x: Vec<f64> = (0..n * p).map(|i| (i as f64 * 0.37).sin()).collect();
    let mut y = vec![0.0; n * p];
    let reps = 20;
    let t = Instant::now();
    for _ in 0..reps {
        transpose_times_rows(k, &x, p, &mut y);
    }
    let dt = t.elapsed().as_secs_f64() / reps as f64;
    let nnz = k.val().len();
    println!(
        "n {n} nnz {nnz} p {p}: {:.2} ms per product, {:.2} GFLOP/s, {:.0} ns per row, check {:.6e}",
        dt * 1e3,
        2.0 * nnz as f64 * p as f64 / dt * 1e-9,
        dt * 1e9 / n as f64,
        y.iter().sum::<f64>()
    );
}
