//! Instruments (`trueaxis::instruments`): readings on the exact chain and raw streams.

mod ballbar_first_order;
mod laser;
mod streams;
