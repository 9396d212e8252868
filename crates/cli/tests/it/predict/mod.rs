//! `trueaxis predict`: every example machine, the error state (directions, temperatures) and the
//! error terms of inputs.

mod error_inputs;
mod error_state;
mod examples;
