//! Transient responses of `C dT/dt + K T = Q(t)` (Zhu 2008 eq. 3.1) to load histories: by modal
//! superposition (eqs. 3.8-3.10; an arbitrary history is a series of steps) and by time stepping
//! (theta method on the sparse matrices), which checks each other.
//!
//! A [`LoadHistory`] has load vectors `Q_j` (W, one per heat source) and, on each interval
//! `[t_k, t_k+1)`, a constant multiplier `u_kj` of each: `Q(t) = sum_j u_kj Q_j`. Temperatures
//! are rises (K) over the initial uniform state.

use super::assembly::{from_triplets, sparse_mul, ThermalSystem};
use super::modal::ModalBasis;
use crate::error::Error;
use faer::linalg::solvers::Solve;
use faer::sparse::Triplet;
use faer::{MatMut, Side};

/// Piecewise-constant loads.
#[derive(Clone, Debug)]
pub struct LoadHistory {
    /// Load vectors (W per node), one per heat source.
    pub loads: Vec<Vec<f64>>,
    /// Increasing times (s), starting at the initial state.
    pub times_s: Vec<f64>,
    /// `inputs[k][j]`: multiplier of load j on `[times_s[k], times_s[k+1])`.
    pub inputs: Vec<Vec<f64>>,
}

impl LoadHistory {
    fn check(&self, nodes: usize) -> Result<(), Error> {
        if self.times_s.is_empty() || self.inputs.len() != self.times_s.len() {
            return Err(Error::input("a load history needs one input row per time"));
        }
        if self.times_s.windows(2).any(|w| w[1].is_nan() || w[1] <= w[0]) || self.times_s.iter().any(|t| !t.is_finite()) {
            return Err(Error::input("the times of a load history must be finite and increase strictly"));
        }
        if self.loads.iter().any(|q| q.len() != nodes) || self.inputs.iter().any(|u| u.len() != self.loads.len()) {
            return Err(Error::input("every load needs one value per node and every input row one value per load"));
        }
        Ok(())
    }
}

/// Step response at `nodes` (eq. 3.10): `T = sum_i phi_i xi_i tau_i (1 - exp(-t/tau_i))` over the
/// modes of `basis`; one row per time.
pub fn step_response(basis: &ModalBasis, q: &[f64], times_s: &[f64], nodes: &[usize]) -> Vec<Vec<f64>> {
    let xi = basis.modal_load(q);
    times_s
        .iter()
        .map(|&t| {
            nodes
                .iter()
                .map(|&r| (0..basis.len()).map(|i| basis.shape(r, i) * xi[i] * basis.tau_s(i) * (1.0 - (-t / basis.tau_s(i)).exp())).sum())
                .collect()
        })
        .collect()
}

/// Temperatures at `nodes` at every time of `history` by modal superposition with the exact
/// solution of eq. 3.9 over each interval: `theta_i <- e^(-lambda dt) theta_i + (1 - e^(-lambda dt))
/// / lambda * xi_i`.
pub fn modal_history(basis: &ModalBasis, history: &LoadHistory, nodes: &[usize]) -> Result<Vec<Vec<f64>>, Error> {
    history.check(basis.shapes.nrows())?;
    let xis: Vec<Vec<f64>> = history.loads.iter().map(|q| basis.modal_load(q)).collect();
    let mut theta = vec![0.0; basis.len()];
    let mut out = Vec::with_capacity(history.times_s.len());
    let at_nodes =
        |theta: &[f64]| -> Vec<f64> { nodes.iter().map(|&r| (0..theta.len()).map(|i| basis.shape(r, i) * theta[i]).sum()).collect() };
    out.push(at_nodes(&theta));
    for k in 1..history.times_s.len() {
        let dt = history.times_s[k] - history.times_s[k - 1];
        for (i, th) in theta.iter_mut().enumerate() {
            let xi: f64 = xis.iter().zip(&history.inputs[k - 1]).map(|(x, u)| x[i] * u).sum();
            let decay = (-basis.lambda[i] * dt).exp();
            *th = decay * *th + (1.0 - decay) / basis.lambda[i] * xi;
        }
        out.push(at_nodes(&theta));
    }
    Ok(out)
}

/// Temperatures at `nodes` at every time of `history` by the theta method (`theta = 1` backward
/// Euler, `0.5` Crank-Nicolson) with `substeps` equal steps per interval:
/// `(C/dt + theta K) T+ = (C/dt - (1-theta) K) T + Q` (Q constant over the interval).
pub fn time_stepping(
    system: &ThermalSystem,
    history: &LoadHistory,
    nodes: &[usize],
    theta: f64,
    substeps: usize,
) -> Result<Vec<Vec<f64>>, Error> {
    let n = system.node_count();
    history.check(n)?;
    if !(0.5..=1.0).contains(&theta) || substeps == 0 {
        return Err(Error::input("theta must lie in [0.5, 1] and substeps be at least 1"));
    }
    let mut t = vec![0.0; n];
    let mut out = vec![nodes.iter().map(|&r| t[r]).collect::<Vec<f64>>()];
    let (mut ct, mut kt, mut rhs, mut q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut factor: Option<(f64, faer::sparse::linalg::solvers::Llt<usize, f64>)> = None;
    for k in 1..history.times_s.len() {
        let dt = (history.times_s[k] - history.times_s[k - 1]) / substeps as f64;
        if factor.as_ref().is_none_or(|(d, _)| (d - dt).abs() > 1e-12 * dt) {
            let mut trip = Vec::new();
            for (m, f) in [(&system.capacity, 1.0 / dt), (&system.conductivity, theta)] {
                let (cp, ri, val) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
                for j in 0..n {
                    for p in cp[j]..cp[j + 1] {
                        trip.push(Triplet::new(ri[p], j, f * val[p]));
                    }
                }
            }
            let a = from_triplets(n, &trip)?;
            let llt =
                a.sp_cholesky(Side::Lower).map_err(|e| Error::computation(format!("C/dt + theta K is not positive definite: {e:?}")))?;
            factor = Some((dt, llt));
        }
        let llt = &factor.as_ref().expect("factored").1;
        q.iter_mut().for_each(|v| *v = 0.0);
        for (load, u) in history.loads.iter().zip(&history.inputs[k - 1]) {
            q.iter_mut().zip(load).for_each(|(a, b)| *a += u * b);
        }
        for _ in 0..substeps {
            sparse_mul(&system.capacity, &t, &mut ct);
            sparse_mul(&system.conductivity, &t, &mut kt);
            for r in 0..n {
                rhs[r] = ct[r] / dt - (1.0 - theta) * kt[r] + q[r];
            }
            llt.solve_in_place(MatMut::from_column_major_slice_mut(&mut rhs, n, 1));
            t.copy_from_slice(&rhs);
        }
        out.push(nodes.iter().map(|&r| t[r]).collect());
    }
    Ok(out)
}
