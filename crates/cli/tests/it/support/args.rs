//! Argument lists the tests share: the example machine most of them run on.

/// The vmc3 example machine (examples/machines/vmc3.toml), the one most tests run on.
pub const VMC3: &str = "examples/machines/vmc3.toml";

/// `COMMAND... --machine examples/machines/vmc3.toml REST...`
pub fn vmc3<'a>(command: &[&'a str], rest: &[&'a str]) -> Vec<&'a str> {
    [command, &["--machine", VMC3], rest].concat()
}
