//! Input tables (`trueaxis::data`).

mod tables;
