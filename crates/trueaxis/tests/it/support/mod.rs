//! Helpers shared by several tests. `basis_campaign` is also included by path by
//! `benches/identify.rs` and `crates/cli/tests/it/identify/basis.rs`.

pub mod basis_campaign;
pub mod examples;
pub mod kx8five_capball;
