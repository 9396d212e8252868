//! `trueaxis identify` and `trueaxis design optimal`: the shipped campaigns and parametric bases.

mod basis;
mod commands;
