//! Choosing and checking the setup of the two-length rotary-table test (Zhu 2008 §5.3): where to
//! put the table ball (`R_x`, §5.3.1) and how far the setup dimensions `R_x`, `R_z`, `H` may be off
//! (§5.3.2).
//!
//! The choice of `R_x`: the thesis compares condition numbers of the design matrix, which depend on
//! the units of the columns (the test `tmbb` prints three). What does not depend on units is the
//! standard uncertainty of `E_x`, `E_y`, `D_z` for a given bar noise: the differenced squared lengths
//! carry the noise `sqrt((2 L1)^2 + (2 L2)^2) sigma` (first order of `2 L dL`), and
//! `u = sigma_Delta sqrt(diag (J^T J)^-1)`. With the table ball farther out, `R_x` and the height
//! difference `H2 - H1` both grow, and the uncertainties fall.
//!
//! The setup dimensions: the readings are simulated with the exact geometry of the test (the table
//! ball at `(R_x', 0, R_z')` turned by `c` with the table's error motion, the spindle ball at the
//! programmed height plus a deviation), and evaluated with the nominal setup; the difference of
//! the estimates from the true errors is the effect of the deviation.
//!
//! Units: lengths in mm, angles in rad, bar noise in mm; results in the same units.

use super::tmbb::{differenced, fit_l2, TmbbSetup};
use super::IdentifyError;
use crate::geometry::{rotation_exp, Vec3};

/// One candidate table-ball radius and what it gives.
#[derive(Clone, Debug, PartialEq)]
pub struct RxChoice {
    pub rx: f64,
    /// `H2 - H1` (mm).
    pub height_difference: f64,
    /// Condition numbers of the design matrix: mm and rad, m and rad, unit-length columns.
    pub cond_mm_rad: f64,
    pub cond_m_rad: f64,
    pub cond_unit_columns: f64,
    /// Standard uncertainty of `E_x`, `E_y` (rad) and `D_z` (mm) for bar noise `noise_mm`.
    pub u_ex: f64,
    pub u_ey: f64,
    pub u_dz: f64,
}

/// For every `rx` of `candidates` (mm, each below the short bar `L1`): the conditioning and the
/// standard uncertainties of the two-length test with bar noise `noise_mm` at `angles` (rad).
pub fn rx_choice(setup: &TmbbSetup, angles: &[f64], candidates: &[f64], noise_mm: f64) -> Result<Vec<RxChoice>, IdentifyError> {
    if !(noise_mm.is_finite() && noise_mm > 0.0) {
        return Err(IdentifyError::Input(format!("bar noise {noise_mm} mm: give a positive value")));
    }
    candidates
        .iter()
        .map(|&rx| {
            let s = TmbbSetup { rx, ..*setup };
            let (h1, h2) = s.heights()?;
            let c = super::tmbb::conditioning(&s, angles)?;
            let j = s.design_matrix(angles, 1.0)?;
            let inverse = (j.transpose() * &j)
                .try_inverse()
                .ok_or_else(|| IdentifyError::RankDeficient { message: "the table angles do not excite E_x, E_y and D_z".into() })?;
            let sigma_delta = 2.0 * (s.l1 * s.l1 + s.l2 * s.l2).sqrt() * noise_mm;
            let u = |k: usize| sigma_delta * inverse[(k, k)].sqrt();
            Ok(RxChoice {
                rx,
                height_difference: h2 - h1,
                cond_mm_rad: c.mm_rad,
                cond_m_rad: c.m_rad,
                cond_unit_columns: c.unit_columns,
                u_ex: u(0),
                u_ey: u(1),
                u_dz: u(2),
            })
        })
        .collect()
}

/// The error motion of the table, constant over the turn (rad, mm): tilts `E_x`, `E_y`, angular
/// positioning `E_z`, translations `D_x`, `D_y`, `D_z`; and the eccentricity `(H_x, H_y)` of the
/// spindle ball (mm).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TableErrors {
    pub ex: f64,
    pub ey: f64,
    pub ez: f64,
    pub dx: f64,
    pub dy: f64,
    pub dz: f64,
    pub hx: f64,
    pub hy: f64,
}

/// A deviation of one setup dimension and the error it causes in the estimates.
#[derive(Clone, Debug, PartialEq)]
pub struct SetupDeviation {
    /// `R_x`, `R_z` or `H` (the spindle-ball height datum, both setups).
    pub dimension: &'static str,
    pub deviation_mm: f64,
    /// Estimate minus truth of `E_x`, `E_y` (rad) and `D_z` (mm).
    pub ex: f64,
    pub ey: f64,
    pub dz: f64,
}

/// Exact bar readings (mm, relative to `L1` and `L2`) of the two setups at table angles `angles`
/// (rad) when the table ball really sits at `(rx, 0, rz)` and the spindle ball at the programmed
/// heights of `programmed` plus `dh`.
pub fn exact_readings(
    programmed: &TmbbSetup,
    rx: f64,
    rz: f64,
    dh: f64,
    errors: &TableErrors,
    angles: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), IdentifyError> {
    let (h1, h2) = programmed.heights()?;
    let tilt = rotation_exp(&Vec3::new(errors.ex, errors.ey, errors.ez));
    let table_ball = |c: f64| -> Vec3 {
        let (s, co) = c.sin_cos();
        tilt * Vec3::new(rx * co, rx * s, rz) + Vec3::new(errors.dx, errors.dy, errors.dz)
    };
    let reading = |h: f64, l: f64| -> Vec<f64> {
        let spindle = Vec3::new(errors.hx, errors.hy, h + dh);
        angles.iter().map(|&c| (table_ball(c) - spindle).norm() - l).collect()
    };
    Ok((reading(h1, programmed.l1), reading(h2, programmed.l2)))
}

/// The estimation errors of the l2 fit when each setup dimension (`R_x`, `R_z`, `H`) in turn is off
/// by each of `deviations` (mm), with the table's true errors `truth`.
pub fn setup_dimension_sensitivity(
    setup: &TmbbSetup,
    angles: &[f64],
    truth: &TableErrors,
    deviations: &[f64],
) -> Result<Vec<SetupDeviation>, IdentifyError> {
    let mut out = Vec::new();
    for dimension in ["R_x", "R_z", "H"] {
        for &d in deviations {
            if !d.is_finite() {
                return Err(IdentifyError::Input(format!("setup deviation {d} mm is not a number")));
            }
            let (rx, rz, dh) = match dimension {
                "R_x" => (setup.rx + d, setup.rz, 0.0),
                "R_z" => (setup.rx, setup.rz + d, 0.0),
                _ => (setup.rx, setup.rz, d),
            };
            let (dl1, dl2) = exact_readings(setup, rx, rz, dh, truth, angles)?;
            let fit = fit_l2(setup, angles, &differenced(setup, &dl1, &dl2)?)?;
            out.push(SetupDeviation { dimension, deviation_mm: d, ex: fit.ex - truth.ex, ey: fit.ey - truth.ey, dz: fit.dz - truth.dz });
        }
    }
    Ok(out)
}
