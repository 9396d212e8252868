//! Smoothed-aggregation algebraic multigrid (Vanek, Mandel & Brezina, "Algebraic multigrid by
//! smoothed aggregation for second and fourth order elliptic problems", Computing 56, 1996) as a
//! preconditioner of a symmetric positive definite sparse matrix A, the conductivity K of a thermal
//! model, for the LOBPCG eigensolver ([`super::lobpcg`]): one V-cycle approximates `A^-1` for a
//! block of vectors at once, at a cost proportional to the nonzeros of A.
//!
//! Setup, level by level until at most [`COARSEST`] nodes are left:
//! - aggregation of the matrix graph (every off-diagonal nonzero counts as a strong connection, as
//!   for the conduction matrices of meshes): the three passes of Vanek et al. (a node whose
//!   neighbours are all free forms an aggregate with them; each node left joins the aggregate of a
//!   neighbour; the rest form aggregates with their free neighbours);
//! - tentative prolongator T: the near-null-space vector (constants on the finest level: a uniform
//!   temperature conducts no heat) restricted to each aggregate and normalised, so that `T^T T = I`;
//!   its norms on the aggregates are the coarse level's near-null-space vector;
//! - prolongator `P = (I - omega D^-1 A) T`, `omega = 4 / (3 rho)` with rho the spectral radius of
//!   `D^-1 A` (D the diagonal of A), estimated by power iteration;
//! - coarse matrix `A_c = P^T A P` (Galerkin).
//!
//! The coarsest matrix is factored densely (Cholesky). The V-cycle smooths with two Jacobi sweeps of
//! weight `omega` before and after the coarse correction, the same on every level, so that the
//! preconditioner is symmetric positive definite (LOBPCG needs that). Blocks of vectors are stored
//! row by row ([`super::sparse_rows`]).

use super::assembly::diagonal;
use super::sparse_rows::{from_rows, to_rows, transpose_times_rows};
use crate::error::Error;
use faer::linalg::solvers::{Llt, Solve};
use faer::sparse::linalg::matmul::sparse_sparse_matmul;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Par, Side};
use rayon::prelude::*;

/// Levels are coarsened until at most this many nodes are left, which are solved densely.
pub const COARSEST: usize = 2000;
/// Jacobi sweeps before and after the coarse correction.
const SWEEPS: usize = 2;
/// Power iterations for the spectral radius of `D^-1 A`.
const POWER_ITERATIONS: usize = 20;

/// One level of the hierarchy: its matrix, the inverse of its diagonal, the smoothing weight and
/// the prolongator to it from the next coarser level (stored with its transpose, so that both
/// `P x` and `P^T x` are row-parallel products).
struct Level {
    a: SparseColMat<usize, f64>,
    inverse_diagonal: Vec<f64>,
    omega: f64,
    /// P (this level's nodes x coarse nodes) and P^T.
    p: SparseColMat<usize, f64>,
    pt: SparseColMat<usize, f64>,
}

/// A smoothed-aggregation hierarchy of a symmetric positive definite matrix.
pub struct SmoothedAggregation {
    levels: Vec<Level>,
    coarsest: Llt<f64>,
    coarsest_nodes: usize,
}

impl SmoothedAggregation {
    /// Builds the hierarchy of `a` (symmetric positive definite; both triangles stored).
    pub fn new(a: &SparseColMat<usize, f64>) -> Result<SmoothedAggregation, Error> {
        let mut levels = Vec::new();
        let mut current = a.clone();
        let mut near_null = vec![1.0; a.nrows()];
        while current.nrows() > COARSEST {
            let inverse_diagonal = inverse_diagonal(&current)?;
            let rho = spectral_radius(&current, &inverse_diagonal);
            let omega = 4.0 / (3.0 * rho);
            let aggregates = aggregate(&current);
            let count = aggregates.iter().max().map_or(0, |m| m + 1);
            if count == 0 || count >= current.nrows() {
                break; // nothing to coarsen (no connections): solve this level densely
            }
            let (tentative, coarse_near_null) = tentative_prolongator(&aggregates, count, &near_null)?;
            let p = smoothed_prolongator(&current, &inverse_diagonal, omega, &tentative)?;
            let pt = transpose(&p)?;
            let ap = sparse_sparse_matmul(current.as_ref(), p.as_ref(), 1.0, Par::rayon(0)).map_err(memory)?;
            let coarse = sparse_sparse_matmul(pt.as_ref(), ap.as_ref(), 1.0, Par::rayon(0)).map_err(memory)?;
            levels.push(Level { a: current, inverse_diagonal, omega, p, pt });
            current = coarse;
            near_null = coarse_near_null;
        }
        let coarsest_nodes = current.nrows();
        let dense = current.to_dense();
        let dense = Mat::from_fn(coarsest_nodes, coarsest_nodes, |i, j| 0.5 * (dense[(i, j)] + dense[(j, i)]));
        let coarsest = dense
            .llt(Side::Lower)
            .map_err(|_| Error::computation("the coarsest multigrid matrix is not positive definite: the conductivity matrix must be (convection or fixed temperatures somewhere)"))?;
        Ok(SmoothedAggregation { levels, coarsest, coarsest_nodes })
    }

    /// Nodes of each level, finest first (the last one solved densely).
    pub fn level_sizes(&self) -> Vec<usize> {
        self.levels.iter().map(|l| l.a.nrows()).chain([self.coarsest_nodes]).collect()
    }

    /// Buffers for V-cycles of up to `p` vectors.
    pub fn workspace(&self, p: usize) -> AmgWorkspace {
        AmgWorkspace {
            levels: self
                .levels
                .iter()
                .map(|l| [vec![0.0; l.a.nrows() * p], vec![0.0; l.p.ncols() * p], vec![0.0; l.p.ncols() * p]])
                .collect(),
        }
    }

    /// `Z ~ A^-1 R` by one V-cycle, for `p` vectors stored row by row (`R`, `Z`: n x p).
    pub fn apply(&self, ws: &mut AmgWorkspace, r: &[f64], p: usize, z: &mut [f64]) {
        self.cycle(0, &mut ws.levels, r, p, z);
    }

    fn cycle(&self, level: usize, ws: &mut [[Vec<f64>; 3]], b: &[f64], p: usize, x: &mut [f64]) {
        let Some(l) = self.levels.get(level) else {
            let mut rhs = Mat::zeros(self.coarsest_nodes, p);
            from_rows(b, rhs.as_mut());
            self.coarsest.solve_in_place(rhs.as_mut());
            x.copy_from_slice(&to_rows(rhs.as_ref()));
            return;
        };
        let (here, coarser) = ws.split_first_mut().expect("a workspace per level");
        let [residual, coarse_b, coarse_x] = here;
        let (n, coarse_n) = (l.a.nrows(), l.p.ncols());
        residual.resize(n * p, 0.0);
        coarse_b.resize(coarse_n * p, 0.0);
        coarse_x.resize(coarse_n * p, 0.0);
        // pre-smoothing from x = 0: the first sweep is omega D^-1 b
        rows_zip(x, b, p, |i, x, b| {
            let w = l.omega * l.inverse_diagonal[i];
            for (x, b) in x.iter_mut().zip(b) {
                *x = w * b;
            }
        });
        for _ in 1..SWEEPS {
            jacobi_sweep(l, b, p, x, residual);
        }
        // coarse correction
        transpose_times_rows(&l.a, x, p, residual);
        rows_zip(residual, b, p, |_, r, b| {
            for (r, b) in r.iter_mut().zip(b) {
                *r = b - *r;
            }
        });
        transpose_times_rows(&l.p, residual, p, coarse_b);
        self.cycle(level + 1, coarser, coarse_b, p, coarse_x);
        transpose_times_rows(&l.pt, coarse_x, p, residual);
        rows_zip(x, residual, p, |_, x, e| {
            for (x, e) in x.iter_mut().zip(e) {
                *x += e;
            }
        });
        for _ in 0..SWEEPS {
            jacobi_sweep(l, b, p, x, residual);
        }
    }
}

/// The buffers of V-cycles (residual, coarse right-hand side and coarse solution per level).
pub struct AmgWorkspace {
    levels: Vec<[Vec<f64>; 3]>,
}

/// One weighted Jacobi sweep `x += omega D^-1 (b - A x)`; `scratch` receives `A x`.
fn jacobi_sweep(l: &Level, b: &[f64], p: usize, x: &mut [f64], scratch: &mut [f64]) {
    transpose_times_rows(&l.a, x, p, scratch);
    x.par_chunks_mut(p).with_min_len(1024).zip(b.par_chunks(p)).zip(scratch.par_chunks(p)).enumerate().for_each(|(i, ((x, b), ax))| {
        let w = l.omega * l.inverse_diagonal[i];
        for ((x, b), ax) in x.iter_mut().zip(b).zip(ax) {
            *x += w * (b - ax);
        }
    });
}

/// `f(i, x_i, y_i)` over the rows of two row-major blocks, in parallel.
fn rows_zip(x: &mut [f64], y: &[f64], p: usize, f: impl Fn(usize, &mut [f64], &[f64]) + Sync) {
    x.par_chunks_mut(p).with_min_len(1024).zip(y.par_chunks(p)).enumerate().for_each(|(i, (x, y))| f(i, x, y));
}

fn memory(e: faer::sparse::FaerError) -> Error {
    Error::computation(format!("the multigrid hierarchy needs more memory than this machine has ({e:?})"))
}

/// `1 / A_ii`; an error for a diagonal entry that is not positive.
fn inverse_diagonal(a: &SparseColMat<usize, f64>) -> Result<Vec<f64>, Error> {
    diagonal(a)
        .into_iter()
        .enumerate()
        .map(|(j, d)| {
            if d > 0.0 && d.is_finite() {
                Ok(1.0 / d)
            } else {
                Err(Error::input(format!("the conductivity matrix has a diagonal entry {d:e} at node {}, not positive", j + 1)))
            }
        })
        .collect()
}

/// The largest eigenvalue of `D^-1 A` (self-adjoint in the D inner product) by power iteration from
/// a fixed pseudo-random vector: the largest Rayleigh quotient `x^T A x / x^T D x` seen, a lower
/// bound that is close after a few iterations for the smooth spectra of meshes. The Jacobi weight
/// `4 / (3 rho)` stays below the stability limit `2 / rho_true` unless rho is underestimated by a
/// third.
fn spectral_radius(a: &SparseColMat<usize, f64>, inverse_diagonal: &[f64]) -> f64 {
    let n = a.nrows();
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut x: Vec<f64> = (0..n)
        .map(|_| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect();
    let mut ax = vec![0.0; n];
    let mut rho = 0.0f64;
    for _ in 0..POWER_ITERATIONS {
        transpose_times_rows(a, &x, 1, &mut ax);
        let (xax, xdx) = x.iter().zip(&ax).zip(inverse_diagonal).fold((0.0, 0.0), |(s, t), ((x, ax), d)| (s + x * ax, t + x * x / d));
        if xdx <= 0.0 {
            break;
        }
        rho = rho.max(xax / xdx);
        let scale = 1.0 / xdx.sqrt();
        for ((x, ax), d) in x.iter_mut().zip(&ax).zip(inverse_diagonal) {
            *x = ax * d * scale;
        }
    }
    if rho > 0.0 && rho.is_finite() {
        rho
    } else {
        1.0
    }
}

/// The aggregate of every node (numbered from 0) by the three passes of Vanek et al. on the graph of
/// `a`'s off-diagonal nonzeros.
fn aggregate(a: &SparseColMat<usize, f64>) -> Vec<usize> {
    const FREE: usize = usize::MAX;
    let n = a.nrows();
    let (cp, ri, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let neighbours = |i: usize| (cp[i]..cp[i + 1]).filter(move |&q| ri[q] != i && val[q] != 0.0).map(move |q| ri[q]);
    let mut of = vec![FREE; n];
    let mut count = 0;
    // pass 1: a node whose neighbours are all free, with its neighbours
    for i in 0..n {
        if of[i] == FREE && neighbours(i).all(|j| of[j] == FREE) {
            of[i] = count;
            for j in neighbours(i) {
                of[j] = count;
            }
            count += 1;
        }
    }
    // pass 2: each node left joins the aggregate of a neighbour aggregated in pass 1
    let first = of.clone();
    for (i, of) in of.iter_mut().enumerate() {
        if *of == FREE {
            if let Some(j) = neighbours(i).find(|&j| first[j] != FREE) {
                *of = first[j];
            }
        }
    }
    // pass 3: the rest with their free neighbours
    for i in 0..n {
        if of[i] == FREE {
            of[i] = count;
            for j in neighbours(i) {
                if of[j] == FREE {
                    of[j] = count;
                }
            }
            count += 1;
        }
    }
    of
}

/// T (nodes x aggregates) with the near-null-space vector `b` on each aggregate, normalised; the
/// norms are the coarse near-null-space vector.
fn tentative_prolongator(aggregates: &[usize], count: usize, b: &[f64]) -> Result<(SparseColMat<usize, f64>, Vec<f64>), Error> {
    let mut norms = vec![0.0f64; count];
    for (&k, v) in aggregates.iter().zip(b) {
        norms[k] += v * v;
    }
    norms.iter_mut().for_each(|s| *s = s.sqrt());
    let triplets: Vec<Triplet<usize, usize, f64>> = aggregates
        .iter()
        .zip(b)
        .enumerate()
        .filter(|(_, (&k, _))| norms[k] > 0.0)
        .map(|(i, (&k, v))| Triplet::new(i, k, v / norms[k]))
        .collect();
    let t = SparseColMat::try_new_from_triplets(aggregates.len(), count, &triplets).map_err(|e| Error::computation(format!("{e:?}")))?;
    Ok((t, norms))
}

/// `P = T - omega D^-1 A T`.
fn smoothed_prolongator(
    a: &SparseColMat<usize, f64>,
    inverse_diagonal: &[f64],
    omega: f64,
    t: &SparseColMat<usize, f64>,
) -> Result<SparseColMat<usize, f64>, Error> {
    let at = sparse_sparse_matmul(a.as_ref(), t.as_ref(), 1.0, Par::rayon(0)).map_err(memory)?;
    let (tcp, tri, tval) = (t.symbolic().col_ptr(), t.symbolic().row_idx(), t.val());
    let (cp, ri, val) = (at.symbolic().col_ptr(), at.symbolic().row_idx(), at.val());
    let mut triplets = Vec::with_capacity(val.len() + tval.len());
    for k in 0..t.ncols() {
        for q in tcp[k]..tcp[k + 1] {
            triplets.push(Triplet::new(tri[q], k, tval[q]));
        }
        for q in cp[k]..cp[k + 1] {
            let i = ri[q];
            triplets.push(Triplet::new(i, k, -omega * inverse_diagonal[i] * val[q]));
        }
    }
    // duplicates (T's entries inside A T's pattern) are summed
    SparseColMat::try_new_from_triplets(t.nrows(), t.ncols(), &triplets).map_err(|e| Error::computation(format!("{e:?}")))
}

/// The transpose of a sparse matrix, stored by columns.
fn transpose(a: &SparseColMat<usize, f64>) -> Result<SparseColMat<usize, f64>, Error> {
    a.as_ref().transpose().to_col_major().map_err(memory)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::thermal::assembly::{assemble, Boundary, Material, Section, ThermalProblem};
    use crate::thermal::mesh::StructuredMesh;

    fn conductivity(cells: usize) -> SparseColMat<usize, f64> {
        let problem = ThermalProblem {
            mesh: StructuredMesh::new(vec![cells; 3], vec![0.5, 0.4, 0.3]).unwrap(),
            material: Material { conductivity_w_mk: 50.0, density_kg_m3: 7850.0, specific_heat_j_kgk: 460.0 },
            section: Section::Solid,
            lateral_convection_w_m2k: 0.0,
            boundaries: vec![
                [Boundary::Convection(20.0), Boundary::Insulated],
                [Boundary::Insulated; 2],
                [Boundary::Insulated, Boundary::Convection(8.0)],
            ],
            fluxes: vec![],
        };
        assemble(&problem).unwrap().conductivity
    }

    #[test]
    fn aggregation_of_a_27_point_grid_equals_pyamgs_standard_aggregation() {
        // pyamg 5 (`standard_aggregation` of `symmetric_strength_of_connection(K, theta=0)`) on the
        // same 27^3-node conductivity matrix, nodes numbered x fastest: 729 aggregates, the first
        // ten of 8, 12, 12, 12, 12, 12, 12, 12, 21 and 12 nodes, from 8 to 46 nodes
        let a = conductivity(26);
        let aggregates = aggregate(&a);
        let count = aggregates.iter().max().unwrap() + 1;
        assert_eq!(count, 729);
        let mut sizes = vec![0; count];
        aggregates.iter().for_each(|&k| sizes[k] += 1);
        assert_eq!(sizes[..10], [8, 12, 12, 12, 12, 12, 12, 12, 21, 12]);
        assert_eq!((sizes.iter().min(), sizes.iter().max()), (Some(&8), Some(&46)));
    }

    #[test]
    fn the_v_cycle_is_a_symmetric_positive_definite_approximate_inverse() {
        // M = V-cycle: x^T M y = y^T M x, x^T M x > 0, and the preconditioned Richardson iteration
        // x <- x + M (b - A x) converges fast (the multigrid contraction, mesh independent)
        let a = conductivity(20); // 9261 nodes: two levels and a dense one
        let amg = SmoothedAggregation::new(&a).unwrap();
        assert!(amg.level_sizes().len() >= 2, "{:?}", amg.level_sizes());
        let n = a.nrows();
        let v = |s: f64| (0..n).map(|i| (i as f64 * s).sin() + 0.3 * (i as f64 * 0.01).cos()).collect::<Vec<f64>>();
        let (x, y) = (v(0.7), v(1.3));
        let (mut mx, mut my) = (vec![0.0; n], vec![0.0; n]);
        let mut ws = amg.workspace(1);
        amg.apply(&mut ws, &x, 1, &mut mx);
        amg.apply(&mut ws, &y, 1, &mut my);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        let (xmy, ymx) = (dot(&x, &my), dot(&y, &mx));
        assert!((xmy - ymx).abs() <= 1e-10 * xmy.abs().max(ymx.abs()), "{xmy} vs {ymx}");
        assert!(dot(&x, &mx) > 0.0);
        let b = x;
        let mut solution = vec![0.0; n];
        let (mut ax, mut correction) = (vec![0.0; n], vec![0.0; n]);
        let mut norms = Vec::new();
        for _ in 0..10 {
            transpose_times_rows(&a, &solution, 1, &mut ax);
            let r: Vec<f64> = b.iter().zip(&ax).map(|(b, ax)| b - ax).collect();
            norms.push(dot(&r, &r).sqrt());
            amg.apply(&mut ws, &r, 1, &mut correction);
            solution.iter_mut().zip(&correction).for_each(|(s, c)| *s += c);
        }
        let rate = (norms[9] / norms[0]).powf(1.0 / 9.0);
        assert!(rate < 0.5, "contraction per V-cycle {rate}, residuals {norms:?}");
    }
}
