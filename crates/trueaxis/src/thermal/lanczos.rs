//! Partial spectrum of a large sparse generalised symmetric eigenproblem `K phi = lambda C phi`
//! (K symmetric positive semi-definite, C symmetric positive definite): the `count` smallest
//! eigenvalues by shift-invert block Lanczos with full reorthogonalisation in the C inner product.
//!
//! Why here: no Rust crate offers a sparse partial eigensolver for generalised problems with
//! blocks (faer 0.24's `partial_self_adjoint_eigen` is a single-vector Krylov-Schur method in the
//! Euclidean inner product: one pass over the 0.5 GB factor per Krylov vector on 10^5 nodes), so
//! this file builds one on faer's sparse Cholesky.
//!
//! Method (Ericsson & Ruhe 1980; Grimes, Lewis & Simon 1994):
//! - shift `sigma < 0` below the spectrum, factor `K - sigma C = P^T L L^T P` once (sparse
//!   Cholesky, P by nested dissection on meshes, [`super::ordering`]);
//! - the operator `Op = (K - sigma C)^-1 C` is self-adjoint in `<x, y>_C = x^T C y`, with
//!   eigenvalues `nu = 1 / (lambda - sigma)`: the smallest lambda become the largest, well separated nu;
//! - a block Krylov basis `V` (block size p, so that eigenvalues of multiplicity up to p, as in
//!   symmetric structures, are found) is kept C-orthonormal by block classical Gram-Schmidt
//!   applied twice against all previous vectors (full reorthogonalisation) and a Cholesky QR
//!   (twice) within the block;
//! - Rayleigh-Ritz on `T = V^T C Op V` (small, dense): Ritz pairs `(theta, s)`, residual norm
//!   `|Op y - theta y|_C = |B s_last|` from the next block's coefficients, converged when
//!   `<= tolerance * theta` for all wanted pairs;
//! - `lambda = sigma + 1/theta`, `phi = V s` (C-orthonormal).
//!
//! Cost per block step: one block solve with p right-hand sides (one pass over the factor per
//! thread), three block products with C, and four products with the n x m basis
//! (reorthogonalisation). Measured on a 47^3 = 103 823-node block, 20 modes, 2 shared threads
//! (issue 23, BENCHMARKS.md): nested dissection and factorisation 2.2 s (6.0e7 nonzeros), 17 Ritz
//! steps of block 8 (160 basis vectors, 20 block solves), 7.1 CPU seconds and 5.1-7.2 s wall in all.

use super::assembly::{diagonal, from_triplets, uniform_decay_rate};
use super::sparse_cholesky::SparseCholesky;
use super::sparse_rows::{from_rows, to_rows, transpose_times_rows};
use crate::error::Error;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::prelude::{Reborrow, ReborrowMut};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Accum, Mat, MatMut, MatRef, Par};

/// Options of [`smallest_eigenpairs`].
#[derive(Clone, Copy, Debug)]
pub struct LanczosOptions {
    /// Block size p (default 8: on the 10^5-node block 17 block steps instead of 23 with p = 4, each
    /// pass over the factor and over C serving twice the vectors).
    pub block: usize,
    /// Relative residual `|Op y - theta y|_C / theta` at convergence (default 1e-10).
    pub tolerance: f64,
    /// Largest Krylov basis (default `max(10 count, 200)`, at most n).
    pub max_basis: Option<usize>,
}

impl Default for LanczosOptions {
    fn default() -> Self {
        LanczosOptions { block: 8, tolerance: 1e-10, max_basis: None }
    }
}

/// Where a long run of a sparse eigensolver is, for a progress display: the shift-invert Lanczos
/// of this module or LOBPCG ([`super::lobpcg`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LanczosProgress {
    /// Lanczos: ordering and factorising `K - sigma C` (n nodes).
    Factorising { nodes: usize },
    /// Lanczos: the factor has this many nonzeros.
    Factorised { nonzeros: usize },
    /// Lanczos, after a block step: `converged` of the `wanted` modes, `basis` of at most
    /// `max_basis` vectors.
    Iterating { converged: usize, wanted: usize, basis: usize, max_basis: usize },
    /// LOBPCG: building the multigrid preconditioner of K (n nodes).
    Preconditioning { nodes: usize },
    /// LOBPCG: the multigrid hierarchy has this many levels.
    Preconditioned { levels: usize },
    /// LOBPCG, after an iteration: `converged` of the `wanted` modes.
    Refining { converged: usize, wanted: usize, iteration: usize, max_iterations: usize },
}

/// The `count` smallest eigenvalues (ascending) of `K phi = lambda C phi` with C-orthonormal
/// eigenvectors (columns); the factor is ordered by approximate minimum degree.
pub fn smallest_eigenpairs(
    k: &SparseColMat<usize, f64>,
    c: &SparseColMat<usize, f64>,
    count: usize,
    options: &LanczosOptions,
) -> Result<(Vec<f64>, Mat<f64>), Error> {
    smallest_eigenpairs_with(k, c, None, count, options, &mut |_| {})
}

/// [`smallest_eigenpairs`] with node coordinates (m) for a nested-dissection ordering of the
/// factor (much less fill on 2D/3D meshes, [`super::ordering`]) and a progress callback.
pub fn smallest_eigenpairs_with(
    k: &SparseColMat<usize, f64>,
    c: &SparseColMat<usize, f64>,
    coordinates: Option<&[[f64; 3]]>,
    count: usize,
    options: &LanczosOptions,
    progress: &mut dyn FnMut(LanczosProgress),
) -> Result<(Vec<f64>, Mat<f64>), Error> {
    let n = k.nrows();
    let p = options.block.max(1);
    if count == 0 || count > n {
        return Err(Error::input(format!("cannot compute {count} modes of a model with {n} nodes")));
    }
    let max_basis = options.max_basis.unwrap_or((10 * count).max(200)).min(n.saturating_sub(p));
    if max_basis < count + 2 * p {
        return Err(Error::input(format!("{n} nodes are too few for the sparse solver with {count} modes: use the dense solver")));
    }
    // shift below the spectrum: a small fraction of the smallest diagonal ratio K_ii / C_ii
    let (kd, cd) = (diagonal(k), diagonal(c));
    if cd.iter().any(|v| v.is_nan() || *v <= 0.0) {
        return Err(Error::input("the capacity matrix C has a diagonal entry that is not positive"));
    }
    let sigma = shift(k, c, &kd, &cd);
    progress(LanczosProgress::Factorising { nodes: n });
    let llt = SparseCholesky::factor(&shifted(k, c, sigma)?, coordinates)?;
    progress(LanczosProgress::Factorised { nonzeros: llt.factor_nonzeros() });
    // V (n x m, C-orthonormal columns) grows by blocks; T = V^T C Op V with the coefficients of each
    // block on the next block (rows m..m+p of the block's columns)
    let mut basis = Mat::<f64>::zeros(n, p);
    let mut capacity = p;
    let mut t = Mat::<f64>::zeros(max_basis + p, max_basis + p);
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut cw = Mat::<f64>::zeros(n, p);
    // first block: pseudo-random vectors
    let mut block = Mat::from_fn(n, p, |_, _| random_value(&mut seed));
    let mut cw_is_c_block = orthonormalize_block(block.as_mut(), basis.subcols(0, 0), c, cw.as_mut(), &mut seed, None);
    basis.copy_from(&block);
    let mut current = 0usize;
    loop {
        let m = basis.ncols();
        // W = Op V_block = (K - sigma C)^-1 C V_block, p right-hand sides in one solve
        if cw_is_c_block {
            block.copy_from(&cw);
        } else {
            symmetric_mul(c, basis.subcols(current, p), block.as_mut());
        }
        llt.solve_in_place(block.as_mut());
        cw_is_c_block = orthonormalize_block(
            block.as_mut(),
            basis.as_ref(),
            c,
            cw.as_mut(),
            &mut seed,
            Some(t.as_mut().submatrix_mut(0, current, m + p, p)),
        );
        if capacity < m + p {
            capacity = (2 * (m + p)).min(max_basis + p).max(m + p);
            basis.reserve(n, capacity);
        }
        basis.resize_with(n, m + p, |_, _| 0.0);
        basis.subcols_mut(m, p).copy_from(&block);
        current = m;
        if m < count + p {
            continue;
        }
        let (theta, s, residual) = ritz(t.as_ref(), m, p);
        let converged = (0..count).take_while(|&i| residual[i] <= options.tolerance * theta[i].abs()).count();
        progress(LanczosProgress::Iterating { converged, wanted: count, basis: m + p, max_basis });
        if converged == count {
            let lambda = theta[..count].iter().map(|th| sigma + 1.0 / th).collect();
            let ritz_vectors = Mat::from_fn(m, count, |r, i| s[(r, i)]);
            let mut shapes = Mat::zeros(n, count);
            matmul(shapes.as_mut(), Accum::Replace, basis.subcols(0, m), ritz_vectors.as_ref(), 1.0, parallelism(n));
            return Ok((lambda, shapes));
        }
        if m + 2 * p > max_basis {
            return Err(Error::computation(format!(
                "shift-invert Lanczos did not converge to {count} modes within a basis of {max_basis} vectors; ask for fewer modes or a larger basis"
            )));
        }
    }
}

/// The shift `sigma < 0` just below the spectrum. Every Rayleigh quotient `x^T K x / x^T C x` is an
/// upper bound of the smallest eigenvalue lambda_1: those of the unit vectors (`K_ii / C_ii`) and of
/// the constant vector (`1^T K 1 / 1^T C 1`, on a thermal model the convective conductance over the
/// heat capacity, within a few per cent of lambda_1). Half the smallest bound puts sigma at the
/// scale of lambda_1, so that `nu = 1 / (lambda - sigma)` separates the wanted eigenvalues about as
/// well as lambda itself; the floor of 1e-6 of the smallest `K_ii / C_ii` keeps `K - sigma C`
/// positive definite when K is singular (no convection: refused after the solve, with its reason).
/// (Ericsson & Ruhe 1980: the shift near the wanted end of the spectrum.) On the 10^5-node block,
/// 1e-3 of the smallest `K_ii / C_ii` (the earlier shift, 60 times lambda_1) needed 128 basis
/// vectors for 20 modes, this shift 20 % fewer; on finer meshes the unit-vector bound grows as
/// 1/h^2 and the earlier shift moved further away still.
fn shift(k: &SparseColMat<usize, f64>, c: &SparseColMat<usize, f64>, kd: &[f64], cd: &[f64]) -> f64 {
    let diagonal_bound = kd.iter().zip(cd).map(|(a, b)| a / b).filter(|r| *r > 0.0).fold(f64::INFINITY, f64::min);
    let diagonal_bound = if diagonal_bound.is_finite() { diagonal_bound } else { 1.0 };
    let constant_bound = uniform_decay_rate(k, c);
    let bound = if constant_bound.is_finite() && constant_bound > 0.0 { constant_bound.min(diagonal_bound) } else { diagonal_bound };
    -(0.5 * bound).max(1e-6 * diagonal_bound)
}

/// `K - sigma C`: directly on the values when both matrices have the same sparsity pattern (a
/// mesh), else summed from triplets.
fn shifted(k: &SparseColMat<usize, f64>, c: &SparseColMat<usize, f64>, sigma: f64) -> Result<SparseColMat<usize, f64>, Error> {
    let same = k.symbolic().col_ptr() == c.symbolic().col_ptr() && k.symbolic().row_idx() == c.symbolic().row_idx();
    if same {
        let mut a = k.clone();
        a.val_mut().iter_mut().zip(c.val()).for_each(|(x, y)| *x -= sigma * y);
        return Ok(a);
    }
    let n = k.nrows();
    let mut triplets = Vec::with_capacity(k.val().len() + c.val().len());
    for (m, factor) in [(k, 1.0), (c, -sigma)] {
        let (cp, ri, val) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
        for j in 0..n {
            for q in cp[j]..cp[j + 1] {
                triplets.push(Triplet::new(ri[q], j, factor * val[q]));
            }
        }
    }
    from_triplets(n, &triplets)
}

/// Ritz values (descending), vectors and residual norms of the m x m leading part of T; the
/// residual of pair i is `|T[m..m+p, 0..m] s_i|`.
fn ritz(t: MatRef<'_, f64>, m: usize, p: usize) -> (Vec<f64>, nalgebra::DMatrix<f64>, Vec<f64>) {
    let sym = nalgebra::DMatrix::from_fn(m, m, |i, j| 0.5 * (t[(i, j)] + t[(j, i)]));
    let eig = nalgebra::SymmetricEigen::new(sym);
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let theta: Vec<f64> = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    let s = nalgebra::DMatrix::from_fn(m, m, |r, c| eig.eigenvectors[(r, order[c])]);
    let residual = (0..m)
        .map(|i| {
            (m..m + p)
                .map(|row| {
                    let v: f64 = (m.saturating_sub(p)..m).map(|j| t[(row, j)] * s[(j, i)]).sum();
                    v * v
                })
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    (theta, s, residual)
}

/// A pseudo-random number in [-0.5, 0.5) (splitmix64), deterministic.
pub(super) fn random_value(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *seed;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// Below this many nodes the vector operations run on one thread: their work is microseconds, less
/// than handing it to another thread costs (at 10^3 nodes the threads spent more time waiting than
/// computing; 74 -> 44-60 ms for 20 modes, and 10^4 nodes 620 -> 483 ms).
const PARALLEL_NODES: usize = 4_000;

/// The parallelism of dense products with `n`-row operands.
fn parallelism(n: usize) -> Par {
    if n < PARALLEL_NODES {
        Par::Seq
    } else {
        Par::rayon(0)
    }
}

/// `Y = C X` for a symmetric sparse C, in one pass over C for all columns of X
/// ([`super::sparse_rows`]): X is first copied row by row, so that each nonzero of C reads its p
/// values of X in one contiguous load instead of p scattered ones (on the 10^5-node block with
/// p = 4: 2.9x faster).
fn symmetric_mul(c: &SparseColMat<usize, f64>, x: MatRef<'_, f64>, y: MatMut<'_, f64>) {
    let mut rows = vec![0.0; x.nrows() * x.ncols()];
    transpose_times_rows(c, &to_rows(x), x.ncols(), &mut rows);
    from_rows(&rows, y);
}

/// Rows per slice of [`transpose_times`]: a slice of X (p columns) stays in the core's cache while
/// the m columns of V pass over it.
const SLICE_ROWS: usize = 2048;

/// `V^T X` (m x p), summed over slices of rows (each a small matrix product, the slices shared out
/// to the threads): X is read once from memory instead of once per column of V.
fn transpose_times(v: MatRef<'_, f64>, x: MatRef<'_, f64>) -> Mat<f64> {
    use rayon::prelude::*;
    let (n, m, p) = (v.nrows(), v.ncols(), x.ncols());
    let slice = |mut acc: Mat<f64>, start: usize| {
        let rows = SLICE_ROWS.min(n - start);
        matmul(acc.as_mut(), Accum::Add, v.subrows(start, rows).transpose(), x.subrows(start, rows), 1.0, Par::Seq);
        acc
    };
    let starts = (0..n).step_by(SLICE_ROWS);
    if n < PARALLEL_NODES {
        starts.fold(Mat::zeros(m, p), slice)
    } else {
        starts.collect::<Vec<_>>().into_par_iter().fold(|| Mat::zeros(m, p), slice).reduce(|| Mat::zeros(m, p), |a, b| a + b)
    }
}

/// C-orthonormalises the columns of `block` against `basis` and within themselves:
/// block classical Gram-Schmidt against the basis applied twice (`W -= V (V^T C W)`), then the
/// Cholesky QR of the block in the C inner product applied twice (`W^T C W = R^T R`, `W <- W R^-1`;
/// "CholQR2"). With `coefficients` ((m + p) x p) it records, for block column j, the projections
/// on the basis (rows `0..m`) and the factor R (rows `m..m+p`, upper triangular), so that
/// `W_in = V H + W_out R`. A block that is (nearly) rank deficient (an invariant subspace was
/// found) goes column by column instead, with fresh random columns where one vanishes.
/// Returns whether `cw` holds `C W_out` on return (the Cholesky QR path), which saves the next
/// block step one product with C.
fn orthonormalize_block(
    mut block: MatMut<'_, f64>,
    basis: MatRef<'_, f64>,
    c: &SparseColMat<usize, f64>,
    mut cw: MatMut<'_, f64>,
    seed: &mut u64,
    mut coefficients: Option<MatMut<'_, f64>>,
) -> bool {
    let (m, p) = (basis.ncols(), block.ncols());
    symmetric_mul(c, block.rb(), cw.rb_mut());
    let original: Vec<f64> = (0..p).map(|j| dot(column(cw.rb(), j), column(block.rb(), j)).max(0.0).sqrt()).collect();
    for pass in 0..2 {
        if m == 0 {
            break;
        }
        if pass > 0 {
            symmetric_mul(c, block.rb(), cw.rb_mut());
        }
        let h = transpose_times(basis, cw.rb());
        matmul(block.rb_mut(), Accum::Add, basis, h.as_ref(), -1.0, parallelism(basis.nrows()));
        if let Some(coef) = coefficients.as_mut() {
            for j in 0..p {
                for i in 0..m {
                    coef[(i, j)] += h[(i, j)];
                }
            }
        }
    }
    let projected = block.to_owned();
    let mut r_total = Mat::<f64>::identity(p, p);
    // C W once; the second pass updates it with W (C W R^-1 = C (W R^-1))
    symmetric_mul(c, block.rb(), cw.rb_mut());
    for _pass in 0..2 {
        let g = transpose_times(block.rb(), cw.rb());
        let g = Mat::from_fn(p, p, |i, j| 0.5 * (g[(i, j)] + g[(j, i)]));
        let Ok(llt) = g.llt(faer::Side::Lower) else {
            orthonormalize_columns(block, projected.as_ref(), basis, c, &original, seed, coefficients);
            return false;
        };
        let r = llt.L().transpose().to_owned();
        if (0..p).any(|i| r[(i, i)].is_nan() || r[(i, i)] <= 1e-10 * original[i].max(f64::MIN_POSITIVE)) {
            orthonormalize_columns(block, projected.as_ref(), basis, c, &original, seed, coefficients);
            return false;
        }
        // W <- W R^-1 and C W <- (C W) R^-1: solve R^T X^T = X^T
        for mut x in [block.rb_mut(), cw.rb_mut()] {
            let mut xt = x.rb().transpose().to_owned();
            solve_lower_triangular_in_place(r.transpose(), xt.as_mut(), Par::Seq);
            x.copy_from(xt.transpose());
        }
        r_total = &r * &r_total;
    }
    if let Some(mut coef) = coefficients {
        coef.rb_mut().subrows_mut(m, p).copy_from(&r_total);
    }
    true
}

/// The column-by-column fallback of [`orthonormalize_block`] from the block already projected on
/// the basis: modified Gram-Schmidt (twice) against the earlier block columns; a column whose norm
/// drops below 1e-10 of its original norm is replaced by a random one, projected on the basis and
/// the earlier columns, with zero coefficients.
fn orthonormalize_columns(
    mut block: MatMut<'_, f64>,
    projected: MatRef<'_, f64>,
    basis: MatRef<'_, f64>,
    c: &SparseColMat<usize, f64>,
    original: &[f64],
    seed: &mut u64,
    mut coefficients: Option<MatMut<'_, f64>>,
) {
    let (n, m, p) = (basis.nrows(), basis.ncols(), block.ncols());
    block.copy_from(projected);
    let mut scratch = Mat::<f64>::zeros(n, 1);
    for i in 0..p {
        let mut fresh = false;
        for _attempt in 0..3 {
            for _pass in 0..2 {
                if fresh && m > 0 {
                    symmetric_mul(c, block.rb().subcols(i, 1), scratch.as_mut());
                    let h = transpose_times(basis, scratch.as_ref());
                    matmul(block.rb_mut().subcols_mut(i, 1), Accum::Add, basis, h.as_ref(), -1.0, Par::Seq);
                }
                symmetric_mul(c, block.rb().subcols(i, 1), scratch.as_mut());
                for j in 0..i {
                    let h = dot(column(scratch.as_ref(), 0), column(block.rb(), j));
                    let (done, rest) = block.rb_mut().split_at_col_mut(i);
                    column_mut(rest, 0).iter_mut().zip(column(done.rb(), j)).for_each(|(x, y)| *x -= h * y);
                    if !fresh {
                        if let Some(coef) = coefficients.as_mut() {
                            coef[(m + j, i)] += h;
                        }
                    }
                }
            }
            symmetric_mul(c, block.rb().subcols(i, 1), scratch.as_mut());
            let norm = dot(column(scratch.as_ref(), 0), column(block.rb(), i)).max(0.0).sqrt();
            if norm > 1e-10 * original[i].max(f64::MIN_POSITIVE) && norm > 0.0 {
                column_mut(block.rb_mut(), i).iter_mut().for_each(|x| *x /= norm);
                if !fresh {
                    if let Some(coef) = coefficients.as_mut() {
                        coef[(m + i, i)] = norm;
                    }
                }
                break;
            }
            // breakdown (invariant subspace): continue from a random direction
            column_mut(block.rb_mut(), i).iter_mut().for_each(|x| *x = random_value(seed));
            fresh = true;
        }
    }
}

fn column<'a>(a: MatRef<'a, f64>, j: usize) -> &'a [f64] {
    a.col(j).try_as_col_major().expect("contiguous columns").as_slice()
}

fn column_mut<'a>(a: MatMut<'a, f64>, j: usize) -> &'a mut [f64] {
    a.col_mut(j).try_as_col_major_mut().expect("contiguous columns").as_slice_mut()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::thermal::assembly::{assemble, to_dense, Boundary, Material, Section, ThermalProblem};
    use crate::thermal::mesh::StructuredMesh;

    #[test]
    fn lanczos_matches_the_dense_solver_on_a_plate() {
        let problem = ThermalProblem {
            mesh: StructuredMesh::new(vec![17, 11], vec![0.37, 0.23]).unwrap(),
            material: Material { conductivity_w_mk: 50.0, density_kg_m3: 7800.0, specific_heat_j_kgk: 450.0 },
            section: Section::Plate { thickness_m: 0.01 },
            lateral_convection_w_m2k: 8.0,
            boundaries: vec![[Boundary::Convection(40.0), Boundary::Insulated], [Boundary::Insulated, Boundary::Convection(15.0)]],
            fluxes: vec![(0, 1.0)],
        };
        let sys = assemble(&problem).unwrap();
        let (lambda, phi) = smallest_eigenpairs(&sys.conductivity, &sys.capacity, 12, &LanczosOptions::default()).unwrap();
        let dense = crate::thermal::modal::dense_eigenpairs(&sys).unwrap();
        for (i, l) in lambda.iter().enumerate() {
            assert!((l - dense.0[i]).abs() < 1e-9 * dense.0[i], "mode {i}: {l} vs {}", dense.0[i]);
        }
        // C-orthonormal and K phi = lambda C phi
        let c = to_dense(&sys.capacity);
        let k = to_dense(&sys.conductivity);
        let g = phi.transpose() * &c * &phi;
        let kp = &k * &phi;
        let cp = &c * &phi;
        for i in 0..12 {
            for j in 0..12 {
                assert!((g[(i, j)] - f64::from(u8::from(i == j))).abs() < 1e-9);
            }
            let r: f64 = (0..phi.nrows()).map(|r| (kp[(r, i)] - lambda[i] * cp[(r, i)]).powi(2)).sum::<f64>().sqrt();
            let s: f64 = (0..phi.nrows()).map(|r| kp[(r, i)].powi(2)).sum::<f64>().sqrt();
            assert!(r < 1e-8 * s, "residual of mode {i}: {r} vs {s}");
        }
    }
}
