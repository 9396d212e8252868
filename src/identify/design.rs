//! Optimal measurement design (seed 000 §4.3-4.4): D-, A-, E- and G-optimality of a design chosen
//! from a discrete candidate set, and an exchange algorithm (Fedorov / Mitchell type) that picks `n`
//! not necessarily distinct candidates.
//!
//! A candidate is a block of rows of the design matrix (one row for a length, three for a 3D-ball
//! pose), already weighted by `1/sigma` so that the information of a design is
//! `M = sum over chosen blocks of X_b^T X_b`. With `n` chosen blocks, the criteria are those of
//! seed 000 Table 4.1 (sigma = 1):
//! - D: `det(n M^-1)^(1/p)` (the volume of the confidence ellipsoid);
//! - A: `trace(n M^-1) / p` (average parameter variance);
//! - E: `lambda_max(n M^-1)` (largest variance in any direction);
//! - G: `max over candidate rows g of n g^T M^-1 g` (largest prediction variance, eq. 4.12).
//!
//! All four are minimised. The Kiefer-Wolfowitz equivalence theorem gives a check: a D-optimal
//! approximate design has G = p.

use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Which criterion to minimise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Criterion {
    D,
    A,
    E,
    G,
}

impl Criterion {
    pub fn parse(text: &str) -> Result<Criterion, String> {
        match text.to_ascii_lowercase().as_str() {
            "d" => Ok(Criterion::D),
            "a" => Ok(Criterion::A),
            "e" => Ok(Criterion::E),
            "g" => Ok(Criterion::G),
            _ => Err(format!("criterion `{text}`: expected d, a, e or g")),
        }
    }
}

/// The criteria of one design (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DesignCriteria {
    pub d: f64,
    pub a: f64,
    pub e: f64,
    pub g: f64,
    /// Mean over the candidate rows of `n g^T M^-1 g`.
    pub average_variance: f64,
}

impl DesignCriteria {
    pub fn value(&self, criterion: Criterion) -> f64 {
        match criterion {
            Criterion::D => self.d,
            Criterion::A => self.a,
            Criterion::E => self.e,
            Criterion::G => self.g,
        }
    }
}

/// Candidate blocks with their information matrices.
#[derive(Clone, Debug)]
pub struct CandidateSet {
    blocks: Vec<DMatrix<f64>>,
    information: Vec<DMatrix<f64>>,
    p: usize,
}

impl CandidateSet {
    /// From blocks of weighted rows, all with the same number of columns `p`.
    pub fn new(blocks: Vec<DMatrix<f64>>) -> Result<CandidateSet, String> {
        let p = blocks.first().map(|b| b.ncols()).ok_or("the candidate set is empty")?;
        if blocks.iter().any(|b| b.ncols() != p || b.nrows() == 0) {
            return Err("every candidate must have at least one row and the same number of columns".into());
        }
        if blocks.iter().any(|b| b.iter().any(|v| !v.is_finite())) {
            return Err("the candidate rows contain numbers that are not finite".into());
        }
        let information = blocks.iter().map(|b| b.transpose() * b).collect();
        Ok(CandidateSet { blocks, information, p })
    }

    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    pub fn parameters(&self) -> usize {
        self.p
    }

    fn information_of(&self, design: &[usize]) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(self.p, self.p);
        for &i in design {
            m += &self.information[i];
        }
        m
    }

    /// The criteria of the design `design` (candidate indices, repetitions allowed); `None` when
    /// its information matrix is singular.
    pub fn criteria(&self, design: &[usize]) -> Option<DesignCriteria> {
        self.criteria_of(&self.information_of(design), design.len(), true)
    }

    fn criteria_of(&self, m: &DMatrix<f64>, n: usize, with_g: bool) -> Option<DesignCriteria> {
        let p = self.p as f64;
        let n = n as f64;
        let cholesky = m.clone().cholesky()?;
        let log_det_m: f64 = 2.0 * cholesky.l_dirty().diagonal().iter().map(|v| v.ln()).sum::<f64>();
        // det(n M^-1)^(1/p) = n / det(M)^(1/p)
        let d = n * (-log_det_m / p).exp();
        let inverse = cholesky.inverse();
        if !d.is_finite() || inverse.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let a = n * inverse.trace() / p;
        let e = n * inverse.clone().symmetric_eigenvalues().max();
        let (mut g, mut total, mut rows) = (0.0f64, 0.0, 0usize);
        if with_g {
            for block in &self.blocks {
                for r in 0..block.nrows() {
                    let row = block.row(r);
                    let v = n * (row * &inverse * row.transpose())[(0, 0)];
                    g = g.max(v);
                    total += v;
                    rows += 1;
                }
            }
        }
        Some(DesignCriteria { d, a, e, g, average_variance: if rows > 0 { total / rows as f64 } else { 0.0 } })
    }

    /// One criterion of the information matrix `m` of `n` blocks (D by a Cholesky factor only).
    fn value_of(&self, m: &DMatrix<f64>, n: usize, criterion: Criterion) -> Option<f64> {
        if criterion == Criterion::D {
            let cholesky = m.clone().cholesky()?;
            let log_det: f64 = 2.0 * cholesky.l_dirty().diagonal().iter().map(|v| v.ln()).sum::<f64>();
            let d = n as f64 * (-log_det / self.p as f64).exp();
            return d.is_finite().then_some(d);
        }
        self.criteria_of(m, n, criterion == Criterion::G).map(|c| c.value(criterion))
    }

    /// Exchange algorithm (seed 000 §4.3: random start, excursions, until no improvement): from
    /// `starts` random designs of `n` candidates (seeded), repeatedly apply the single exchange
    /// (design point out, candidate in) that improves `criterion` most, until none does; returns the
    /// best design found, sorted, with its criteria. `None` if no start gave a regular design.
    pub fn exchange(&self, n: usize, criterion: Criterion, starts: usize, seed: u64) -> Option<(Vec<usize>, DesignCriteria)> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let with_g = criterion == Criterion::G;
        let mut best: Option<(Vec<usize>, f64)> = None;
        for _ in 0..starts.max(1) {
            let Some(mut design) = (0..100)
                .map(|_| (0..n).map(|_| rng.gen_range(0..self.len())).collect::<Vec<_>>())
                .find(|d| self.criteria_of(&self.information_of(d), n, false).is_some())
            else {
                continue;
            };
            let mut m = self.information_of(&design);
            let mut value = self.criteria_of(&m, n, with_g).expect("regular start").value(criterion);
            loop {
                let mut improvement: Option<(usize, usize, f64)> = None;
                for (i, &out) in design.iter().enumerate() {
                    let without = &m - &self.information[out];
                    for j in 0..self.len() {
                        if j == out {
                            continue;
                        }
                        let trial = &without + &self.information[j];
                        if let Some(v) = self.value_of(&trial, n, criterion) {
                            if v < value * (1.0 - 1e-10) && improvement.is_none_or(|(_, _, b)| v < b) {
                                improvement = Some((i, j, v));
                            }
                        }
                    }
                }
                let Some((i, j, v)) = improvement else { break };
                m = &m - &self.information[design[i]] + &self.information[j];
                design[i] = j;
                value = v;
            }
            if best.as_ref().is_none_or(|(_, b)| value < *b) {
                best = Some((design, value));
            }
        }
        let (mut design, _) = best?;
        design.sort_unstable();
        let criteria = self.criteria(&design)?;
        Some((design, criteria))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_line_design_puts_half_the_points_at_each_end() {
        // y = b0 + b1 x on x in {-1, -0.5, 0, 0.5, 1}: the D-optimal 4-point design is {-1,-1,1,1},
        // D = det(4 M^-1)^(1/2) = 4 / sqrt(16) = 1, and G = p = 2 (seed 000 §4.3, the line example)
        let xs = [-1.0, -0.5, 0.0, 0.5, 1.0];
        let set = CandidateSet::new(xs.iter().map(|x| DMatrix::from_row_slice(1, 2, &[1.0, *x])).collect()).unwrap();
        let (design, c) = set.exchange(4, Criterion::D, 5, 7).unwrap();
        assert_eq!(design, vec![0, 0, 4, 4]);
        assert!((c.d - 1.0).abs() < 1e-12);
        assert!((c.g - 2.0).abs() < 1e-12);
        assert!(set.criteria(&[2, 2, 2]).is_none(), "one point cannot fix a line");
    }
}
