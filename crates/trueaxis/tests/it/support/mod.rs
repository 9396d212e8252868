//! Helpers shared by several tests. `basis_campaign` is also included by path by
//! `benches/identify.rs` and `crates/cli/tests/it/identify/basis.rs`; `damage` makes the damaged
//! variants of the shipped examples the screening tests read; `tools` (also included by path by
//! `crates/cli/tests/it/live/mod.rs`) finds the outside tools and runs LinuxCNC's.

pub mod basis_campaign;
pub mod damage;
pub mod examples;
pub mod kx8five_capball;
pub mod tools;
