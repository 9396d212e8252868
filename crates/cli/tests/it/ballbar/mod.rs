//! `trueaxis ballbar`: the shipped examples, every method's round trip, raw streams and planning.

mod examples;
mod methods;
mod streams;
