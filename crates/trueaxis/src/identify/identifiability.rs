//! Identifiability of a linear problem `y = X theta + noise` with weights `W`: singular values and
//! condition number of the scaled design matrix, rank, the parameter combinations the data cannot
//! see (the null space, named in ISO terms), correlations, and a per-parameter sensitivity index.
//!
//! Scaling (stated because a condition number means nothing without it): the rows are multiplied by
//! `sqrt(w_i)` and every column is then divided by its norm ("unit-length scaling", Soons 1993
//! §3.2.2), so the singular values are dimensionless and independent of the parameter units.
//! Soons 1993 §4.3: `lambda^T theta` is estimable iff `lambda` lies in the row space of `X`.

use super::least_squares::{column_norms, weighted_column_norm};
use super::reduction::{reduce, reduce_by_gram, ReducedProblem, GRAM_CONDITION_LIMIT, GRAM_MIN_ENTRIES};
use faer::Mat;
use nalgebra::{DMatrix, DVector};

/// Default relative threshold: singular values below `RANK_TOLERANCE * largest` are zero.
pub const RANK_TOLERANCE: f64 = 1e-8;

/// How the scaled problem was reduced to `p x p` ([`super::reduction`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reduction {
    /// Householder QR of `[A | b]`.
    Qr,
    /// Cholesky factor of the Gram matrix, kept only for a condition number of at most
    /// [`GRAM_CONDITION_LIMIT`].
    Gram,
}

/// The SVD of the weighted, unit-length scaled design matrix `A = W^(1/2) X S^-1`, computed from its
/// reduction to `R` with `R^T R = A^T A` (see [`super::reduction`]): `R = U_r Sigma V^T`, so `A`
/// and `R` share the singular values and right singular vectors, and the left singular vectors of
/// `A` are never formed (they would be `n x p`). Large problems (at least [`GRAM_MIN_ENTRIES`]
/// entries) are reduced through the Gram matrix when the result shows a condition number of at most
/// [`GRAM_CONDITION_LIMIT`], otherwise (and always for smaller ones) by QR.
#[derive(Clone, Debug)]
pub struct ScaledSvd {
    /// Column norms `s_j` of `W^(1/2) X` (the scaling `S`).
    pub scale: Vec<f64>,
    /// Singular values, descending (`min(n, p)` of them).
    pub singular_values: Vec<f64>,
    /// Right singular vectors (`p x p`): the columns of `singular_values` in their order, then an
    /// orthonormal basis of the remaining (null) directions of a wide matrix.
    pub v: DMatrix<f64>,
    /// Number of singular values above the tolerance.
    pub rank: usize,
    pub tolerance: f64,
    pub reduction: Reduction,
    /// The reduced problem `R theta ~ Q^T b` (scaled units).
    reduced: ReducedProblem,
    /// `U_r^T Q^T b`: the observations in the left singular basis.
    observations_in_singular_basis: DVector<f64>,
}

impl ScaledSvd {
    /// Scales and decomposes (no observations: the solutions are zero). A column that is zero
    /// everywhere keeps scale 1 (and gives a zero singular value).
    pub fn new(matrix: &DMatrix<f64>, weights: &[f64], tolerance: f64) -> ScaledSvd {
        Self::with_observations(matrix, weights, &vec![0.0; matrix.nrows()], tolerance)
    }

    /// Scales and decomposes `W^(1/2) X S^-1` together with the weighted observations
    /// `W^(1/2) y` (um), so that [`ScaledSvd::solve_minimum_norm`] and
    /// [`ScaledSvd::solve_triangular`] give the least-squares solution.
    pub fn with_observations(matrix: &DMatrix<f64>, weights: &[f64], observations: &[f64], tolerance: f64) -> ScaledSvd {
        Self::decompose(matrix, weights, observations, tolerance, GRAM_MIN_ENTRIES)
    }

    /// [`ScaledSvd::with_observations`] with the size from which the Gram reduction is tried.
    fn decompose(matrix: &DMatrix<f64>, weights: &[f64], observations: &[f64], tolerance: f64, gram_min_entries: usize) -> ScaledSvd {
        let (n, p) = matrix.shape();
        let sqrt_w: Vec<f64> = weights.iter().map(|w| w.sqrt()).collect();
        if n * (p + 1) >= gram_min_entries {
            // the column norms come with the Gram matrix (its diagonal): no pass of their own
            if let Some((scale, reduced)) = reduce_by_gram(matrix, observations, &sqrt_w) {
                let svd = Self::of_reduced(scale, reduced, tolerance, Reduction::Gram);
                let largest = svd.singular_values.first().copied().unwrap_or(0.0);
                let smallest = svd.singular_values.last().copied().unwrap_or(0.0);
                if smallest > 0.0 && largest <= GRAM_CONDITION_LIMIT * smallest {
                    return svd;
                }
            }
        }
        let scale: Vec<f64> = (0..p)
            .map(|j| weighted_column_norm(matrix.column(j).as_slice(), &sqrt_w))
            .map(|s| if s > 0.0 && s.is_finite() { s } else { 1.0 })
            .collect();
        let reduced = reduce(matrix, observations, &sqrt_w, &scale);
        Self::of_reduced(scale, reduced, tolerance, Reduction::Qr)
    }

    /// The SVD of the reduced problem.
    fn of_reduced(scale: Vec<f64>, reduced: ReducedProblem, tolerance: f64, reduction: Reduction) -> ScaledSvd {
        let p = reduced.r.ncols();
        let m = reduced.r.nrows();
        let svd = Mat::from_fn(m, p, |i, j| reduced.r[(i, j)]).svd();
        let (singular_values, v, observations_in_singular_basis) = match svd {
            Ok(svd) => {
                let sigma = svd.S().column_vector();
                let (u, v) = (svd.U(), svd.V());
                let k = m.min(p);
                (
                    (0..k).map(|i| sigma[i]).collect::<Vec<f64>>(),
                    DMatrix::from_fn(p, p, |r, c| v[(r, c)]),
                    DVector::from_fn(k, |i, _| (0..m).map(|r| u[(r, i)] * reduced.qtb[r]).sum()),
                )
            }
            // no convergence (only for non-finite input): every direction is reported unseen
            Err(_) => (vec![0.0; m.min(p)], DMatrix::identity(p, p), DVector::zeros(m.min(p))),
        };
        let largest = singular_values.first().copied().unwrap_or(0.0);
        let rank = singular_values.iter().filter(|s| **s > tolerance * largest && **s > 0.0).count();
        ScaledSvd { scale, singular_values, v, rank, tolerance, reduction, reduced, observations_in_singular_basis }
    }

    /// Singular values padded with zeros to the number of parameters.
    pub fn all_singular_values(&self) -> Vec<f64> {
        let p = self.scale.len();
        let mut s = self.singular_values.clone();
        s.resize(p, 0.0);
        s
    }

    /// Right singular vectors of the null space (scaled units), `p x (p - rank)`.
    pub fn null_space(&self) -> DMatrix<f64> {
        let p = self.scale.len();
        self.v.columns(self.rank, p - self.rank).into_owned()
    }

    /// `(X^T W X)^+` in the units of the parameters, from the retained singular values.
    pub fn pseudo_inverse_normal(&self) -> DMatrix<f64> {
        // V_r S_r^-2 V_r^T as W W^T with W = V_r S_r^-1 (one matrix product)
        let mut w = self.v.columns(0, self.rank).into_owned();
        for (k, mut column) in w.column_iter_mut().enumerate() {
            column /= self.singular_values[k];
        }
        self.unscale_covariance(&w * w.transpose())
    }

    /// Minimum-norm (in scaled units) least-squares solution of `W^(1/2) X theta = W^(1/2) y`
    /// (Andolfatto et al. 2011 eq. 5, the pseudo-inverse), from the retained singular values.
    pub fn solve_minimum_norm(&self) -> Vec<f64> {
        let mut beta = DVector::zeros(self.scale.len());
        for k in 0..self.rank {
            beta += self.v.column(k) * (self.observations_in_singular_basis[k] / self.singular_values[k]);
        }
        beta.iter().zip(&self.scale).map(|(b, s)| b / s).collect()
    }

    /// The least-squares solution by back substitution `R theta = Q^T b` (QR, Soons 1993 §3.2.2) and
    /// its unscaled covariance `(X^T W X)^-1 = S^-1 R^-1 R^-T S^-1`; `None` unless of full rank.
    pub fn solve_triangular(&self) -> Option<(Vec<f64>, DMatrix<f64>)> {
        let p = self.scale.len();
        if self.rank < p || self.reduced.r.nrows() < p {
            return None;
        }
        let beta = self.reduced.r.solve_upper_triangular(&self.reduced.qtb)?;
        let r_inv = self.reduced.r.solve_upper_triangular(&DMatrix::identity(p, p))?;
        let solution = beta.iter().zip(&self.scale).map(|(b, s)| b / s).collect();
        Some((solution, self.unscale_covariance(&r_inv * r_inv.transpose())))
    }

    /// A covariance in scaled units converted to parameter units: `S^-1 C S^-1`.
    fn unscale_covariance(&self, mut c: DMatrix<f64>) -> DMatrix<f64> {
        let p = self.scale.len();
        for i in 0..p {
            for j in 0..p {
                c[(i, j)] /= self.scale[i] * self.scale[j];
            }
        }
        c
    }
}

/// A combination of parameters the measurements do not see: changing the parameters by
/// `coefficients` (user units) leaves every reading unchanged to first order.
#[derive(Clone, Debug, PartialEq)]
pub struct Combination {
    pub parameters: Vec<String>,
    pub coefficients: Vec<f64>,
    pub units: Vec<String>,
    /// e.g. "EZ0C and WZ cannot be separated: changing EZ0C by +1 um and WZ by -1 um leaves every
    /// reading unchanged".
    pub message: String,
}

/// The identifiability report of one design.
#[derive(Clone, Debug)]
pub struct IdentifiabilityReport {
    /// Singular values of the scaled design matrix (dimensionless), descending.
    pub singular_values: Vec<f64>,
    /// Largest over smallest singular value, `None` when the smallest is exactly zero.
    pub condition_number: Option<f64>,
    pub rank: usize,
    /// The null space as named combinations (empty when every parameter is identifiable).
    pub unidentifiable: Vec<Combination>,
    /// Parameter correlation matrix from `(X^T W X)^+`.
    pub correlation: DMatrix<f64>,
    /// RMS change of the readings per unit of each parameter (um per user unit), unweighted.
    pub sensitivity: Vec<f64>,
    /// Independence index in [0, 1]: `1 / sqrt(VIF)`, the fraction of a parameter's effect that no
    /// combination of the others reproduces (1: orthogonal to all others; 0: inseparable).
    pub independence: Vec<f64>,
    /// Whether each parameter is estimable on its own (outside every null combination).
    pub identifiable: Vec<bool>,
}

impl IdentifiabilityReport {
    /// Builds the report of design `matrix` (unweighted, `n x p`) from its scaled SVD.
    pub fn new(matrix: &DMatrix<f64>, svd: &ScaledSvd, names: &[String], units: &[String]) -> IdentifiabilityReport {
        let (n, p) = matrix.shape();
        let singular_values = svd.all_singular_values();
        let smallest = singular_values.last().copied().unwrap_or(0.0);
        let condition_number = (smallest > 0.0).then(|| singular_values[0] / smallest).filter(|c| c.is_finite());
        let null = svd.null_space();
        let identifiable: Vec<bool> = (0..p).map(|j| (0..null.ncols()).all(|k| null[(j, k)].abs() < 1e-6)).collect();
        let unidentifiable = name_null_space(&null, &svd.scale, names, units);
        let normal_inverse = svd.pseudo_inverse_normal();
        let correlation = DMatrix::from_fn(p, p, |i, j| {
            let d = (normal_inverse[(i, i)] * normal_inverse[(j, j)]).sqrt();
            if d > 0.0 {
                normal_inverse[(i, j)] / d
            } else {
                f64::from(u8::from(i == j))
            }
        });
        let sensitivity = column_norms(matrix).iter().map(|s| s / (n.max(1) as f64).sqrt()).collect();
        let independence = (0..p)
            .map(|j| {
                let scaled = normal_inverse[(j, j)] * svd.scale[j] * svd.scale[j];
                if identifiable[j] && scaled > 0.0 {
                    (1.0 / scaled.sqrt()).min(1.0)
                } else {
                    0.0
                }
            })
            .collect();
        IdentifiabilityReport {
            singular_values,
            condition_number,
            rank: svd.rank,
            unidentifiable,
            correlation,
            sensitivity,
            independence,
            identifiable,
        }
    }

    /// Pairs of parameters with `|correlation| >= threshold`, strongest first.
    pub fn strong_correlations(&self, threshold: f64) -> Vec<(usize, usize, f64)> {
        let p = self.correlation.nrows();
        let mut pairs: Vec<(usize, usize, f64)> = (0..p)
            .flat_map(|i| (i + 1..p).map(move |j| (i, j)))
            .map(|(i, j)| (i, j, self.correlation[(i, j)]))
            .filter(|(i, j, r)| r.abs() >= threshold && self.identifiable[*i] && self.identifiable[*j])
            .collect();
        pairs.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
        pairs
    }
}

/// A readable basis of the null space: reduced row echelon form of its transpose (in scaled units,
/// where coefficients are comparable), so each combination has one pivot parameter not shared with
/// the others; then converted to user units with the pivot coefficient 1.
fn name_null_space(null: &DMatrix<f64>, scale: &[f64], names: &[String], units: &[String]) -> Vec<Combination> {
    let (p, k) = null.shape();
    let mut rows = null.transpose();
    let mut pivots = Vec::new();
    for r in 0..k {
        // the largest entry; among entries equal to it up to rounding, the first parameter, so that
        // the wording does not depend on the last bits of the decomposition
        let largest = (0..p).filter(|c| !pivots.contains(c)).map(|c| rows[(r, c)].abs()).fold(0.0, f64::max);
        let Some((pivot, value)) =
            (0..p).filter(|c| !pivots.contains(c)).map(|c| (c, rows[(r, c)])).find(|(_, v)| v.abs() >= (1.0 - 1e-9) * largest)
        else {
            break;
        };
        if value.abs() < 1e-12 {
            continue;
        }
        let row = rows.row(r) / value;
        rows.set_row(r, &row);
        for o in 0..k {
            if o != r {
                let f = rows[(o, pivot)];
                let sub = rows.row(r) * f;
                let new = rows.row(o) - sub;
                rows.set_row(o, &new);
            }
        }
        pivots.push(pivot);
    }
    let mut combos = Vec::new();
    for (r, &pivot) in pivots.iter().enumerate() {
        let largest = rows.row(r).amax();
        let members: Vec<usize> = (0..p).filter(|&c| rows[(r, c)].abs() > 1e-6 * largest).collect();
        let user: Vec<f64> = members.iter().map(|&c| rows[(r, c)] / scale[c]).collect();
        let at_pivot = user[members.iter().position(|&c| c == pivot).expect("pivot is a member")];
        let coefficients: Vec<f64> = user.iter().map(|v| v / at_pivot).collect();
        let parameters: Vec<String> = members.iter().map(|&c| names[c].clone()).collect();
        let member_units: Vec<String> = members.iter().map(|&c| units[c].clone()).collect();
        let weight: Vec<f64> = members.iter().map(|&c| rows[(r, c)].abs()).collect();
        let message = describe(&parameters, &coefficients, &member_units, &weight);
        combos.push(Combination { parameters, coefficients, units: member_units, message });
    }
    combos
}

/// Terms named in one combination's message; the others (smaller in scaled units, i.e. in their
/// effect on the readings) are counted. The full combination is in [`Combination::coefficients`].
const TERMS_IN_MESSAGE: usize = 8;

/// Combinations named in a rank-deficiency error; the others are counted (all are in the report).
const COMBINATIONS_IN_MESSAGE: usize = 6;

/// The sentence of one combination: its parameters, and the changes (user units) that leave every
/// reading unchanged, the [`TERMS_IN_MESSAGE`] largest by `weight` (scaled magnitude) in order.
fn describe(parameters: &[String], coefficients: &[f64], units: &[String], weight: &[f64]) -> String {
    if parameters.len() == 1 {
        return format!("{} is not seen by these measurements (it changes no reading)", parameters[0]);
    }
    let mut shown: Vec<usize> = (0..parameters.len()).collect();
    shown.sort_by(|&a, &b| weight[b].total_cmp(&weight[a]));
    shown.truncate(TERMS_IN_MESSAGE);
    shown.sort_unstable();
    let names: Vec<&str> = shown.iter().map(|&i| parameters[i].as_str()).collect();
    let hidden = parameters.len() - shown.len();
    let list = match (names.as_slice(), hidden) {
        ([a, b], 0) => format!("{a} and {b}"),
        (_, 0) => format!("{} and {}", names[..names.len() - 1].join(", "), names[names.len() - 1]),
        (_, k) => format!("{} and {k} more parameters", names.join(", ")),
    };
    let changes: Vec<String> = shown.iter().map(|&i| format!("{} by {} {}", parameters[i], signed(coefficients[i]), units[i])).collect();
    let rest = if hidden > 0 { format!(" (with smaller changes of the {hidden} others)") } else { String::new() };
    format!("{list} cannot be separated: changing {}{rest} leaves every reading unchanged", changes.join(", "))
}

/// `+1.2345` for ordinary magnitudes, `+1.234e-7` for very small or large ones.
fn signed(v: f64) -> String {
    if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
        format!("{v:+.4}")
    } else {
        format!("{v:+.3e}")
    }
}

impl IdentifiabilityReport {
    /// The unseen combinations for an error message: the first [`COMBINATIONS_IN_MESSAGE`] sentences
    /// and the count of the others, or `fallback` when none could be named.
    pub fn combinations_summary(&self, fallback: &str) -> String {
        let all = &self.unidentifiable;
        if all.is_empty() {
            return fallback.to_string();
        }
        let shown: Vec<&str> = all.iter().take(COMBINATIONS_IN_MESSAGE).map(|c| c.message.as_str()).collect();
        let more = all.len() - shown.len();
        let tail = if more > 0 {
            format!("; and {more} more combinations (`identify --allow-rank-deficient --json` lists them all under `unidentifiable`)")
        } else {
            String::new()
        };
        format!("{}{tail}", shown.join("; "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_duplicated_column_is_named_with_its_ratio() {
        // column 2 = -3 * column 0: the unseen change is (1, 0, 1/3) in user units
        let x = DMatrix::from_fn(8, 3, |i, j| match j {
            0 => 1.0 + i as f64,
            1 => ((i * i) as f64).sin(),
            _ => -3.0 * (1.0 + i as f64),
        });
        let names: Vec<String> = ["A", "B", "C"].iter().map(|s| s.to_string()).collect();
        let units: Vec<String> = ["um", "um", "urad"].iter().map(|s| s.to_string()).collect();
        let svd = ScaledSvd::new(&x, &[1.0; 8], RANK_TOLERANCE);
        assert_eq!(svd.rank, 2);
        let report = IdentifiabilityReport::new(&x, &svd, &names, &units);
        assert_eq!(report.unidentifiable.len(), 1);
        let c = &report.unidentifiable[0];
        assert_eq!(c.parameters, vec!["A", "C"]);
        // pivot is the member with the largest scaled entry; either way A = 3 C in the unseen change
        let ratio = c.coefficients[0] / c.coefficients[1];
        assert!((ratio - 3.0).abs() < 1e-9, "{ratio}");
        assert!(c.message.contains("A and C cannot be separated"), "{}", c.message);
        assert_eq!(report.identifiable, vec![false, true, false]);
        assert!(report.condition_number.is_none_or(|k| k > 1e8));
    }

    #[test]
    fn long_combinations_and_many_of_them_are_summarised() {
        // columns 0..12 sum to column 12 (a 13-member combination); columns 13..21 are 8 pairs of
        // duplicates: 9 combinations in all
        let (n, p) = (60, 29);
        let base = |i: usize, j: usize| ((i * (j + 3)) as f64 * 0.37 + j as f64).sin();
        let x = DMatrix::from_fn(n, p, |i, j| match j {
            12 => (0..12).map(|k| base(i, k)).sum(),
            j if j > 12 && (j - 13) % 2 == 1 => 2.0 * base(i, j - 1),
            j => base(i, j),
        });
        let names: Vec<String> = (0..p).map(|j| format!("P{j}")).collect();
        let units = vec!["um".to_string(); p];
        let svd = ScaledSvd::new(&x, &vec![1.0; n], RANK_TOLERANCE);
        assert_eq!(svd.rank, p - 9);
        let report = IdentifiabilityReport::new(&x, &svd, &names, &units);
        assert_eq!(report.unidentifiable.len(), 9);
        let long = report.unidentifiable.iter().find(|c| c.parameters.len() == 13).expect("the 13-member combination");
        assert!(long.message.contains("and 5 more parameters"), "{}", long.message);
        assert!(long.message.contains("(with smaller changes of the 5 others)"), "{}", long.message);
        let summary = report.combinations_summary("singular");
        assert_eq!(summary.matches("cannot be separated").count(), COMBINATIONS_IN_MESSAGE, "{summary}");
        assert!(summary.contains("and 3 more combinations"), "{summary}");
        assert_eq!(signed(2.5e-7), "+2.500e-7");
        assert_eq!(signed(-3.0), "-3.0000");
    }

    #[test]
    fn large_problems_use_the_gram_reduction_only_when_well_conditioned() {
        let (n, p) = (4000, 30);
        let x = DMatrix::from_fn(n, p, |i, j| ((i * (j + 3)) as f64 * 0.291 + j as f64).sin() * 10f64.powi(j as i32 % 5 - 2));
        let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.013).sin() + 0.01 * (i as f64 * 2.9).cos()).collect();
        let w: Vec<f64> = (0..n).map(|i| 1.0 + (i % 3) as f64).collect();
        let qr = ScaledSvd::decompose(&x, &w, &y, RANK_TOLERANCE, usize::MAX);
        let gram = ScaledSvd::decompose(&x, &w, &y, RANK_TOLERANCE, 0);
        assert_eq!((qr.reduction, gram.reduction), (Reduction::Qr, Reduction::Gram));
        for (a, b) in qr.singular_values.iter().zip(&gram.singular_values) {
            assert!((a - b).abs() <= 1e-10 * qr.singular_values[0], "{a} vs {b}");
        }
        let (a, b) = (qr.solve_minimum_norm(), gram.solve_minimum_norm());
        let size = a.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(a.iter().zip(&b).all(|(u, v)| (u - v).abs() <= 1e-9 * size));
        assert!((qr.pseudo_inverse_normal() - gram.pseudo_inverse_normal()).norm() <= 1e-8 * qr.pseudo_inverse_normal().norm());
        // a nearly dependent column (condition number ~1e6 after scaling): QR despite the size
        let near = DMatrix::from_fn(n, p, |i, j| if j == 1 { x[(i, 0)] * 1e-2 + 1e-8 * x[(i, 2)] } else { x[(i, j)] });
        let fallback = ScaledSvd::decompose(&near, &w, &y, RANK_TOLERANCE, 0);
        assert_eq!(fallback.reduction, Reduction::Qr);
        let reference = ScaledSvd::decompose(&near, &w, &y, RANK_TOLERANCE, usize::MAX);
        assert_eq!(fallback.singular_values, reference.singular_values);
    }

    /// A dense weighted problem with standard normal entries (seeded), weights `1 / sigma^2` with
    /// `sigma` between 0.5 and 2 um, observations from known parameters plus noise.
    fn random_weighted(n: usize, p: usize) -> (DMatrix<f64>, Vec<f64>, Vec<f64>) {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(23);
        let x = DMatrix::from_fn(n, p, |_, _| rng.sample::<f64, _>(rand_distr::StandardNormal));
        let truth: Vec<f64> = (0..p).map(|j| (j as f64 * 0.7).sin()).collect();
        let sigma: Vec<f64> = (0..n).map(|_| rng.gen_range(0.5..2.0)).collect();
        let y = (0..n)
            .map(|i| (0..p).map(|j| x[(i, j)] * truth[j]).sum::<f64>() + sigma[i] * rng.sample::<f64, _>(rand_distr::StandardNormal))
            .collect();
        (x, sigma.iter().map(|s| 1.0 / (s * s)).collect(), y)
    }

    #[test]
    fn the_gram_path_agrees_with_qr_on_a_large_random_weighted_problem() {
        let (x, w, y) = random_weighted(20_000, 200);
        let qr = ScaledSvd::decompose(&x, &w, &y, RANK_TOLERANCE, usize::MAX);
        let gram = ScaledSvd::decompose(&x, &w, &y, RANK_TOLERANCE, 0);
        assert_eq!((qr.reduction, gram.reduction), (Reduction::Qr, Reduction::Gram));
        for (a, b) in qr.scale.iter().zip(&gram.scale) {
            assert!((a - b).abs() <= 1e-14 * a, "column norm {a} vs {b}");
        }
        // singular values to 1e-10 relative each (condition number ~1.2: eps cond^2 ~ 3e-16)
        for (a, b) in qr.singular_values.iter().zip(&gram.singular_values) {
            assert!((a - b).abs() <= 1e-10 * a, "{a} vs {b}");
        }
        // the solution and its covariance to 1e-9 relative
        let ((a, ca), (b, cb)) = (qr.solve_triangular().unwrap(), gram.solve_triangular().unwrap());
        let size = a.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(a.iter().zip(&b).all(|(u, v)| (u - v).abs() <= 1e-9 * size));
        assert!((ca - &cb).norm() <= 1e-9 * cb.norm());
    }

    #[test]
    fn an_ill_conditioned_large_problem_falls_back_to_qr() {
        // column 1 = column 0 + 1e-6 column 2 after scaling: condition number ~1e6 > 1e4
        let (mut x, w, y) = random_weighted(20_000, 200);
        for i in 0..x.nrows() {
            x[(i, 1)] = x[(i, 0)] + 1e-6 * x[(i, 2)];
        }
        let fallback = ScaledSvd::decompose(&x, &w, &y, RANK_TOLERANCE, 0);
        assert_eq!(fallback.reduction, Reduction::Qr);
        let condition = fallback.singular_values[0] / fallback.singular_values[199];
        assert!(condition > 10.0 * GRAM_CONDITION_LIMIT, "condition number {condition}");
        let reference = ScaledSvd::decompose(&x, &w, &y, RANK_TOLERANCE, usize::MAX);
        assert_eq!(fallback.singular_values, reference.singular_values);
        assert_eq!(fallback.scale, reference.scale);
    }
}
