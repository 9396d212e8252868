//! Shared by the modules of the test binary.

pub mod thermal;
