//! Orthogonal reduction of a tall weighted least-squares problem (seed 000 §3.2.2).
//!
//! `min |A theta - b|` with `A` (`n x p`, `n > p`) has the same solution, singular values and right
//! singular vectors as `min |R theta - Q^T b|`, where `A = Q R` (`R` upper triangular, `p x p`).
//! One Householder QR of the augmented matrix `[A | b]` gives both `R` and `Q^T b` without ever
//! forming `Q` (`n x n`) or the left singular vectors of `A` (`n x p`): `2 n p^2` flops in faer's
//! blocked, parallel QR, which is what keeps `10^5 x 500` identifications within seconds
//! (DESIGN.md section 5).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::qr::no_pivoting::factor::{qr_in_place, qr_in_place_scratch, recommended_block_size};
use faer::{get_global_parallelism, Mat, Par};
use nalgebra::{DMatrix, DVector};

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
    // [A | b] column by column (column-major on both sides)
    let mut augmented = Mat::<f64>::zeros(n, size);
    let columns = x.as_slice().chunks_exact(n.max(1)).zip(column_divisor).map(|(column, divisor)| (column, 1.0 / divisor));
    for (j, (source, factor)) in columns.chain(std::iter::once((y, 1.0))).enumerate() {
        for ((a, v), w) in augmented.col_mut(j).iter_mut().zip(source).zip(row_factor) {
            *a = v * w * factor;
        }
    }
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
}
