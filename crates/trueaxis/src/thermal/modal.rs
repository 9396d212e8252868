//! Thermal modal analysis (Zhu 2008 §3.2.1, eqs. 3.2-3.10): the generalised symmetric eigenproblem
//! `K phi = C phi lambda` with C-orthonormal modes (`Phi^T C Phi = I`, `Phi^T K Phi = Lambda`;
//! the seed's eq. 3.7 prints `[A]` for `Lambda`), time constants `tau = 1/lambda` (eq. 3.3), and the
//! modal load `xi = Phi^T Q` (eq. 3.8).
//!
//! Small models: dense Cholesky `C = L L^T` and the symmetric eigendecomposition of
//! `L^-1 K L^-T` (faer). Large sparse models: the partial spectrum by shift-invert block Lanczos
//! ([`super::lanczos`]).

use super::assembly::{diagonal, to_dense, uniform_decay_rate, ThermalSystem};
use super::lanczos::{smallest_eigenpairs_with, LanczosOptions, LanczosProgress};
use super::lobpcg::{smallest_eigenpairs_lobpcg, LobpcgOptions};
use crate::error::Error;
use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
use faer::{Mat, Par, Side};

/// Which eigensolver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumMethod {
    /// Dense up to [`DENSE_LIMIT`] nodes, shift-invert Lanczos up to [`LANCZOS_LIMIT`], LOBPCG
    /// with a multigrid preconditioner above.
    Auto,
    /// Full spectrum, dense.
    Dense,
    /// Partial spectrum, sparse shift-invert block Lanczos (a sparse Cholesky factor).
    Lanczos,
    /// Partial spectrum, LOBPCG preconditioned by smoothed-aggregation multigrid (no factor: memory
    /// and work proportional to the nonzeros).
    Lobpcg,
}

/// Largest model solved densely by [`SpectrumMethod::Auto`] when a number of modes is asked for
/// (all modes are always dense): for 20 modes of the benchmark block the dense solver and the
/// shift-invert Lanczos take the same time near 400 nodes; at 1000 nodes Lanczos takes 70 ms, the
/// dense solver 450 ms.
pub const DENSE_LIMIT: usize = 400;
/// Largest model solved by shift-invert Lanczos by [`SpectrumMethod::Auto`]; LOBPCG above. On the
/// benchmark block (3D, trilinear hexahedra) the two take the same time near 3 x 10^4 nodes; at
/// 10^5 nodes LOBPCG takes two thirds of the time, at 10^6 a fifth and a third of the memory.
pub const LANCZOS_LIMIT: usize = 50_000;

/// Options of [`modal_analysis`].
#[derive(Clone, Copy, Debug)]
pub struct ModalOptions {
    /// Number of modes (lowest first); `None` = all (dense only).
    pub count: Option<usize>,
    pub method: SpectrumMethod,
    pub lanczos: LanczosOptions,
    pub lobpcg: LobpcgOptions,
}

impl Default for ModalOptions {
    fn default() -> Self {
        ModalOptions { count: None, method: SpectrumMethod::Auto, lanczos: LanczosOptions::default(), lobpcg: LobpcgOptions::default() }
    }
}

/// Eigenvalues `lambda` (1/s, ascending) and C-orthonormal mode shapes (columns, K^(-1/2)... units
/// of `1/sqrt(J/K)`), so that temperatures are `T = Phi theta` (eq. 3.4).
#[derive(Clone, Debug)]
pub struct ModalBasis {
    pub lambda: Vec<f64>,
    pub shapes: Mat<f64>,
}

impl ModalBasis {
    pub fn len(&self) -> usize {
        self.lambda.len()
    }

    pub fn is_empty(&self) -> bool {
        self.lambda.is_empty()
    }

    /// Time constant of mode i in s (eq. 3.3).
    pub fn tau_s(&self, i: usize) -> f64 {
        1.0 / self.lambda[i]
    }

    /// Modal load `xi = Phi^T Q` (eq. 3.8), Q in W.
    pub fn modal_load(&self, q: &[f64]) -> Vec<f64> {
        (0..self.len()).map(|i| (0..q.len()).map(|r| self.shapes[(r, i)] * q[r]).sum()).collect()
    }

    /// Value of mode i at node r.
    pub fn shape(&self, r: usize, i: usize) -> f64 {
        self.shapes[(r, i)]
    }
}

/// The modes of `system`, each with a deterministic sign (its first entry of at least half the
/// largest magnitude is positive).
/// A model that loses no heat (no convection anywhere) has a mode with an infinite time constant
/// and is refused.
pub fn modal_analysis(system: &ThermalSystem, options: &ModalOptions) -> Result<ModalBasis, Error> {
    modal_analysis_with_progress(system, options, &mut |_| {})
}

/// [`modal_analysis`] reporting the progress of the sparse solver (factorisation, then converged
/// modes per block step) to `progress`. The sparse factor is ordered by nested dissection when the
/// system has node coordinates (meshes), else by approximate minimum degree.
pub fn modal_analysis_with_progress(
    system: &ThermalSystem,
    options: &ModalOptions,
    progress: &mut dyn FnMut(LanczosProgress),
) -> Result<ModalBasis, Error> {
    let n = system.node_count();
    if n == 0 {
        return Err(Error::input("the thermal model has no nodes"));
    }
    if loses_no_heat(system) {
        return Err(Error::input(
            "the model loses no heat (no convection and no fixed temperature anywhere): a uniform temperature rise would never decay, so its time constant is infinite; add convection",
        ));
    }
    let method = match options.method {
        SpectrumMethod::Auto if n <= DENSE_LIMIT || options.count.is_none_or(|c| 2 * (c + 2 * options.lanczos.block) >= n) => {
            SpectrumMethod::Dense
        }
        SpectrumMethod::Auto if n <= LANCZOS_LIMIT => SpectrumMethod::Lanczos,
        SpectrumMethod::Auto => SpectrumMethod::Lobpcg,
        method => method,
    };
    let count = || options.count.ok_or_else(|| Error::input("the sparse solver needs a number of modes"));
    let (mut lambda, mut shapes) = match method {
        SpectrumMethod::Lanczos => smallest_eigenpairs_with(
            &system.conductivity,
            &system.capacity,
            system.coordinates.as_deref(),
            count()?,
            &options.lanczos,
            progress,
        )?,
        SpectrumMethod::Lobpcg => smallest_eigenpairs_lobpcg(&system.conductivity, &system.capacity, count()?, &options.lobpcg, progress)?,
        _ => {
            let (l, s) = dense_eigenpairs(system)?;
            let keep = options.count.unwrap_or(n).min(n);
            (l[..keep].to_vec(), s.subcols(0, keep).to_owned())
        }
    };
    let largest = lambda.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    if let Some(i) = lambda.iter().position(|l| l.is_nan() || *l <= 1e-12 * largest) {
        return Err(Error::input(format!(
            "mode {} has eigenvalue {:.3e} 1/s: the model loses no heat (add convection), so its time constant is infinite",
            i + 1,
            lambda[i]
        )));
    }
    // deterministic sign: the first node reaching half the largest magnitude is positive
    for i in 0..lambda.len() {
        let big = (0..n).fold(0.0f64, |a, r| a.max(shapes[(r, i)].abs()));
        if let Some(r) = (0..n).find(|&r| shapes[(r, i)].abs() >= 0.5 * big) {
            if shapes[(r, i)] < 0.0 {
                for r in 0..n {
                    shapes[(r, i)] = -shapes[(r, i)];
                }
            }
        }
    }
    lambda.iter_mut().for_each(|l| *l = l.max(0.0));
    Ok(ModalBasis { lambda, shapes })
}

/// Whether a uniform temperature is (numerically) in the null space of K: its decay rate
/// ([`uniform_decay_rate`]) is below 1e-12 of the largest `K_ii / C_ii`.
fn loses_no_heat(system: &ThermalSystem) -> bool {
    let (k, c) = (&system.conductivity, &system.capacity);
    let largest = diagonal(k).iter().zip(diagonal(c)).map(|(kd, cd)| kd / cd).filter(|r| r.is_finite()).fold(0.0f64, f64::max);
    largest > 0.0 && uniform_decay_rate(k, c).abs() <= 1e-12 * largest
}

/// All eigenpairs (ascending) by dense Cholesky of C and the eigendecomposition of `L^-1 K L^-T`.
pub fn dense_eigenpairs(system: &ThermalSystem) -> Result<(Vec<f64>, Mat<f64>), Error> {
    let n = system.node_count();
    if n > 20_000 {
        return Err(Error::input(format!("{n} nodes are too many for the dense eigensolver: ask for a number of modes")));
    }
    let c = to_dense(&system.capacity);
    let k = to_dense(&system.conductivity);
    let llt = c.llt(Side::Lower).map_err(|_| Error::input("the capacity matrix C is not positive definite"))?;
    let l = llt.L();
    // A = L^-1 K L^-T: X = L^-1 K, then A = L^-1 X^T (= A^T = A)
    let mut x = k;
    solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
    let mut a = x.transpose().to_owned();
    solve_lower_triangular_in_place(l, a.as_mut(), Par::Seq);
    let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let evd = a.self_adjoint_eigen(Side::Lower).map_err(|e| Error::computation(format!("the eigensolver failed: {e:?}")))?;
    let lambda: Vec<f64> = (0..n).map(|i| evd.S().column_vector()[i]).collect();
    let mut phi = evd.U().to_owned();
    solve_upper_triangular_in_place(l.transpose(), phi.as_mut(), Par::Seq);
    Ok((lambda, phi))
}
