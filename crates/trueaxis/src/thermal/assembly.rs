//! Assembly of the heat capacity matrix C and the conductivity matrix K (with convection) of the
//! transient heat-conduction equation `C dT/dt + K T = Q(t)` (Zhu 2008 eq. 3.1) on a structured
//! mesh, and the nodal load vector of point heat fluxes.
//!
//! Element matrices of the bilinear/trilinear elements of a rectangular cell are tensor products of
//! the 1D linear-element matrices `K1 = [[1,-1],[-1,1]]/h` and `M1 = h [[2,1],[1,2]]/6`:
//! `C_e = rho c_p s prod_d M1_d`, `K_e = k s sum_d K1_d prod_(e != d) M1_e` (exact integration).
//! Convection `h (T - T_ambient)` on a surface adds `h int N_a N_b dS` to K (the consistent
//! "film" matrix); temperatures are rises over the ambient (Zhu 2008 §3.4: over 20 degC).

use super::mesh::StructuredMesh;
use crate::error::Error;
use faer::sparse::{SparseColMat, SymbolicSparseColMat, Triplet};

/// Conductivity k (W/m/K), density rho (kg/m^3), specific heat c_p (J/kg/K).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub conductivity_w_mk: f64,
    pub density_kg_m3: f64,
    pub specific_heat_j_kgk: f64,
}

impl Material {
    /// Thermal diffusivity `a = k / (rho c_p)` (m^2/s).
    pub fn diffusivity(&self) -> f64 {
        self.conductivity_w_mk / (self.density_kg_m3 * self.specific_heat_j_kgk)
    }
}

/// What the mesh's dimensions leave out: a bar has a cross-section, a plate a thickness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Section {
    /// 1D: cross-section area A (m^2) and the perimeter P (m) of its lateral surface.
    Bar { area_m2: f64, perimeter_m: f64 },
    /// 2D: thickness t (m); lateral convection acts on both faces.
    Plate { thickness_m: f64 },
    /// 3D: nothing left out.
    Solid,
}

impl Section {
    /// Integration measure of the missing dimensions (A, t or 1).
    fn measure(&self) -> f64 {
        match self {
            Section::Bar { area_m2, .. } => *area_m2,
            Section::Plate { thickness_m } => *thickness_m,
            Section::Solid => 1.0,
        }
    }

    /// Lateral surface per unit of mesh measure (P per length, 2 faces per area, none).
    fn lateral(&self) -> f64 {
        match self {
            Section::Bar { perimeter_m, .. } => *perimeter_m,
            Section::Plate { .. } => 2.0,
            Section::Solid => 0.0,
        }
    }

    fn dimensions(&self) -> usize {
        match self {
            Section::Bar { .. } => 1,
            Section::Plate { .. } => 2,
            Section::Solid => 3,
        }
    }
}

/// A boundary face of the mesh: insulated (no heat flow) or convection with h (W/m^2/K).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Boundary {
    Insulated,
    Convection(f64),
}

/// Everything the assembly needs.
#[derive(Clone, Debug)]
pub struct ThermalProblem {
    pub mesh: StructuredMesh,
    pub material: Material,
    pub section: Section,
    /// Convection coefficient on the lateral surface (bar perimeter, plate faces), W/m^2/K.
    pub lateral_convection_w_m2k: f64,
    /// `[d][side]`: the face at coordinate 0 (side 0) or at the far end (side 1) of dimension d.
    pub boundaries: Vec<[Boundary; 2]>,
    /// Point heat fluxes `(node, W)` of the representative step load.
    pub fluxes: Vec<(usize, f64)>,
}

/// The assembled model: C (J/K), K (W/K), the step load Q (W), and node coordinates (m).
#[derive(Clone, Debug)]
pub struct ThermalSystem {
    pub capacity: SparseColMat<usize, f64>,
    pub conductivity: SparseColMat<usize, f64>,
    pub load: Vec<f64>,
    /// Node coordinates, when the model comes from a mesh.
    pub coordinates: Option<Vec<[f64; 3]>>,
}

impl ThermalSystem {
    /// A system from matrices given by another tool (e.g. Matrix Market files): both square of the
    /// same size, `load` of that size.
    pub fn from_matrices(
        capacity: SparseColMat<usize, f64>,
        conductivity: SparseColMat<usize, f64>,
        load: Vec<f64>,
    ) -> Result<ThermalSystem, Error> {
        let n = capacity.nrows();
        if capacity.ncols() != n || conductivity.nrows() != n || conductivity.ncols() != n {
            return Err(Error::input(format!(
                "C is {}x{} and K is {}x{}: both must be square of the same size",
                capacity.nrows(),
                capacity.ncols(),
                conductivity.nrows(),
                conductivity.ncols()
            )));
        }
        if load.len() != n {
            return Err(Error::input(format!("the load has {} entries for {n} nodes", load.len())));
        }
        Ok(ThermalSystem { capacity, conductivity, load, coordinates: None })
    }

    pub fn node_count(&self) -> usize {
        self.capacity.nrows()
    }
}

/// `y = A x` for a sparse column-major matrix (allocation free).
pub fn sparse_mul(a: &SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
    y.iter_mut().for_each(|v| *v = 0.0);
    let col_ptr = a.symbolic().col_ptr();
    let row_idx = a.symbolic().row_idx();
    let val = a.val();
    for (j, xj) in x.iter().enumerate() {
        if *xj != 0.0 {
            for p in col_ptr[j]..col_ptr[j + 1] {
                y[row_idx[p]] += val[p] * xj;
            }
        }
    }
}

/// The dense copy of a sparse matrix (small models, tests).
pub fn to_dense(a: &SparseColMat<usize, f64>) -> faer::Mat<f64> {
    let mut m = faer::Mat::zeros(a.nrows(), a.ncols());
    let col_ptr = a.symbolic().col_ptr();
    let row_idx = a.symbolic().row_idx();
    for j in 0..a.ncols() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            m[(row_idx[p], j)] += a.val()[p];
        }
    }
    m
}

/// The diagonal of a sparse matrix (duplicate entries summed, a missing one 0).
pub(crate) fn diagonal(a: &SparseColMat<usize, f64>) -> Vec<f64> {
    let (cp, ri, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    (0..a.ncols()).map(|j| (cp[j]..cp[j + 1]).filter(|&q| ri[q] == j).map(|q| val[q]).sum()).collect()
}

/// The Rayleigh quotient of a uniform temperature, `1^T K 1 / 1^T C 1` (1/s): the rate at which a
/// uniform rise decays (conduction alone conserves heat: only convection and fixed temperatures
/// make it positive), and an upper bound of the smallest eigenvalue of `K phi = lambda C phi`.
pub(crate) fn uniform_decay_rate(k: &SparseColMat<usize, f64>, c: &SparseColMat<usize, f64>) -> f64 {
    let total = |a: &SparseColMat<usize, f64>| a.val().iter().sum::<f64>();
    total(k) / total(c)
}

/// A sparse matrix from triplets (duplicates summed).
pub fn from_triplets(n: usize, triplets: &[Triplet<usize, usize, f64>]) -> Result<SparseColMat<usize, f64>, Error> {
    SparseColMat::try_new_from_triplets(n, n, triplets).map_err(|e| Error::input(format!("cannot build a sparse matrix: {e:?}")))
}

/// The 1D linear-element matrices: stiffness `[[1,-1],[-1,1]]/h` and mass `h [[2,1],[1,2]]/6`.
fn line_matrices(h: f64) -> ([[f64; 2]; 2], [[f64; 2]; 2]) {
    ([[1.0 / h, -1.0 / h], [-1.0 / h, 1.0 / h]], [[h / 3.0, h / 6.0], [h / 6.0, h / 3.0]])
}

/// Assembles C, K (conduction, lateral and boundary convection) and the step load Q.
pub fn assemble(problem: &ThermalProblem) -> Result<ThermalSystem, Error> {
    let mesh = &problem.mesh;
    let dim = mesh.dimensions();
    if problem.section.dimensions() != dim {
        return Err(Error::input(format!("a {dim}D mesh needs a {dim}D section (bar, plate or solid)")));
    }
    let m = &problem.material;
    for (name, v) in [
        ("conductivity_w_mk", m.conductivity_w_mk),
        ("density_kg_m3", m.density_kg_m3),
        ("specific_heat_j_kgk", m.specific_heat_j_kgk),
        ("section", problem.section.measure()),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::input(format!("`{name}` must be a positive finite number (got {v})")));
        }
    }
    let h_lat = problem.lateral_convection_w_m2k;
    if !(h_lat.is_finite() && h_lat >= 0.0) || problem.section.lateral() < 0.0 {
        return Err(Error::input(format!("the lateral convection coefficient must be finite and >= 0 (got {h_lat})")));
    }
    if problem.boundaries.len() != dim {
        return Err(Error::input(format!("{} boundary pairs for a {dim}D mesh", problem.boundaries.len())));
    }
    for b in problem.boundaries.iter().flatten() {
        if let Boundary::Convection(h) = b {
            if !(h.is_finite() && *h >= 0.0) {
                return Err(Error::input(format!("a convection coefficient must be finite and >= 0 (got {h})")));
            }
        }
    }
    let n = mesh.node_count();
    let s = problem.section.measure();
    let lines: Vec<_> = (0..dim).map(|d| line_matrices(mesh.spacing(d))).collect();
    let local = 1usize << dim;
    let bit = |a: usize, d: usize| (a >> d) & 1;
    // element matrices (the same for every cell)
    let mut ce = [[0.0; 8]; 8];
    let mut ke = [[0.0; 8]; 8];
    for a in 0..local {
        for b in 0..local {
            let mass: f64 = (0..dim).map(|d| lines[d].1[bit(a, d)][bit(b, d)]).product();
            let mut stiff = 0.0;
            for d in 0..dim {
                let mut t = lines[d].0[bit(a, d)][bit(b, d)];
                for e in (0..dim).filter(|&e| e != d) {
                    t *= lines[e].1[bit(a, e)][bit(b, e)];
                }
                stiff += t;
            }
            ce[a][b] = m.density_kg_m3 * m.specific_heat_j_kgk * s * mass;
            ke[a][b] = m.conductivity_w_mk * s * stiff + h_lat * problem.section.lateral() * mass;
        }
    }
    // boundary face matrices: [d][side], film h times the face mass over the other dimensions
    let face_measure = match problem.section {
        Section::Bar { area_m2, .. } => area_m2,
        Section::Plate { thickness_m } => thickness_m,
        Section::Solid => 1.0,
    };
    let cells = mesh.cell_count();
    let pattern = NeighbourPattern::new(mesh);
    let mut c_val = vec![0.0; pattern.row_idx.len()];
    let mut k_val = vec![0.0; pattern.row_idx.len()];
    let mut nodes = [0usize; 8];
    for cell in 0..cells {
        mesh.cell_nodes(cell, &mut nodes);
        let grid = mesh.cell_grid(cell);
        for a in 0..local {
            for b in 0..local {
                // entry (row nodes[b], column nodes[a])
                let at = pattern.position(mesh, nodes[a], nodes[b]);
                c_val[at] += ce[a][b];
                let mut k = ke[a][b];
                for (d, (&g, &cells_d)) in grid.iter().zip(mesh.cells()).enumerate() {
                    for side in 0..2 {
                        let on_face = if side == 0 { g == 0 } else { g + 1 == cells_d };
                        if !on_face || bit(a, d) != side || bit(b, d) != side {
                            continue;
                        }
                        if let Boundary::Convection(h) = problem.boundaries[d][side] {
                            let face: f64 = (0..dim).filter(|&e| e != d).map(|e| lines[e].1[bit(a, e)][bit(b, e)]).product();
                            k += h * face_measure * face;
                        }
                    }
                }
                k_val[at] += k;
            }
        }
    }
    let symbolic = SymbolicSparseColMat::new_checked(n, n, pattern.col_ptr, None, pattern.row_idx);
    let mut load = vec![0.0; n];
    for &(node, w) in &problem.fluxes {
        if node >= n {
            return Err(Error::input(format!("flux node {node} does not exist (the mesh has nodes 0..{})", n - 1)));
        }
        if !w.is_finite() {
            return Err(Error::input("a heat flux must be a finite number of W"));
        }
        load[node] += w;
    }
    Ok(ThermalSystem {
        capacity: SparseColMat::new(symbolic.clone(), c_val),
        conductivity: SparseColMat::new(symbolic, k_val),
        load,
        coordinates: Some((0..n).map(|i| mesh.node_coordinates(i)).collect()),
    })
}

/// The sparsity pattern of K and C on a structured mesh, built directly in compressed columns:
/// node a couples with every node b whose grid indices differ by at most 1 in each dimension (the
/// nodes of the cells around a), rows sorted.
struct NeighbourPattern {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl NeighbourPattern {
    fn new(mesh: &StructuredMesh) -> NeighbourPattern {
        let n = mesh.node_count();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(n * 3usize.pow(mesh.dimensions() as u32));
        col_ptr.push(0);
        for node in 0..n {
            let (lo, hi) = Self::window(mesh, node);
            let g = mesh.node_grid(node);
            for dk in lo[2]..=hi[2] {
                for dj in lo[1]..=hi[1] {
                    for di in lo[0]..=hi[0] {
                        let ijk = [g[0] as isize + di, g[1] as isize + dj, g[2] as isize + dk].map(|v| v as usize);
                        row_idx.push(mesh.node_index(&ijk[..mesh.dimensions()]));
                    }
                }
            }
            col_ptr.push(row_idx.len());
        }
        NeighbourPattern { col_ptr, row_idx }
    }

    /// Offsets (per dimension, -1..=1) of the neighbours of `node` inside the mesh.
    fn window(mesh: &StructuredMesh, node: usize) -> ([isize; 3], [isize; 3]) {
        let g = mesh.node_grid(node);
        let (mut lo, mut hi) = ([0isize; 3], [0isize; 3]);
        for (d, &c) in mesh.cells().iter().enumerate() {
            lo[d] = if g[d] > 0 { -1 } else { 0 };
            hi[d] = if g[d] < c { 1 } else { 0 };
        }
        (lo, hi)
    }

    /// Index into the values of entry (row `row`, column `col`), both nodes of one cell.
    fn position(&self, mesh: &StructuredMesh, col: usize, row: usize) -> usize {
        let (lo, hi) = Self::window(mesh, col);
        let (gc, gr) = (mesh.node_grid(col), mesh.node_grid(row));
        let mut offset = 0isize;
        for d in (0..3).rev() {
            offset = offset * (hi[d] - lo[d] + 1) + (gr[d] as isize - gc[d] as isize - lo[d]);
        }
        self.col_ptr[col] + offset as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steel() -> Material {
        Material { conductivity_w_mk: 60.5, density_kg_m3: 7800.0, specific_heat_j_kgk: 434.0 }
    }

    #[test]
    fn capacity_sums_to_the_heat_capacity_and_conduction_conserves_heat() {
        // 2D plate 0.3 x 0.2 m, 5 mm thick: sum of C = rho c_p V; K 1 = convective film only
        let mesh = StructuredMesh::new(vec![6, 4], vec![0.3, 0.2]).unwrap();
        let problem = ThermalProblem {
            mesh,
            material: steel(),
            section: Section::Plate { thickness_m: 0.005 },
            lateral_convection_w_m2k: 10.0,
            boundaries: vec![[Boundary::Convection(50.0), Boundary::Insulated], [Boundary::Insulated, Boundary::Insulated]],
            fluxes: vec![(0, 5.0)],
        };
        let sys = assemble(&problem).unwrap();
        let c = to_dense(&sys.capacity);
        let k = to_dense(&sys.conductivity);
        let n = sys.node_count();
        let total_c: f64 = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| c[(i, j)]).sum();
        assert!((total_c - 7800.0 * 434.0 * 0.3 * 0.2 * 0.005).abs() < 1e-6 * total_c);
        // K times a uniform rise of 1 K: heat lost = h_lat * 2 faces * area + h_edge * edge area
        let total_k: f64 = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| k[(i, j)]).sum();
        let want = 10.0 * 2.0 * 0.3 * 0.2 + 50.0 * 0.2 * 0.005;
        assert!((total_k - want).abs() < 1e-9 * want, "{total_k} vs {want}");
        for i in 0..n {
            for j in 0..n {
                assert!((k[(i, j)] - k[(j, i)]).abs() < 1e-12 && (c[(i, j)] - c[(j, i)]).abs() < 1e-9);
            }
        }
        assert_eq!(sys.load[0], 5.0);
    }
}
