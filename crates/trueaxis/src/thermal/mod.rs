//! Thermal errors (Zhu 2008 ch. 3-4, Soons 1993 §3.4, NISTIR 5236 §3.5-3.6): transient heat-conduction
//! finite elements, thermal modal analysis, mode weights and truncation, temperature-sensor
//! placement, time-constant fits, regression (PITE/PDTE) and state-space thermal error models,
//! their validation, and thermal links expressed as error terms of the kinematic chain.
//!
//! Units: SI inside this module (m, s, W, J, K) for the heat-conduction model; temperatures in
//! degC, time in s (minutes only where named `_min`); thermal errors in um and urad, axis positions
//! in mm or deg, as everywhere in trueaxis (docs/design.md, Conventions).

pub mod amg;
pub mod assembly;
pub mod beam;
pub mod campaign_fit;
pub mod campaign_predict;
pub mod drift_model;
pub mod error_model;
pub mod lanczos;
pub mod levenberg_marquardt;
pub mod links;
pub mod lobpcg;
pub mod matrix_market;
pub mod mesh;
pub mod modal;
pub mod model_file;
pub mod modes_report;
pub mod ordering;
pub mod placement;
pub mod placement_comparison;
pub mod placement_job;
pub mod placement_score;
pub mod regression;
pub mod response;
pub mod segmented;
pub mod sparse_cholesky;
mod sparse_rows;
pub mod state_space;
pub mod stepping;
pub mod temperature_model;
pub mod thermal_campaign;
pub mod thermal_screening;
pub mod time_constants;
pub mod tuning;
pub mod validation;
pub mod weights;

pub use assembly::{assemble, Boundary, Material, Section, ThermalSystem};
pub use lanczos::LanczosProgress;
pub use mesh::StructuredMesh;
pub use modal::{modal_analysis, modal_analysis_with_progress, ModalBasis, ModalOptions, SpectrumMethod};
pub use weights::{dominant_modes, mode_weights, ModeWeight, DEFAULT_SHARE};
