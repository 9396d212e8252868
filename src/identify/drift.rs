//! Per-cycle linear drift removal (seed 000 §3.2.2): within each back-and-forth cycle, the error
//! is fitted by a straight line against elapsed time, and its slope part is removed.

use super::IdentifyError;

/// Removes, cycle by cycle, the time-linear part `b (t - t_mean)` of `values` (um), where `b` is the
/// least-squares slope of the values against time `t` (s) within the cycle. The cycle mean is kept
/// (the seed takes the residuals, which also removes it; for an error known up to a constant the two
/// are equivalent). On a back-and-forth cycle the position-dependent error is symmetric in time
/// about the cycle middle, so it does not project onto the slope. Only valid without significant
/// backlash (seed 000 §3.2.2). Returns the corrected values and the drift rate of each cycle (um/s).
pub fn remove_cycle_drift(cycles: &[i64], time_s: &[f64], values: &[f64]) -> Result<(Vec<f64>, Vec<(i64, f64)>), IdentifyError> {
    if cycles.len() != values.len() || time_s.len() != values.len() {
        return Err(IdentifyError::Input("cycle, time and value columns must have the same length".into()));
    }
    let mut ids: Vec<i64> = cycles.to_vec();
    ids.sort_unstable();
    ids.dedup();
    let mut out = values.to_vec();
    let mut rates = Vec::new();
    for id in ids {
        let idx: Vec<usize> = (0..values.len()).filter(|&i| cycles[i] == id).collect();
        if idx.len() < 3 {
            return Err(IdentifyError::Input(format!("cycle {id} has {} samples; drift removal needs at least 3", idx.len())));
        }
        let n = idx.len() as f64;
        let tm = idx.iter().map(|&i| time_s[i]).sum::<f64>() / n;
        let vm = idx.iter().map(|&i| values[i]).sum::<f64>() / n;
        let stt: f64 = idx.iter().map(|&i| (time_s[i] - tm).powi(2)).sum();
        if stt <= 0.0 {
            return Err(IdentifyError::Input(format!("cycle {id}: all samples have the same time")));
        }
        let slope = idx.iter().map(|&i| (time_s[i] - tm) * (values[i] - vm)).sum::<f64>() / stt;
        for &i in &idx {
            out[i] -= slope * (time_s[i] - tm);
        }
        rates.push((id, slope));
    }
    Ok((out, rates))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drift_is_removed_and_the_error_shape_kept() {
        // one back-and-forth cycle over 0..100 mm, error e(x) = 0.001 x^2 - 0.05 x, drift 0.02 um/s
        let mut x = Vec::new();
        for i in 0..=10 {
            x.push(10.0 * i as f64);
        }
        for i in (0..=10).rev() {
            x.push(10.0 * i as f64);
        }
        let t: Vec<f64> = (0..x.len()).map(|i| 5.0 * i as f64).collect();
        let e = |x: f64| 0.001 * x * x - 0.05 * x;
        let v: Vec<f64> = x.iter().zip(&t).map(|(x, t)| e(*x) + 0.02 * t).collect();
        let (clean, rates) = remove_cycle_drift(&vec![1; x.len()], &t, &v).unwrap();
        assert!((rates[0].1 - 0.02).abs() < 1e-12);
        let offset = clean[0] - e(x[0]);
        for (c, x) in clean.iter().zip(&x) {
            assert!((c - e(*x) - offset).abs() < 1e-12);
        }
    }
}
