//! Reversal techniques with test arbors and a flat-face disk (NISTIR 5236 §3.4,
//! eqs. 3.1-3.8).
//!
//! Units: positions in mm, probe readings and straightness in um, slopes (parallelism,
//! orthogonality, misalignment) in urad. A slope of 1 um/mm is 1000 urad.
//!
//! Sign conventions are the seed's, as printed:
//! - arbor reversal (eqs. 3.1-3.2): `m1(z) = a(z) - s(z)`, `m2(z) = a(z) + s(z)`; `m1` is probe 1
//!   in the first set-up, `m2` is probe 2 (mounted 180 deg from probe 1) after the arbor has been
//!   turned 180 deg with the spindle. The arbor profile `a` therefore enters both readings with the
//!   same sign and the machine straightness `s` with opposite signs; `s` is counted positive when it
//!   decreases probe 1's reading. With readings that grow when the arbor surface approaches the probe
//!   (a "radius" reading, as the seed's eq. 3.4 calls them), `s` is the displacement of the carriage
//!   towards the side of probe 1, relative to the spindle;
//! - flat-face disk (eqs. 3.6-3.7): `m1(x) = -delta_z(x) + e(x)`, `m2(x) = -delta_z(x) - e(x)`, the
//!   second set with the spindle turned 180 deg and the same probe; `e` is the face squareness plus
//!   mounting misalignment (it turns with the spindle), `delta_z` the z straightness of the x motion
//!   including the orthogonality term: `delta_z(x) = delta'_z(x) + alpha_o x` (NISTIR 5236 §2.3).

use super::least_squares_line;
use thiserror::Error;

/// An input error of a reversal reduction; the message names the quantity at fault.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ReversalError {
    #[error("{what}: {first} has {first_len} values but {second} has {second_len}; they must be taken at the same positions")]
    LengthMismatch { what: &'static str, first: &'static str, first_len: usize, second: &'static str, second_len: usize },
    #[error("{what}: needs at least {needed} points, got {got}")]
    TooFewPoints { what: &'static str, needed: usize, got: usize },
    #[error("{what}: {name}[{index}] is not a finite number ({value})")]
    NonFinite { what: &'static str, name: &'static str, index: usize, value: f64 },
    #[error("{what}: all positions are equal ({position} mm), so no least-squares line can be fitted")]
    DegeneratePositions { what: &'static str, position: f64 },
    #[error("parallelism: the distance dz between the two locations must be finite and non-zero, got {0} mm")]
    InvalidDistance(f64),
}

crate::error::error_of_kind!(ReversalError, Input);

/// A least-squares line through deviations (um) against positions (mm):
/// `value(x) = intercept_um + slope_urad * 1e-3 * x`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BestFitLine {
    /// Slope in urad (um/m); 1 um/mm = 1000 urad.
    pub slope_urad: f64,
    /// Value of the line at position 0 mm, um.
    pub intercept_um: f64,
}

impl BestFitLine {
    /// The line's value (um) at `position_mm`.
    pub fn value_um(&self, position_mm: f64) -> f64 {
        self.intercept_um + self.slope_urad * 1e-3 * position_mm
    }

    /// Least-squares line of `values_um` against `positions_mm` (inputs already checked).
    fn fit(what: &'static str, positions_mm: &[f64], values_um: &[f64]) -> Result<Self, ReversalError> {
        let (slope, intercept) =
            least_squares_line(positions_mm, values_um).ok_or(ReversalError::DegeneratePositions { what, position: positions_mm[0] })?;
        Ok(BestFitLine { slope_urad: slope * 1e3, intercept_um: intercept })
    }
}

/// Options of [`straightness_reversal`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReversalOptions {
    /// Remove the least-squares line from the straightness (ISO 230-1 reference straight line by
    /// least squares) and report it separately: its slope is the arbor-to-axis misalignment plus
    /// the parallelism of the axis to the spindle axis average line (NISTIR 5236 §3.4: "the best fit
    /// slope subtraction on the resultant data eliminates the misalignment errors").
    pub remove_line: bool,
}

/// Result of [`straightness_reversal`].
#[derive(Clone, Debug, PartialEq)]
pub struct ReversalStraightness {
    /// Machine straightness `s(z) = (m2 - m1) / 2` (NISTIR 5236 eq. 3.3), um; minus the least-squares
    /// line when [`ReversalOptions::remove_line`] is set.
    pub straightness_um: Vec<f64>,
    /// Arbor profile `a(z) = (m1 + m2) / 2` (from NISTIR 5236 eqs. 3.1 + 3.2), um. It contains the
    /// arbor's form error and its mounting misalignment (both turn with the spindle); no line is
    /// removed from it.
    pub arbor_form_um: Vec<f64>,
    /// The least-squares line removed from the straightness, when asked for.
    pub line: Option<BestFitLine>,
}

impl ReversalStraightness {
    /// Straightness deviation (ISO 230-1): largest minus smallest value of `straightness_um`, um.
    pub fn straightness_deviation_um(&self) -> f64 {
        peak_to_valley(&self.straightness_um)
    }
}

/// Straightness of an axis and form of the test arbor by reversal (NISTIR 5236 §3.4, eqs. 3.1-3.3).
///
/// `positions_mm`: the axis positions z of the readings (mm, any order, at least 2 points);
/// `m1_um`: probe 1 readings in the first set-up; `m2_um`: probe 2 readings (probe 2 is mounted
/// 180 deg from probe 1) after the arbor has been turned 180 deg with the spindle, at the same
/// positions (um). With `m1 = a - s` (eq. 3.1) and `m2 = a + s` (eq. 3.2):
/// `s = (m2 - m1) / 2` (eq. 3.3) and `a = (m1 + m2) / 2`.
///
/// With `options.remove_line` the least-squares line of `s` against z is subtracted and returned
/// (slope in urad), which needs at least two distinct positions.
pub fn straightness_reversal(
    positions_mm: &[f64],
    m1_um: &[f64],
    m2_um: &[f64],
    options: ReversalOptions,
) -> Result<ReversalStraightness, ReversalError> {
    const WHAT: &str = "reversal straightness";
    check_series(WHAT, positions_mm, &[("m1 (probe 1 readings)", m1_um), ("m2 (probe 2 readings, arbor reversed)", m2_um)])?;
    let mut straightness_um: Vec<f64> = m1_um.iter().zip(m2_um).map(|(m1, m2)| 0.5 * (m2 - m1)).collect();
    let arbor_form_um = m1_um.iter().zip(m2_um).map(|(m1, m2)| 0.5 * (m1 + m2)).collect();
    let line = if options.remove_line {
        let line = BestFitLine::fit(WHAT, positions_mm, &straightness_um)?;
        for (s, &z) in straightness_um.iter_mut().zip(positions_mm) {
            *s -= line.value_um(z);
        }
        Some(line)
    } else {
        None
    };
    Ok(ReversalStraightness { straightness_um, arbor_form_um, line })
}

/// Best-fit circle radius of one revolution of probe readings: their mean,
/// `R = (sum r_i) / n` (NISTIR 5236 eq. 3.4), um.
///
/// The mean is the least-squares circle radius for readings equally spaced in angle over whole
/// revolutions (512 per revolution in the seed); it removes the eccentricity (the limacon of a
/// misaligned round arbor) and the arbor's out-of-roundness. At least 3 readings.
pub fn best_fit_radius(readings_um: &[f64]) -> Result<f64, ReversalError> {
    const WHAT: &str = "best-fit radius";
    if readings_um.len() < 3 {
        return Err(ReversalError::TooFewPoints { what: WHAT, needed: 3, got: readings_um.len() });
    }
    check_finite(WHAT, "readings", readings_um)?;
    Ok(readings_um.iter().sum::<f64>() / readings_um.len() as f64)
}

/// The four best-fit radii of the parallelism test (NISTIR 5236 eq. 3.5), um. The seed's `R_ij` has the
/// location first and the probe second: `R11` = probe 1 at location 1, `R21` = probe 1 at location 2,
/// `R12` = probe 2 at location 1, `R22` = probe 2 at location 2. The fields spell this out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BestFitRadii {
    /// `R11`: probe 1 at location 1.
    pub probe1_location1_um: f64,
    /// `R21`: probe 1 at location 2.
    pub probe1_location2_um: f64,
    /// `R12`: probe 2 at location 1.
    pub probe2_location1_um: f64,
    /// `R22`: probe 2 at location 2.
    pub probe2_location2_um: f64,
}

impl BestFitRadii {
    /// The radii from four revolutions of readings, each by [`best_fit_radius`] (NISTIR 5236 eq. 3.4).
    pub fn from_readings(
        probe1_location1_um: &[f64],
        probe1_location2_um: &[f64],
        probe2_location1_um: &[f64],
        probe2_location2_um: &[f64],
    ) -> Result<Self, ReversalError> {
        Ok(BestFitRadii {
            probe1_location1_um: best_fit_radius(probe1_location1_um)?,
            probe1_location2_um: best_fit_radius(probe1_location2_um)?,
            probe2_location1_um: best_fit_radius(probe2_location1_um)?,
            probe2_location2_um: best_fit_radius(probe2_location2_um)?,
        })
    }
}

/// Parallelism between an axis and the spindle axis average line from best-fit radii (NISTIR 5236
/// eq. 3.5): `alpha_p = [(R21 - R11) - (R22 - R12)] / (2 dz)`, in urad, with the radii in um and the
/// distance `dz_mm` from location 1 to location 2 in mm (signed: negative if location 2 is at the
/// smaller axis position).
///
/// Sign: with readings that grow when the arbor surface approaches the probe (a "radius"), a change
/// of the arbor diameter moves both probes' radii the same way and cancels; a shift of the spindle
/// axis towards probe 1 raises probe 1's radius and lowers probe 2's. So `alpha_p` is the slope of the
/// spindle axis average line, relative to the carriage, towards probe 1, per unit of travel from
/// location 1 to location 2. With probe 1 on the -x side of the arbor this is the slope of the x
/// deviation of the carriage, `delta_x(z) = delta'_x(z) + alpha_p dz` (NISTIR 5236 §2.3). The
/// straightness of the axis at the two locations is not removed: `alpha_p` is the slope of the chord
/// through the two locations.
pub fn parallelism_urad(radii: &BestFitRadii, dz_mm: f64) -> Result<f64, ReversalError> {
    if !dz_mm.is_finite() || dz_mm == 0.0 {
        return Err(ReversalError::InvalidDistance(dz_mm));
    }
    let r = [radii.probe1_location1_um, radii.probe1_location2_um, radii.probe2_location1_um, radii.probe2_location2_um];
    check_finite("parallelism", "radii [R11, R21, R12, R22]", &r)?;
    let probe1_change = radii.probe1_location2_um - radii.probe1_location1_um;
    let probe2_change = radii.probe2_location2_um - radii.probe2_location1_um;
    Ok((probe1_change - probe2_change) / (2.0 * dz_mm) * 1e3)
}

/// Result of [`flat_face_reversal`].
#[derive(Clone, Debug, PartialEq)]
pub struct FlatFaceReversal {
    /// `delta_z(x) = -(m1 + m2) / 2` (NISTIR 5236 eq. 3.8), um: the z straightness of the x motion
    /// including the orthogonality term `alpha_o x`.
    pub delta_z_um: Vec<f64>,
    /// `e(x) = (m1 - m2) / 2` (from NISTIR 5236 eqs. 3.6 - 3.7), um: disk face squareness plus its
    /// mounting misalignment, as seen by the probe.
    pub face_error_um: Vec<f64>,
    /// Least-squares line of `delta_z` against x; its slope is the orthogonality `alpha_o` between
    /// the x motion and the spindle axis average line, urad (`delta_z(x) = delta'_z(x) + alpha_o x`).
    pub line: BestFitLine,
    /// `delta'_z(x)`: `delta_z` minus the least-squares line, um (the straightness per ISO 230-1).
    pub straightness_um: Vec<f64>,
}

impl FlatFaceReversal {
    /// The orthogonality `alpha_o`, urad: slope of the least-squares line of `delta_z(x)`.
    pub fn orthogonality_urad(&self) -> f64 {
        self.line.slope_urad
    }

    /// Straightness deviation of `delta'_z` (largest minus smallest), um.
    pub fn straightness_deviation_um(&self) -> f64 {
        peak_to_valley(&self.straightness_um)
    }
}

/// z straightness of the x motion and its orthogonality to the spindle axis with a flat-face disk
/// and a spindle reversal (NISTIR 5236 §3.4, eqs. 3.6-3.8).
///
/// `positions_mm`: cross-slide positions x (mm, at least 2 distinct); `m1_um`: the probe readings of
/// the first scan; `m2_um`: the same probe after the spindle (with the disk) has been turned 180 deg
/// (um). With `m1 = -delta_z + e` (eq. 3.6) and `m2 = -delta_z - e` (eq. 3.7):
/// `delta_z = -(m1 + m2) / 2` (eq. 3.8), `e = (m1 - m2) / 2`, and the orthogonality is the slope of
/// the least-squares line of `delta_z` against x (um/mm x 1000 = urad). The seed assumes a disk face
/// of perfect form (calibrated beforehand, e.g. on a CMM by reversal); form errors of the face are
/// not separated.
pub fn flat_face_reversal(positions_mm: &[f64], m1_um: &[f64], m2_um: &[f64]) -> Result<FlatFaceReversal, ReversalError> {
    const WHAT: &str = "flat-face reversal";
    check_series(WHAT, positions_mm, &[("m1 (first scan)", m1_um), ("m2 (spindle turned 180 deg)", m2_um)])?;
    let delta_z_um: Vec<f64> = m1_um.iter().zip(m2_um).map(|(m1, m2)| -0.5 * (m1 + m2)).collect();
    let face_error_um = m1_um.iter().zip(m2_um).map(|(m1, m2)| 0.5 * (m1 - m2)).collect();
    let line = BestFitLine::fit(WHAT, positions_mm, &delta_z_um)?;
    let straightness_um = delta_z_um.iter().zip(positions_mm).map(|(d, &x)| d - line.value_um(x)).collect();
    Ok(FlatFaceReversal { delta_z_um, face_error_um, line, straightness_um })
}

fn peak_to_valley(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    max - min
}

/// Positions plus two reading series: equal lengths, at least 2 points, all finite.
fn check_series(what: &'static str, positions_mm: &[f64], series: &[(&'static str, &[f64])]) -> Result<(), ReversalError> {
    for &(name, values) in series {
        if values.len() != positions_mm.len() {
            return Err(ReversalError::LengthMismatch {
                what,
                first: "positions",
                first_len: positions_mm.len(),
                second: name,
                second_len: values.len(),
            });
        }
    }
    if positions_mm.len() < 2 {
        return Err(ReversalError::TooFewPoints { what, needed: 2, got: positions_mm.len() });
    }
    check_finite(what, "positions", positions_mm)?;
    for &(name, values) in series {
        check_finite(what, name, values)?;
    }
    Ok(())
}

fn check_finite(what: &'static str, name: &'static str, values: &[f64]) -> Result<(), ReversalError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(ReversalError::NonFinite { what, name, index, value: values[index] }),
        None => Ok(()),
    }
}
