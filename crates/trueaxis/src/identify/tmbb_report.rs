//! The two-length rotary-table test of Zhu (2008) from its two files, end to end: the document of
//! `trueaxis ballbar tmbb --json`, and what the calibration report quotes. The command line and the
//! report both call [`tmbb_files`].
//!
//! Estimates (`identify::tmbb`): the tilts `E_x`, `E_y` (the ISO 230-1 motion errors `EAC`, `EBC` of
//! the table axis C, rad) and the axial error `D_z` (`EZC`, mm) by least squares (l2) and by minimax
//! (l-infinity) from the differenced squared lengths `Delta2(L1) - Delta2(L2)` (mm^2). The standard
//! uncertainty of the l2 estimate is that of a linear least-squares fit (GUM, JCGM 100 annex H.3):
//! `u^2 = s^2 diag (J^T J)^-1`, `s^2 = sum e_i^2 / (n - 3)` from the residuals `e_i` of the
//! differenced data, so that it holds the bar noise and whatever else the model does not explain.
//!
//! What is left of each bar: its readings minus the identified errors' first-order effect
//! `single(H_i, c) x / (2 L_i)` (Zhu (2008) Eqs. 5.11, 5.13), minus the once-per-turn term of the
//! spindle ball's eccentricity together with the radial errors, which the test cannot separate
//! (a least-squares `a cos c + b sin c`). Units: readings and what is left in um.

use super::tmbb::{conditioning, differenced, fit_l2, fit_linf, Conditioning, TmbbEstimate, TmbbSetup, UNIDENTIFIABLE};
use super::IdentifyError;
use crate::instruments::ballbar::{read_trace, TraceFile};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// One bar of the test: its file, its readings and what is left of them (um).
#[derive(Clone, Debug)]
pub struct TmbbBar {
    pub path: PathBuf,
    pub length_mm: f64,
    pub trace: TraceFile,
    pub left_um: Vec<f64>,
    pub rms_um: f64,
    pub band_um: f64,
}

/// The test's estimates, their standard uncertainties and what is left of each bar.
#[derive(Clone, Debug)]
pub struct TmbbReport {
    pub setup: TmbbSetup,
    /// Table angles (rad), the same for both bars.
    pub angles: Vec<f64>,
    pub l2: TmbbEstimate,
    pub linf: TmbbEstimate,
    /// Standard uncertainty of the l2 `E_x`, `E_y` (rad) and `D_z` (mm).
    pub std_uncertainty: [f64; 3],
    pub conditioning: Conditioning,
    /// The short bar, then the long one.
    pub bars: [TmbbBar; 2],
}

/// Reads the short- and long-bar files (table angle in column `C` or `angle`, deg; `dL`, um) and
/// evaluates the test.
pub fn tmbb_files(setup: &TmbbSetup, short: &Path, long: &Path) -> Result<TmbbReport, IdentifyError> {
    let (h1, h2) = setup.heights()?;
    let read = |p: &Path| read_trace(p, &["C", "angle"]).map_err(IdentifyError::Data);
    let (s, l) = (read(short)?, read(long)?);
    if s.angles_deg.len() != l.angles_deg.len() || s.angles_deg.iter().zip(&l.angles_deg).any(|(x, y)| (x - y).abs() > 1e-6) {
        return Err(IdentifyError::Input(format!(
            "{} and {}: the two bars must be read at the same table angles",
            short.display(),
            long.display()
        )));
    }
    let angles: Vec<f64> = s.angles_deg.iter().map(|d| d.to_radians()).collect();
    let mm = |t: &TraceFile| t.dl_um.iter().map(|v| v * 1e-3).collect::<Vec<f64>>();
    let delta = differenced(setup, &mm(&s), &mm(&l))?;
    let l2 = fit_l2(setup, &angles, &delta)?;
    let linf = fit_linf(setup, &angles, &delta)?;
    let conditioning = conditioning(setup, &angles)?;
    let std_uncertainty = l2_uncertainty(setup, &angles, &l2)?;
    let bar = |path: &Path, length_mm: f64, h: f64, trace: TraceFile| {
        let left_um = bar_left_um(setup, &angles, h, length_mm, &trace.dl_um, &l2);
        let rms_um = (left_um.iter().map(|v| v * v).sum::<f64>() / left_um.len() as f64).sqrt();
        let (lo, hi) = left_um.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
        TmbbBar { path: path.to_path_buf(), length_mm, trace, left_um, rms_um, band_um: hi - lo }
    };
    let bars = [bar(short, setup.l1, h1, s), bar(long, setup.l2, h2, l)];
    Ok(TmbbReport { setup: *setup, angles, l2, linf, std_uncertainty, conditioning, bars })
}

/// The standard uncertainty of the l2 estimate `E_x`, `E_y` (rad), `D_z` (mm) at table angles
/// `angles` (rad): `u = s sqrt(diag (J^T J)^-1)`, `s^2 = sum e^2 / (n - 3)` of its residuals.
pub fn l2_uncertainty(setup: &TmbbSetup, angles: &[f64], l2: &TmbbEstimate) -> Result<[f64; 3], IdentifyError> {
    let n = angles.len();
    let j = setup.design_matrix(angles, 1.0)?;
    let inverse = (j.transpose() * &j)
        .try_inverse()
        .ok_or_else(|| IdentifyError::RankDeficient { message: "the table angles do not excite E_x, E_y and D_z".into() })?;
    let s2 = l2.residuals.iter().map(|e| e * e).sum::<f64>() / (n - 3) as f64;
    Ok([0, 1, 2].map(|k| (s2 * inverse[(k, k)]).sqrt()))
}

/// The readings of one bar (um) minus the identified errors' effect and minus the least-squares
/// once-per-turn term (eccentricity and radial errors).
fn bar_left_um(setup: &TmbbSetup, angles: &[f64], h: f64, length: f64, dl_um: &[f64], x: &TmbbEstimate) -> Vec<f64> {
    let (rx, rz) = (setup.rx, setup.rz);
    let after: Vec<f64> = angles
        .iter()
        .zip(dl_um)
        .map(|(&c, dl)| {
            let (s, co) = c.sin_cos();
            let delta2 = -2.0 * rx * h * s * x.ex + 2.0 * rx * h * co * x.ey + 2.0 * (rz - h) * x.dz;
            dl - delta2 / (2.0 * length) * 1e3
        })
        .collect();
    // least squares of a cos c + b sin c + k (the constant: the bar's calibration offset)
    let g = nalgebra::DMatrix::from_fn(angles.len(), 3, |i, k| match k {
        0 => angles[i].cos(),
        1 => angles[i].sin(),
        _ => 1.0,
    });
    let y = nalgebra::DVector::from_column_slice(&after);
    match g.clone().svd(true, true).solve(&y, 1e-12) {
        Ok(b) => (y - g * b).iter().copied().collect(),
        Err(_) => after,
    }
}

fn round(v: f64, digits: i32) -> f64 {
    let f = 10f64.powi(digits);
    (v * f).round() / f
}

fn arcsec(rad: f64) -> f64 {
    rad.to_degrees() * 3600.0
}

impl TmbbReport {
    /// The document of `trueaxis ballbar tmbb --json`: each estimate in arcsec and urad (tilts) or
    /// um (`D_z`) with its ISO parameter; the l2 estimate with its standard uncertainty; the
    /// residuals of the differenced data (mm^2), the condition numbers, what cannot be identified,
    /// what is left of each bar (um) and the files' metadata.
    pub fn to_json(&self) -> Value {
        let fit = |f: &TmbbEstimate, u: Option<[f64; 3]>| {
            let su = |k: usize, scale: f64| u.map(|u| round(u[k] * scale, 4));
            json!({"E_x": {"value": round(arcsec(f.ex), 4), "unit": "arcsec", "urad": round(f.ex * 1e6, 4), "parameter": "EAC",
                           "std_uncertainty_urad": su(0, 1e6)},
                   "E_y": {"value": round(arcsec(f.ey), 4), "unit": "arcsec", "urad": round(f.ey * 1e6, 4), "parameter": "EBC",
                           "std_uncertainty_urad": su(1, 1e6)},
                   "D_z": {"value": round(f.dz * 1e3, 4), "unit": "um", "parameter": "EZC", "std_uncertainty": su(2, 1e3)},
                   "max_abs_residual_mm2": round(f.max_abs, 6), "range_mm2": round(f.range, 6), "rms_mm2": round(f.rms, 6)})
        };
        let c = &self.conditioning;
        let unident: Vec<_> = UNIDENTIFIABLE.iter().map(|(n, p, why)| json!({"name": n, "parameter": p, "reason": why})).collect();
        let bars: Vec<_> = self
            .bars
            .iter()
            .map(|b| json!({"file": b.path.display().to_string(), "length_mm": b.length_mm, "left_rms_um": round(b.rms_um, 4), "left_band_um": round(b.band_um, 4)}))
            .collect();
        json!({"l2": fit(&self.l2, Some(self.std_uncertainty)), "linf": fit(&self.linf, None),
            "condition_number": {"mm_rad": round(c.mm_rad, 4), "m_rad": round(c.m_rad, 4), "unit_columns": round(c.unit_columns, 4)},
            "unidentifiable": unident, "samples": self.angles.len(), "bars": bars,
            "metadata": {"short": self.bars[0].trace.metadata.to_json(), "long": self.bars[1].trace.metadata.to_json()}})
    }

    /// The plausibility warnings of both files.
    pub fn warnings(&self) -> Vec<String> {
        self.bars.iter().flat_map(|b| b.trace.warnings.clone()).collect()
    }
}
