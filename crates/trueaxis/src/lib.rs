//! trueaxis: find, explain and remove the quasi-static errors of multi-axis machine tools.
//!
//! The modules follow the pipeline of docs/design.md, The pipeline; data flows one way:
//! `machine` -> `model` (with `error_model`) -> instruments -> identify -> uncertainty -> compensate -> `report`.
//! Internal units are mm and rad; files and outputs use mm, deg, um and urad (docs/design.md, Conventions).

pub mod budget;
pub mod compensate;
pub mod data;
pub mod error;
pub mod error_model;
pub mod evaluate;
pub mod files;
pub mod geometry;
pub mod identify;
pub mod instruments;
pub mod io;
pub mod machine;
pub mod model;
pub mod poses;
pub mod screen;
pub mod thermal;
pub mod uncertainty;

pub use error::{Error, ErrorKind, Origin};
