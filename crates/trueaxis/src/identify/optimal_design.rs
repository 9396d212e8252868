//! Optimal measurement design (Soons 1993 §4.3-4.4): D-, A-, E- and G-optimality of a design chosen
//! from a discrete candidate set, and an exchange algorithm (Fedorov / Mitchell type) that picks `n`
//! not necessarily distinct candidates.
//!
//! A candidate is a *record*: a block of rows of the design matrix (one row for a length, three for
//! a 3D-ball pose), already weighted by `1/sigma`, chosen or left out as a whole. The information
//! of a design is `M = sum over chosen records of X_r^T X_r`. With `n` chosen records, the criteria
//! are those of Soons 1993 Table 4.1 (sigma = 1):
//! - D: `det(n M^-1)^(1/p)` (the volume of the confidence ellipsoid);
//! - A: `trace(n M^-1) / p` (average parameter variance);
//! - E: `lambda_max(n M^-1)` (largest variance in any direction);
//! - G: `max over candidate records r of n trace(X_r M^-1 X_r^T)`: the largest summed prediction
//!   variance of the readings of one record (eq. 4.12 summed over the record's channels). For
//!   one-reading records this is the largest prediction variance of Soons 1993 Table 4.1.
//!
//! All four are minimised. The Kiefer-Wolfowitz equivalence theorem, in its form for records of
//! several readings (Fedorov 1972, multiresponse designs), gives a check: at the D-optimal
//! *approximate* design `max_r n trace(X_r M^-1 X_r^T) = p`; and for every design the mean of that
//! quantity over the chosen records is exactly `p` (`sum_r trace(M^-1 X_r^T X_r) = trace(I_p)`).
//! The largest variance of a single reading (`max_reading_variance`) is smaller and is not `p` at
//! the optimum when a record has several readings.
//!
//! Singular designs: the rank of a design is decided as in [`super::identify`], on the weighted,
//! unit-length scaled rows with the relative tolerance [`RANK_TOLERANCE`] ([`ScaledSvd`]), and a
//! deficient design is an error naming the unseen parameter combinations. Inside the exchange
//! algorithm a trial design is accepted only when the Cholesky factor of its scaled information
//! matrix has no relative pivot below [`PIVOT_GUARD`] (stricter than the rank tolerance), and the
//! returned design is checked again with the rank decision.

use super::identifiability::{IdentifiabilityReport, ScaledSvd, RANK_TOLERANCE};
use super::IdentifyError;
use nalgebra::{DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Smallest relative Cholesky pivot `L_jj^2 / M_jj` (the squared sine of the angle between a scaled
/// column and the span of the columns before it) a trial design of the exchange may have: `1e-12`
/// (a sine of 1e-6, stricter than the singular-value ratio [`RANK_TOLERANCE`] = 1e-8 that the
/// normal equations cannot resolve).
pub const PIVOT_GUARD: f64 = 1e-12;

/// Which criterion to minimise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Criterion {
    D,
    A,
    E,
    G,
}

impl Criterion {
    pub fn parse(text: &str) -> crate::error::Result<Criterion> {
        match text.to_ascii_lowercase().as_str() {
            "d" => Ok(Criterion::D),
            "a" => Ok(Criterion::A),
            "e" => Ok(Criterion::E),
            "g" => Ok(Criterion::G),
            _ => Err(crate::Error::input(format!("criterion `{text}`: expected d, a, e or g"))),
        }
    }
}

/// The criteria of one design (see the module documentation; variances in units of sigma^2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DesignCriteria {
    pub d: f64,
    pub a: f64,
    pub e: f64,
    /// Largest `n trace(X_r M^-1 X_r^T)` over the candidate records.
    pub g: f64,
    /// Mean over the candidate records of `n trace(X_r M^-1 X_r^T)`.
    pub average_variance: f64,
    /// Largest `n x M^-1 x^T` over the single candidate rows (one reading).
    pub max_reading_variance: f64,
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

/// Candidate records with their information matrices.
#[derive(Clone, Debug)]
pub struct CandidateSet {
    blocks: Vec<DMatrix<f64>>,
    information: Vec<DMatrix<f64>>,
    p: usize,
    names: Vec<String>,
    units: Vec<String>,
    /// Column norms of all candidate rows stacked: the fixed scaling of the information matrices,
    /// so that the criteria are computed on well-scaled numbers whatever the parameter units.
    scale: Vec<f64>,
}

impl CandidateSet {
    /// From blocks of weighted rows, all with the same number of columns `p`. The columns are named
    /// `column 1, ...` until [`CandidateSet::with_names`].
    pub fn new(blocks: Vec<DMatrix<f64>>) -> crate::error::Result<CandidateSet> {
        let p = blocks.first().map(|b| b.ncols()).ok_or_else(|| crate::Error::input("the candidate set is empty"))?;
        if blocks.iter().any(|b| b.ncols() != p || b.nrows() == 0) {
            return Err(crate::Error::input("every candidate must have at least one row and the same number of columns"));
        }
        if blocks.iter().any(|b| b.iter().any(|v| !v.is_finite())) {
            return Err(crate::Error::input("the candidate rows contain numbers that are not finite"));
        }
        let information: Vec<DMatrix<f64>> = blocks.iter().map(|b| b.transpose() * b).collect();
        let scale =
            (0..p).map(|j| information.iter().map(|m| m[(j, j)]).sum::<f64>().sqrt()).map(|s| if s > 0.0 { s } else { 1.0 }).collect();
        let names = (1..=p).map(|j| format!("column {j}")).collect();
        let units = vec![String::new(); p];
        Ok(CandidateSet { blocks, information, p, names, units, scale })
    }

    /// Names and units of the columns, for the messages about unseen combinations.
    pub fn with_names(mut self, names: &[String], units: &[String]) -> CandidateSet {
        if names.len() == self.p && units.len() == self.p {
            self.names = names.to_vec();
            self.units = units.to_vec();
        }
        self
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

    /// Rows of candidate `i`.
    pub fn rows_of(&self, i: usize) -> usize {
        self.blocks[i].nrows()
    }

    fn information_of(&self, design: &[usize]) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(self.p, self.p);
        for &i in design {
            m += &self.information[i];
        }
        m
    }

    /// Rank and unseen combinations of a design (candidate indices, repetitions allowed): the
    /// decision of [`super::identify`] ([`ScaledSvd`] with [`RANK_TOLERANCE`] on the stacked
    /// weighted rows, unit-length scaled), computed on the triangular factor `R` of a QR of the
    /// stacked rows (same singular values and right singular vectors). Only `rank`,
    /// `singular_values`, `condition_number` and `unidentifiable` of the report are meaningful.
    pub fn identifiability(&self, design: &[usize]) -> IdentifiabilityReport {
        let rows: usize = design.iter().map(|&i| self.blocks[i].nrows()).sum();
        let mut stacked = DMatrix::zeros(rows, self.p);
        let mut at = 0;
        for &i in design {
            let b = &self.blocks[i];
            stacked.rows_mut(at, b.nrows()).copy_from(b);
            at += b.nrows();
        }
        let factor = if rows > self.p { stacked.qr().r() } else { stacked };
        let svd = ScaledSvd::new(&factor, &vec![1.0; factor.nrows()], RANK_TOLERANCE);
        IdentifiabilityReport::new(&factor, &svd, &self.names, &self.units)
    }

    /// The rank check of a design: an error naming the unseen combinations when it is deficient.
    fn check_rank(&self, design: &[usize], what: &str) -> Result<(), IdentifyError> {
        let report = self.identifiability(design);
        if report.rank == self.p {
            return Ok(());
        }
        Err(IdentifyError::RankDeficient {
            message: format!(
                "{what} determines only {} of {} parameter combinations: {}",
                report.rank,
                self.p,
                report.combinations_summary("the information matrix is singular")
            ),
        })
    }

    /// The criteria of the design `design` (candidate indices, repetitions allowed); an error
    /// (rank deficient, naming the unseen combinations) when it does not determine every parameter.
    pub fn criteria(&self, design: &[usize]) -> Result<DesignCriteria, IdentifyError> {
        if design.is_empty() || design.iter().any(|&i| i >= self.len()) {
            return Err(IdentifyError::Input(format!("a design is a non-empty list of candidates 0..{}", self.len())));
        }
        self.check_rank(design, &format!("a design of {} records", design.len()))?;
        self.criteria_of(&self.information_of(design), design.len(), true).ok_or_else(|| IdentifyError::RankDeficient {
            message: format!("the information matrix of the design of {} records is numerically singular", design.len()),
        })
    }

    /// Cholesky factor of the scaled information matrix `S^-1 M S^-1`, `None` when a relative pivot
    /// is below [`PIVOT_GUARD`].
    fn scaled_cholesky(&self, m: &DMatrix<f64>) -> Option<nalgebra::Cholesky<f64, nalgebra::Dyn>> {
        let scaled = DMatrix::from_fn(self.p, self.p, |i, j| m[(i, j)] / (self.scale[i] * self.scale[j]));
        let diagonal: Vec<f64> = (0..self.p).map(|j| scaled[(j, j)]).collect();
        let cholesky = scaled.cholesky()?;
        let l = cholesky.l_dirty();
        (0..self.p).all(|j| diagonal[j] > 0.0 && l[(j, j)] * l[(j, j)] >= PIVOT_GUARD * diagonal[j]).then_some(cholesky)
    }

    /// `ln det M` from the scaled factor.
    fn log_det(&self, cholesky: &nalgebra::Cholesky<f64, nalgebra::Dyn>) -> f64 {
        let l = cholesky.l_dirty();
        (0..self.p).map(|j| 2.0 * (l[(j, j)].ln() + self.scale[j].ln())).sum()
    }

    fn criteria_of(&self, m: &DMatrix<f64>, n: usize, with_g: bool) -> Option<DesignCriteria> {
        let p = self.p as f64;
        let n = n as f64;
        let cholesky = self.scaled_cholesky(m)?;
        // det(n M^-1)^(1/p) = n / det(M)^(1/p)
        let d = n * (-self.log_det(&cholesky) / p).exp();
        let scaled_inverse = cholesky.inverse();
        let inverse = DMatrix::from_fn(self.p, self.p, |i, j| scaled_inverse[(i, j)] / (self.scale[i] * self.scale[j]));
        if !d.is_finite() || inverse.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let a = n * inverse.trace() / p;
        let e = n * inverse.clone().symmetric_eigenvalues().max();
        let (mut g, mut total, mut reading) = (0.0f64, 0.0, 0.0f64);
        if with_g {
            for block in &self.blocks {
                let mut record = 0.0;
                for r in 0..block.nrows() {
                    let row = block.row(r);
                    let v = n * (row * &inverse * row.transpose())[(0, 0)];
                    reading = reading.max(v);
                    record += v;
                }
                g = g.max(record);
                total += record;
            }
        }
        Some(DesignCriteria { d, a, e, g, average_variance: total / self.len() as f64, max_reading_variance: reading })
    }

    /// One criterion of the information matrix `m` of `n` records (D by the Cholesky factor only);
    /// `None` for a (numerically) singular `m`.
    fn value_of(&self, m: &DMatrix<f64>, n: usize, criterion: Criterion) -> Option<f64> {
        if criterion == Criterion::D {
            let cholesky = self.scaled_cholesky(m)?;
            let d = n as f64 * (-self.log_det(&cholesky) / self.p as f64).exp();
            return d.is_finite().then_some(d);
        }
        self.criteria_of(m, n, criterion == Criterion::G).map(|c| c.value(criterion))
    }

    /// A regular design of `n` records: at most `p` records chosen greedily, each adding the most
    /// new (scaled) row space to the ones before (Gram-Schmidt), the rest random. `None` when `n`
    /// records chosen this way do not reach full rank.
    fn greedy_start(&self, n: usize, rng: &mut ChaCha8Rng) -> Option<Vec<usize>> {
        let mut basis: Vec<DVector<f64>> = Vec::new();
        let mut design = Vec::new();
        let scaled_row = |i: usize, r: usize| DVector::from_fn(self.p, |j, _| self.blocks[i][(r, j)] / self.scale[j]);
        let residual = |v: &DVector<f64>, basis: &[DVector<f64>]| {
            let mut v = v.clone();
            for b in basis {
                v -= b * b.dot(&v);
            }
            v
        };
        while basis.len() < self.p && design.len() < n {
            let gain = |i: usize| (0..self.blocks[i].nrows()).map(|r| residual(&scaled_row(i, r), &basis).norm_squared()).sum::<f64>();
            let (best, value) = (0..self.len()).map(|i| (i, gain(i))).max_by(|a, b| a.1.total_cmp(&b.1))?;
            if value <= PIVOT_GUARD {
                return None;
            }
            for r in 0..self.blocks[best].nrows() {
                let row = scaled_row(best, r);
                let v = residual(&row, &basis);
                if v.norm_squared() > PIVOT_GUARD * row.norm_squared().max(f64::MIN_POSITIVE) && basis.len() < self.p {
                    basis.push(v.normalize());
                }
            }
            design.push(best);
        }
        if basis.len() < self.p {
            return None;
        }
        while design.len() < n {
            design.push(rng.gen_range(0..self.len()));
        }
        Some(design)
    }

    /// Exchange algorithm (Soons 1993 §4.3: random start, excursions, until no improvement): from
    /// `starts` random designs of `n` candidates (seeded; a greedy regular start when no random one
    /// is regular), repeatedly apply the single exchange (design record out, candidate in) that
    /// improves `criterion` most, until none does; returns the best design found, sorted, with its
    /// criteria. The starts run in parallel; each has its own random stream ([`start_rng`]) and
    /// the best is chosen by value, then by the lowest start, so the result does not depend on
    /// how the starts are spread over threads, processes or machines
    /// ([`CandidateSet::exchange_starts`], [`CandidateSet::best_of`]).
    ///
    /// Errors: `n` or `starts` zero, or `n` records too few to hold `p` readings (input); a
    /// candidate set that does not determine every parameter, naming the unseen combinations, or no
    /// regular design of `n` records found (rank deficient). A singular design is never returned.
    pub fn exchange(
        &self,
        n: usize,
        criterion: Criterion,
        starts: usize,
        seed: u64,
    ) -> Result<(Vec<usize>, DesignCriteria), IdentifyError> {
        self.check_exchange(n, starts)?;
        let found = self.exchange_starts(n, criterion, seed, 0..starts);
        self.best_of(n, &found)
    }

    /// The checks of [`CandidateSet::exchange`] before any start: `n` and `starts` at least 1,
    /// enough readings for the unknowns, a candidate set that determines every parameter.
    pub fn check_exchange(&self, n: usize, starts: usize) -> Result<(), IdentifyError> {
        if n == 0 {
            return Err(IdentifyError::Input("the number of records to choose must be at least 1".into()));
        }
        if starts == 0 {
            return Err(IdentifyError::Input("the number of random starts must be at least 1".into()));
        }
        let all: Vec<usize> = (0..self.len()).collect();
        self.check_rank(&all, &format!("the candidate set ({} records)", self.len()))?;
        let most_rows = (0..self.len()).map(|i| self.rows_of(i)).max().unwrap_or(0);
        if n * most_rows < self.p {
            return Err(IdentifyError::Input(format!(
                "{n} records give at most {} readings for {} unknowns; choose at least {} records",
                n * most_rows,
                self.p,
                self.p.div_ceil(most_rows)
            )));
        }
        Ok(())
    }

    /// The exchange from each start of `starts` (a chunk of the starts of
    /// [`CandidateSet::exchange`]; run [`CandidateSet::check_exchange`] first): per start its
    /// number and the design it ends in with its criterion value, `None` when no regular start
    /// design was found. Starts run in parallel (rayon).
    pub fn exchange_starts(&self, n: usize, criterion: Criterion, seed: u64, starts: std::ops::Range<usize>) -> Vec<ExchangeOutcome> {
        starts.into_par_iter().map(|start| ExchangeOutcome { start, found: self.exchange_from(n, criterion, seed, start) }).collect()
    }

    /// One start of the exchange algorithm.
    fn exchange_from(&self, n: usize, criterion: Criterion, seed: u64, start: usize) -> Option<(Vec<usize>, f64)> {
        if self.is_empty() {
            return None;
        }
        let mut rng = start_rng(seed, start);
        let random = (0..100)
            .map(|_| (0..n).map(|_| rng.gen_range(0..self.len())).collect::<Vec<_>>())
            .find(|d| self.scaled_cholesky(&self.information_of(d)).is_some());
        let mut design = random.or_else(|| self.greedy_start(n, &mut rng))?;
        let mut m = self.information_of(&design);
        let mut value = self.value_of(&m, n, criterion)?;
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
        design.sort_unstable();
        Some((design, value))
    }

    /// The best of the outcomes of any chunks of starts (smallest criterion value, then lowest
    /// start number), sorted, with its criteria: the merge of [`CandidateSet::exchange_starts`].
    pub fn best_of(&self, n: usize, outcomes: &[ExchangeOutcome]) -> Result<(Vec<usize>, DesignCriteria), IdentifyError> {
        let best = outcomes
            .iter()
            .filter_map(|o| o.found.as_ref().map(|(d, v)| (o.start, d, *v)))
            .min_by(|a, b| a.2.total_cmp(&b.2).then(a.0.cmp(&b.0)))
            .ok_or_else(|| IdentifyError::RankDeficient {
                message: format!("no design of {n} records that determines the {} unknowns was found; choose more records", self.p),
            })?;
        let design = best.1.clone();
        let criteria = self.criteria(&design)?;
        Ok((design, criteria))
    }
}

/// The outcome of one start of the exchange algorithm: the start's number and the (sorted)
/// design it ends in with its criterion value, `None` when no regular start design was found.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExchangeOutcome {
    pub start: usize,
    pub found: Option<(Vec<usize>, f64)>,
}

/// The random stream of start `start` of the exchange algorithm: ChaCha8 seeded with `seed`, on
/// stream `start` (counter-based: independent of the other starts and of their order).
pub fn start_rng(seed: u64, start: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(start as u64);
    rng
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_line_design_puts_half_the_points_at_each_end() {
        // y = b0 + b1 x on x in {-1, -0.5, 0, 0.5, 1}: the D-optimal 4-point design is {-1,-1,1,1},
        // D = det(4 M^-1)^(1/2) = 4 / sqrt(16) = 1, and G = p = 2 (Soons 1993 §4.3, the line example)
        let xs = [-1.0, -0.5, 0.0, 0.5, 1.0];
        let set = CandidateSet::new(xs.iter().map(|x| DMatrix::from_row_slice(1, 2, &[1.0, *x])).collect()).unwrap();
        let (design, c) = set.exchange(4, Criterion::D, 5, 7).unwrap();
        assert_eq!(design, vec![0, 0, 4, 4]);
        assert!((c.d - 1.0).abs() < 1e-12);
        assert!((c.g - 2.0).abs() < 1e-12);
        assert!((c.max_reading_variance - 2.0).abs() < 1e-12, "one reading per record: the same");
        let e = set.criteria(&[2, 2, 2]).unwrap_err().to_string();
        assert!(e.contains("rank deficient") && e.contains("column 2 is not seen"), "one point cannot fix a line: {e}");
    }

    #[test]
    fn records_of_two_readings_reach_g_equal_p_per_record() {
        // two independent straight lines measured together: record x gives the rows [1 x 0 0] and
        // [0 0 1 x] (p = 4). The D-optimal design is half at each end; Kiefer-Wolfowitz for records
        // of several readings: max over records of n trace(X_r M^-1 X_r^T) = p = 4, while the
        // largest single-reading variance is 2.
        let xs = [-1.0, -0.5, 0.0, 0.5, 1.0];
        let blocks = xs.iter().map(|x| DMatrix::from_row_slice(2, 4, &[1.0, *x, 0.0, 0.0, 0.0, 0.0, 1.0, *x])).collect();
        let set = CandidateSet::new(blocks).unwrap();
        let (design, c) = set.exchange(4, Criterion::D, 3, 1).unwrap();
        assert_eq!(design, vec![0, 0, 4, 4]);
        assert!((c.g - 4.0).abs() < 1e-12, "G {}", c.g);
        assert!((c.max_reading_variance - 2.0).abs() < 1e-12);
        // two records hold four readings: enough; one record is too few
        assert!(set.exchange(1, Criterion::D, 1, 1).unwrap_err().to_string().contains("choose at least 2 records"));
        assert!(set.exchange(0, Criterion::D, 1, 1).is_err() && set.exchange(4, Criterion::D, 0, 1).is_err());
    }

    #[test]
    fn a_singular_candidate_set_is_refused_with_the_combination() {
        // column 3 = 2 x column 1 in every candidate: no design can separate them
        let blocks: Vec<DMatrix<f64>> =
            (0..6).map(|i| i as f64).map(|x| DMatrix::from_row_slice(1, 3, &[1.0 + x, (x * x).sin(), 2.0 * (1.0 + x)])).collect();
        let names: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
        let set = CandidateSet::new(blocks).unwrap().with_names(&names, &vec!["um".to_string(); 3]);
        match set.exchange(5, Criterion::D, 2, 1) {
            Err(IdentifyError::RankDeficient { message }) => assert!(message.contains("a and c cannot be separated"), "{message}"),
            other => panic!("expected rank deficiency, got {other:?}"),
        }
    }

    #[test]
    fn the_greedy_start_finds_the_rare_regular_design() {
        // 200 candidates see only b0, one sees b1: random starts of 2 records almost never hold it
        let mut blocks: Vec<DMatrix<f64>> = (0..200).map(|_| DMatrix::from_row_slice(1, 2, &[1.0, 0.0])).collect();
        blocks.push(DMatrix::from_row_slice(1, 2, &[0.0, 1.0]));
        let set = CandidateSet::new(blocks).unwrap();
        let (design, c) = set.exchange(2, Criterion::D, 1, 5).unwrap();
        assert_eq!(design[1], 200);
        assert!((c.d - 2.0).abs() < 1e-12, "det(2 I)^(1/2) = 2: {}", c.d);
    }
}
