//! Screening of measurement data before any fit: what in a file is suspect, where, and what it
//! would do to the result.
//!
//! Data from a shop floor is damaged in parts more often than as a whole: one run or column in
//! another unit, one run of another axis, a stuck sensor, a pose recorded twice, a beam
//! interruption, a re-seated temperature sensor, a logger gap, a feed-rate spike on a ballbar. Whole
//! files that are wrong are refused by the readers (`io::plausibility`); the checks here look at the
//! parts, with robust statistics (median and median absolute deviation, MAD, scaled by 1.4826 to
//! estimate a normal standard deviation; Huber 1981, Rousseeuw and Croux 1993) so that the damage
//! does not hide itself by inflating the scale it is measured with.
//!
//! Every check returns [`Finding`]s of one type: the kind of damage, the file, where in it (run,
//! column, rows and file lines), what was seen and what it means for the result. Thresholds are
//! stated at each check and in docs/screening.md, with the false-alarm rate measured on simulated
//! clean data.
//!
//! Units: deviations and readings in um, temperatures in degC, time in s, positions in mm / deg.

pub mod finding;
pub mod irls;
pub mod robust;
pub mod series;

pub use finding::{findings_json, Finding, Kind};
