//! Nominal and actual forward kinematics, the exact volumetric error and its first-order Jacobian
//! (docs/design.md, Conventions), with batch evaluation over many poses.

mod batch;
mod chain;
mod jacobian;
mod kernel;
mod lanes;
mod volumetric;

pub use batch::{jacobian_batch, Predictor};
pub use chain::{actual_chain, nominal_chain};
pub use jacobian::{jacobian, JacobianWorkspace, JACOBIAN_ROWS};
pub(crate) use kernel::{BlockState, RelativeTargets};
pub use kernel::{KernelWorkspace, VolumetricKernel, INSTRUCTION_SETS};
pub(crate) use lanes::{set_mat_lane, LANES};
pub use volumetric::{volumetric_error, Frame, Setup, VolumetricError};
