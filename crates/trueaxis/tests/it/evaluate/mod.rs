//! Evaluations by the standards (`trueaxis::evaluate`): ISO 230-4 circular tests, ISO 230-2 uncertainty.

mod iso230_4;
mod positioning_uncertainty;
