//! The kinematic model (`trueaxis::model`): exact chain, first-order Jacobian, batch kernel.

mod chain_vs_jacobian;
mod kernel;
mod lathe_closed_form;
