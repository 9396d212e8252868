//! Stepwise selection of regressors by partial F tests (Soons 1993 §3.2.2: start from a generous
//! model, remove insignificant terms, re-admit significant ones; Montgomery & Peck).

use super::least_squares::{fit_linear, LinearFit};
use super::IdentifyError;
use nalgebra::DMatrix;
use statrs::distribution::{ContinuousCDF, FisherSnedecor};

/// The outcome of a stepwise selection.
#[derive(Clone, Debug)]
pub struct StepwiseResult {
    /// Indices (into the full design) of the kept columns, ascending.
    pub kept: Vec<usize>,
    /// The fit with the kept columns.
    pub fit: LinearFit,
    /// Each step taken: `(column, "removed" | "added", F statistic, critical F)`.
    pub steps: Vec<(usize, &'static str, f64, f64)>,
}

/// Critical value of `F(1, dof)` at confidence `level` (e.g. 0.9999 for the seed's 99.99 %).
pub fn f_critical(level: f64, dof: usize) -> f64 {
    FisherSnedecor::new(1.0, dof.max(1) as f64).map(|f| f.inverse_cdf(level)).unwrap_or(f64::INFINITY)
}

/// Backward elimination from all columns, then alternating forward/backward steps, each at the
/// partial F test `F = (RSS_reduced - RSS_full) / s^2_full` against `F(1, n - p)` at `level`.
/// Columns in `forced` are never removed.
pub fn stepwise(
    design: &DMatrix<f64>,
    y: &[f64],
    weights: Option<&[f64]>,
    names: &[String],
    level: f64,
    forced: &[usize],
) -> Result<StepwiseResult, IdentifyError> {
    if !(level > 0.0 && level < 1.0) {
        return Err(IdentifyError::Input(format!("significance level {level} must lie strictly between 0 and 1 (e.g. 0.9999)")));
    }
    let p = design.ncols();
    let fit_subset = |cols: &[usize]| -> Result<LinearFit, IdentifyError> {
        let sub = design.select_columns(cols.iter());
        let sub_names: Vec<String> = cols.iter().map(|&c| names.get(c).cloned().unwrap_or_else(|| format!("column {}", c + 1))).collect();
        fit_linear(&sub, y, weights, &sub_names)
    };
    let mut kept: Vec<usize> = (0..p).collect();
    let mut fit = fit_subset(&kept)?;
    let mut steps = Vec::new();
    for _ in 0..4 * p + 4 {
        let mut changed = false;
        // backward: the least significant kept column
        let mut weakest: Option<(usize, f64, LinearFit)> = None;
        for (pos, &c) in kept.iter().enumerate() {
            if forced.contains(&c) || kept.len() == 1 {
                continue;
            }
            let mut reduced = kept.clone();
            reduced.remove(pos);
            if let Ok(r) = fit_subset(&reduced) {
                let f = (r.rss - fit.rss) / (fit.sigma * fit.sigma);
                if weakest.as_ref().is_none_or(|w| f < w.1) {
                    weakest = Some((c, f, r));
                }
            }
        }
        if let Some((c, f, r)) = weakest {
            let crit = f_critical(level, fit.dof);
            if f < crit {
                kept.retain(|&k| k != c);
                fit = r;
                steps.push((c, "removed", f, crit));
                changed = true;
            }
        }
        // forward: the most significant excluded column
        let mut strongest: Option<(usize, f64, LinearFit)> = None;
        for c in (0..p).filter(|c| !kept.contains(c)) {
            let mut extended = kept.clone();
            extended.push(c);
            extended.sort_unstable();
            if let Ok(e) = fit_subset(&extended) {
                let f = (fit.rss - e.rss) / (e.sigma * e.sigma);
                if strongest.as_ref().is_none_or(|s| f > s.1) {
                    strongest = Some((c, f, e));
                }
            }
        }
        if let Some((c, f, e)) = strongest {
            let crit = f_critical(level, e.dof);
            let just_removed = steps.last().is_some_and(|s| s.0 == c);
            if f > crit && !just_removed {
                kept.push(c);
                kept.sort_unstable();
                fit = e;
                steps.push((c, "added", f, crit));
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    Ok(StepwiseResult { kept, fit, steps })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stepwise_drops_absent_terms_and_keeps_present_ones() {
        // y = 1.5 x - 0.8 x^3 + small deterministic noise; candidates x, x^2, x^3, x^4
        let xs: Vec<f64> = (0..60).map(|i| -1.0 + 2.0 * i as f64 / 59.0).collect();
        let noise = |i: usize| 1e-3 * ((i as f64 * 12.9898).sin() * 43758.5453).fract();
        let y: Vec<f64> = xs.iter().enumerate().map(|(i, x)| 1.5 * x - 0.8 * x.powi(3) + noise(i)).collect();
        let design = DMatrix::from_fn(60, 4, |i, j| xs[i].powi(j as i32 + 1));
        let names: Vec<String> = (1..=4).map(|k| format!("x^{k}")).collect();
        let result = stepwise(&design, &y, None, &names, 0.9999, &[]).unwrap();
        assert_eq!(result.kept, vec![0, 2]);
        assert!((result.fit.coefficients[0] - 1.5).abs() < 2e-3);
        assert!((result.fit.coefficients[1] + 0.8).abs() < 4e-3);
        // F(1, 56) at 99.99 %: about 17.1
        let f = f_critical(0.9999, 56);
        assert!(f > 16.0 && f < 18.5, "{f}");
    }
}
