//! Thermal models (`trueaxis::thermal`): modes, Lanczos accuracy, fitted models, campaigns.

mod lanczos;
mod modal;
mod models;
mod thermal_campaign;
