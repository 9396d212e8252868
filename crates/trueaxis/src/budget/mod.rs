//! Error budget for machine design (Zhu 2008, appendices B and C): which component errors
//! matter at the tool point, how tight each must be, and which five-axis configuration suits a part.
//!
//! - [`components`]: the component errors of a budget (ISO 230 names), their kind (linear, angular,
//!   squareness) and homogenisation length; [`spec`]: the tolerance and cost file.
//! - [`sensitivity`]: the sensitivity (error-gain) matrix of the tool-point position error with
//!   respect to every component, the derivative of the exact chain at zero errors (eqs. B.1-B.2).
//! - [`stackup`]: root-sum-square and worst-case stack-up per direction and of the 3D error (B.3-B.4).
//! - [`measures`]: singular values, condition number, part and machine sensitivity measures (B.9-B.19)
//!   and the contribution of each group (B.20-B.21); [`analysis`] binds them over a pose set.
//! - [`cost`], [`allocate`], [`barrier`], [`global`]: the cost model `A / e^k` with lower limits and
//!   the cost-optimal allocation (B.5-B.8): a seeded genetic global stage, then an interior-point
//!   local stage on the convex form of the problem, with a KKT check.
//! - [`configurations`], [`form_shaping`], [`travel`], [`ranking`]: the five-axis configurations of
//!   appendix C, their ideal form-shaping functions (Table C.1), required travel (Table C.2) and their
//!   budgets; [`miniaturisation`]: the three-axis case of appendix B.2 (parts 10 to 300 mm), run over
//!   every size with its document by [`miniaturisation_study`];
//!   [`configuration_study`]: the whole study of `trueaxis budget configurations`.
//! - [`problem`]: a budget problem (machine, budget, points, frame, pose sets) as the command line
//!   and the Python package state it; [`documents`]: its JSON documents and CSV tables.
//!
//! Units: component tolerances in um (translations) and urad (rotations); volumetric errors in um;
//! homogenised tolerances in um/m (linear errors divided by their axis length) or urad.

pub mod allocate;
pub mod analysis;
pub mod barrier;
pub mod components;
pub mod configuration_study;
pub mod configurations;
pub mod cost;
pub mod documents;
pub mod form_shaping;
pub mod global;
pub mod measures;
pub mod miniaturisation;
pub mod miniaturisation_study;
pub mod poses;
pub mod problem;
pub mod ranking;
pub mod sensitivity;
pub mod spec;
pub mod stackup;
pub mod travel;

pub use allocate::{allocate, Allocation, AllocationOptions, Stack, Target};
pub use analysis::{analyse, Analysis, PoseResult};
pub use components::{default_components, BudgetComponent, ErrorKind};
pub use cost::{CostModel, CostTerm};
pub use spec::BudgetSpec;
