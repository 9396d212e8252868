//! Basis functions for parametric errors (Soons 1993 ch. 3): an error is `E(x) = sum_l beta_l p_l(x)`
//! with `p_l` from
//! - truncated-power piecewise polynomials with fixed knots and per-knot continuity (eqs. 3.2-3.3),
//! - Legendre polynomials over the axis range,
//! - B-splines (the same piecewise polynomials as the truncated powers with continuity
//!   `degree - 1` at every knot, in the local, well-conditioned basis of de Boor),
//! - periodic terms of a wavelength, continuous across the period boundary (eqs. 3.11-3.15),
//!
//! optionally constrained to have no linear trend over the axis range (straightness, eqs. 3.4-3.8)
//! or no once-per-revolution term (rotary axes, eqs. 3.9-3.10).
//!
//! Positions `x` are in user units (mm, or deg for rotary axes). A basis with its coefficients is an
//! [`super::ErrorFunction::Basis`].

use super::quadrature::{integrate, legendre};
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// What a basis is made of; stored in error-values files as `[basis.NAME]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BasisSpec {
    /// `"piecewise"` (truncated powers, the default), `"bspline"`, `"legendre"`, or `"none"`
    /// (periodic terms only).
    #[serde(default = "default_family")]
    pub family: String,
    /// Polynomial degree (piecewise: of each piece; legendre: highest order).
    #[serde(default = "default_degree")]
    pub degree: usize,
    /// Interior knots (mm or deg) of the piecewise family.
    #[serde(default)]
    pub knots: Vec<f64>,
    /// Continuity order at each knot: `c` keeps derivatives up to `c` continuous (so only the terms
    /// `(x - t)_+^l`, `l > c`, are added). One value for all knots, or one per knot.
    #[serde(default = "default_continuity")]
    pub continuity: Vec<usize>,
    /// Include the constant term (most errors are defined only up to a constant: false).
    #[serde(default)]
    pub constant: bool,
    /// `"none"`, `"straightness"` (no linear trend over `domain`, eqs. 3.4-3.8) or `"revolution"`
    /// (no once-per-revolution term over `domain` in deg, eqs. 3.9-3.10).
    #[serde(default = "default_constraint")]
    pub constraint: String,
    /// Axis range `[min, max]` the basis is defined on (mm or deg): the Legendre scaling and the
    /// domain of the constraints.
    pub domain: [f64; 2],
    /// Periodic terms (eqs. 3.11-3.15).
    #[serde(default)]
    pub periodic: Vec<PeriodicSpec>,
}

/// One periodic component: a C^(n-1)-continuous piecewise polynomial in the wavelength fraction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PeriodicSpec {
    /// Wavelength (mm or deg).
    pub wavelength: f64,
    /// Phase (mm or deg): `w = frac((x - phase) / wavelength)`.
    #[serde(default)]
    pub phase: f64,
    /// Degree of the polynomial pieces in `w`.
    #[serde(default = "default_degree")]
    pub degree: usize,
    /// Interior knots in `w`, within (0, 1).
    #[serde(default)]
    pub knots: Vec<f64>,
    /// Continuity order at the knots and across the period boundary.
    #[serde(default = "default_periodic_continuity")]
    pub continuity: usize,
}

fn default_family() -> String {
    "piecewise".into()
}
fn default_degree() -> usize {
    2
}
fn default_continuity() -> Vec<usize> {
    vec![1]
}
fn default_periodic_continuity() -> usize {
    1
}
fn default_constraint() -> String {
    "none".into()
}

/// A raw (unconstrained) basis function of the position.
#[derive(Clone, Debug, PartialEq)]
enum Raw {
    /// `x^l`
    Power(i32),
    /// `(x - knot)_+^l`
    Truncated { knot: f64, power: i32 },
    /// `P_l(u)`, `u = 2 (x - a)/(b - a) - 1`
    Legendre { order: usize, a: f64, b: f64 },
    /// `B_(index, degree)(x)` on the clamped knot vector `knots` (the domain ends repeated
    /// `degree + 1` times around the interior knots); `x` held within the domain.
    BSpline { knots: std::sync::Arc<[f64]>, index: usize, degree: usize },
    /// `g(w) - alpha_1 w - alpha_2 w^2 - ...`, `w = frac((x - phase)/wavelength)`, `g` a power or a
    /// truncated power of `w`
    Periodic { wavelength: f64, phase: f64, g: Box<Raw>, alpha: Vec<f64> },
}

impl Raw {
    fn eval(&self, x: f64) -> f64 {
        match self {
            Raw::Power(l) => x.powi(*l),
            Raw::Truncated { knot, power } => {
                if x > *knot {
                    (x - knot).powi(*power)
                } else {
                    0.0
                }
            }
            Raw::Legendre { order, a, b } => legendre(*order, 2.0 * (x - a) / (b - a) - 1.0).0,
            Raw::BSpline { knots, index, degree } => bspline(knots, *index, *degree, x),
            Raw::Periodic { wavelength, phase, g, alpha } => {
                let w = ((x - phase) / wavelength).rem_euclid(1.0);
                g.eval(w) - alpha.iter().enumerate().map(|(c, a)| a * w.powi(c as i32 + 1)).sum::<f64>()
            }
        }
    }

    /// Derivative of order `k` of a power or truncated power of `w` (periodic construction).
    fn derivative(&self, w: f64, k: i32) -> f64 {
        let (base, power) = match self {
            Raw::Power(l) => (w, *l),
            Raw::Truncated { knot, power } => (if w > *knot { w - knot } else { return 0.0 }, *power),
            _ => unreachable!("periodic terms are built from powers"),
        };
        if k > power {
            return 0.0;
        }
        let falling: f64 = (0..k).map(|i| (power - i) as f64).product();
        falling * base.powi(power - k)
    }

    fn describe(&self) -> String {
        match self {
            Raw::Power(l) => format!("x^{l}"),
            Raw::Truncated { knot, power } if *knot < 0.0 => format!("(x+{})_+^{power}", -knot),
            Raw::Truncated { knot, power } => format!("(x-{knot})_+^{power}"),
            Raw::Legendre { order, .. } => format!("P{order}"),
            Raw::BSpline { knots, index, degree } => format!("B{degree}[{index}] on [{}, {}]", knots[*index], knots[index + degree + 1]),
            Raw::Periodic { wavelength, g, .. } => format!("periodic[{wavelength}] {}", g.describe().replace('x', "w")),
        }
    }
}

/// A linear correction subtracted from a raw function to satisfy a constraint.
#[derive(Clone, Debug, PartialEq)]
enum Correction {
    None,
    /// `- a1 - a2 x` (straightness, eq. 3.4)
    Line(f64, f64),
    /// `- a1 cos x - a2 sin x`, x in deg (revolution, eq. 3.9)
    Revolution(f64, f64),
}

/// An evaluated basis: functions `p_l(x)` (Soons 1993 eq. 3.1 / 4.2).
#[derive(Clone, Debug, PartialEq)]
pub struct Basis {
    pub spec: BasisSpec,
    functions: Vec<(Raw, Correction)>,
}

impl Basis {
    /// Builds the basis of a spec, checking it (knots inside the domain and increasing, wavelengths
    /// positive, ...). Functions that vanish identically (a periodic `w` or `w^2` made continuous) are
    /// dropped.
    pub fn new(spec: BasisSpec) -> Result<Basis> {
        let [a, b] = spec.domain;
        if !(a.is_finite() && b.is_finite() && a < b) {
            return Err(Error::input(format!("domain [{a}, {b}] must be two finite numbers, the smaller first")));
        }
        let mut raws = Vec::new();
        match spec.family.as_str() {
            "piecewise" => {
                check_knots(&spec.knots, a, b)?;
                let continuity = match spec.continuity.len() {
                    1 => vec![spec.continuity[0]; spec.knots.len()],
                    n if n == spec.knots.len() => spec.continuity.clone(),
                    n => {
                        return Err(Error::input(format!("`continuity` has {n} values; give one, or one per knot ({})", spec.knots.len())))
                    }
                };
                let first = if spec.constant { 0 } else { 1 };
                raws.extend((first..=spec.degree as i32).map(Raw::Power));
                for (knot, c) in spec.knots.iter().zip(continuity) {
                    raws.extend((c as i32 + 1..=spec.degree as i32).map(|power| Raw::Truncated { knot: *knot, power }));
                }
            }
            "bspline" => raws.extend(bspline_functions(&spec)?),
            "legendre" => {
                let first = if spec.constant { 0 } else { 1 };
                raws.extend((first..=spec.degree).map(|order| Raw::Legendre { order, a, b }));
            }
            "none" => {}
            other => return Err(Error::input(format!("unknown basis family `{other}` (piecewise, bspline, legendre, none)"))),
        }
        for p in &spec.periodic {
            raws.extend(periodic_functions(p)?);
        }
        let functions = raws
            .into_iter()
            .map(|raw| {
                let correction = constraint_correction(&spec.constraint, &raw, a, b, &spec.knots)?;
                Ok((raw, correction))
            })
            .collect::<Result<Vec<_>>>()?;
        let basis = Basis { spec, functions };
        Ok(basis.without_vanishing_functions())
    }

    fn without_vanishing_functions(mut self) -> Basis {
        let [a, b] = self.spec.domain;
        let probe: Vec<f64> = (0..=997).map(|i| a + (b - a) * i as f64 / 997.0).collect();
        self.functions.retain(|f| probe.iter().any(|x| eval_one(f, *x).abs() > 1e-9));
        self
    }

    pub fn len(&self) -> usize {
        self.functions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.functions.is_empty()
    }

    /// Evaluates every basis function at `x` into `out` (length [`Basis::len`]).
    pub fn eval_into(&self, x: f64, out: &mut [f64]) {
        self.for_each_value(x, |i, v| out[i] = v);
    }

    /// `sum_l coefficients[l] p_l(x)`.
    pub fn eval(&self, coefficients: &[f64], x: f64) -> f64 {
        let mut sum = 0.0;
        self.for_each_value(x, |i, v| sum += coefficients[i] * v);
        sum
    }

    /// Calls `f(l, p_l(x))` for every function in order. Consecutive Legendre orders continue one
    /// three-term recurrence (`k P_k = (2k - 1) u P_(k-1) - (k - 1) P_(k-2)`), so orders 1..n cost n
    /// steps instead of n^2 / 2; the values are the same bits as [`legendre`] of each order.
    fn for_each_value(&self, x: f64, mut f: impl FnMut(usize, f64)) {
        // (u, k, P_(k-1)(u), P_k(u)) of the last Legendre function evaluated
        let mut last: Option<(f64, usize, f64, f64)> = None;
        for (l, function) in self.functions.iter().enumerate() {
            let value = match function.0 {
                Raw::Legendre { order, a, b } => {
                    let u = 2.0 * (x - a) / (b - a) - 1.0;
                    let (previous, current) = match last {
                        Some((v, k, p0, p1)) if v == u && k + 1 == order => {
                            let n = order as f64;
                            (p1, ((2.0 * n - 1.0) * u * p1 - (n - 1.0) * p0) / n)
                        }
                        _ => (if order == 0 { 0.0 } else { legendre(order - 1, u).0 }, legendre(order, u).0),
                    };
                    last = Some((u, order, previous, current));
                    current - function.1.at(x)
                }
                _ => eval_one(function, x),
            };
            f(l, value);
        }
    }

    /// A readable name of each function, e.g. `(x-150)_+^2` or `periodic[0.635025] w^3`.
    pub fn names(&self) -> Vec<String> {
        self.functions
            .iter()
            .map(|(raw, c)| match c {
                Correction::None => raw.describe(),
                Correction::Line(..) => format!("{} (no trend)", raw.describe()),
                Correction::Revolution(..) => format!("{} (no 1/rev)", raw.describe()),
            })
            .collect()
    }

    /// For each function, the power of the position (mm or deg) its value carries: `x^l` and
    /// `(x - t)_+^l` are in position units to the `l`; Legendre, B-spline and periodic functions (of
    /// the scaled position, of the wavelength fraction) are dimensionless.
    pub fn position_powers(&self) -> Vec<i32> {
        self.functions
            .iter()
            .map(|(raw, _)| match raw {
                Raw::Power(l) | Raw::Truncated { power: l, .. } => *l,
                Raw::Legendre { .. } | Raw::BSpline { .. } | Raw::Periodic { .. } => 0,
            })
            .collect()
    }

    /// Keeps only the functions whose indices are listed (stepwise selection).
    pub fn select(&self, keep: &[usize]) -> Basis {
        Basis { spec: self.spec.clone(), functions: keep.iter().map(|&i| self.functions[i].clone()).collect() }
    }
}

fn eval_one((raw, correction): &(Raw, Correction), x: f64) -> f64 {
    raw.eval(x) - correction.at(x)
}

impl Correction {
    /// The subtracted trend at `x`.
    fn at(&self, x: f64) -> f64 {
        match self {
            Correction::None => 0.0,
            Correction::Line(a1, a2) => a1 + a2 * x,
            Correction::Revolution(a1, a2) => a1 * x.to_radians().cos() + a2 * x.to_radians().sin(),
        }
    }
}

/// Interior knots of the piecewise and B-spline families: finite, strictly inside `(a, b)`,
/// strictly increasing.
fn check_knots(knots: &[f64], a: f64, b: f64) -> Result<()> {
    if knots.iter().any(|t| !t.is_finite() || *t <= a || *t >= b) {
        return Err(Error::input(format!("knots must lie strictly inside the domain [{a}, {b}]")));
    }
    if knots.windows(2).any(|w| w[1] <= w[0]) {
        return Err(Error::input("knots must increase strictly"));
    }
    Ok(())
}

/// Highest B-spline degree (the evaluation keeps its `degree + 1` values on the stack).
const BSPLINE_MAX_DEGREE: usize = 7;

/// The B-splines of a `bspline` spec (de Boor, A Practical Guide to Splines, ch. IX): degree k,
/// interior knots `t`, clamped at the domain ends, `len(t) + k + 1` functions that sum to 1. They
/// span the truncated-power piecewise polynomials with continuity `k - 1` at every knot. Which are
/// kept: without the constant term the first is left out (the error is zero at the domain start);
/// with the straightness constraint (each function minus its line over the domain), the first and
/// the last are left out: the corrected functions satisfy exactly two linear relations (their sum
/// and their sum weighted by the Greville abscissae are zero), in which the first and last have
/// independent coefficients, so the rest is a basis of the splines without a linear trend.
fn bspline_functions(spec: &BasisSpec) -> Result<Vec<Raw>> {
    let [a, b] = spec.domain;
    let k = spec.degree;
    if !(1..=BSPLINE_MAX_DEGREE).contains(&k) {
        return Err(Error::input(format!("a B-spline degree must be 1 to {BSPLINE_MAX_DEGREE}, got {k}")));
    }
    check_knots(&spec.knots, a, b)?;
    let knots: std::sync::Arc<[f64]> =
        std::iter::repeat_n(a, k + 1).chain(spec.knots.iter().copied()).chain(std::iter::repeat_n(b, k + 1)).collect();
    let count = spec.knots.len() + k + 1;
    let keep = |i: usize| match spec.constraint.as_str() {
        "straightness" => i != 0 && i != count - 1,
        _ => spec.constant || i != 0,
    };
    Ok((0..count).filter(|&i| keep(i)).map(|index| Raw::BSpline { knots: knots.clone(), index, degree: k }).collect())
}

/// `B_(i,k)(x)` by the Cox-de Boor recursion on its `k + 2` knots `t[i..=i+k+1]`; `x` is held within
/// `[t_0, t_last]`, and at `x = t_last` the last non-empty interval counts as closed (so that the
/// functions sum to 1 on the whole closed domain).
fn bspline(t: &[f64], i: usize, k: usize, x: f64) -> f64 {
    let (first, last) = (t[0], t[t.len() - 1]);
    let x = x.clamp(first, last);
    if x < t[i] || x > t[i + k + 1] {
        return 0.0;
    }
    let mut n = [0.0; BSPLINE_MAX_DEGREE + 1];
    for (j, value) in n.iter_mut().enumerate().take(k + 1) {
        let (lo, hi) = (t[i + j], t[i + j + 1]);
        let inside = (lo <= x && x < hi) || (x == last && hi == last && lo < hi);
        *value = if inside { 1.0 } else { 0.0 };
    }
    for d in 1..=k {
        for j in 0..=k - d {
            let (l0, l1, r0, r1) = (t[i + j], t[i + j + d], t[i + j + 1], t[i + j + d + 1]);
            let left = if l1 > l0 { (x - l0) / (l1 - l0) * n[j] } else { 0.0 };
            let right = if r1 > r0 { (r1 - x) / (r1 - r0) * n[j + 1] } else { 0.0 };
            n[j] = left + right;
        }
    }
    n[0]
}

/// The periodic functions of one spec: powers `w^l` and truncated powers `(w - t)_+^l` made
/// continuous across the period boundary up to order `continuity` by subtracting
/// `sum_{c=1..continuity+1} alpha_c w^c` (Soons 1993 eqs. 3.12-3.15).
///
/// ERRATUM (Soons 1993 eq. 3.14-3.15): the printed system `[[1,1],[1,2]] alpha = [g(1)-g(0); g'(1)-g'(0)]`
/// omits the derivative of the subtracted polynomial at `w = 0` (`alpha_1`); continuity of the
/// first derivative requires `2 alpha_2 = g'(1) - g'(0)`. In general, for derivative order `k`,
/// `sum_c alpha_c (d^k w^c/dw^k)(1) - (d^k w^c/dw^k)(0) = g^(k)(1) - g^(k)(0)`, which is solved here.
fn periodic_functions(p: &PeriodicSpec) -> Result<Vec<Raw>> {
    if !(p.wavelength.is_finite() && p.wavelength > 0.0) {
        return Err(Error::input(format!("periodic wavelength {} must be a positive number", p.wavelength)));
    }
    if !p.phase.is_finite() {
        return Err(Error::input("periodic phase must be a finite number"));
    }
    if p.knots.iter().any(|t| !(*t > 0.0 && *t < 1.0)) || p.knots.windows(2).any(|w| w[1] <= w[0]) {
        return Err(Error::input("periodic knots are fractions of the wavelength, increasing, strictly between 0 and 1"));
    }
    if p.continuity >= p.degree {
        return Err(Error::input(format!("periodic continuity {} must be below the degree {}", p.continuity, p.degree)));
    }
    let nc = p.continuity + 1;
    // matrix M[k][c] = d^k/dw^k (w^(c+1)) at 1 minus at 0, k = 0..nc-1
    let mut m = nalgebra::DMatrix::<f64>::zeros(nc, nc);
    for k in 0..nc {
        for c in 0..nc {
            let power = c as i32 + 1;
            let at = |w: f64| Raw::Power(power).derivative(w, k as i32);
            m[(k, c)] = at(1.0) - at(0.0);
        }
    }
    let lu = m.lu();
    let mut gs: Vec<Raw> = (1..=p.degree as i32).map(Raw::Power).collect();
    for &knot in &p.knots {
        gs.extend((p.continuity as i32 + 1..=p.degree as i32).map(|power| Raw::Truncated { knot, power }));
    }
    Ok(gs
        .into_iter()
        .map(|g| {
            let rhs = nalgebra::DVector::from_iterator(nc, (0..nc).map(|k| g.derivative(1.0, k as i32) - g.derivative(0.0, k as i32)));
            let alpha = lu.solve(&rhs).expect("the continuity system is triangular with a non-zero diagonal");
            Raw::Periodic { wavelength: p.wavelength, phase: p.phase, g: Box::new(g), alpha: alpha.iter().copied().collect() }
        })
        .collect())
}

/// The correction that removes the linear trend (eq. 3.8) or the once-per-revolution term (eq. 3.9,
/// the least-squares projection over the domain; eq. 3.10 for a full turn) of `raw` over `[a, b]`.
fn constraint_correction(constraint: &str, raw: &Raw, a: f64, b: f64, knots: &[f64]) -> Result<Correction> {
    let panels = 64;
    type Weight = Box<dyn Fn(f64) -> f64>;
    let (f1, f2): (Weight, Weight) = match constraint {
        "none" => return Ok(Correction::None),
        "straightness" => (Box::new(|_| 1.0), Box::new(|x| x)),
        "revolution" => (Box::new(|x: f64| x.to_radians().cos()), Box::new(|x: f64| x.to_radians().sin())),
        other => return Err(Error::input(format!("unknown constraint `{other}` (none, straightness, revolution)"))),
    };
    let i = |f: &dyn Fn(f64) -> f64| integrate(f, a, b, knots, panels);
    let g11 = i(&|x| f1(x) * f1(x));
    let g12 = i(&|x| f1(x) * f2(x));
    let g22 = i(&|x| f2(x) * f2(x));
    let r1 = i(&|x| raw.eval(x) * f1(x));
    let r2 = i(&|x| raw.eval(x) * f2(x));
    let det = g11 * g22 - g12 * g12;
    if det.abs() < 1e-12 * (g11 * g22).abs().max(1e-300) {
        return Err(Error::input(format!("the `{constraint}` constraint is undefined over the domain [{a}, {b}]")));
    }
    let a1 = (g22 * r1 - g12 * r2) / det;
    let a2 = (g11 * r2 - g12 * r1) / det;
    Ok(if constraint == "straightness" { Correction::Line(a1, a2) } else { Correction::Revolution(a1, a2) })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(family: &str, constraint: &str) -> BasisSpec {
        BasisSpec {
            family: family.into(),
            degree: 2,
            knots: vec![-100.0, 50.0],
            continuity: vec![1],
            constant: false,
            constraint: constraint.into(),
            domain: [-300.0, 300.0],
            periodic: vec![],
        }
    }

    #[test]
    fn truncated_powers_follow_the_continuity_rule() {
        // degree 2, C1 at two knots: x, x^2, (x+100)_+^2, (x-50)_+^2 (eq. 3.2 without the constant)
        let b = Basis::new(spec("piecewise", "none")).unwrap();
        assert_eq!(b.names(), vec!["x^1", "x^2", "(x+100)_+^2", "(x-50)_+^2"]);
        let mut s = spec("piecewise", "none");
        s.continuity = vec![0, 1];
        assert_eq!(Basis::new(s).unwrap().len(), 5, "C0 at the first knot adds (x+100)_+^1");
    }

    #[test]
    fn straightness_basis_has_no_mean_and_no_trend() {
        // Soons 1993 eqs. 3.6-3.7: integral p = integral p x = 0 over the domain
        let b = Basis::new(spec("piecewise", "straightness")).unwrap();
        assert_eq!(b.len(), 3, "x loses its trend and vanishes; x^2 and the two knot terms stay");
        for l in 0..b.len() {
            let f = |x: f64| {
                let mut w = vec![0.0; b.len()];
                b.eval_into(x, &mut w);
                w[l]
            };
            let m0 = integrate(f, -300.0, 300.0, &[-100.0, 50.0], 8);
            let m1 = integrate(|x| f(x) * x, -300.0, 300.0, &[-100.0, 50.0], 8);
            assert!(m0.abs() < 1e-9 * 300f64.powi(3), "{m0}");
            assert!(m1.abs() < 1e-9 * 300f64.powi(4), "{m1}");
        }
    }

    #[test]
    fn revolution_basis_has_no_once_per_turn_term() {
        // Soons 1993 eq. 3.10 over a full turn
        let mut s = spec("legendre", "revolution");
        s.domain = [0.0, 360.0];
        s.knots = vec![];
        s.degree = 4;
        let b = Basis::new(s).unwrap();
        for l in 0..b.len() {
            let f = |x: f64| {
                let mut w = vec![0.0; b.len()];
                b.eval_into(x, &mut w);
                w[l]
            };
            let c = integrate(|x| f(x) * x.to_radians().cos(), 0.0, 360.0, &[], 32);
            let s = integrate(|x| f(x) * x.to_radians().sin(), 0.0, 360.0, &[], 32);
            assert!(c.abs() < 1e-9 && s.abs() < 1e-9, "{c} {s}");
        }
    }

    #[test]
    fn periodic_terms_are_c1_across_the_period_boundary() {
        // eqs. 3.12-3.15 (corrected): value and slope continuous at w = 0 / 1
        let p = PeriodicSpec { wavelength: 0.635025, phase: 0.0, degree: 3, knots: vec![0.3, 0.7], continuity: 1 };
        let mut s = spec("none", "none");
        s.periodic = vec![p];
        let b = Basis::new(s).unwrap();
        assert!(b.len() >= 3);
        let h = 1e-7;
        let tau = 0.635025;
        for l in 0..b.len() {
            let f = |x: f64| {
                let mut w = vec![0.0; b.len()];
                b.eval_into(x, &mut w);
                w[l]
            };
            let x0 = 10.0 * tau; // a period boundary
            let left = f(x0 - h);
            let right = f(x0 + h);
            assert!((left - right).abs() < 1e-5, "value jump {left} {right}");
            let slope_left = (f(x0 - h) - f(x0 - 2.0 * h)) / h;
            let slope_right = (f(x0 + 2.0 * h) - f(x0 + h)) / h;
            assert!((slope_left - slope_right).abs() < 1e-3 * (1.0 + slope_left.abs()) / tau, "slope jump {slope_left} {slope_right}");
            assert!((f(x0 + 0.3 * tau) - f(x0 + 0.3 * tau + 7.0 * tau)).abs() < 1e-9, "periodic");
        }
    }

    #[test]
    fn bad_specs_are_refused() {
        let mut s = spec("piecewise", "none");
        s.knots = vec![400.0];
        assert!(Basis::new(s).unwrap_err().to_string().contains("inside the domain"));
        let mut s = spec("piecewise", "none");
        s.continuity = vec![1, 1, 1];
        assert!(Basis::new(s).unwrap_err().to_string().contains("one per knot"));
        assert!(Basis::new(spec("spline", "none")).unwrap_err().to_string().contains("unknown basis family"));
        assert!(Basis::new(spec("piecewise", "flat")).unwrap_err().to_string().contains("unknown constraint"));
        let mut s = spec("none", "none");
        s.periodic = vec![PeriodicSpec { wavelength: -1.0, phase: 0.0, degree: 2, knots: vec![], continuity: 1 }];
        assert!(Basis::new(s).unwrap_err().to_string().contains("positive"));
        for degree in [0, 8] {
            let mut s = spec("bspline", "none");
            s.degree = degree;
            assert!(Basis::new(s).unwrap_err().to_string().contains("B-spline degree must be 1 to 7"), "degree {degree}");
        }
        let mut s = spec("bspline", "none");
        s.knots = vec![50.0, -100.0];
        assert!(Basis::new(s).unwrap_err().to_string().contains("increase strictly"));
        let mut s = spec("bspline", "none");
        s.knots = vec![-300.0];
        assert!(Basis::new(s).unwrap_err().to_string().contains("inside the domain"));
    }

    #[test]
    fn legendre_recurrence_across_orders_equals_each_order_alone() {
        for constraint in ["none", "straightness"] {
            let mut s = spec("legendre", constraint);
            s.degree = 40;
            s.constant = true;
            let basis = Basis::new(s).unwrap();
            let mut out = vec![0.0; basis.len()];
            for x in [-300.0, -123.4, 0.0, 77.7, 299.9] {
                basis.eval_into(x, &mut out);
                for (l, f) in basis.functions.iter().enumerate() {
                    assert_eq!(out[l].to_bits(), eval_one(f, x).to_bits(), "{constraint} l = {l} x = {x}");
                }
                let coefficients: Vec<f64> = (0..basis.len()).map(|l| 1.0 / (1.0 + l as f64)).collect();
                let direct: f64 = basis.functions.iter().zip(&coefficients).map(|(f, c)| c * eval_one(f, x)).sum();
                assert!((basis.eval(&coefficients, x) - direct).abs() <= 1e-14 * direct.abs().max(1.0));
            }
        }
    }

    fn knotted(family: &str, knots: Vec<f64>, constant: bool, constraint: &str) -> Basis {
        let mut s = spec(family, constraint);
        s.degree = 3;
        s.knots = knots;
        s.continuity = vec![2];
        s.constant = constant;
        Basis::new(s).unwrap()
    }

    /// The `points x len` matrix of a basis at equally spaced positions over its domain.
    fn design(basis: &Basis, points: usize) -> nalgebra::DMatrix<f64> {
        let [a, b] = basis.spec.domain;
        let mut row = vec![0.0; basis.len()];
        nalgebra::DMatrix::from_fn(points, basis.len(), |i, j| {
            basis.eval_into(a + (b - a) * i as f64 / (points - 1) as f64, &mut row);
            row[j]
        })
    }

    /// Condition number of the matrix with unit-length columns.
    fn scaled_condition(mut m: nalgebra::DMatrix<f64>) -> f64 {
        for mut c in m.column_iter_mut() {
            let n = c.norm();
            c /= n;
        }
        let s = m.singular_values();
        s.max() / s.min()
    }

    #[test]
    fn bsplines_sum_to_one_and_span_the_truncated_powers() {
        let knots = vec![-220.0, -100.0, -10.0, 60.0, 200.0];
        let all = knotted("bspline", knots.clone(), true, "none");
        assert_eq!(all.len(), knots.len() + 4);
        let m = design(&all, 301);
        for (i, row) in m.row_iter().enumerate() {
            assert!((row.sum() - 1.0).abs() < 1e-14, "partition of unity at point {i}");
            assert!(row.iter().all(|v| *v >= 0.0) && row.iter().filter(|v| **v > 0.0).count() <= 4, "local support at point {i}");
        }
        // outside the domain the end values are held
        let mut out = vec![0.0; all.len()];
        all.eval_into(400.0, &mut out);
        assert_eq!(out[all.len() - 1], 1.0);
        // the same space as the truncated powers of continuity 2 (with and without a linear trend):
        // least squares of the same data give the same fit
        let data: Vec<f64> = (0..301).map(|i| (i as f64 * 0.05).sin() * 3.0 + (i as f64 * 0.013).cos()).collect();
        let y = nalgebra::DVector::from_vec(data);
        for constraint in ["none", "straightness"] {
            let (b, p) = (knotted("bspline", knots.clone(), true, constraint), knotted("piecewise", knots.clone(), true, constraint));
            assert_eq!(b.len(), p.len(), "{constraint}");
            let fit = |m: nalgebra::DMatrix<f64>| &m * m.clone().svd(true, true).solve(&y, 1e-12).unwrap();
            let (fb, fp) = (fit(design(&b, 301)), fit(design(&p, 301)));
            // (to the accuracy of the ill-conditioned truncated powers; another space differs by ~0.1)
            assert!((&fb - &fp).amax() < 1e-7 * y.amax(), "{constraint}: {}", (&fb - &fp).amax());
        }
        // without the constant term: zero at the domain start
        let no_constant = knotted("bspline", knots, false, "none");
        let mut out = vec![0.0; no_constant.len()];
        no_constant.eval_into(-300.0, &mut out);
        assert!(out.iter().all(|v| *v == 0.0));
    }

    #[test]
    fn bsplines_stay_well_conditioned_where_truncated_powers_do_not() {
        let knots: Vec<f64> = (1..=53).map(|i| -300.0 + 600.0 * i as f64 / 54.0).collect();
        let b = scaled_condition(design(&knotted("bspline", knots.clone(), false, "straightness"), 2000));
        let p = scaled_condition(design(&knotted("piecewise", knots, false, "straightness"), 2000));
        assert!(b < 1e3, "B-splines: condition number {b:.3e}");
        assert!(p > 1e4 * b, "truncated powers: condition number {p:.3e}, B-splines {b:.3e}");
    }
}
