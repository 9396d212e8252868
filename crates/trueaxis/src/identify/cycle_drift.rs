//! Per-cycle linear drift removal (Soons 1993 §3.2.2): within each back-and-forth cycle, the error
//! is fitted by a straight line against elapsed time and the time-linear part removed.

use super::IdentifyError;

/// Drift found in one cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleDrift {
    pub cycle: i64,
    /// Drift rate (unit of the values per s).
    pub rate: f64,
    /// Level of the cycle relative to the mean of all cycles (unit of the values), removed too.
    pub offset: f64,
}

/// Removes per-cycle drift from `values` (um or urad) at times `time_s` (s).
///
/// In each cycle, `values = a + b (t - t_mean) + c d` is fitted by least squares, with `d = +1/-1` the
/// direction of approach when `direction` is given (so that backlash, antisymmetric in time over a
/// back-and-forth cycle, does not bias the slope; without it Soons 1993 §3.2.2 allows drift removal
/// only when backlash is insignificant). The time-linear part `b (t - t_mean)` is removed, and so is
/// the difference between the cycle's level `a` and the mean level of all cycles (drift between
/// cycles). On a back-and-forth cycle at a uniform pace the position-dependent error is symmetric in
/// time about the cycle middle and does not project onto the slope.
pub fn remove_cycle_drift(
    cycles: &[i64],
    time_s: &[f64],
    values: &[f64],
    direction: Option<&[f64]>,
) -> Result<(Vec<f64>, Vec<CycleDrift>), IdentifyError> {
    let n = values.len();
    if cycles.len() != n || time_s.len() != n || direction.is_some_and(|d| d.len() != n) {
        return Err(IdentifyError::Input("cycle, time, direction and value columns must have the same length".into()));
    }
    let mut ids: Vec<i64> = cycles.to_vec();
    ids.sort_unstable();
    ids.dedup();
    let mut fits = Vec::new();
    for &id in &ids {
        let idx: Vec<usize> = (0..n).filter(|&i| cycles[i] == id).collect();
        let columns = if direction.is_some() { 3 } else { 2 };
        if idx.len() < columns + 1 {
            return Err(IdentifyError::Input(format!(
                "cycle {id} has {} samples; drift removal needs at least {}",
                idx.len(),
                columns + 1
            )));
        }
        let tm = idx.iter().map(|&i| time_s[i]).sum::<f64>() / idx.len() as f64;
        let x = nalgebra::DMatrix::from_fn(idx.len(), columns, |r, c| match c {
            0 => 1.0,
            1 => time_s[idx[r]] - tm,
            _ => direction.map_or(0.0, |d| d[idx[r]]),
        });
        let y = nalgebra::DVector::from_iterator(idx.len(), idx.iter().map(|&i| values[i]));
        let beta = x.clone().svd(true, true).solve(&y, 1e-12).map_err(|e| IdentifyError::Input(format!("cycle {id}: {e}")))?;
        if x.column(1).norm() == 0.0 {
            return Err(IdentifyError::Input(format!("cycle {id}: all samples have the same time")));
        }
        if direction.is_some() && x.column(2).iter().all(|d| *d == x[(0, 2)]) {
            return Err(IdentifyError::Input(format!("cycle {id} has one direction only; drift removal needs back-and-forth cycles")));
        }
        fits.push((id, idx, tm, beta[0], beta[1]));
    }
    let mean_level = fits.iter().map(|f| f.3).sum::<f64>() / fits.len() as f64;
    let mut out = values.to_vec();
    let mut drifts = Vec::new();
    for (id, idx, tm, level, rate) in fits {
        for &i in &idx {
            out[i] -= rate * (time_s[i] - tm) + (level - mean_level);
        }
        drifts.push(CycleDrift { cycle: id, rate, offset: level - mean_level });
    }
    Ok((out, drifts))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drift_is_removed_and_the_error_shape_and_backlash_kept() {
        // three back-and-forth cycles over 0..100 mm, e(x) = 0.001 x^2 - 0.05 x, backlash +-0.3,
        // drift 0.02 um/s throughout (so the cycles also sit at different levels)
        let e = |x: f64| 0.001 * x * x - 0.05 * x;
        let (mut cyc, mut t, mut v, mut d, mut xs) = (vec![], vec![], vec![], vec![], vec![]);
        let mut time = 0.0;
        for c in 0..3 {
            let forward: Vec<f64> = (0..=10).map(|i| 10.0 * i as f64).collect();
            for (dir, seq) in [(1.0, forward.clone()), (-1.0, forward.iter().rev().copied().collect())] {
                for x in seq {
                    cyc.push(c);
                    t.push(time);
                    d.push(dir);
                    xs.push(x);
                    v.push(e(x) + 0.3 * dir + 0.02 * time);
                    time += 5.0;
                }
            }
        }
        let (clean, drifts) = remove_cycle_drift(&cyc, &t, &v, Some(&d)).unwrap();
        for dr in &drifts {
            assert!((dr.rate - 0.02).abs() < 1e-12, "{dr:?}");
        }
        // every cycle now reads the same error shape with the same backlash
        let level = clean[0] - (e(xs[0]) + 0.3 * d[0]);
        for i in 0..clean.len() {
            assert!((clean[i] - (e(xs[i]) + 0.3 * d[i]) - level).abs() < 1e-9, "sample {i}");
        }
    }
}
