//! Argument lists the tests share: the example machine most of them run on, paths as arguments.

use std::path::Path;

/// The vmc3 example machine (examples/machines/vmc3.toml), the one most tests run on.
pub const VMC3: &str = "examples/machines/vmc3.toml";

/// `COMMAND... --machine examples/machines/vmc3.toml REST...`
pub fn vmc3<'a>(command: &[&'a str], rest: &[&'a str]) -> Vec<&'a str> {
    [command, &["--machine", VMC3], rest].concat()
}

/// A path as the argument a command takes.
pub fn arg(path: &Path) -> &str {
    path.to_str().unwrap()
}
