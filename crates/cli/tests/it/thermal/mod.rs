//! `trueaxis thermal`: modes, placement, fit and predict, and each model kind.

mod beam;
mod commands;
mod drift;
mod gt;
mod links;
mod matrix_market;
mod place_score;
mod plots;
mod selection;
mod temperatures;
mod tune;
