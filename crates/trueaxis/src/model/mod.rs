//! Nominal and actual forward kinematics, the exact volumetric error and its first-order Jacobian
//! (docs/design.md, Conventions), with batch evaluation over many poses.

mod chain;
mod jacobian;
mod kernel;
mod lanes;
mod predictor;
mod volumetric;

pub use chain::{actual_chain, nominal_chain};
pub use jacobian::{jacobian, JacobianWorkspace, JACOBIAN_ROWS};
pub(crate) use kernel::{BlockState, RelativeTargets};
pub use kernel::{KernelWorkspace, VolumetricKernel, INSTRUCTION_SETS};
pub(crate) use lanes::{set_mat_lane, LANES};
pub use predictor::{jacobian_batch, Predictor};
pub use volumetric::{volumetric_error, Frame, Setup, VolumetricError};
