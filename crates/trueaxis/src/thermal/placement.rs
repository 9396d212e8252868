//! Temperature-sensor placement (Zhu 2008 §3.3.1, §3.4.2): the modal rule of the thesis, Kammer's
//! effective independence, and exhaustive search as the baseline.
//!
//! - Modal rule (formalised from §3.3.1): for each dominant mode in order of weight, place a
//!   sensor at the candidate with the largest `|phi_i|` (an extreme of the mode's field), or reuse
//!   an already placed sensor that reaches `reuse` (default 0.8) of that maximum; ties go to the
//!   candidate nearest a heat-flux source; a mode whose field vanishes at every candidate is
//!   skipped (nodal region).
//! - Effective independence (Kammer 1991): start from every candidate, repeatedly drop the one
//!   with the smallest `E_D = diag(Phi_s (Phi_s^T Phi_s)^-1 Phi_s^T)` until `count` remain.
//! - Exhaustive: every subset of `count` candidates, scored by a caller-supplied criterion (for
//!   example `log det(Phi_s^T Phi_s)`, or the residual of the thermal error regression on
//!   simulated temperatures, Zhu 2008 §3.4.2 after Lo et al. 1995).

use super::modal::ModalBasis;
use super::time_constants::combinations;
use crate::error::Error;
use nalgebra::DMatrix;

/// A placed sensor and the dominant modes it serves.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedSensor {
    pub node: usize,
    pub modes: Vec<usize>,
}

/// The modal rule. `modes` are the dominant modes in order of weight; `distance(node)` is the
/// distance to the nearest heat source (for ties).
pub fn modal_rule(
    basis: &ModalBasis,
    modes: &[usize],
    candidates: &[usize],
    reuse: f64,
    distance: impl Fn(usize) -> f64,
) -> Result<Vec<PlacedSensor>, Error> {
    if candidates.is_empty() {
        return Err(Error::input("no sensor candidates"));
    }
    let mut placed: Vec<PlacedSensor> = Vec::new();
    for &mode in modes {
        let magnitude = |node: usize| basis.shape(node, mode).abs();
        let best = candidates.iter().map(|&c| magnitude(c)).fold(0.0f64, f64::max);
        let overall = (0..basis.shapes.nrows()).map(magnitude).fold(0.0f64, f64::max);
        if best <= 1e-6 * overall {
            continue; // every candidate lies in the nodal region of this mode
        }
        if let Some(s) =
            placed.iter_mut().filter(|s| magnitude(s.node) >= reuse * best).max_by(|a, b| magnitude(a.node).total_cmp(&magnitude(b.node)))
        {
            s.modes.push(mode);
            continue;
        }
        let node = candidates
            .iter()
            .copied()
            .filter(|&c| magnitude(c) >= best * (1.0 - 1e-9))
            .min_by(|&a, &b| distance(a).total_cmp(&distance(b)).then(a.cmp(&b)))
            .expect("the maximum is attained");
        placed.push(PlacedSensor { node, modes: vec![mode] });
    }
    Ok(placed)
}

/// Effective independence: keeps `count` of `candidates` for the modes `modes`.
pub fn effective_independence(basis: &ModalBasis, modes: &[usize], candidates: &[usize], count: usize) -> Result<Vec<usize>, Error> {
    if count < modes.len() || count > candidates.len() {
        return Err(Error::input(format!(
            "effective independence needs between {} (the modes) and {} (the candidates) sensors",
            modes.len(),
            candidates.len()
        )));
    }
    let mut kept = candidates.to_vec();
    while kept.len() > count {
        let phi = mode_matrix(basis, modes, &kept);
        let fisher = phi.transpose() * &phi;
        let inv = fisher.try_inverse().ok_or_else(|| Error::input("the dominant modes are not independent at the candidates"))?;
        let ed: Vec<f64> = (0..kept.len()).map(|r| (phi.row(r) * &inv * phi.row(r).transpose())[(0, 0)]).collect();
        let worst = (0..kept.len()).min_by(|&a, &b| ed[a].total_cmp(&ed[b]).then(kept[b].cmp(&kept[a]))).expect("non-empty");
        kept.remove(worst);
    }
    kept.sort_unstable();
    Ok(kept)
}

/// `log det(Phi_s^T Phi_s)` of the sensor set (the D-optimality that EfI approximates); minus
/// infinity when singular.
pub fn log_det_information(basis: &ModalBasis, modes: &[usize], sensors: &[usize]) -> f64 {
    let phi = mode_matrix(basis, modes, sensors);
    let f = phi.transpose() * &phi;
    match f.cholesky() {
        Some(c) => 2.0 * c.l().diagonal().iter().map(|v| v.ln()).sum::<f64>(),
        None => f64::NEG_INFINITY,
    }
}

/// Exhaustive search: the subset of `count` candidates with the largest `score` (ties: the first
/// in lexicographic order). At most 10^7 subsets.
pub fn exhaustive(candidates: &[usize], count: usize, mut score: impl FnMut(&[usize]) -> f64) -> Result<(Vec<usize>, f64), Error> {
    let n = candidates.len();
    if count == 0 || count > n {
        return Err(Error::input(format!("cannot choose {count} of {n} candidates")));
    }
    let subsets = (0..count).fold(1.0f64, |acc, i| acc * (n - i) as f64 / (i + 1) as f64);
    if subsets > 1e7 {
        return Err(Error::input(format!("{subsets:.0} subsets are too many for exhaustive search; restrict the candidates")));
    }
    let mut best = (Vec::new(), f64::NEG_INFINITY);
    let mut idx = vec![0usize; count];
    let mut chosen = vec![0usize; count];
    combinations(n, count, 0, 0, &mut idx, &mut |ix: &[usize]| {
        for (c, &i) in chosen.iter_mut().zip(ix) {
            *c = candidates[i];
        }
        let s = score(&chosen);
        if s > best.1 {
            best = (chosen.clone(), s);
        }
    });
    Ok(best)
}

/// Rows: sensors; columns: modes.
pub fn mode_matrix(basis: &ModalBasis, modes: &[usize], sensors: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(sensors.len(), modes.len(), |r, c| basis.shape(sensors[r], modes[c]))
}

/// How well the sensors determine the modal coordinates of the modes: the rank and condition
/// number of the sensor-mode matrix `Phi_s` (sensors x modes; Zhu 2008 §3.3.1: check the
/// conditioning of Phi_s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditioning {
    pub sensors: usize,
    pub modes: usize,
    /// Numerical rank of `Phi_s` (singular values above `max(s, m) eps sigma_max`).
    pub rank: usize,
    /// `sigma_max / sigma_min` when the rank equals the number of modes (every modal coordinate
    /// can be estimated from the sensors); `None` when it is smaller: the sensors cannot tell the
    /// modes apart, the condition number is infinite.
    pub condition_number: Option<f64>,
}

impl Conditioning {
    /// One line on what the rank means (for the CLI and reports).
    pub fn explanation(&self) -> String {
        match self.condition_number {
            Some(k) => format!("condition number of Phi_s ({} sensors x {} modes): {k:.3e}", self.sensors, self.modes),
            None => format!(
                "condition number of Phi_s ({} sensors x {} modes): infinite, rank {} < {} modes: the sensor readings cannot separate every dominant mode",
                self.sensors, self.modes, self.rank, self.modes
            ),
        }
    }
}

/// Rank and condition number of `Phi_s` for `modes` at `sensors`.
pub fn conditioning(basis: &ModalBasis, modes: &[usize], sensors: &[usize]) -> Conditioning {
    let phi = mode_matrix(basis, modes, sensors);
    let sv = if phi.is_empty() { nalgebra::DVector::zeros(0) } else { phi.singular_values() };
    let largest = sv.iter().copied().fold(0.0f64, f64::max);
    let threshold = sensors.len().max(modes.len()) as f64 * f64::EPSILON * largest;
    let rank = sv.iter().filter(|s| **s > threshold && **s > 0.0).count();
    let condition_number =
        if rank == modes.len() && rank > 0 { Some(largest / sv.iter().copied().fold(f64::INFINITY, f64::min)) } else { None };
    Conditioning { sensors: sensors.len(), modes: modes.len(), rank, condition_number }
}
