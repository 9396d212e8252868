//! Rotary-table calibration with a telescopic magnetic ball bar (TMBB) at two bar lengths
//! (Zhu 2008, ch. 5; digest `specs/zhu.md` §5).
//!
//! Geometry (Eqs. 5.3-5.7): the table ball A at `(R_x, 0, R_z)` in the rotating table frame, the
//! spindle ball B at `(0, 0, H)` on the table axis. A short bar `L1` and a long bar `L2` put B at
//! `H_i = R_z + sqrt(L_i^2 - R_x^2)`; A stays, the spindle only moves vertically, so an eccentricity
//! `(H_x, H_y)` of B is the same in both setups. With the squared-length change
//! `Delta2 = |L^E|^2 - |L|^2 = 2 L dL + dL^2` (Eq. 5.11, first order in the errors), the difference
//! of the two setups at table angle `c` is (Eq. 5.16)
//!
//! `Delta2(L1) - Delta2(L2) = 2 R_x (H2-H1) sin c E_x - 2 R_x (H2-H1) cos c E_y + 2 (H2-H1) D_z`,
//!
//! linear in the tilts `E_x`, `E_y` (rad; the library's `EAC`, `EBC` of the table axis C) and the
//! axial error `D_z` (mm; `EZC`). The radial errors `D_x`, `D_y` (`EXC`, `EYC`) cancel together with
//! the eccentricity (they are coupled: only a reversal separates them), and `E_z` (`ECC`) does not
//! appear at all: they are reported as unidentifiable. Estimators: l2 (least squares, Eq. 5.17) and
//! l-infinity (minimax, Eq. 5.18) as the linear program `min t s.t. -t <= J x - Delta <= t`, solved
//! with `microlp` (a small pure-Rust simplex solver: no system library, no unsafe code in the
//! dependency chain that we call; the problem has 4 variables and 2n constraints).

use super::IdentifyError;
use nalgebra::{DMatrix, DVector};

/// The two-length setup (mm): table-ball radius `R_x` and height `R_z`, bar lengths `L1 < L2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TmbbSetup {
    pub rx: f64,
    pub rz: f64,
    pub l1: f64,
    pub l2: f64,
}

impl TmbbSetup {
    /// Zhu 2008 §5.4 (Table 5.1 test): `R_x = 71.8420`, `L1 = 90.850`, `L2 = 217.952` mm, table
    /// ball in the plane of the table reference (`R_z = 0`).
    pub const ZHU_TABLE_5_1: TmbbSetup = TmbbSetup { rx: 71.8420, rz: 0.0, l1: 90.850, l2: 217.952 };

    /// Spindle-ball heights `H1`, `H2` (mm): `R_z + sqrt(L_i^2 - R_x^2)`.
    pub fn heights(&self) -> Result<(f64, f64), IdentifyError> {
        let valid = [self.rx, self.l1, self.l2].iter().all(|v| v.is_finite() && *v > 0.0) && self.rz.is_finite();
        if !valid || self.l1 <= self.rx || self.l2 <= self.l1 {
            return Err(IdentifyError::Input(format!(
                "the TMBB setup needs 0 < R_x < L1 < L2 (mm); got R_x = {}, L1 = {}, L2 = {}",
                self.rx, self.l1, self.l2
            )));
        }
        let h = |l: f64| self.rz + (l * l - self.rx * self.rx).sqrt();
        Ok((h(self.l1), h(self.l2)))
    }

    /// Angle of each bar from the vertical (rad): `atan(R_x / (H_i - R_z))` (the thesis's eta).
    pub fn bar_angles(&self) -> Result<(f64, f64), IdentifyError> {
        let (h1, h2) = self.heights()?;
        Ok((self.rx.atan2(h1 - self.rz), self.rx.atan2(h2 - self.rz)))
    }

    /// The design matrix of Eq. 5.19 (rows `[2R_x dH sin c, -2R_x dH cos c, 2 dH]`, `dH = H2 - H1`),
    /// columns `E_x` (rad), `E_y` (rad), `D_z` (mm), rows in mm^2. `length_unit` scales lengths
    /// (1 for mm, 1e-3 for m) to show the effect of units on the condition number.
    pub fn design_matrix(&self, angles: &[f64], length_unit: f64) -> Result<DMatrix<f64>, IdentifyError> {
        let (h1, h2) = self.heights()?;
        let dh = (h2 - h1) * length_unit;
        let rx = self.rx * length_unit;
        Ok(DMatrix::from_fn(angles.len(), 3, |i, j| match j {
            0 => 2.0 * rx * dh * angles[i].sin(),
            1 => -2.0 * rx * dh * angles[i].cos(),
            _ => 2.0 * dh,
        }))
    }
}

/// Condition numbers `sigma_max / sigma_min` of the design matrix (Eq. 5.20) under three explicit
/// scalings: lengths in mm and angles in rad; lengths in m and angles in rad (the thesis's choice,
/// which makes cond fall with `R_x`); and every column scaled to unit length (independent of units:
/// the one to compare setups with).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditioning {
    pub mm_rad: f64,
    pub m_rad: f64,
    pub unit_columns: f64,
}

fn condition(m: &DMatrix<f64>) -> f64 {
    let s = m.clone().svd(false, false).singular_values;
    let max = s.iter().copied().fold(0.0, f64::max);
    let min = s.iter().copied().fold(f64::INFINITY, f64::min);
    if min > 0.0 {
        max / min
    } else {
        f64::INFINITY
    }
}

pub fn conditioning(setup: &TmbbSetup, angles: &[f64]) -> Result<Conditioning, IdentifyError> {
    let mm = setup.design_matrix(angles, 1.0)?;
    let m = setup.design_matrix(angles, 1e-3)?;
    let mut unit = mm.clone();
    for mut col in unit.column_iter_mut() {
        let n = col.norm();
        if n > 0.0 {
            col /= n;
        }
    }
    Ok(Conditioning { mm_rad: condition(&mm), m_rad: condition(&m), unit_columns: condition(&unit) })
}

/// Estimates of `E_x`, `E_y` (rad) and `D_z` (mm) with the residuals of the differenced data.
#[derive(Clone, Debug, PartialEq)]
pub struct TmbbEstimate {
    pub ex: f64,
    pub ey: f64,
    pub dz: f64,
    /// `J x - Delta` per angle (mm^2).
    pub residuals: Vec<f64>,
    /// Max |e|, max e - min e, RMS e (mm^2): the thesis's Table 5.3 measures.
    pub max_abs: f64,
    pub range: f64,
    pub rms: f64,
}

fn estimate(j: &DMatrix<f64>, delta: &[f64], x: [f64; 3]) -> TmbbEstimate {
    let residuals: Vec<f64> = (0..j.nrows()).map(|i| (0..3).map(|k| j[(i, k)] * x[k]).sum::<f64>() - delta[i]).collect();
    let max_abs = residuals.iter().fold(0.0f64, |a, r| a.max(r.abs()));
    let (lo, hi) = residuals.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &r| (a.min(r), b.max(r)));
    let rms = (residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len() as f64).sqrt();
    TmbbEstimate { ex: x[0], ey: x[1], dz: x[2], residuals, max_abs, range: hi - lo, rms }
}

/// The differenced squared-length data `Delta2(L1) - Delta2(L2)` (mm^2) from the bar readings `dl1`,
/// `dl2` (mm, relative to `L1`, `L2`) at the same table angles.
pub fn differenced(setup: &TmbbSetup, dl1: &[f64], dl2: &[f64]) -> Result<Vec<f64>, IdentifyError> {
    if dl1.len() != dl2.len() {
        return Err(IdentifyError::Input(format!("{} short-bar readings but {} long-bar readings", dl1.len(), dl2.len())));
    }
    Ok(dl1.iter().zip(dl2).map(|(a, b)| (2.0 * setup.l1 * a + a * a) - (2.0 * setup.l2 * b + b * b)).collect())
}

/// Column norms of the design matrix, for scaling.
fn column_scales(j: &DMatrix<f64>) -> Result<[f64; 3], IdentifyError> {
    let s = [0, 1, 2].map(|k| j.column(k).norm());
    if s.iter().any(|v| v.is_nan() || *v <= 0.0) {
        return Err(IdentifyError::RankDeficient { message: "the table angles do not excite E_x, E_y and D_z".into() });
    }
    Ok(s)
}

fn check(angles: &[f64], delta: &[f64]) -> Result<(), IdentifyError> {
    if angles.len() != delta.len() {
        return Err(IdentifyError::Input(format!("{} angles but {} differenced readings", angles.len(), delta.len())));
    }
    if angles.len() < 4 {
        return Err(IdentifyError::Input(format!("the TMBB fit needs at least 4 table angles, got {}", angles.len())));
    }
    if angles.iter().chain(delta).any(|v| !v.is_finite()) {
        return Err(IdentifyError::Input("a table angle or bar reading is not a finite number".into()));
    }
    Ok(())
}

/// l2 estimate (Eq. 5.17): least squares by SVD of the unit-column-scaled design matrix.
pub fn fit_l2(setup: &TmbbSetup, angles: &[f64], delta: &[f64]) -> Result<TmbbEstimate, IdentifyError> {
    check(angles, delta)?;
    let j = setup.design_matrix(angles, 1.0)?;
    let s = column_scales(&j)?;
    let mut scaled = j.clone();
    for (mut col, scale) in scaled.column_iter_mut().zip(s) {
        col.unscale_mut(scale);
    }
    let y = scaled
        .svd(true, true)
        .solve(&DVector::from_column_slice(delta), 1e-12)
        .map_err(|e| IdentifyError::RankDeficient { message: e.to_string() })?;
    Ok(estimate(&j, delta, [y[0] / s[0], y[1] / s[1], y[2] / s[2]]))
}

/// l-infinity (minimax) estimate (Eq. 5.18): the linear program `min t` subject to
/// `-t <= J x - Delta <= t`, on unit-scaled columns and data.
pub fn fit_linf(setup: &TmbbSetup, angles: &[f64], delta: &[f64]) -> Result<TmbbEstimate, IdentifyError> {
    use microlp::{ComparisonOp, OptimizationDirection, Problem};
    check(angles, delta)?;
    let j = setup.design_matrix(angles, 1.0)?;
    let s = column_scales(&j)?;
    let scale = delta.iter().fold(0.0f64, |a, d| a.max(d.abs())).max(f64::MIN_POSITIVE);
    let mut lp = Problem::new(OptimizationDirection::Minimize);
    let x: Vec<_> = (0..3).map(|_| lp.add_var(0.0, (f64::NEG_INFINITY, f64::INFINITY))).collect();
    let t = lp.add_var(1.0, (0.0, f64::INFINITY));
    for (i, d) in delta.iter().enumerate() {
        let row: Vec<_> = (0..3).map(|k| (x[k], j[(i, k)] / s[k])).collect();
        let with_t = |sign: f64| row.iter().copied().chain(std::iter::once((t, sign))).collect::<Vec<_>>();
        lp.add_constraint(with_t(-1.0).as_slice(), ComparisonOp::Le, d / scale);
        lp.add_constraint(with_t(1.0).as_slice(), ComparisonOp::Ge, d / scale);
    }
    let solution = lp
        .solve()
        .map_err(|e| IdentifyError::RankDeficient { message: format!("the l-infinity linear program failed: {e}") })?
        .into_solution()
        .map_err(|_| IdentifyError::RankDeficient { message: "the l-infinity linear program was interrupted".into() })?;
    let value = |k: usize| solution.var_value(x[k]) * scale / s[k];
    Ok(estimate(&j, delta, [value(0), value(1), value(2)]))
}

/// The components of the table axis that the differenced two-length data cannot give, with why.
pub const UNIDENTIFIABLE: [(&str, &str, &str); 3] = [
    ("D_x", "EXC", "radial error along x: enters both bar lengths as 2 R_x cos c D_x and cancels with the eccentricity H_x of the spindle ball (Eq. 5.13); separating them needs a reversal"),
    ("D_y", "EYC", "radial error along y: cancels with the eccentricity H_y in the same way"),
    ("E_z", "ECC", "angular positioning error: moves the table ball along the circle, no change of any bar length; needs an angular reference (laser, autocollimator)"),
];

/// Column norms of the first-order single-bar model (Eqs. 5.11, 5.13) and of the differenced model
/// for the eight unknowns `E_x E_y E_z D_x D_y D_z H_x H_y` (mm^2 per rad or mm): a column that is
/// zero in the differenced model is not identifiable from it.
pub fn observability(setup: &TmbbSetup, angles: &[f64]) -> Result<Vec<(&'static str, f64, f64)>, IdentifyError> {
    let (h1, h2) = setup.heights()?;
    let (rx, rz) = (setup.rx, setup.rz);
    let single = |h: f64, c: f64| -> [f64; 8] {
        let (s, co) = c.sin_cos();
        [-2.0 * rx * h * s, 2.0 * rx * h * co, 0.0, 2.0 * rx * co, 2.0 * rx * s, 2.0 * (rz - h), -2.0 * rx * co, -2.0 * rx * s]
    };
    let names = ["E_x", "E_y", "E_z", "D_x", "D_y", "D_z", "H_x", "H_y"];
    Ok(names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let a = angles.iter().map(|&c| single(h1, c)[k].powi(2)).sum::<f64>().sqrt();
            let d = angles.iter().map(|&c| (single(h1, c)[k] - single(h2, c)[k]).powi(2)).sum::<f64>().sqrt();
            (*name, a, d)
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn angles_0_to_360_by_10() -> Vec<f64> {
        (0..=36).map(|i| f64::from(i * 10).to_radians()).collect()
    }

    #[test]
    fn heights_of_the_table_5_1_setup() {
        // digest §5.3 [derived]: H1 - R_z = 55.610 mm, H2 - R_z = 205.771 mm, H2 - H1 = 150.161 mm;
        // bar angles from vertical 52.26 deg and 19.25 deg.
        let (h1, h2) = TmbbSetup::ZHU_TABLE_5_1.heights().unwrap();
        assert!((h1 - 55.610).abs() < 1e-3 && (h2 - 205.771).abs() < 1e-3 && (h2 - h1 - 150.161).abs() < 1e-3);
        let (e1, e2) = TmbbSetup::ZHU_TABLE_5_1.bar_angles().unwrap();
        assert!((e1.to_degrees() - 52.26).abs() < 0.01 && (e2.to_degrees() - 19.25).abs() < 0.01);
    }

    #[test]
    fn condition_number_depends_on_units() {
        // digest §5.3 [derived]: 37 samples at 0:10:360 deg: cond = 19.96 in m/rad, 51.5 in mm/rad.
        let c = conditioning(&TmbbSetup::ZHU_TABLE_5_1, &angles_0_to_360_by_10()).unwrap();
        assert!((c.m_rad - 19.96).abs() < 0.01, "{c:?}");
        assert!((c.mm_rad - 51.5).abs() < 0.1, "{c:?}");
        assert!(c.unit_columns < 1.1, "{c:?}");
    }

    #[test]
    fn radial_errors_and_eccentricity_cancel() {
        let obs = observability(&TmbbSetup::ZHU_TABLE_5_1, &angles_0_to_360_by_10()).unwrap();
        for (name, single, diff) in obs {
            let identifiable = ["E_x", "E_y", "D_z"].contains(&name);
            assert_eq!(diff > 1e-9 * single.max(1.0), identifiable, "{name}: single {single}, differenced {diff}");
        }
    }
}
