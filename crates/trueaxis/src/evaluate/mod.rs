//! Standard evaluations: ISO 230-2 positioning accuracy (and a positioning test from its file,
//! `positioning_test`; its measurement uncertainty, `positioning_uncertainty`), ISO 230-4 circular
//! tests with ballbar diagnostics (and from a file, `circular_test`), verification of a
//! compensation by a re-measurement.
//!
//! Errors are [`crate::Error`]s: a file, a line or an option that cannot be evaluated is bad input
//! (the message names the file, the line and the offending value); an evaluation that overflows is
//! a failed computation.

pub mod ballbar_diagnostics;
pub mod ballbar_screening;
pub mod circular_test;
pub mod iso230_2;
pub mod iso230_4;
pub mod positioning_screening;
pub mod positioning_test;
pub mod positioning_uncertainty;
pub mod verification;
