//! Sparse Cholesky factorisation `A = P^T L L^T P` of a symmetric positive definite matrix (faer's
//! supernodal factorisation) with a chosen fill-reducing permutation P, and solves with a block of
//! right-hand sides in one pass over the factor (the solve is memory bound: p columns at once read
//! L once instead of p times).

use super::ordering::nested_dissection;
use crate::error::Error;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::SparseColMat;
use faer::{Conj, MatMut, Par, Side};

/// A numeric factor of a sparse symmetric positive definite matrix.
pub struct SparseCholesky {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
}

impl SparseCholesky {
    /// Factors `a` (only its lower triangle is read). With `coordinates` (one point per node), the
    /// ordering is nested dissection ([`nested_dissection`]); without, approximate minimum degree.
    pub fn factor(a: &SparseColMat<usize, f64>, coordinates: Option<&[[f64; 3]]>) -> Result<SparseCholesky, Error> {
        let symbolic = analyse(a, coordinates)?;
        let mut values = Vec::new();
        values.try_reserve_exact(symbolic.len_val()).map_err(|_| {
            Error::input(format!("the Cholesky factor needs {} nonzeros, more than this machine's memory", symbolic.len_val()))
        })?;
        values.resize(symbolic.len_val(), 0.0);
        let par = Par::rayon(0);
        let mut scratch = MemBuffer::try_new(symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()))
            .map_err(|_| Error::input("not enough memory for the Cholesky factorisation"))?;
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut values,
                a.as_ref(),
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            .map_err(|e| {
                Error::computation(format!(
                    "the shifted matrix K - sigma C is not positive definite ({e:?}): K must be positive semi-definite and C positive definite"
                ))
            })?;
        Ok(SparseCholesky { symbolic, values })
    }

    /// Nonzeros of the factor L.
    pub fn factor_nonzeros(&self) -> usize {
        self.values.len()
    }

    /// Overwrites the columns of `rhs` with `A^-1 rhs`. The columns are shared out to the threads
    /// (each solves its columns sequentially): on the 1e5-node block this is 25 % faster than
    /// faer's parallel solve of all columns, whose triangular solves gain little from a second
    /// thread.
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        // small factors: one thread (a solve takes microseconds, less than a hand-over)
        let threads = if self.values.len() < 1 << 18 { 1 } else { rayon::current_num_threads() };
        self.solve_columns(rhs, threads);
    }

    fn solve_columns(&self, rhs: MatMut<'_, f64>, threads: usize) {
        let k = rhs.ncols();
        if threads < 2 || k < 2 {
            let mut scratch = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(k, Par::Seq));
            let factor = LltRef::new(&self.symbolic, &self.values);
            factor.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut scratch));
            return;
        }
        let (a, b) = rhs.split_at_col_mut(k / 2);
        rayon::join(|| self.solve_columns(a, threads / 2), || self.solve_columns(b, threads - threads / 2));
    }
}

/// The ordering (nested dissection with `coordinates`, else approximate minimum degree) and the
/// symbolic factorisation of `a` (only its pattern is read).
fn analyse(a: &SparseColMat<usize, f64>, coordinates: Option<&[[f64; 3]]>) -> Result<SymbolicCholesky<usize>, Error> {
    let n = a.nrows();
    let order = coordinates.filter(|c| c.len() == n).map(|c| nested_dissection(a.symbolic(), c));
    let inverse = order.as_ref().map(|fwd| {
        let mut inv = vec![0usize; n];
        for (new, &old) in fwd.iter().enumerate() {
            inv[old] = new;
        }
        inv
    });
    let ordering = match (&order, &inverse) {
        (Some(fwd), Some(inv)) => SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, n)),
        _ => SymmetricOrdering::Amd,
    };
    factorize_symbolic_cholesky(a.symbolic(), Side::Lower, ordering, CholeskySymbolicParams::default())
        .map_err(|e| Error::computation(format!("symbolic Cholesky factorisation failed: {e:?}")))
}

/// The size of the Cholesky factor of a matrix with the pattern of `a` in the ordering
/// [`SparseCholesky::factor`] chooses: its nonzeros and the floating-point operations of the
/// numeric factorisation, `sum_j c_j^2` over the columns (c_j nonzeros below the diagonal of column
/// j: c_j^2 / 2 multiply-add pairs for the updates it makes; George & Liu 1981, sec. 2.2), without
/// factorising. For the hardware limit in BENCHMARKS.md.
pub fn factorisation_work(a: &SparseColMat<usize, f64>, coordinates: Option<&[[f64; 3]]>) -> Result<(usize, f64), Error> {
    let symbolic = analyse(a, coordinates)?;
    let flops = match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => (0..s.n_supernodes())
            .map(|i| {
                let (w, r) = (s.supernode_end()[i] - s.supernode_begin()[i], s.supernode(i).pattern().len());
                (0..w).map(|k| ((w - 1 - k + r) as f64).powi(2)).sum::<f64>()
            })
            .sum(),
        SymbolicCholeskyRaw::Simplicial(s) => {
            let cp = s.col_ptr();
            (0..s.ncols()).map(|j| ((cp[j + 1] - cp[j]) as f64 - 1.0).max(0.0).powi(2)).sum()
        }
    };
    Ok((symbolic.len_val(), flops))
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;

    #[test]
    fn the_factor_of_a_path_has_no_fill_and_n_minus_1_flops() {
        // tridiagonal [-1 2 -1]: L has one entry below the diagonal in every column but the last,
        // in any ordering that keeps the path (minimum degree starts at an end)
        let n = 500;
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 2.0));
            if i + 1 < n {
                t.push(Triplet::new(i + 1, i, -1.0));
                t.push(Triplet::new(i, i + 1, -1.0));
            }
        }
        let a = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
        let (nonzeros, flops) = factorisation_work(&a, None).unwrap();
        assert_eq!(nonzeros, 2 * n - 1);
        assert_eq!(flops, (n - 1) as f64);
        assert_eq!(SparseCholesky::factor(&a, None).unwrap().factor_nonzeros(), nonzeros);
    }
}
