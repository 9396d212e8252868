//! Instrument files (`trueaxis::io`): vendor formats read back, plausibility checks, readers that never panic,
//! the calendar of the times written.

mod ballbar;
mod calendar;
mod etalon;
mod fuzz;
mod plausibility;
mod rtl;
