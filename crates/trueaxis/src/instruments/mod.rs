//! Measurement equations and reductions of instruments.
//!
//! - [`laser`], [`level`], [`direct`]: direct instruments on the exact chain: laser linear,
//!   straightness and angular optics with the Abbe effect of their position, electronic levels
//!   (single or differential), the instrument that measures a given motion error, simulation.
//! - [`reversal`]: straightness with an imperfect test arbor by reversal, parallelism from best-fit
//!   circle radii, and the flat-face disk reversal for straightness and orthogonality (NISTIR 5236
//!   NISTIR 5236 §3.4, eqs. 3.1-3.8).
//! - [`ballbar`]: ballbar (DBB) setups and bar readings simulated on the exact chain: ISO 230-4
//!   planar circles and the rotary-axis tests of Jiang 2014 (ch. 4, 5, 6); [`ballbar_simulation`]:
//!   their readings as `trueaxis ballbar simulate` writes them, with seeded Gaussian noise.
//! - [`ballbar_raw`]: the capture arc of a raw ballbar stream (overshoot and feed moves stripped,
//!   sample index to angle, Jiang 2014 §4.2).
//! - [`steady`]: steady values of a sampled stream (one 3D-ball reading per pose from a 1000 Hz
//!   recording with a dwell at each pose, Andolfatto et al. 2011 §3.4).
//! - [`scale`]: correction of linear-displacement readings to the 20 degC reference temperature
//!   (ISO 1) for the thermal expansion of the machine scale or of the reference artefact, and the
//!   apparent expansion coefficient of a scale from two runs at two temperatures (Soons 1993 §3.2.4,
//!   §5.1.1).
//!
//! Units at this interface are the user-facing ones of docs/design.md, Conventions: positions in mm,
//! readings and deviations in um, slopes and angles in urad, temperatures in degC, expansion
//! coefficients in um/m/K (= 1e-6 /K).

pub mod ball3d;
pub mod ballbar;
pub mod ballbar_raw;
pub mod ballbar_simulation;
pub mod direct;
pub mod laser;
pub mod length;
pub mod level;
pub mod measurement;
pub mod probe;
pub mod reversal;
pub mod scale;
pub mod scale_options;
pub mod steady;
pub mod trajectory;

pub use ball3d::{Ball3d, SensorCalibration};
pub use ballbar_raw::{capture_arc, ArcProgramme, CapturedArc};
pub use direct::{motion_error_axis, DirectError, DirectInstrument, DirectKind, DirectSetup};
pub use laser::{Laser, LaserError, LaserOptics};
pub use length::{Length, PointLength};
pub use level::{Level, LevelBody, LevelError};
pub use measurement::{nominal_vector, Instrument};
pub use probe::{plate_displacement, plate_rows, Probe};
pub use reversal::{
    best_fit_radius, flat_face_reversal, parallelism_urad, straightness_reversal, BestFitLine, BestFitRadii, FlatFaceReversal,
    ReversalError, ReversalOptions, ReversalStraightness,
};
pub use scale::{
    apparent_expansion_coefficient, correct_to_20c, thermal_expansion_um, uniform_expansion_um, ApparentExpansion, ExpandingBody,
    ScaleError, ScaleTemperature, TableCorrection, TableCorrectionError, TemperatureSource, ThermalCorrection, ThermalRun,
    REFERENCE_TEMPERATURE_DEGC,
};
pub use scale_options::{AppliedCorrection, TemperatureOptions};
pub use steady::{plateaus, steady_values, Plateau, SteadySettings};
pub use trajectory::{ball_trajectory, Sweep};

/// Unweighted least-squares line `y = intercept + slope * x`, returned as `(slope, intercept)`.
/// `None` when all `x` are equal (no line through them is defined). The caller checks lengths and
/// finiteness. Centred sums, so that large position offsets do not cost precision.
pub(crate) fn least_squares_line(x: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    debug_assert_eq!(x.len(), y.len());
    let first = *x.first()?;
    if x.iter().all(|&v| v == first) {
        return None;
    }
    let n = x.len() as f64;
    let x_mean = x.iter().sum::<f64>() / n;
    let y_mean = y.iter().sum::<f64>() / n;
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for (&xi, &yi) in x.iter().zip(y) {
        let dx = xi - x_mean;
        sxx += dx * dx;
        sxy += dx * (yi - y_mean);
    }
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    Some((slope, y_mean - slope * x_mean))
}
