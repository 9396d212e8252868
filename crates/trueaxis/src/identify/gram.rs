//! The weighted Gram matrix `M^T W M` of `M = [X | y]` (`n x (p + 1)`, `W = diag(w)`), formed
//! from the unscaled `X` without a weighted copy of it (Soons 1993 §3.2.2, the normal equations).
//!
//! Rows are taken in blocks of [`BLOCK_ROWS`]: each block is multiplied by `sqrt(w_i)` into a
//! small buffer that stays in the core's cache, and the lower triangle of its rank-k update
//! `B^T B` is added by faer's triangular matrix product (`n p^2` flops for the whole triangle, at
//! matrix-product speed). Threads take whole chunks of [`CHUNK_BLOCKS`] blocks; the chunk sums are
//! added along a binary tree fixed by the number of chunks alone, so the result is the same to the
//! last bit on any number of threads and under any scheduling.

use faer::linalg::matmul::triangular::{matmul as triangular_matmul, BlockStructure};
use faer::{Accum, Mat, MatMut, Par};
use nalgebra::DMatrix;

/// Rows per block: `BLOCK_ROWS x (p + 1)` doubles (2 MB for `p = 500`, in the L2 and L3 caches
/// while faer packs them). On 501 columns faer's triangular product of one block reaches 99, 108
/// and 107 GFLOP/s per CPU-second for 256, 512 and 1024 rows; 128 rows is slower.
pub const BLOCK_ROWS: usize = 512;

/// Blocks per unit of parallel work (4096 rows): 25 chunks for 10^5 rows, small enough for two
/// threads to finish together, large enough that the chunk sums cost nothing.
pub const CHUNK_BLOCKS: usize = 8;

/// The lower triangle (upper triangle zero) of `[X | y]^T diag(r)^2 [X | y]`, `(p + 1) x (p + 1)`,
/// `r = row_factor` (`sqrt` of the weights). Units: products of the units of the columns.
/// Threads: the global rayon pool.
pub fn weighted_gram(x: &DMatrix<f64>, y: &[f64], row_factor: &[f64]) -> Mat<f64> {
    let (n, p) = x.shape();
    assert_eq!((y.len(), row_factor.len()), (n, n), "one observation and one row factor per row of X");
    let rows = BLOCK_ROWS * CHUNK_BLOCKS;
    let mut gram = Mat::<f64>::zeros(p + 1, p + 1);
    let rows_of = |chunk: usize| chunk * rows..((chunk + 1) * rows).min(n);
    add_chunks(gram.as_mut(), 0..n.div_ceil(rows), &|chunk, g| add_rows(g, x, y, row_factor, rows_of(chunk)));
    gram
}

/// Adds the chunks `range` into `gram`: the first half here, the second half (possibly on another
/// thread) into a zero matrix added afterwards, so the order of the sums depends on `range` only.
fn add_chunks(mut gram: MatMut<'_, f64>, range: std::ops::Range<usize>, chunk: &(dyn Fn(usize, MatMut<'_, f64>) + Sync)) {
    if range.len() <= 1 {
        range.for_each(|c| chunk(c, gram.as_mut()));
        return;
    }
    let middle = range.start + range.len() / 2;
    let size = gram.nrows();
    let mut second = Mat::<f64>::zeros(size, size);
    rayon::join(|| add_chunks(gram.as_mut(), range.start..middle, chunk), || add_chunks(second.as_mut(), middle..range.end, chunk));
    for j in 0..size {
        for i in j..size {
            gram[(i, j)] += second[(i, j)];
        }
    }
}

/// Adds the lower triangle of `B^T B`, `B` the rows `rows` of `diag(r) [X | y]`, block by block.
fn add_rows(mut gram: MatMut<'_, f64>, x: &DMatrix<f64>, y: &[f64], row_factor: &[f64], rows: std::ops::Range<usize>) {
    let (n, p) = x.shape();
    let mut block = Mat::<f64>::zeros(BLOCK_ROWS.min(rows.len()), p + 1);
    for start in rows.clone().step_by(BLOCK_ROWS) {
        let m = BLOCK_ROWS.min(rows.end - start);
        let factors = &row_factor[start..start + m];
        for (j, column) in block.col_iter_mut().enumerate() {
            let source = if j < p { &x.as_slice()[j * n + start..j * n + start + m] } else { &y[start..start + m] };
            for ((b, v), r) in column.iter_mut().zip(source).zip(factors) {
                *b = v * r;
            }
        }
        let b = block.as_ref().subrows(0, m);
        triangular_matmul(
            gram.as_mut(),
            BlockStructure::TriangularLower,
            Accum::Add,
            b.transpose(),
            BlockStructure::Rectangular,
            b,
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `[X | y]^T W [X | y]` summed row by row in the obvious way (an independent formulation).
    fn by_rows(x: &DMatrix<f64>, y: &[f64], w: &[f64]) -> DMatrix<f64> {
        let (n, p) = x.shape();
        let mut g = DMatrix::zeros(p + 1, p + 1);
        for i in 0..n {
            let row: Vec<f64> = (0..=p).map(|j| if j < p { x[(i, j)] } else { y[i] }).collect();
            for a in 0..=p {
                for b in 0..=a {
                    g[(a, b)] += w[i] * row[a] * row[b];
                }
            }
        }
        g
    }

    #[test]
    fn the_blocked_gram_is_the_row_by_row_sum_on_any_number_of_threads() {
        // n not a multiple of the block or chunk size, weights and magnitudes that differ by 1e6
        let (n, p) = (2 * BLOCK_ROWS * CHUNK_BLOCKS + 3 * BLOCK_ROWS + 17, 23);
        let x = DMatrix::from_fn(n, p, |i, j| ((i * (j + 7)) as f64 * 0.0137 + j as f64).sin() * 10f64.powi(j as i32 % 7 - 3));
        let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.021).cos()).collect();
        let w: Vec<f64> = (0..n).map(|i| 0.25 + (i % 5) as f64).collect();
        let r: Vec<f64> = w.iter().map(|w| w.sqrt()).collect();
        let reference = by_rows(&x, &y, &w);
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| weighted_gram(&x, &y, &r));
        let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap().install(|| weighted_gram(&x, &y, &r));
        for a in 0..=p {
            for b in 0..=p {
                // each entry to 1e-13 of the product of its two column norms (Cauchy-Schwarz bound)
                let bound = 1e-13 * (reference[(a, a)] * reference[(b, b)]).sqrt();
                let expected = if b <= a { reference[(a, b)] } else { 0.0 };
                assert!((one[(a, b)] - expected).abs() <= bound, "({a}, {b}): {} vs {expected}", one[(a, b)]);
                assert_eq!(one[(a, b)].to_bits(), two[(a, b)].to_bits(), "({a}, {b}) differs between 1 and 2 threads");
            }
        }
    }
}
