//! Instrument files (`trueaxis::io`): vendor formats read back, plausibility checks, readers that never panic.

mod ballbar;
mod etalon;
mod fuzz;
mod plausibility;
mod rtl;
