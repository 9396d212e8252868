//! Problems of a given size shared by the benchmarks and the scaling runs
//! (`examples/scaling.rs`): a dense identification design (the thermal block is in
//! `thermal_block.rs`).
#![allow(dead_code)]

use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use trueaxis::identify::DesignMatrix;

/// A dense `rows x cols` problem with independent standard normal entries (seeded), as the
/// NumPy baseline draws it: the cost of a dense solve does not depend on the structure.
pub fn random_design(rows: usize, cols: usize) -> DesignMatrix {
    let mut rng = ChaCha8Rng::seed_from_u64(500);
    let normal = rand_distr::StandardNormal;
    DesignMatrix {
        names: (0..cols).map(|j| format!("c{j}")).collect(),
        units: vec!["um".into(); cols],
        matrix: DMatrix::from_fn(rows, cols, |_, _| rng.sample::<f64, _>(normal)),
        observations: (0..rows).map(|_| rng.sample::<f64, _>(normal)).collect(),
        sigma_um: vec![1.0; rows],
        weights: vec![1.0; rows],
        channels: vec![0; rows],
        channel_names: vec!["x".into()],
        records: (0..rows).map(|i| (0, i)).collect(),
    }
}
