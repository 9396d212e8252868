//! trueaxis: find, explain and remove the quasi-static errors of multi-axis machine tools.
//!
//! The modules follow the pipeline of DESIGN.md section 1; data flows one way:
//! `machine` -> `model` (with `errors`) -> instruments -> identify -> uncertainty -> compensate -> `report`.
//! Internal units are mm and rad; files and outputs use mm, deg, um and urad (DESIGN.md section 2).

pub mod budget;
pub mod compensate;
pub mod data;
pub mod errors;
pub mod evaluate;
pub mod geometry;
pub mod identify;
pub mod instruments;
pub mod io;
pub mod machine;
pub mod model;
pub mod screen;
pub mod thermal;
pub mod uncertainty;
