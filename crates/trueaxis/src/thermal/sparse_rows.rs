//! Products of a sparse matrix with a block of vectors stored row by row (n x p, row-major): each
//! nonzero reads the p values of its row of the block in one contiguous load, and the rows of the
//! result are independent, so they are shared out to the threads. Used by the shift-invert Lanczos
//! ([`super::lanczos`]) for `C X` and by the multigrid V-cycle and LOBPCG ([`super::amg`],
//! [`super::lobpcg`]) for every sparse product.

use faer::prelude::ReborrowMut;
use faer::sparse::SparseColMat;
use faer::{MatMut, MatRef};
use rayon::prelude::*;

/// Columns of a product summed side by side in registers (two AVX2 registers).
const WIDTH: usize = 8;

/// Rows of a product below which it runs on the calling thread (a hand-over costs more).
const PARALLEL_ROWS: usize = 4_000;

/// `Y = M^T X` for a sparse M stored by columns (`m.ncols()` rows of Y, `m.nrows()` rows of X, p
/// values per row, row-major): row j of Y is `sum_q M_qj X_q` over column j of M. For a symmetric M
/// this is `M X`; for a prolongator P stored with its transpose, `P^T X` and `P X`.
pub(crate) fn transpose_times_rows(m: &SparseColMat<usize, f64>, x: &[f64], p: usize, y: &mut [f64]) {
    debug_assert_eq!(x.len(), m.nrows() * p);
    debug_assert_eq!(y.len(), m.ncols() * p);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2
        return unsafe { transpose_times_rows_avx2(m, x, p, y) };
    }
    transpose_times_rows_of(m, x, p, y)
}

/// [`transpose_times_rows_of`] compiled with AVX2 (4 values per instruction instead of 2); the
/// same operations in the same order. The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn transpose_times_rows_avx2(m: &SparseColMat<usize, f64>, x: &[f64], p: usize, y: &mut [f64]) {
    transpose_times_rows_of(m, x, p, y)
}

#[inline(always)]
fn transpose_times_rows_of(m: &SparseColMat<usize, f64>, x: &[f64], p: usize, y: &mut [f64]) {
    let (cp, ri, val) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
    /// Row j of the product, `WIDTH` columns at a time with the sums in registers (each sum still
    /// over the nonzeros in their order).
    #[inline(always)]
    fn row(cp: &[usize], ri: &[usize], val: &[f64], x: &[f64], p: usize, j: usize, out: &mut [f64]) {
        let (nonzeros, values) = (&ri[cp[j]..cp[j + 1]], &val[cp[j]..cp[j + 1]]);
        let mut k = 0;
        while k + WIDTH <= p {
            let mut acc = [0.0f64; WIDTH];
            for (&i, &v) in nonzeros.iter().zip(values) {
                let xs: &[f64; WIDTH] = x[i * p + k..][..WIDTH].try_into().expect("WIDTH values");
                for (a, x) in acc.iter_mut().zip(xs) {
                    *a += v * x;
                }
            }
            out[k..k + WIDTH].copy_from_slice(&acc);
            k += WIDTH;
        }
        for k in k..p {
            let mut acc = 0.0;
            for (&i, &v) in nonzeros.iter().zip(values) {
                acc += v * x[i * p + k];
            }
            out[k] = acc;
        }
    }
    if m.ncols() < PARALLEL_ROWS || p == 0 {
        for (j, out) in y.chunks_mut(p.max(1)).enumerate() {
            row(cp, ri, val, x, p, j, out);
        }
    } else {
        // chunks of rows, each a plain loop (compiled with the caller's instruction set)
        y.par_chunks_mut(p * 1024).enumerate().for_each(|(c, chunk)| {
            for (k, out) in chunk.chunks_mut(p).enumerate() {
                row(cp, ri, val, x, p, c * 1024 + k, out);
            }
        });
    }
}

/// The columns of `x` (n x p) row by row.
pub(crate) fn to_rows(x: MatRef<'_, f64>) -> Vec<f64> {
    let (n, p) = (x.nrows(), x.ncols());
    let mut rows = vec![0.0; n * p];
    for k in 0..p {
        for (row, v) in rows.chunks_exact_mut(p.max(1)).zip(x.col(k).iter()) {
            row[k] = *v;
        }
    }
    rows
}

/// Writes a block stored row by row (p values per row) into the columns of `y`.
pub(crate) fn from_rows(rows: &[f64], mut y: MatMut<'_, f64>) {
    let p = y.ncols();
    for k in 0..p {
        for (out, row) in y.rb_mut().col_mut(k).iter_mut().zip(rows.chunks_exact(p.max(1))) {
            *out = row[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;
    use faer::Mat;

    #[test]
    fn products_by_rows_equal_the_dense_products() {
        // a 7 x 4 matrix with an empty column, blocks of 3 vectors
        let triplets = [(0, 0, 2.0), (3, 0, -1.0), (6, 0, 0.5), (1, 2, 4.0), (2, 2, -3.0), (6, 3, 1.5), (0, 3, 7.0)]
            .map(|(i, j, v)| Triplet::new(i, j, v));
        let m = SparseColMat::<usize, f64>::try_new_from_triplets(7, 4, &triplets).unwrap();
        let dense = m.to_dense();
        let x = Mat::from_fn(7, 3, |i, k| (i as f64 + 1.0) * (k as f64 - 0.5));
        let mut y_rows = vec![f64::NAN; 4 * 3];
        transpose_times_rows(&m, &to_rows(x.as_ref()), 3, &mut y_rows);
        let mut y = Mat::zeros(4, 3);
        from_rows(&y_rows, y.as_mut());
        let want = dense.transpose() * &x;
        assert!((&y - &want).norm_max() < 1e-14, "{y:?} vs {want:?}");
    }
}
