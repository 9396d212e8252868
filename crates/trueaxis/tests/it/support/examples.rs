//! The shipped examples (`examples/` at the top of the repository), as the tests load them: paths
//! relative to the crate's directory, where `cargo test` runs the tests.

use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// The machine `examples/machines/{machine}.toml` with the errors `examples/errors/{errors}.toml`.
pub fn load(machine: &str, errors: &str) -> (Machine, ErrorModel) {
    let m = Machine::load(format!("../../examples/machines/{machine}.toml")).unwrap();
    let e = ErrorModel::load(format!("../../examples/errors/{errors}.toml"), &m).unwrap();
    (m, e)
}
