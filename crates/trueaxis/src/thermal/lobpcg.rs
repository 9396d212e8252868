//! The smallest eigenpairs of a large sparse generalised symmetric eigenproblem `K phi = lambda C
//! phi` (K symmetric positive definite, C symmetric positive definite) by the locally optimal block
//! preconditioned conjugate gradient method (LOBPCG; Knyazev, "Toward the optimal preconditioned
//! eigensolver", SIAM J. Sci. Comput. 23, 2001), preconditioned by a smoothed-aggregation multigrid
//! V-cycle of K ([`super::amg`]).
//!
//! Why: the shift-invert Lanczos of [`super::lanczos`] factors `K - sigma C`, whose fill on a 3D
//! mesh grows as `n^(4/3)` and whose work as `n^2` (10^6 nodes: 1.3e9 nonzeros, 10.6 GB, 6.7e12
//! flops). LOBPCG needs only products with K and C and the V-cycle, all proportional to the
//! nonzeros of K, and a number of iterations that a multigrid preconditioner keeps independent of
//! the mesh size (26-27 for 20 modes of the benchmark block at 10^5 and 10^6 nodes).
//!
//! Iteration (as SciPy's `lobpcg`, with soft locking): a block X of `m = count + guard`
//! C-orthonormal vectors with Ritz values Lambda; residuals `R = K X - C X Lambda` of the columns
//! not yet converged; preconditioned `W = M R`, C-orthogonalised against X and C-orthonormalised
//! (Cholesky QR); the previous search directions P (C-orthonormalised); Rayleigh-Ritz on
//! `[X W P]` (Gram matrices in K and C, a dense generalised eigenproblem by Cholesky of the C
//! Gram matrix, without P if that is singular); X and P updated from the Ritz vectors. Products
//! `K X` and `C X` are carried along with X, W and P instead of recomputed. A column has converged
//! when `|K x - lambda C x| <= tolerance * lambda |C x|` (Euclidean norms).
//!
//! Blocks are stored row by row ([`super::sparse_rows`]); the dense products with them are faer's.

use super::amg::SmoothedAggregation;
use super::lanczos::{random_value, LanczosProgress};
use super::sparse_rows::transpose_times_rows;
use crate::error::Error;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
use faer::prelude::ReborrowMut;
use faer::sparse::SparseColMat;
use faer::{Accum, Mat, MatMut, MatRef, Par, Side};
use rayon::prelude::*;

/// Options of [`smallest_eigenpairs_lobpcg`].
#[derive(Clone, Copy, Debug)]
pub struct LobpcgOptions {
    /// Relative residual `|K x - lambda C x| / (lambda |C x|)` at convergence (default 1e-7: the
    /// eigenvalues are then exact to about the square of it, the time constants of the benchmark
    /// block to 1e-10 and better; 1e-8 costs three more iterations there, 1e-6 saves three).
    pub tolerance: f64,
    /// Most iterations (default 500).
    pub max_iterations: usize,
}

impl Default for LobpcgOptions {
    fn default() -> Self {
        LobpcgOptions { tolerance: 1e-7, max_iterations: 500 }
    }
}

/// A block of p vectors of length n, stored row by row; resized in place, so that its allocation
/// is reused from one iteration to the next.
#[derive(Clone, Default)]
struct Block {
    data: Vec<f64>,
    p: usize,
}

impl Block {
    fn zeros(n: usize, p: usize) -> Block {
        Block { data: vec![0.0; n * p], p }
    }

    fn rows(&self) -> usize {
        self.data.len().checked_div(self.p).unwrap_or(0)
    }

    fn resize(&mut self, n: usize, p: usize) {
        self.data.resize(n * p, 0.0);
        self.p = p;
    }

    fn view(&self) -> MatRef<'_, f64> {
        MatRef::from_row_major_slice(&self.data, self.rows(), self.p)
    }

    /// The columns `columns` of `from`.
    fn select_from(&mut self, from: &Block, columns: &[usize]) {
        let q = columns.len();
        self.resize(from.rows(), q);
        if q == 0 {
            return;
        }
        self.data.par_chunks_mut(q).zip(from.data.par_chunks(from.p)).with_min_len(1024).for_each(|(row, from)| {
            for (o, &c) in row.iter_mut().zip(columns) {
                *o = from[c];
            }
        });
    }

    /// `self += alpha other` (the same shape).
    fn add(&mut self, alpha: f64, other: &Block) {
        self.data.par_iter_mut().zip(&other.data).with_min_len(8192).for_each(|(a, b)| *a += alpha * b);
    }

    /// `M^T x` for a sparse M stored by columns (`M x` for a symmetric M).
    fn product(&mut self, m: &SparseColMat<usize, f64>, x: &Block) {
        self.resize(m.ncols(), x.p);
        transpose_times_rows(m, &x.data, x.p, &mut self.data);
    }

    /// Right-multiplies by `L^-T` (L lower triangular, p x p), row chunks in parallel.
    fn solve_lower_transposed(&mut self, l: MatRef<'_, f64>) {
        let p = self.p;
        if p == 0 {
            return;
        }
        self.data.par_chunks_mut(p * CHUNK_ROWS).for_each(|chunk| {
            // the row-major rows x p storage is the column-major p x rows storage of the transpose
            let rows = chunk.len() / p;
            solve_lower_triangular_in_place(l, MatMut::from_column_major_slice_mut(chunk, p, rows), Par::Seq);
        });
    }

    /// Scales column j by `scale[j]`.
    fn scale_columns(&mut self, scale: &[f64]) {
        let p = self.p;
        self.data.par_chunks_mut(p.max(1)).with_min_len(1024).for_each(|row| row.iter_mut().zip(scale).for_each(|(v, s)| *v *= s));
    }
}

/// A block V with its products `K V` and `C V`, carried along instead of recomputed.
#[derive(Clone, Default)]
struct Triple {
    v: Block,
    kv: Block,
    cv: Block,
}

impl Triple {
    fn parts_mut(&mut self) -> [&mut Block; 3] {
        [&mut self.v, &mut self.kv, &mut self.cv]
    }

    fn select_from(&mut self, from: &Triple, columns: &[usize]) {
        self.v.select_from(&from.v, columns);
        self.kv.select_from(&from.kv, columns);
        self.cv.select_from(&from.cv, columns);
    }
}

/// Rows per chunk of the dense block products: a chunk of a 24-column block (1.5 MB) stays in the
/// core's cache while the product runs over it; chunks are shared out to the threads.
const CHUNK_ROWS: usize = 8192;

/// `A^T B`: the products of the row chunks in parallel, summed in chunk order (the same bits on
/// any number of threads).
fn gram(a: &Block, b: &Block) -> Mat<f64> {
    let (n, pa, pb) = (a.rows(), a.p, b.p);
    let chunks = n.div_ceil(CHUNK_ROWS).max(1);
    let partial: Vec<Mat<f64>> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let (start, end) = (c * CHUNK_ROWS, ((c + 1) * CHUNK_ROWS).min(n));
            let mut g = Mat::zeros(pa, pb);
            matmul(
                g.as_mut(),
                Accum::Replace,
                a.view().subrows(start, end - start).transpose(),
                b.view().subrows(start, end - start),
                1.0,
                Par::Seq,
            );
            g
        })
        .collect();
    let mut g = Mat::zeros(pa, pb);
    for part in &partial {
        g += part;
    }
    g
}

/// `out = sum_t block_t Y_t` (every block n rows, `Y_t` p_t x q), row chunks in parallel.
fn combine(out: &mut Block, terms: &[(&Block, MatRef<'_, f64>)], q: usize) {
    let n = terms.first().map_or(0, |(b, _)| b.rows());
    out.resize(n, q);
    if q == 0 {
        return;
    }
    out.data.par_chunks_mut(q * CHUNK_ROWS).enumerate().for_each(|(c, chunk)| {
        let rows = chunk.len() / q;
        let mut dst = MatMut::from_row_major_slice_mut(chunk, rows, q);
        let mut first = true;
        for (block, y) in terms.iter().filter(|(b, _)| b.p > 0) {
            let accum = if first { Accum::Replace } else { Accum::Add };
            matmul(dst.rb_mut(), accum, block.view().subrows(c * CHUNK_ROWS, rows), *y, 1.0, Par::Seq);
            first = false;
        }
        if first {
            dst.fill(0.0);
        }
    });
}

fn symmetric(g: &Mat<f64>) -> Mat<f64> {
    Mat::from_fn(g.nrows(), g.ncols(), |i, j| 0.5 * (g[(i, j)] + g[(j, i)]))
}

/// C-orthonormalises the block of `t` (and its products with K and C) by Cholesky QR: the columns
/// scaled to unit C-norm first (converged columns are small), then the factor L of `V^T C V` and
/// `V L^-T`. `None` when the block is numerically rank deficient.
fn c_orthonormalise(t: &mut Triple) -> Option<()> {
    let g = symmetric(&gram(&t.v, &t.cv));
    let p = g.nrows();
    let scale: Vec<f64> = (0..p).map(|i| 1.0 / g[(i, i)].sqrt()).collect();
    if scale.iter().any(|s| !s.is_finite()) {
        return None;
    }
    let g = Mat::from_fn(p, p, |i, j| g[(i, j)] * scale[i] * scale[j]);
    let llt = g.llt(Side::Lower).ok()?;
    let l = llt.L();
    if (0..p).any(|i| (l[(i, i)] * l[(i, i)]).is_nan() || l[(i, i)] * l[(i, i)] <= 1e-12) {
        return None;
    }
    for block in t.parts_mut() {
        block.scale_columns(&scale);
        block.solve_lower_transposed(l);
    }
    Some(())
}

/// The Ritz pairs of the Gram matrices `(ga, gb)` (both symmetric, gb positive definite): the
/// eigenvalues ascending and the eigenvectors `Y` (gb-orthonormal columns); `None` when gb is not
/// numerically positive definite.
fn rayleigh_ritz(ga: &Mat<f64>, gb: &Mat<f64>) -> Option<(Vec<f64>, Mat<f64>)> {
    let t = ga.nrows();
    let llt = symmetric(gb).llt(Side::Lower).ok()?;
    let l = llt.L();
    let largest = (0..t).map(|i| gb[(i, i)]).fold(0.0f64, f64::max);
    if (0..t).any(|i| (l[(i, i)] * l[(i, i)]).is_nan() || l[(i, i)] * l[(i, i)] <= 1e-12 * largest) {
        return None;
    }
    // A~ = L^-1 ga L^-T
    let mut z = symmetric(ga);
    solve_lower_triangular_in_place(l, z.as_mut(), Par::Seq);
    let mut a = z.transpose().to_owned();
    solve_lower_triangular_in_place(l, a.as_mut(), Par::Seq);
    let evd = symmetric(&a).self_adjoint_eigen(Side::Lower).ok()?;
    let mut order: Vec<usize> = (0..t).collect();
    let s = evd.S().column_vector();
    order.sort_by(|&i, &j| s[i].total_cmp(&s[j]));
    let theta = order.iter().map(|&i| s[i]).collect();
    let mut y = Mat::from_fn(t, t, |r, c| evd.U()[(r, order[c])]);
    solve_upper_triangular_in_place(l.transpose(), y.as_mut(), Par::Seq);
    Some((theta, y))
}

/// The `count` smallest eigenvalues (ascending) of `K phi = lambda C phi` and C-orthonormal
/// eigenvectors (columns), by LOBPCG with a multigrid preconditioner (see the module
/// documentation); `progress` hears of the multigrid setup and of each iteration.
pub fn smallest_eigenpairs_lobpcg(
    k: &SparseColMat<usize, f64>,
    c: &SparseColMat<usize, f64>,
    count: usize,
    options: &LobpcgOptions,
    progress: &mut dyn FnMut(LanczosProgress),
) -> Result<(Vec<f64>, Mat<f64>), Error> {
    let n = k.nrows();
    let m = (count + (count / 5).max(4)).min(n / 3);
    if count == 0 || count > m {
        return Err(Error::input(format!("cannot compute {count} modes of a model with {n} nodes by LOBPCG: use the dense solver")));
    }
    progress(LanczosProgress::Preconditioning { nodes: n });
    let amg = SmoothedAggregation::new(k)?;
    let mut amg_ws = amg.workspace(m);
    progress(LanczosProgress::Preconditioned { levels: amg.level_sizes().len() });
    // start: pseudo-random vectors, C-orthonormalised, and a Rayleigh-Ritz step on them
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut start = Triple { v: Block { data: (0..n * m).map(|_| random_value(&mut seed)).collect(), p: m }, ..Default::default() };
    start.cv.product(c, &start.v);
    c_orthonormalise(&mut start).ok_or_else(|| Error::computation("LOBPCG: the starting block is rank deficient"))?;
    start.kv.product(k, &start.v);
    let (theta, y) = rayleigh_ritz(&gram(&start.v, &start.kv), &gram(&start.v, &start.cv))
        .ok_or_else(|| Error::computation("LOBPCG: the capacity matrix C is not positive definite"))?;
    let mut lambda = theta;
    let mut x = Triple::default();
    for (to, from) in x.parts_mut().into_iter().zip([&start.v, &start.kv, &start.cv]) {
        combine(to, &[(from, y.as_ref())], m);
    }
    // the search directions P of every column and their next values; the residuals; the blocks of
    // the active columns; the next X
    let (mut directions, mut next_directions, mut next) = (Triple::default(), Triple::default(), start);
    let mut has_directions = false;
    let (mut r, mut r_active) = (Block::zeros(n, m), Block::default());
    let (mut w, mut p_active) = (Triple::default(), Triple::default());
    for iteration in 0..options.max_iterations {
        // residuals R = K X - C X Lambda and convergence
        r.data.par_chunks_mut(m).zip(x.kv.data.par_chunks(m).zip(x.cv.data.par_chunks(m))).with_min_len(1024).for_each(|(r, (kx, cx))| {
            for (((r, kx), cx), l) in r.iter_mut().zip(kx).zip(cx).zip(&lambda) {
                *r = kx - l * cx;
            }
        });
        let norms = column_norms(&[&r, &x.cv]);
        let relative: Vec<f64> = (0..m).map(|i| norms[0][i] / (lambda[i].abs() * norms[1][i]).max(f64::MIN_POSITIVE)).collect();
        // a NaN residual stays active (and fails the Cholesky QR below with its reason)
        let active: Vec<usize> = (0..m).filter(|&i| relative[i].is_nan() || relative[i] > options.tolerance).collect();
        let converged = (0..count).take_while(|&i| relative[i] <= options.tolerance).count();
        progress(LanczosProgress::Refining { converged, wanted: count, iteration: iteration + 1, max_iterations: options.max_iterations });
        if converged == count {
            let mut shapes = Mat::zeros(n, count);
            shapes.as_mut().copy_from(x.v.view().subcols(0, count));
            return Ok((lambda[..count].to_vec(), shapes));
        }
        // preconditioned residuals W = M R, C-orthogonal to X and C-orthonormal
        let a = active.len();
        r_active.select_from(&r, &active);
        w.v.resize(n, a);
        amg.apply(&mut amg_ws, &r_active.data, a, &mut w.v.data);
        let h = gram(&x.cv, &w.v);
        combine(&mut w.kv, &[(&x.v, h.as_ref())], a); // X (C X)^T W, in a spare block
        w.v.add(-1.0, &w.kv);
        w.cv.product(c, &w.v);
        c_orthonormalise(&mut w).ok_or_else(|| Error::computation("LOBPCG: the preconditioned residuals are rank deficient"))?;
        w.kv.product(k, &w.v);
        // the previous directions of the active columns, C-orthonormalised (dropped if dependent)
        let mut with_p = has_directions && {
            p_active.select_from(&directions, &active);
            c_orthonormalise(&mut p_active).is_some()
        };
        // Rayleigh-Ritz on [X W P]
        let (theta, y) = loop {
            let blocks: Vec<&Triple> = if with_p { vec![&x, &w, &p_active] } else { vec![&x, &w] };
            let (ga, gb) = gram_matrices(&blocks);
            match rayleigh_ritz(&ga, &gb) {
                Some(pair) => break pair,
                None if with_p => with_p = false,
                None => return Err(Error::computation("LOBPCG: the Rayleigh-Ritz basis is rank deficient")),
            }
        };
        lambda = theta[..m].to_vec();
        let y = y.subcols(0, m);
        let (yx, yw) = (y.subrows(0, m), y.subrows(m, a));
        // P_next = W Y_w + P Y_p; X_next = X Y_x + P_next
        for ((to, w), p) in next_directions.parts_mut().into_iter().zip([&w.v, &w.kv, &w.cv]).zip([&p_active.v, &p_active.kv, &p_active.cv])
        {
            match with_p {
                true => combine(to, &[(w, yw), (p, y.subrows(m + a, a))], m),
                false => combine(to, &[(w, yw)], m),
            }
        }
        for ((to, x), p) in
            next.parts_mut().into_iter().zip([&x.v, &x.kv, &x.cv]).zip([&next_directions.v, &next_directions.kv, &next_directions.cv])
        {
            combine(to, &[(x, yx)], m);
            to.add(1.0, p);
        }
        std::mem::swap(&mut x, &mut next);
        std::mem::swap(&mut directions, &mut next_directions);
        has_directions = true;
    }
    Err(Error::computation(format!(
        "LOBPCG did not converge to {count} modes in {} iterations; use the shift-invert Lanczos method",
        options.max_iterations
    )))
}

/// The Gram matrices `S^T K S` and `S^T C S` of `S = [V_1 V_2 ...]`.
fn gram_matrices(blocks: &[&Triple]) -> (Mat<f64>, Mat<f64>) {
    let t: usize = blocks.iter().map(|b| b.v.p).sum();
    let (mut ga, mut gb) = (Mat::zeros(t, t), Mat::zeros(t, t));
    let mut row = 0;
    for (i, bi) in blocks.iter().enumerate() {
        let mut col = 0;
        for bj in &blocks[..=i] {
            let (a, b) = (gram(&bi.v, &bj.kv), gram(&bi.v, &bj.cv));
            for r in 0..bi.v.p {
                for s in 0..bj.v.p {
                    ga[(row + r, col + s)] = a[(r, s)];
                    ga[(col + s, row + r)] = a[(r, s)];
                    gb[(row + r, col + s)] = b[(r, s)];
                    gb[(col + s, row + r)] = b[(r, s)];
                }
            }
            col += bj.v.p;
        }
        row += bi.v.p;
    }
    (ga, gb)
}

/// The Euclidean norm of every column of each block (all with the same columns).
fn column_norms(blocks: &[&Block]) -> Vec<Vec<f64>> {
    blocks
        .iter()
        .map(|b| {
            let mut sums = vec![0.0; b.p];
            for row in b.data.chunks_exact(b.p.max(1)) {
                for (s, v) in sums.iter_mut().zip(row) {
                    *s += v * v;
                }
            }
            sums.into_iter().map(f64::sqrt).collect()
        })
        .collect()
}
