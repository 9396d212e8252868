//! The correction limit of a machine (`[limits]` of the machine file): the largest correction
//! trueaxis may write for an axis, in every table, NC program and real-time call. A correction
//! beyond it is refused, never clipped: it means an error value in the wrong unit (a 1e12 typed
//! for 12) or a model that does not describe the machine, and clipping would hide that.
//!
//! Defaults (when the machine file has no `[limits]`):
//! - linear axes 1000 um: the largest "amount of change" Heidenhain's KinematicsOpt accepts for a
//!   kinematic correction (iTNC 530 technical manual, July 2013, §6.5, MP6600: input 0.010 to
//!   1.000 mm, default 0.05 mm). Geometric errors of machine tools are tens to hundreds of um
//!   (the shipped examples: at most 164 um).
//! - rotary axes 10 000 urad (0.57 deg): near the tool-axis singularity of a five-axis machine the
//!   rotary correction is the orientation error divided by the sine of the tilt (damped), so
//!   orientation errors of 0.1 mrad already need a few mrad there (the shipped C600U: 3.4 mrad);
//!   a unit slip (deg for urad, mrad for urad) is still 100 to 17 000 times beyond it.

/// Default largest correction of a linear axis (um).
pub const DEFAULT_CORRECTION_UM: f64 = 1000.0;
/// Default largest correction of a rotary axis (urad).
pub const DEFAULT_CORRECTION_URAD: f64 = 10_000.0;

/// The `[limits]` of a machine file; `None` where the file does not set a value.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CorrectionLimits {
    /// Largest correction of a linear axis (um).
    pub correction_um: Option<f64>,
    /// Largest correction of a rotary axis (urad).
    pub correction_urad: Option<f64>,
}

impl CorrectionLimits {
    /// The linear limit (um), the file's or the default.
    pub fn linear_um(&self) -> f64 {
        self.correction_um.unwrap_or(DEFAULT_CORRECTION_UM)
    }

    /// The rotary limit (urad), the file's or the default.
    pub fn rotary_urad(&self) -> f64 {
        self.correction_urad.unwrap_or(DEFAULT_CORRECTION_URAD)
    }

    /// Checks the values of a `[limits]` table: positive finite numbers.
    pub(super) fn validate(&self) -> Result<(), String> {
        for (name, v) in [("correction_um", self.correction_um), ("correction_urad", self.correction_urad)] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0) {
                    return Err(format!("[limits] {name} = {v} must be a positive number"));
                }
            }
        }
        Ok(())
    }
}
