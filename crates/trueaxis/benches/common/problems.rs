//! Problems of a given size shared by the benchmarks and the scaling runs
//! (`examples/scaling.rs`, `examples/identify_solve.rs`): a dense identification design and one from
//! a design file (the thermal block is in `thermal_block.rs`).
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

/// The identification problem of a design file of `trueaxis uncertainty --design` (rows: readings,
/// columns: parameters, weights `1 / sigma^2`), reading `i` recorded as `record(i)`.
pub fn design_of_file(d: &trueaxis::uncertainty::DesignMatrix, record: impl Fn(usize) -> (usize, usize)) -> DesignMatrix {
    DesignMatrix {
        names: d.parameters.clone(),
        units: d.units.clone(),
        matrix: d.x.clone(),
        observations: d.measured.clone(),
        sigma_um: d.weight.iter().map(|w| 1.0 / w.sqrt()).collect(),
        weights: d.weight.clone(),
        channels: d.channel.clone(),
        channel_names: d.channels.clone(),
        records: (0..d.observations()).map(record).collect(),
    }
}
