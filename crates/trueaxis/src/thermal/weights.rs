//! Mode weights and truncation (Zhu 2008 §3.2.2, eq. 3.11): `w_i = |xi_i tau_i|`, the steady-state
//! modal amplitude under the representative step load Q (eq. 3.10 at t -> infinity), with
//! `xi = Phi^T Q` on C-orthonormal modes. Keep the modes that carry a cumulative share of the total
//! weight (default 90 %, Zhu 2008 §3.4.1).

use super::modal::ModalBasis;

/// Default cumulative share of the total weight kept by truncation (Zhu 2008 §3.4.1).
pub const DEFAULT_SHARE: f64 = 0.9;

/// One mode with its weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeWeight {
    /// Index into the modal basis (0 = lowest eigenvalue, longest time constant).
    pub mode: usize,
    pub tau_s: f64,
    /// Modal load `xi` (W per sqrt(J/K)).
    pub xi: f64,
    /// `|xi tau|`: the steady-state amplitude of the C-orthonormal mode coordinate, K sqrt(J/K).
    pub weight: f64,
    /// `weight / sum of weights` over the computed modes.
    pub share: f64,
}

/// Weights of every mode of `basis` under the step load `q` (W), in mode order.
pub fn mode_weights(basis: &ModalBasis, q: &[f64]) -> Vec<ModeWeight> {
    let xi = basis.modal_load(q);
    let weights: Vec<f64> = xi.iter().enumerate().map(|(i, x)| (x * basis.tau_s(i)).abs()).collect();
    let total: f64 = weights.iter().sum();
    (0..basis.len())
        .map(|i| ModeWeight {
            mode: i,
            tau_s: basis.tau_s(i),
            xi: xi[i],
            weight: weights[i],
            share: if total > 0.0 { weights[i] / total } else { 0.0 },
        })
        .collect()
}

/// The dominant modes: sorted by decreasing weight, the fewest whose shares add up to at least
/// `share` (0 < share <= 1). Returns mode indices in that order.
pub fn dominant_modes(weights: &[ModeWeight], share: f64) -> Vec<usize> {
    let mut order: Vec<&ModeWeight> = weights.iter().collect();
    order.sort_by(|a, b| b.weight.total_cmp(&a.weight).then(a.mode.cmp(&b.mode)));
    let mut kept = Vec::new();
    let mut sum = 0.0;
    for w in order {
        if sum >= share - 1e-12 || w.weight == 0.0 {
            break;
        }
        kept.push(w.mode);
        sum += w.share;
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    #[test]
    fn weights_are_xi_tau_and_truncation_stops_at_the_share() {
        // two nodes with C = I: modes e1 (lambda 1), e2 (lambda 4); Q = (3, 8): xi = (3, 8), w = (3, 2)
        let basis = ModalBasis { lambda: vec![1.0, 4.0, 10.0], shapes: Mat::from_fn(3, 3, |i, j| f64::from(u8::from(i == j))) };
        let w = mode_weights(&basis, &[3.0, 8.0, 0.5]);
        assert_eq!(w.iter().map(|m| m.weight).collect::<Vec<_>>(), vec![3.0, 2.0, 0.05]);
        assert!((w[0].share - 3.0 / 5.05).abs() < 1e-15);
        assert_eq!(dominant_modes(&w, 0.9), vec![0, 1]);
        assert_eq!(dominant_modes(&w, 0.5), vec![0]);
        assert_eq!(dominant_modes(&w, 1.0), vec![0, 1, 2]);
    }
}
