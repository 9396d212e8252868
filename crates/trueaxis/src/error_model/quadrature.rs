//! Gauss-Legendre quadrature and Legendre polynomials, used to build constrained bases
//! (Soons 1993 eqs. 3.5-3.10 need integrals of basis functions over the axis range).

/// Legendre polynomial `P_n(u)` and its derivative, by the three-term recurrence.
pub fn legendre(n: usize, u: f64) -> (f64, f64) {
    if n == 0 {
        return (1.0, 0.0);
    }
    let (mut p0, mut p1) = (1.0, u);
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * u * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    let n = n as f64;
    let dp = if (1.0 - u * u).abs() < 1e-300 { 0.5 * n * (n + 1.0) * u.powi(n as i32 + 1) } else { n * (p0 - u * p1) / (1.0 - u * u) };
    (p1, dp)
}

/// Nodes and weights of the `n`-point Gauss-Legendre rule on [-1, 1] (Newton on `P_n`).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (1..=n)
        .map(|i| {
            let mut u = (std::f64::consts::PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre(n, u);
                let step = p / dp;
                u -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            let (_, dp) = legendre(n, u);
            (u, 2.0 / ((1.0 - u * u) * dp * dp))
        })
        .collect()
}

/// `integral_a^b f(x) dx`, split at `breaks` (e.g. knots) and into `panels` equal panels per piece,
/// 10-point Gauss-Legendre per panel: exact for piecewise polynomials up to degree 19.
pub fn integrate(f: impl Fn(f64) -> f64, a: f64, b: f64, breaks: &[f64], panels: usize) -> f64 {
    let rule = gauss_legendre(10);
    let mut points: Vec<f64> =
        std::iter::once(a).chain(breaks.iter().copied().filter(|t| *t > a && *t < b)).chain(std::iter::once(b)).collect();
    points.sort_by(f64::total_cmp);
    let mut sum = 0.0;
    for w in points.windows(2) {
        let h = (w[1] - w[0]) / panels as f64;
        for p in 0..panels {
            let (lo, hi) = (w[0] + h * p as f64, w[0] + h * (p + 1) as f64);
            let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            sum += rule.iter().map(|(u, wt)| wt * f(mid + half * u)).sum::<f64>() * half;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_is_exact_for_polynomials_and_accurate_for_cosines() {
        assert!((integrate(|x| x.powi(7) - 3.0 * x * x, -2.0, 3.0, &[], 1) - ((3f64.powi(8) - 2f64.powi(8)) / 8.0 - 35.0)).abs() < 1e-9);
        assert!((integrate(|x| x.cos().powi(2), 0.0, 2.0 * std::f64::consts::PI, &[], 16) - std::f64::consts::PI).abs() < 1e-13);
        let (p3, _) = legendre(3, 0.5);
        assert!((p3 - 0.5 * (5.0 * 0.125 - 1.5)).abs() < 1e-15);
    }
}
