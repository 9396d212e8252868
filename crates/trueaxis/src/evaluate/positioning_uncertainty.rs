//! The measurement uncertainty of an ISO 230-2 positioning test: one expanded uncertainty U
//! (k = 2) for each of the results A, E, M, R and B, from the contributors ISO 230-2:2014 Annex A
//! lists for a laser interferometer (the basic equations of ISO/TR 230-9):
//!
//! | contributor | standard uncertainty | from |
//! |---|---|---|
//! | measuring device, `u_DEVICE` | `(U_0 + U_L L) / 2` | the device's calibration certificate: `U = U_0 + U_L L` (k = 2) |
//! | machine temperature measurement, `u_M,MACHINE` | `alpha L U_T / 2` | the thermometer's certificate, `U_T` (k = 2) |
//! | expansion coefficient, `u_E,MACHINE` | `L |T - 20 degC| (p alpha) / sqrt(3)` | `alpha` known to `+-p` (rectangular) |
//! | misalignment of the beam (cosine error), `u_MISALIGNMENT` | `c / (2 sqrt(3))` | the largest cosine error `c` over the length (one-sided, rectangular from 0 to `c`) |
//! | environmental variation error, `u_EVE` | `EVE / (2 sqrt(3))` | the drift check of ISO 230-2 Annex A (a range, rectangular) |
//!
//! `L` is the measured length (the span of the targets). The systematic results E and M combine
//! every contributor above with the uncertainty of the mean deviations `s / sqrt(n)` (type A, the
//! largest estimator of the standard uncertainty of positioning `s` of the test, `n` runs); the
//! statistical results R and B are estimates from `n` runs whose own uncertainty is that of a
//! standard deviation, `s / sqrt(2 (n - 1))` (GUM, JCGM 100 Annex E.4.3), combined with `u_EVE`
//! (the device's own error cancels in a difference of readings at one target); A combines both.
//! A rotary axis (urad) has no thermal or length terms: only the device's fixed part, the
//! misalignment and EVE, all in urad.
//!
//! Units: um (urad for a rotary axis), temperatures in degC and K, expansion coefficients in
//! um/m/K, lengths in mm.

use super::iso230_2::Iso2302Result;

/// What the uncertainty is estimated from (every value >= 0).
#[derive(Clone, Debug, PartialEq)]
pub struct PositioningUncertaintyInputs {
    /// Expanded uncertainty (k = 2) of the device independent of length, um (urad).
    pub device_um: f64,
    /// Expanded uncertainty (k = 2) of the device per metre measured, um/m (ppm).
    pub device_um_per_m: f64,
    /// Expanded uncertainty (k = 2) of the machine (material) temperature measurement, K.
    pub temperature_k: f64,
    /// Expansion coefficient of the machine's scale, um/m/K.
    pub expansion_um_per_m_k: f64,
    /// Half-width of the rectangular uncertainty of the expansion coefficient, as a fraction of it
    /// (0.1 = +-10 %).
    pub expansion_fraction: f64,
    /// Mean machine temperature during the test minus 20 degC, K.
    pub temperature_offset_k: f64,
    /// Largest cosine error over the measured length, um.
    pub misalignment_um: f64,
    /// Environmental variation error, um.
    pub eve_um: f64,
}

impl Default for PositioningUncertaintyInputs {
    /// Nothing known but the usual expansion coefficient's spread (+-10 %): every other
    /// contributor zero until stated.
    fn default() -> Self {
        PositioningUncertaintyInputs {
            device_um: 0.0,
            device_um_per_m: 0.0,
            temperature_k: 0.0,
            expansion_um_per_m_k: 0.0,
            expansion_fraction: 0.1,
            temperature_offset_k: 0.0,
            misalignment_um: 0.0,
            eve_um: 0.0,
        }
    }
}

/// One contributor: its name and standard uncertainty (um or urad).
#[derive(Clone, Debug, PartialEq)]
pub struct Contribution {
    pub name: &'static str,
    pub standard_uncertainty: f64,
}

/// Expanded uncertainties (k = 2) of the ISO 230-2 results, um (urad), and the budget.
#[derive(Clone, Debug, PartialEq)]
pub struct PositioningUncertainty {
    pub a: f64,
    pub e: f64,
    pub m: f64,
    pub r: f64,
    pub b: f64,
    /// The measured length `L`, mm (deg for a rotary axis).
    pub length: f64,
    /// The contributors, standard uncertainties (k = 1).
    pub budget: Vec<Contribution>,
}

impl PositioningUncertainty {
    /// U of the result named `A`, `E`, `M`, `R` or `B` (the unidirectional values take the
    /// bidirectional one's U).
    pub fn of(&self, symbol: &str) -> Option<f64> {
        match symbol.trim_end_matches(['+', '-']) {
            "A" => Some(self.a),
            "E" => Some(self.e),
            "M" => Some(self.m),
            "R" => Some(self.r),
            "B" | "B_mean" => Some(self.b),
            _ => None,
        }
    }
}

/// The expanded uncertainties (k = 2) of `result` (see the module documentation for each
/// contributor; ISO 230-2:2014 Annex A, JCGM 100 Annex E.4.3 for the uncertainty of a standard
/// deviation). `rotary`: the test is of a rotary axis (no thermal or length terms).
pub fn positioning_uncertainty(result: &Iso2302Result, inputs: &PositioningUncertaintyInputs, rotary: bool) -> PositioningUncertainty {
    let targets = result.positions.iter().map(|p| p.target);
    let length = targets.clone().fold(f64::NEG_INFINITY, f64::max) - targets.fold(f64::INFINITY, f64::min);
    let length = if length.is_finite() { length } else { 0.0 };
    let metres = if rotary { 0.0 } else { length / 1000.0 };
    let sqrt3 = 3f64.sqrt();
    let device = (inputs.device_um + inputs.device_um_per_m * metres) / 2.0;
    let thermometer = inputs.expansion_um_per_m_k * metres * inputs.temperature_k / 2.0;
    let expansion = metres * inputs.temperature_offset_k.abs() * inputs.expansion_fraction * inputs.expansion_um_per_m_k / sqrt3;
    let misalignment = inputs.misalignment_um / (2.0 * sqrt3);
    let eve = inputs.eve_um / (2.0 * sqrt3);
    // the largest estimator of the standard uncertainty of positioning, and the runs behind it
    let s_max = result.positions.iter().flat_map(|p| [p.s_plus, p.s_minus]).fold(0.0, f64::max);
    let n = result.runs.max(2) as f64;
    let mean = s_max / n.sqrt();
    let of_s = s_max / (2.0 * (n - 1.0)).sqrt();
    let rss = |terms: &[f64]| terms.iter().map(|t| t * t).sum::<f64>().sqrt();
    let systematic = rss(&[device, thermometer, expansion, misalignment, eve, mean]);
    // R = 4 s (unidirectional) or 2 s + 2 s + |B| (bidirectional): four estimated s
    let r = 2.0 * rss(&[4.0 * of_s, eve]);
    // B = difference of two means of n readings each
    let b = 2.0 * rss(&[mean * 2f64.sqrt(), eve]);
    // A = E widened by 2 s at its two ends
    let a = 2.0 * rss(&[systematic, 2.0 * of_s * 2f64.sqrt()]);
    let budget = vec![
        Contribution { name: "measuring device (calibration certificate)", standard_uncertainty: device },
        Contribution { name: "machine temperature measurement", standard_uncertainty: thermometer },
        Contribution { name: "expansion coefficient of the machine", standard_uncertainty: expansion },
        Contribution { name: "misalignment of the beam (cosine error)", standard_uncertainty: misalignment },
        Contribution { name: "environmental variation error (EVE)", standard_uncertainty: eve },
        Contribution { name: "mean of the runs (type A, s / sqrt(n))", standard_uncertainty: mean },
        Contribution { name: "repeatability estimate (type A, s / sqrt(2 (n - 1)))", standard_uncertainty: of_s },
    ];
    PositioningUncertainty { a, e: 2.0 * systematic, m: 2.0 * systematic, r, b, length, budget }
}
