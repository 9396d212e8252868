//! Shared by the modules of the test binary: the one runner of `trueaxis` and what several
//! commands' tests use.

mod args;
mod runner;
pub mod thermal;

pub use args::*;
pub use runner::*;
