//! The error model (`trueaxis::error_model`).

mod inputs;
