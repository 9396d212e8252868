//! Shared by the modules of the test binary: the one runner of `trueaxis` and what several
//! commands' tests use.

mod runner;
pub mod thermal;

pub use runner::*;
