//! Evaluations by the standards (`trueaxis::evaluate`): ISO 230-4 circular tests, ISO 230-2 uncertainty,
//! the screening of positioning tests and ballbar files against damaged variants of the examples.

mod ballbar_screening;
mod iso230_4;
pub mod positioning_screening;
mod positioning_uncertainty;
