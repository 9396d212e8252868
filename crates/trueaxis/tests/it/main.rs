//! The core's integration tests, one binary (`cargo test -p trueaxis --test it`): one module per
//! module of `crates/trueaxis/src` (`it/identify/tmbb.rs` checks `identify::tmbb`), the shared
//! helpers in [`support`], and the checks that span the library at the top ([`bad_input`],
//! [`fuzz_replay`], [`python_reference`], and the rules the repository keeps about
//! itself, [`repository`]). Run one part by its path:
//! `cargo test -p trueaxis --test it compensate::nc::linuxcnc_samples`.
//!
//! Every test here shares one process with the others and runs on its own thread: none may set
//! environment variables, change the current directory or install a global thread pool; each
//! writes only below its own temporary directory.

mod bad_input;
mod budget;
mod compensate;
mod data;
mod error_model;
mod evaluate;
mod fuzz_replay;
mod identify;
mod instruments;
mod io;
mod model;
mod python_reference;
mod repository;
mod screen;
mod support;
mod thermal;
mod uncertainty;
