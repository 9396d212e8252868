//! Shared inputs of the benchmarks: the KX8-Five with all 30 motion-error tables
//! (`bench/kx8five_tables.toml`, written by `bench/make_tables.py`) and a deterministic pose set
//! that `bench/baseline.py` reproduces exactly.

use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

pub fn kx8five_with_tables() -> (Machine, ErrorModel) {
    let root = env!("CARGO_MANIFEST_DIR");
    let machine = Machine::load(format!("{root}/../../examples/machines/kx8five.toml")).expect("kx8five machine");
    let errors = ErrorModel::load(format!("{root}/../../bench/kx8five_tables.toml"), &machine).expect("bench error model");
    (machine, errors)
}

/// `n` poses (internal units: mm, rad) in canonical axis order, spread over each axis's travel
/// (0..360 deg for a continuous rotary axis) by `u_k(i) = frac(i sqrt(p_k))`, `p = 2, 3, 5, 7, 11, ...`
/// (the same formula as bench/baseline.py).
pub fn poses(machine: &Machine, n: usize) -> Vec<f64> {
    const PRIMES: [f64; 9] = [2.0, 3.0, 5.0, 7.0, 11.0, 13.0, 17.0, 19.0, 23.0];
    let mut out = Vec::with_capacity(n * machine.axis_count());
    for i in 0..n {
        for (k, axis) in machine.axes().iter().enumerate() {
            let u = (i as f64 * PRIMES[k].sqrt()).fract();
            let [lo, hi] = axis.range.unwrap_or([0.0, 360.0]);
            out.push(axis.position_to_internal(lo + u * (hi - lo)));
        }
    }
    out
}
