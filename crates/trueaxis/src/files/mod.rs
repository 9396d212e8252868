//! The file system as the library meets it, below every other module: the input files a run reads
//! (tracked, so that no output of the run overwrites one: [`inputs`]) and the system errors that
//! come from the environment rather than from the input (a full disk, a permission, memory:
//! [`environment`]; docs/reliability.md).

pub mod environment;
pub mod inputs;

pub use environment::{environment_cause, is_environment};
