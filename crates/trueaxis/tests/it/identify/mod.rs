//! Identification (`trueaxis::identify`): round trips from simulated measurements back to the errors;
//! the screened, robust and direct identifications of damaged variants of the examples.

mod ball3d;
mod campaign_screening;
mod direct;
pub mod direct_screening;
mod instruments;
mod kx8five;
mod optimal_design;
mod pige;
mod pige_sensitivity;
mod robust_campaign;
mod tmbb;
mod tmbb_setup;
