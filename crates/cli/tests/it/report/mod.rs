//! `trueaxis report`: the sections for the inputs given, the positioning tests, the printed page.

mod positioning;
mod print;
mod sections;
