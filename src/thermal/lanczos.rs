//! Partial spectrum of a large sparse generalised symmetric eigenproblem `K phi = lambda C phi`
//! (K symmetric positive semi-definite, C symmetric positive definite): the `count` smallest
//! eigenvalues by shift-invert block Lanczos with full reorthogonalisation in the C inner product.
//!
//! Why here: no Rust crate offers a robust sparse partial eigensolver for generalised problems
//! (faer has sparse Cholesky/LU and dense eigensolvers only), so this file builds one on faer's
//! sparse Cholesky.
//!
//! Method (Ericsson & Ruhe 1980; Grimes, Lewis & Simon 1994):
//! - shift `sigma < 0` below the spectrum, factor `K - sigma C = L L^T` once (sparse Cholesky);
//! - the operator `Op = (K - sigma C)^-1 C` is self-adjoint in `<x, y>_C = x^T C y`, with
//!   eigenvalues `nu = 1 / (lambda - sigma)`: the smallest lambda become the largest, well separated nu;
//! - a block Krylov basis `V` (block size p, so that eigenvalues of multiplicity up to p, as in
//!   symmetric structures, are found) is kept C-orthonormal by classical Gram-Schmidt applied
//!   twice against all previous vectors (full reorthogonalisation);
//! - Rayleigh-Ritz on `T = V^T C Op V` (small, dense): Ritz pairs `(theta, s)`, residual norm
//!   `|Op y - theta y|_C = |B s_last|` from the next block's coefficients, converged when
//!   `<= tolerance * theta` for all wanted pairs;
//! - `lambda = sigma + 1/theta`, `phi = V s` (C-orthonormal).
//!
//! Cost per block step: p sparse triangular solve pairs, p+p sparse products with C, and
//! O(n m p) for the reorthogonalisation against the m basis vectors.

use super::assembly::{from_triplets, sparse_mul};
use super::{computation, input, ThermalError};
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, MatMut, Side};

/// Options of [`smallest_eigenpairs`].
#[derive(Clone, Copy, Debug)]
pub struct LanczosOptions {
    /// Block size p (default 4).
    pub block: usize,
    /// Relative residual `|Op y - theta y|_C / theta` at convergence (default 1e-10).
    pub tolerance: f64,
    /// Largest Krylov basis (default `max(10 count, 200)`, at most n).
    pub max_basis: Option<usize>,
}

impl Default for LanczosOptions {
    fn default() -> Self {
        LanczosOptions { block: 4, tolerance: 1e-10, max_basis: None }
    }
}

/// The `count` smallest eigenvalues (ascending) of `K phi = lambda C phi` with C-orthonormal
/// eigenvectors (columns).
pub fn smallest_eigenpairs(
    k: &SparseColMat<usize, f64>,
    c: &SparseColMat<usize, f64>,
    count: usize,
    options: &LanczosOptions,
) -> Result<(Vec<f64>, Mat<f64>), ThermalError> {
    let n = k.nrows();
    let p = options.block.max(1);
    if count == 0 || count > n {
        return Err(input(format!("cannot compute {count} modes of a model with {n} nodes")));
    }
    let max_basis = options.max_basis.unwrap_or((10 * count).max(200)).min(n.saturating_sub(p));
    if max_basis < count + 2 * p {
        return Err(input(format!("{n} nodes are too few for the sparse solver with {count} modes: use the dense solver")));
    }
    // shift below the spectrum: a small fraction of the smallest diagonal ratio K_ii / C_ii
    let (kd, cd) = (diagonal(k), diagonal(c));
    if cd.iter().any(|v| v.is_nan() || *v <= 0.0) {
        return Err(input("the capacity matrix C has a diagonal entry that is not positive"));
    }
    let ratio = kd.iter().zip(&cd).map(|(a, b)| a / b).filter(|r| *r > 0.0).fold(f64::INFINITY, f64::min);
    let sigma = -1e-3 * if ratio.is_finite() { ratio } else { 1.0 };
    let mut triplets = Vec::with_capacity(k.val().len() + c.val().len());
    for (m, factor) in [(k, 1.0), (c, -sigma)] {
        let (cp, ri, val) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
        for j in 0..n {
            for q in cp[j]..cp[j + 1] {
                triplets.push(Triplet::new(ri[q], j, factor * val[q]));
            }
        }
    }
    let shifted = from_triplets(n, &triplets)?;
    let llt = shifted.sp_cholesky(Side::Lower).map_err(|e| {
        computation(format!("K - sigma C is not positive definite ({e:?}): K must be positive semi-definite and C positive definite"))
    })?;
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(max_basis + p);
    // T = V^T C Op V, stored by columns with the coefficients on the next block
    let mut t_cols: Vec<Vec<f64>> = Vec::new();
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut scratch = vec![0.0; n];
    // first block: pseudo-random vectors
    let mut block: Vec<Vec<f64>> = (0..p).map(|_| random_vector(n, &mut seed)).collect();
    orthonormalize_block(&mut block, &basis, c, &mut scratch, &mut seed, None);
    basis.extend(block);
    let mut current = 0usize;
    loop {
        let m = basis.len();
        // W = Op V_block
        let mut w: Vec<Vec<f64>> = Vec::with_capacity(p);
        for v in &basis[current..m] {
            let mut x = vec![0.0; n];
            sparse_mul(c, v, &mut x);
            llt.solve_in_place(MatMut::from_column_major_slice_mut(&mut x, n, 1));
            w.push(x);
        }
        let mut coefficients = vec![vec![0.0; m + p]; w.len()];
        orthonormalize_block(&mut w, &basis, c, &mut scratch, &mut seed, Some(&mut coefficients));
        t_cols.extend(coefficients);
        current = m;
        basis.extend(w);
        if m < count + p {
            continue;
        }
        let (theta, s, residual) = ritz(&t_cols, m, m + p);
        let converged = (0..count).all(|i| residual[i] <= options.tolerance * theta[i].abs());
        if converged {
            let mut shapes = Mat::zeros(n, count);
            let mut lambda = Vec::with_capacity(count);
            for i in 0..count {
                lambda.push(sigma + 1.0 / theta[i]);
                for (j, v) in basis[..m].iter().enumerate() {
                    let sj = s[(j, i)];
                    for r in 0..n {
                        shapes[(r, i)] += sj * v[r];
                    }
                }
            }
            return Ok((lambda, shapes));
        }
        if basis.len() + p > max_basis {
            return Err(computation(format!(
                "shift-invert Lanczos did not converge to {count} modes within a basis of {max_basis} vectors; ask for fewer modes or a larger basis"
            )));
        }
    }
}

/// Ritz values (descending), vectors and residual norms of the m x m leading part of T.
fn ritz(t_cols: &[Vec<f64>], m: usize, rows: usize) -> (Vec<f64>, nalgebra::DMatrix<f64>, Vec<f64>) {
    let at = |i: usize, j: usize| t_cols[j].get(i).copied().unwrap_or(0.0);
    let t = nalgebra::DMatrix::from_fn(m, m, |i, j| 0.5 * (at(i, j) + at(j, i)));
    let eig = nalgebra::SymmetricEigen::new(t);
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let theta: Vec<f64> = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    let s = nalgebra::DMatrix::from_fn(m, m, |r, c| eig.eigenvectors[(r, order[c])]);
    let residual = (0..m)
        .map(|i| {
            (m..rows)
                .map(|row| {
                    let v: f64 = (0..m).map(|j| at(row, j) * s[(j, i)]).sum();
                    v * v
                })
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    (theta, s, residual)
}

fn diagonal(a: &SparseColMat<usize, f64>) -> Vec<f64> {
    let (cp, ri, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    (0..a.ncols()).map(|j| (cp[j]..cp[j + 1]).filter(|&q| ri[q] == j).map(|q| val[q]).sum()).collect()
}

/// A pseudo-random vector (splitmix64), deterministic.
fn random_vector(n: usize, seed: &mut u64) -> Vec<f64> {
    (0..n)
        .map(|_| {
            *seed = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = *seed;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

fn c_dot(cx: &[f64], y: &[f64]) -> f64 {
    cx.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// C-orthonormalises `block` against `basis` (twice) and within itself. With `coefficients`,
/// records for block vector i the projections on `basis` (rows `0..m`) and its own Gram-Schmidt
/// factors on the new block (rows `m..m+p`). A vector that vanishes (invariant subspace) is replaced
/// by a fresh random one with zero coefficients.
fn orthonormalize_block(
    block: &mut [Vec<f64>],
    basis: &[Vec<f64>],
    c: &SparseColMat<usize, f64>,
    cw: &mut [f64],
    seed: &mut u64,
    mut coefficients: Option<&mut Vec<Vec<f64>>>,
) {
    let m = basis.len();
    let n = cw.len();
    for i in 0..block.len() {
        let original_norm = {
            sparse_mul(c, &block[i], cw);
            c_dot(cw, &block[i]).max(0.0).sqrt()
        };
        let mut fresh = false;
        let (done, rest) = block.split_at_mut(i);
        let target = &mut rest[0];
        for _attempt in 0..3 {
            for _pass in 0..2 {
                sparse_mul(c, target, cw);
                for (j, v) in basis.iter().enumerate().chain(done.iter().enumerate().map(|(j, v)| (m + j, v))) {
                    let h = c_dot(cw, v);
                    for (x, y) in target.iter_mut().zip(v) {
                        *x -= h * y;
                    }
                    if !fresh {
                        if let Some(coef) = coefficients.as_deref_mut() {
                            coef[i][j] += h;
                        }
                    }
                }
            }
            sparse_mul(c, target, cw);
            let norm = c_dot(cw, target).max(0.0).sqrt();
            if norm > 1e-10 * original_norm.max(f64::MIN_POSITIVE) && norm > 0.0 {
                target.iter_mut().for_each(|x| *x /= norm);
                if !fresh {
                    if let Some(coef) = coefficients.as_deref_mut() {
                        coef[i][m + i] = norm;
                    }
                }
                break;
            }
            // breakdown (invariant subspace): continue from a random direction
            *target = random_vector(n, seed);
            fresh = true;
        }
    }
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
