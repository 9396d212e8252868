//! `trueaxis uncertainty`: the Monte Carlo of the sources, the campaign form, correlated sources.

mod campaign;
mod commands;
mod correlated;
