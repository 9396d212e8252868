//! The controller formats (`trueaxis::compensate::export`): written, parsed back by independent readers and by the controllers' own tools.

mod controllers;
mod formats;
