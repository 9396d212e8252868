//! Argument lists the tests share: the example machine most of them run on, paths as arguments.

use std::path::Path;

/// The vmc3 example machine (examples/machines/vmc3.toml), the one most tests run on.
pub const VMC3: &str = "examples/machines/vmc3.toml";

/// `COMMAND... --machine examples/machines/vmc3.toml REST...`
pub fn vmc3<'a>(command: &[&'a str], rest: &[&'a str]) -> Vec<&'a str> {
    [command, &["--machine", VMC3], rest].concat()
}

/// `ballbar identify --machine examples/machines/c600u.toml` of the shipped rotary-axis ballbar
/// steps (examples/ballbar/A1.csv, A2, C1, C2), then `rest`.
pub fn identify_c600u<'a>(rest: &[&'a str]) -> Vec<&'a str> {
    let steps = [
        "--a1",
        "examples/ballbar/A1.csv",
        "--a2",
        "examples/ballbar/A2.csv",
        "--c1",
        "examples/ballbar/C1.csv",
        "--c2",
        "examples/ballbar/C2.csv",
    ];
    [&["ballbar", "identify", "--machine", "examples/machines/c600u.toml"][..], &steps, rest].concat()
}

/// A path as the argument a command takes.
pub fn arg(path: &Path) -> &str {
    path.to_str().unwrap()
}
