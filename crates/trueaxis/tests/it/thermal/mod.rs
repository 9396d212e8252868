//! Thermal models (`trueaxis::thermal`): modes, Lanczos accuracy, fitted models, campaigns, the
//! screening of damaged thermal campaigns.

mod lanczos;
mod modal;
mod models;
mod thermal_campaign;
mod thermal_screening;
