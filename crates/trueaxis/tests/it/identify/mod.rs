//! Identification (`trueaxis::identify`): round trips from simulated measurements back to the errors.

mod ball3d;
mod direct;
mod instruments;
mod kx8five;
mod optimal_design;
mod pige;
mod pige_sensitivity;
mod tmbb;
mod tmbb_setup;
