//! Reduction of a tall weighted least-squares problem to `p x p` (Soons 1993 §3.2.2).
//!
//! `min |A theta - b|` with `A` (`n x p`, `n > p`) has the same solution, singular values and right
//! singular vectors as `min |R theta - Q^T b|` for any `R` with `R^T R = A^T A` and `R^T (Q^T b) =
//! A^T b`. Two ways to get it, never forming `Q` (`n x n`) or the left singular vectors of `A`:
//!
//! - [`reduce`]: one Householder QR of the augmented matrix `[A | b]` (faer, blocked): `2 n p^2`
//!   flops, backward stable at any condition number;
//! - [`reduce_by_gram`]: the lower triangle of `[A | b]^T [A | b]` (a symmetric rank-n update, `n p^2`
//!   flops at matrix-product speed, formed from the unscaled `X` in cache-sized blocks of rows: no
//!   scaled copy of the design matrix, [`super::gram`]), then the Cholesky factor `A^T A = R^T R`
//!   and `R^T (Q^T b) = A^T b`. It squares the condition number: the relative error of the smallest singular value is
//!   about `eps cond^2`, so it is used only when the scaled matrix is well conditioned
//!   ([`GRAM_CONDITION_LIMIT`], checked on the result by the caller; see `ScaledSvd`).
//!
//! On 10^5 x 501 (BENCHMARKS.md (targets)) the Gram reduction takes a fraction of the QR's time.

use super::gram::weighted_gram;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::qr::no_pivoting::factor::{qr_in_place, qr_in_place_scratch, recommended_block_size};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{get_global_parallelism, Mat, Par, Side};
use nalgebra::{DMatrix, DVector};

/// Largest condition number of the unit-length scaled matrix for which the Gram reduction is used:
/// `eps cond^2 = 2e-8`, the relative accuracy of the smallest singular value (and about that of
/// the solution), far below what any measurement resolves. Above it the caller reduces by QR.
pub const GRAM_CONDITION_LIMIT: f64 = 1e4;

/// Problems with at least this many entries in `[A | b]` are worth the Gram attempt (below it the
/// QR takes milliseconds and is kept for its accuracy).
pub const GRAM_MIN_ENTRIES: usize = 1 << 22;

/// The reduced problem `R theta ~ Q^T b`.
#[derive(Clone, Debug)]
pub struct ReducedProblem {
    /// `min(n, p) x p`: the triangular factor of `A` when `n >= p`, `A` itself otherwise.
    pub r: DMatrix<f64>,
    /// `Q^T b` (first `min(n, p)` components), or `b` itself when `n < p`.
    pub qtb: DVector<f64>,
}

/// Reduces `A = X` with row `i` multiplied by `row_factor[i]` and column `j` divided by
/// `column_divisor[j]`, and `b_i = row_factor[i] y_i`, to its triangular form.
pub fn reduce(x: &DMatrix<f64>, y: &[f64], row_factor: &[f64], column_divisor: &[f64]) -> ReducedProblem {
    let (n, p) = x.shape();
    let size = p + 1;
    let mut augmented = augmented(x, y, row_factor, column_divisor);
    if n < p {
        return ReducedProblem { r: DMatrix::from_fn(n, p, |i, j| augmented[(i, j)]), qtb: DVector::from_fn(n, |i, _| augmented[(i, p)]) };
    }
    let block = recommended_block_size::<f64>(n, size).max(1);
    let mut householder = Mat::<f64>::zeros(block, n.min(size));
    // threads pay off only for large matrices (below ~10^6 entries the synchronisation dominates)
    let par = if n * size < 1 << 20 { Par::Seq } else { get_global_parallelism() };
    let mut buffer = MemBuffer::new(qr_in_place_scratch::<f64>(n, size, block, par, Default::default()));
    qr_in_place(augmented.as_mut(), householder.as_mut(), par, MemStack::new(&mut buffer), Default::default());
    // the upper triangle of the first p rows holds [R | Q^T b]
    let r = DMatrix::from_fn(p, p, |i, j| if j >= i { augmented[(i, j)] } else { 0.0 });
    let qtb = DVector::from_fn(p, |i, _| augmented[(i, p)]);
    ReducedProblem { r, qtb }
}

/// `[A | b]` with `A = X` scaled as in [`reduce`], column by column (column-major on both sides).
/// Columns in parallel for large problems (the copy of 10^5 x 501 is memory-bound).
fn augmented(x: &DMatrix<f64>, y: &[f64], row_factor: &[f64], column_divisor: &[f64]) -> Mat<f64> {
    let (n, p) = x.shape();
    let mut augmented = Mat::<f64>::zeros(n, p + 1);
    let fill = |j: usize, column: faer::ColMut<'_, f64>| {
        let (source, factor) = if j < p { (&x.as_slice()[j * n..(j + 1) * n], 1.0 / column_divisor[j]) } else { (y, 1.0) };
        for ((a, v), w) in column.iter_mut().zip(source).zip(row_factor) {
            *a = v * w * factor;
        }
    };
    if n * (p + 1) < 1 << 20 {
        augmented.col_iter_mut().enumerate().for_each(|(j, c)| fill(j, c));
    } else {
        use rayon::prelude::*;
        augmented.par_col_iter_mut().enumerate().for_each(|(j, c)| fill(j, c));
    }
    augmented
}

/// As [`reduce`] with unit-length column scaling, by the Cholesky factor of the Gram matrix (module
/// documentation), formed from the unscaled `X` ([`weighted_gram`]): the column divisors are the
/// weighted column norms `s_j = sqrt((X^T W X)_jj)` (1 for a zero column), and the scaled Gram
/// matrix is `S^-1 X^T W X S^-1`. Returns `(s, R, Q^T b)`, `R` upper triangular with a positive
/// diagonal; `None` when `n < p` or the scaled Gram matrix is not numerically positive definite
/// (or not finite). The caller must check the condition number of `R` against
/// [`GRAM_CONDITION_LIMIT`] before trusting it.
pub fn reduce_by_gram(x: &DMatrix<f64>, y: &[f64], row_factor: &[f64]) -> Option<(Vec<f64>, ReducedProblem)> {
    let (n, p) = x.shape();
    if n < p {
        return None;
    }
    let gram = weighted_gram(x, y, row_factor);
    let scale: Vec<f64> = (0..p).map(|j| gram[(j, j)].sqrt()).map(|s| if s > 0.0 && s.is_finite() { s } else { 1.0 }).collect();
    // the lower triangle of S^-1 X^T W X S^-1, and S^-1 X^T W y (the last row of the Gram matrix)
    let scaled = Mat::<f64>::from_fn(p, p, |i, j| if i >= j { gram[(i, j)] / (scale[i] * scale[j]) } else { 0.0 });
    let factor = scaled.llt(Side::Lower).ok()?;
    let lower = factor.L();
    // R^T z = A^T b with R^T = L: z is Q^T b of the QR form
    let mut qtb = Mat::<f64>::from_fn(p, 1, |i, _| gram[(p, i)] / scale[i]);
    solve_lower_triangular_in_place(lower, qtb.as_mut(), Par::Seq);
    let r = DMatrix::from_fn(p, p, |i, j| if j >= i { lower[(j, i)] } else { 0.0 });
    let qtb = DVector::from_fn(p, |i, _| qtb[(i, 0)]);
    r.iter().chain(qtb.iter()).all(|v| v.is_finite()).then_some((scale, ReducedProblem { r, qtb }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reduction_keeps_the_normal_equations_and_the_solution() {
        // R^T R = A^T A and R^T Q^T b = A^T b (orthogonal invariance), on a scaled random-like matrix
        let (n, p) = (40, 5);
        let x = DMatrix::from_fn(n, p, |i, j| ((i * 7 + j * 13) as f64 * 0.37).sin() + if i == j { 2.0 } else { 0.0 });
        let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.11).cos()).collect();
        let rows: Vec<f64> = (0..n).map(|i| 1.0 + (i % 3) as f64).collect();
        let cols: Vec<f64> = (0..p).map(|j| 0.5 + j as f64).collect();
        let a = DMatrix::from_fn(n, p, |i, j| x[(i, j)] * rows[i] / cols[j]);
        let b = DVector::from_fn(n, |i, _| y[i] * rows[i]);
        let reduced = reduce(&x, &y, &rows, &cols);
        assert!((reduced.r.transpose() * &reduced.r - a.transpose() * &a).norm() < 1e-11);
        assert!((reduced.r.transpose() * &reduced.qtb - a.transpose() * &b).norm() < 1e-11);
        let direct = a.clone().svd(true, true).solve(&b, 1e-14).unwrap();
        let via_r = reduced.r.clone().solve_upper_triangular(&reduced.qtb).unwrap();
        assert!((direct - via_r).norm() < 1e-12);
    }

    #[test]
    fn the_gram_reduction_keeps_the_normal_equations_too() {
        let (n, p) = (3000, 40);
        let x = DMatrix::from_fn(n, p, |i, j| {
            (((i * (j + 5)) as f64 * 0.173 + j as f64).sin() + if i % p == j { 1.0 } else { 0.0 }) * 10f64.powi(j as i32 % 7 - 3)
        });
        let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.011).cos() + 0.1 * (i as f64 * 1.7).sin()).collect();
        let rows: Vec<f64> = (0..n).map(|i| 1.0 + (i % 4) as f64 * 0.5).collect();
        let (scale, gram) = reduce_by_gram(&x, &y, &rows).expect("positive definite");
        // the divisors are the weighted column norms, as the QR path computes them
        for (j, s) in scale.iter().enumerate() {
            let norm = (0..n).map(|i| (x[(i, j)] * rows[i]).powi(2)).sum::<f64>().sqrt();
            assert!((s - norm).abs() <= 1e-14 * norm, "column {j}: {s} vs {norm}");
        }
        let qr = reduce(&x, &y, &rows, &scale);
        let ata = qr.r.transpose() * &qr.r;
        assert!((gram.r.transpose() * &gram.r - &ata).norm() < 1e-10 * ata.norm());
        assert!((gram.r.transpose() * &gram.qtb - qr.r.transpose() * &qr.qtb).norm() < 1e-10 * qr.qtb.norm());
        let a = qr.r.clone().solve_upper_triangular(&qr.qtb).unwrap();
        let b = gram.r.clone().solve_upper_triangular(&gram.qtb).unwrap();
        assert!((&a - &b).norm() < 1e-9 * a.norm(), "{} vs {}", a.norm(), (&a - &b).norm());
        // a dependent column: not positive definite (or a useless factor the caller rejects)
        let dependent = DMatrix::from_fn(n, p, |i, j| if j == 1 { 2.0 * x[(i, 0)] } else { x[(i, j)] });
        if let Some((_, g)) = reduce_by_gram(&dependent, &y, &rows) {
            let d: Vec<f64> = (0..p).map(|i| g.r[(i, i)].abs()).collect();
            assert!(d.iter().cloned().fold(f64::INFINITY, f64::min) < 1e-6 * d.iter().cloned().fold(0.0, f64::max));
        }
    }
}
