//! The thermal benchmark model, shared by `benches/thermal.rs` and `examples/thermal_cost.rs`
//! (and the scaling runs of `examples/scaling.rs`): a steel block
//! 0.5 x 0.4 x 0.3 m on a structured grid of `cells`^3 trilinear hexahedra ((cells + 1)^3 nodes),
//! convection on four faces, 1 W at one corner; the model of `bench/baseline_thermal.py`.
#![allow(dead_code)]

use trueaxis::thermal::assembly::{assemble, Boundary, Material, Section, ThermalProblem, ThermalSystem};
use trueaxis::thermal::mesh::StructuredMesh;

/// The block of `bench/baseline_thermal.py` with `cells` cells per direction.
pub fn block(cells: usize) -> ThermalSystem {
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

/// Cells per direction for a block of about `nodes` nodes.
pub fn cells_for_nodes(nodes: usize) -> usize {
    ((nodes as f64).cbrt().round() as usize).saturating_sub(1).max(1)
}
