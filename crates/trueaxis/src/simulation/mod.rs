//! Simulated calibrations of a machine with known errors: the measurements a calibration would
//! record, computed on the exact kinematic chain with the true errors, seeded sensor noise and a
//! drift of the measuring chain, so that what the identification finds can be compared with the
//! truth (`trueaxis demo`; the round trip of docs/design.md).
//!
//! - [`kx8five`]: the built-in machine, the Huron KX8-Five of Andolfatto et al. 2011 (structure
//!   `WCAYFXZT`, A tilted 45 deg), with the link and setup errors of their Table 1, the 807-pose
//!   CapBall campaign and the uncertainty sources of their Tables 3 and 4 with a cyclic drift.
//! - [`capball`]: the CapBall campaign simulated with the sensor noise and the cyclic drift, and
//!   the true errors expressed in the campaign's parameter set.
//! - [`circle`]: an ISO 230-4 ballbar circle, CCW then CW, simulated with noise.

pub mod capball;
pub mod circle;
pub mod kx8five;
