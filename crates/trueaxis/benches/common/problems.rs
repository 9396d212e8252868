//! Problems of a given size shared by the benchmarks and the scaling runs
//! (`examples/scaling.rs`): a dense identification design and the thermal block of
//! `bench/baseline_thermal.py`.
#![allow(dead_code)]

use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use trueaxis::identify::DesignMatrix;
use trueaxis::thermal::assembly::{assemble, Boundary, Material, Section, ThermalProblem, ThermalSystem};
use trueaxis::thermal::mesh::StructuredMesh;

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

/// The steel block of `bench/baseline_thermal.py` with `cells` cells per direction
/// (`(cells + 1)^3` nodes): 0.5 x 0.4 x 0.3 m, 1 W at one corner, convection on five faces.
pub fn thermal_block(cells: usize) -> ThermalSystem {
    let problem = ThermalProblem {
        mesh: StructuredMesh::new(vec![cells; 3], vec![0.5, 0.4, 0.3]).expect("mesh"),
        material: Material { conductivity_w_mk: 50.0, density_kg_m3: 7850.0, specific_heat_j_kgk: 460.0 },
        section: Section::Solid,
        lateral_convection_w_m2k: 0.0,
        boundaries: vec![
            [Boundary::Convection(20.0), Boundary::Convection(10.0)],
            [Boundary::Convection(5.0), Boundary::Insulated],
            [Boundary::Insulated, Boundary::Convection(8.0)],
        ],
        fluxes: vec![(0, 1.0)],
    };
    assemble(&problem).expect("assembly")
}
