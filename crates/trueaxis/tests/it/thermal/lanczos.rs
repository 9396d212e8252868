//! The fast shift-invert Lanczos (issue 23: shift near lambda_1, block 8, row-major C products,
//! sliced V^T X) against independent formulations, 20 time constants to 1e-10 relative:
//! - on a block of 1331 nodes, the dense solver (Cholesky of C, full symmetric eigendecomposition);
//! - on the 10 648-node benchmark block, the separable closed form: on a structured grid of
//!   trilinear hexahedra with convection on whole faces, C = rho c_p Mz (x) My (x) Mx and
//!   K = Az (x) My (x) Mx + Mz (x) Ay (x) Mx + Mz (x) My (x) Ax with the 1D matrices
//!   A = k K_1D + sum over the line's convective ends h e e^T (the assembly of
//!   `bench/baseline_thermal.py`), so that every eigenvalue is
//!   `lambda = (mu_x + mu_y + mu_z) / (rho c_p)` with `A u = mu M u` on each line (21 + 1 nodes,
//!   dense), the smallest 20 of all sums.

use nalgebra::{DMatrix, SymmetricEigen};
use trueaxis::thermal::assembly::{assemble, Boundary, Material, Section, ThermalProblem};
use trueaxis::thermal::mesh::StructuredMesh;
use trueaxis::thermal::{modal_analysis, ModalOptions, SpectrumMethod};

const SIZE_M: [f64; 3] = [0.5, 0.4, 0.3];
const K_W_MK: f64 = 50.0;
const RHO_CP: f64 = 7850.0 * 460.0;
/// Convection (W/m^2K) at the [min, max] end of each axis, as in `benches/thermal.rs`.
const FACES: [[f64; 2]; 3] = [[20.0, 10.0], [5.0, 0.0], [0.0, 8.0]];

fn block(cells: usize) -> ThermalProblem {
    let boundary = |h: f64| if h > 0.0 { Boundary::Convection(h) } else { Boundary::Insulated };
    ThermalProblem {
        mesh: StructuredMesh::new(vec![cells; 3], SIZE_M.to_vec()).unwrap(),
        material: Material { conductivity_w_mk: K_W_MK, density_kg_m3: 7850.0, specific_heat_j_kgk: 460.0 },
        section: Section::Solid,
        lateral_convection_w_m2k: 0.0,
        boundaries: FACES.iter().map(|[lo, hi]| [boundary(*lo), boundary(*hi)]).collect(),
        fluxes: vec![(0, 1.0)],
    }
}

/// Generalised eigenvalues `A u = mu M u` of one line of `cells` linear elements (ascending).
fn line_eigenvalues(cells: usize, length: f64, ends: [f64; 2]) -> Vec<f64> {
    let (n, h) = (cells + 1, length / cells as f64);
    let mut a = DMatrix::<f64>::zeros(n, n);
    let mut m = DMatrix::<f64>::zeros(n, n);
    for e in 0..cells {
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let same = i == j;
            a[(e + i, e + j)] += K_W_MK * if same { 1.0 } else { -1.0 } / h;
            m[(e + i, e + j)] += h * if same { 1.0 / 3.0 } else { 1.0 / 6.0 };
        }
    }
    a[(0, 0)] += ends[0];
    a[(n - 1, n - 1)] += ends[1];
    let l = m.cholesky().unwrap().l();
    let l_inv = l.clone().try_inverse().unwrap();
    let s = &l_inv * a * l_inv.transpose();
    let mut mu: Vec<f64> = SymmetricEigen::new(0.5 * (&s + s.transpose())).eigenvalues.iter().copied().collect();
    mu.sort_by(f64::total_cmp);
    mu
}

/// The `count` smallest eigenvalues of the block by separation of variables.
fn separable_eigenvalues(cells: usize, count: usize) -> Vec<f64> {
    let lines: Vec<Vec<f64>> = (0..3).map(|d| line_eigenvalues(cells, SIZE_M[d], FACES[d])).collect();
    let mut sums: Vec<f64> = Vec::new();
    for x in &lines[0] {
        for y in &lines[1] {
            for z in &lines[2] {
                sums.push((x + y + z) / RHO_CP);
            }
        }
    }
    sums.sort_by(f64::total_cmp);
    sums.truncate(count);
    sums
}

fn lanczos_lambda(cells: usize) -> Vec<f64> {
    let system = assemble(&block(cells)).unwrap();
    let options = ModalOptions { count: Some(20), method: SpectrumMethod::Lanczos, ..Default::default() };
    modal_analysis(&system, &options).unwrap().lambda
}

#[test]
fn the_20_time_constants_equal_the_dense_solvers_on_1331_nodes() {
    let system = assemble(&block(10)).unwrap();
    assert_eq!(system.node_count(), 1331);
    let dense = modal_analysis(&system, &ModalOptions { count: Some(20), method: SpectrumMethod::Dense, ..Default::default() }).unwrap();
    let sparse = lanczos_lambda(10);
    for (i, (l, d)) in sparse.iter().zip(&dense.lambda).enumerate() {
        let (tau, reference) = (1.0 / l, 1.0 / d);
        assert!((tau - reference).abs() <= 1e-10 * reference, "tau_{i}: {tau} s vs dense {reference} s");
    }
    // and the dense solver equals the separable form (the closed form is right for this assembly)
    let exact = separable_eigenvalues(10, 20);
    for (i, (d, e)) in dense.lambda.iter().zip(&exact).enumerate() {
        assert!((d - e).abs() <= 1e-10 * e, "lambda_{i}: dense {d} vs separable {e}");
    }
}

#[test]
fn the_20_time_constants_equal_the_separable_closed_form_on_10648_nodes() {
    let sparse = lanczos_lambda(21);
    let exact = separable_eigenvalues(21, 20);
    assert_eq!(sparse.len(), 20);
    for (i, (l, e)) in sparse.iter().zip(&exact).enumerate() {
        let (tau, reference) = (1.0 / l, 1.0 / e);
        assert!((tau - reference).abs() <= 1e-10 * reference, "tau_{i}: {tau} s vs separable {reference} s");
    }
}

/// LOBPCG with the multigrid preconditioner (the solver `SpectrumMethod::Auto` takes above 50,000
/// nodes) on the 4096-node block (two multigrid levels and a dense one): the 20 time constants equal
/// the separable closed form to 1e-10 relative, the modes are C-orthonormal (1e-10) and equal the
/// shift-invert Lanczos modes (the same deterministic sign) to 1e-6 of their largest entry, and the
/// relative residual of each pair `|K phi - lambda C phi| / (lambda |C phi|)` is within its
/// tolerance (1e-7).
#[test]
fn lobpcg_equals_the_separable_closed_form_and_the_lanczos_modes() {
    let system = assemble(&block(15)).unwrap();
    assert_eq!(system.node_count(), 4096);
    let options = ModalOptions { count: Some(20), method: SpectrumMethod::Lobpcg, ..Default::default() };
    let lobpcg = modal_analysis(&system, &options).unwrap();
    let exact = separable_eigenvalues(15, 20);
    for (i, (l, e)) in lobpcg.lambda.iter().zip(&exact).enumerate() {
        let (tau, reference) = (1.0 / l, 1.0 / e);
        assert!((tau - reference).abs() <= 1e-10 * reference, "tau_{i}: {tau} s vs separable {reference} s");
    }
    let lanczos = modal_analysis(&system, &ModalOptions { method: SpectrumMethod::Lanczos, ..options }).unwrap();
    let (k, c) = (system.conductivity.to_dense(), system.capacity.to_dense());
    let (phi, reference) = (&lobpcg.shapes, &lanczos.shapes);
    let gram = phi.transpose() * &c * phi;
    for i in 0..20 {
        for j in 0..20 {
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((gram[(i, j)] - want).abs() <= 1e-10, "Phi^T C Phi [{i}, {j}] = {}", gram[(i, j)]);
        }
        // the separable spectrum has no repeated eigenvalue among the first 20 here
        let largest = (0..phi.nrows()).map(|r| reference[(r, i)].abs()).fold(0.0, f64::max);
        let difference = (0..phi.nrows()).map(|r| (phi[(r, i)] - reference[(r, i)]).abs()).fold(0.0, f64::max);
        assert!(difference <= 1e-6 * largest, "mode {i}: LOBPCG and Lanczos differ by {difference} of {largest}");
        let kphi = &k * phi.col(i);
        let cphi = &c * phi.col(i);
        let residual = (&kphi - &cphi * lobpcg.lambda[i]).norm_l2() / (lobpcg.lambda[i] * cphi.norm_l2());
        assert!(residual <= 1.01e-7, "mode {i}: relative residual {residual}");
    }
}

/// A block with no convection loses no heat (K is singular: a uniform temperature stays): every
/// sparse solver refuses it with its reason instead of returning an infinite time constant.
#[test]
fn a_block_that_loses_no_heat_is_refused_by_every_sparse_solver() {
    let mut problem = block(15);
    problem.boundaries = vec![[Boundary::Insulated; 2]; 3];
    let system = assemble(&problem).unwrap();
    for method in [SpectrumMethod::Lanczos, SpectrumMethod::Lobpcg] {
        let error = modal_analysis(&system, &ModalOptions { count: Some(5), method, ..Default::default() }).unwrap_err().to_string();
        assert!(error.contains("loses no heat") || error.contains("convection"), "{method:?}: {error}");
    }
}
