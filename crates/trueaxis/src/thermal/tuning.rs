//! Tuning the boundary conditions of a heat-conduction model to measured time constants (Zhu 2008
//! §4.4.2: "the boundary conditions are assigned to give rise to relatively reasonable results in
//! terms of the agreement between simulated and measured time constants"; §1.5 of its digest: a
//! model-updating step).
//!
//! The convection coefficients named by their keys in the model file (`convection_w_m2k`,
//! `left_end`, `right_end`, `boundary.xmin` ...) are the unknowns; the n largest time constants of
//! the model are matched to n measured ones (e.g. the eq. 3.17 fit of `thermal fit
//! --time-constants`) by Levenberg-Marquardt on `ln h`, minimising `sum (ln tau_model,i -
//! ln tau_measured,i)^2` (relative errors, so that a 6-hour and a 20-minute mode weigh alike).
//! The result is the model file with the tuned coefficients written in place, comments kept.

use super::levenberg_marquardt::{levenberg_marquardt, LmOptions};
use super::modal::{modal_analysis, ModalOptions};
use super::model_file::parse_model;
use crate::error::Error;
use std::path::Path;
use toml_edit::{value, DocumentMut, Item};

/// The tuned model.
#[derive(Clone, Debug)]
pub struct Tuning {
    /// `(key, tuned value W/m^2/K)`.
    pub values: Vec<(String, f64)>,
    /// `(key, starting value)`.
    pub start: Vec<(String, f64)>,
    /// The model's largest time constants (s) after tuning, decreasing, one per measured one.
    pub model_tau_s: Vec<f64>,
    pub measured_tau_s: Vec<f64>,
    pub iterations: usize,
    /// The model file with the tuned coefficients.
    pub text: String,
}

/// The item of `key` (`a` or `a.b`) in `doc`.
fn item_mut<'d>(doc: &'d mut DocumentMut, key: &str) -> Option<&'d mut Item> {
    let mut parts = key.split('.');
    let mut item = doc.as_item_mut().get_mut(parts.next()?)?;
    for p in parts {
        item = item.get_mut(p)?;
    }
    (!item.is_none()).then_some(item)
}

/// Tunes the convection coefficients `keys` of the model file `text` so that its largest time
/// constants equal `measured_tau_s` (s, any order); `dir` resolves the paths of the file.
pub fn tune_boundaries(text: &str, origin: &str, dir: &Path, keys: &[String], measured_tau_s: &[f64]) -> Result<Tuning, Error> {
    let mut doc: DocumentMut =
        text.parse().map_err(|e: toml_edit::TomlError| Error::input(format!("{origin}: {}", e.to_string().replace('\n', " "))))?;
    if keys.is_empty() {
        return Err(Error::input("name at least one convection coefficient to tune (--tune KEY)"));
    }
    if measured_tau_s.len() < keys.len() {
        return Err(Error::input(format!(
            "{} measured time constants cannot determine {} coefficients; give at least as many time constants as coefficients",
            measured_tau_s.len(),
            keys.len()
        )));
    }
    if measured_tau_s.iter().any(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(Error::input("the measured time constants must be positive numbers of seconds"));
    }
    let mut measured = measured_tau_s.to_vec();
    measured.sort_by(|a, b| b.total_cmp(a));
    let mut start = Vec::new();
    for key in keys {
        let item = item_mut(&mut doc, key)
            .ok_or_else(|| Error::input(format!("{origin}: no key `{key}` to tune (e.g. convection_w_m2k, right_end, boundary.xmin)")))?;
        let v = item.as_float().or_else(|| item.as_integer().map(|i| i as f64)).filter(|h| h.is_finite() && *h > 0.0).ok_or_else(|| {
            Error::input(format!("{origin}: `{key}` must be a positive convection coefficient to start from (an insulated face cannot be tuned; give it a value)"))
        })?;
        start.push((key.clone(), v));
    }
    let n = measured.len();
    let model_taus = |doc: &mut DocumentMut, h: &[f64]| -> Result<Vec<f64>, Error> {
        for (key, v) in keys.iter().zip(h) {
            *item_mut(doc, key).expect("checked") = value(*v);
        }
        let model = parse_model(&doc.to_string(), origin, dir)?;
        let basis = modal_analysis(&model.system, &ModalOptions { count: Some(n), ..ModalOptions::default() })?;
        let mut taus: Vec<f64> = (0..basis.len()).map(|i| basis.tau_s(i)).collect();
        taus.sort_by(|a, b| b.total_cmp(a));
        Ok(taus)
    };
    let mut work = doc.clone();
    let residuals = |x: &[f64], r: &mut [f64]| -> bool {
        if x.iter().any(|v| !v.is_finite() || v.abs() > 30.0) {
            return false;
        }
        let h: Vec<f64> = x.iter().map(|v| v.exp()).collect();
        match model_taus(&mut work, &h) {
            Ok(t) if t.len() >= n => {
                for i in 0..n {
                    r[i] = (t[i] / measured[i]).ln();
                }
                true
            }
            _ => false,
        }
    };
    let x0: Vec<f64> = start.iter().map(|(_, v)| v.ln()).collect();
    let lm = levenberg_marquardt(residuals, &x0, n, &LmOptions { max_iterations: 100, tolerance: 1e-14 });
    let h: Vec<f64> = lm.x.iter().map(|v| v.exp()).collect();
    let taus = model_taus(&mut doc, &h)?;
    if taus.iter().any(|t| !t.is_finite()) {
        return Err(Error::computation("the tuned model has no finite time constants"));
    }
    Ok(Tuning {
        values: keys.iter().cloned().zip(h).collect(),
        start,
        model_tau_s: taus[..n].to_vec(),
        measured_tau_s: measured,
        iterations: lm.iterations,
        text: doc.to_string(),
    })
}
