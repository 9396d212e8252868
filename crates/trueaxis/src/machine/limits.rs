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
//!
//! A limit set higher (in the file or for one run) is bounded too, at ten times the defaults:
//! 10 mm for a linear axis, 0.1 rad (5.7 deg, the largest angular error value trueaxis reads,
//! `io::ranges`) for a rotary one. A correction beyond them is not of a quasi-static error but of
//! a wrong nominal geometry, or a value in mm read as um: a limit of `1e308` would let it through.

use crate::error::Result;

/// Default largest correction of a linear axis (um).
pub const DEFAULT_CORRECTION_UM: f64 = 1000.0;
/// Default largest correction of a rotary axis (urad).
pub const DEFAULT_CORRECTION_URAD: f64 = 10_000.0;
/// Largest limit of a linear axis that may be set (um).
pub const MAX_CORRECTION_UM: f64 = 10.0 * DEFAULT_CORRECTION_UM;
/// Largest limit of a rotary axis that may be set (urad).
pub const MAX_CORRECTION_URAD: f64 = 10.0 * DEFAULT_CORRECTION_URAD;

/// Checks a correction limit (`rotary`: urad, else um) named `name` in messages: a positive
/// number at most [`MAX_CORRECTION_UM`] or [`MAX_CORRECTION_URAD`].
pub fn check_limit_value(name: &str, value: f64, rotary: bool) -> Result<()> {
    let (max, unit) = if rotary { (MAX_CORRECTION_URAD, "urad") } else { (MAX_CORRECTION_UM, "um") };
    let shown = if (1e-3..1e6).contains(&value.abs()) { format!("{value}") } else { format!("{value:e}") };
    crate::ensure!(value.is_finite() && value > 0.0, input, "{name} = {shown} must be a positive number ({unit})");
    crate::ensure!(
        value <= max,
        input,
        "{name} = {shown} {unit} is more than the {max} {unit} a correction limit may be (ten times the default: a larger \
         correction is not of a machine's quasi-static errors but of a wrong geometry or unit)"
    );
    Ok(())
}

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

    /// Checks the values of a `[limits]` table ([`check_limit_value`]).
    pub(super) fn validate(&self) -> Result<()> {
        for (name, v, rotary) in
            [("[limits] correction_um", self.correction_um, false), ("[limits] correction_urad", self.correction_urad, true)]
        {
            if let Some(v) = v {
                check_limit_value(name, v, rotary)?;
            }
        }
        Ok(())
    }
}
