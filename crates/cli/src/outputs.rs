//! The outputs a command names, typed so that they are known before it runs (docs/reliability.md):
//! every option that names an output takes an [`OutputPath`] (its value parser says whether it is
//! a file, `-` meaning standard output, a directory replaced whole, or a directory of figures), and
//! every other path is an input. Before anything runs, [`check`] refuses an output that is the
//! same file as an input (`report --out m.toml --machine m.toml`, `nc P --out P`), a directory
//! replaced whole that holds an input, and standard output given to two outputs; and when an
//! output goes to standard output, what the command prints for the user goes to stderr instead
//! ([`route_standard_output`]), so that the data on standard output stays clean.

use crate::Failure;
use clap::{ArgMatches, Command};
use std::path::{Path, PathBuf};
use trueaxis::data::is_standard_output;
use trueaxis::data::overlap::{refuse_overlap, NamedOutput};

/// What an output option names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// A file (`-`: standard output).
    File,
    /// A directory replaced whole by the run's files (`compensate --out DIR`).
    Directory,
    /// A directory of figures, created when missing, that may hold other files (`--plots DIR`).
    Figures,
}

/// The path of an output, as given.
#[derive(Clone, Debug)]
pub struct OutputPath {
    path: PathBuf,
    kind: OutputKind,
}

impl std::ops::Deref for OutputPath {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for OutputPath {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

fn parse(text: &str, kind: OutputKind) -> Result<OutputPath, String> {
    if text.is_empty() {
        return Err("an empty path".into());
    }
    // `/dev/stdout` is standard output too: the same stream, and the same clean-up of it
    let path = if text == "/dev/stdout" { PathBuf::from(trueaxis::data::STANDARD_OUTPUT) } else { PathBuf::from(text) };
    if kind != OutputKind::File && is_standard_output(&path) {
        return Err(format!("`{text}` is standard output, but this option names a directory"));
    }
    Ok(OutputPath { path, kind })
}

/// Value parser of an output file (`-`: standard output).
pub fn file(text: &str) -> Result<OutputPath, String> {
    parse(text, OutputKind::File)
}

/// Value parser of an output directory replaced whole.
pub fn directory(text: &str) -> Result<OutputPath, String> {
    parse(text, OutputKind::Directory)
}

/// Value parser of a directory of figures.
pub fn figures(text: &str) -> Result<OutputPath, String> {
    parse(text, OutputKind::Figures)
}

/// `--out`, or `<PROGRAM>` for a positional argument.
fn option_name(arg: &clap::Arg) -> String {
    match arg.get_long() {
        Some(long) => format!("--{long}"),
        None => format!("<{}>", arg.get_id().as_str().to_uppercase()),
    }
}

/// Every output and every input path of the command line (`matches` of `command`).
pub fn named(matches: &ArgMatches, command: &Command) -> (Vec<NamedOutput>, Vec<(String, PathBuf)>) {
    let (mut outputs, mut inputs) = (Vec::new(), Vec::new());
    collect(matches, command, &mut outputs, &mut inputs);
    (outputs, inputs)
}

fn collect(matches: &ArgMatches, command: &Command, outputs: &mut Vec<NamedOutput>, inputs: &mut Vec<(String, PathBuf)>) {
    for arg in command.get_arguments() {
        let id = arg.get_id().as_str();
        if let Ok(Some(values)) = matches.try_get_many::<OutputPath>(id) {
            outputs.extend(values.map(|v| NamedOutput {
                option: option_name(arg),
                path: v.path.clone(),
                whole_directory: v.kind == OutputKind::Directory,
            }));
        } else if let Ok(Some(values)) = matches.try_get_many::<PathBuf>(id) {
            inputs.extend(values.map(|v| (option_name(arg), v.clone())));
        }
    }
    if let Some((name, sub)) = matches.subcommand() {
        if let Some(c) = command.find_subcommand(name) {
            collect(sub, c, outputs, inputs);
        }
    }
}

/// Refuses outputs that would destroy an input (module documentation): bad input, before anything
/// runs.
pub fn check(outputs: &[NamedOutput], inputs: &[(String, PathBuf)]) -> Result<(), Failure> {
    refuse_overlap(outputs, inputs).map_err(Failure::input)
}

/// When an output goes to standard output, moves what the command prints for the user to stderr
/// and keeps the original standard output for that output (`trueaxis::data` writes `-` there).
pub fn route_standard_output(outputs: &[NamedOutput]) {
    if !outputs.iter().any(|o| is_standard_output(&o.path)) {
        return;
    }
    #[cfg(unix)]
    {
        use std::io::Write;
        let _ = std::io::stdout().flush();
        // SAFETY: duplicating descriptors 1 and 2, which the process holds open; no other thread
        // writes yet (called before the command runs)
        unsafe {
            let data = libc::dup(1);
            if data >= 0 && libc::dup2(2, 1) >= 0 {
                trueaxis::data::set_standard_output_descriptor(data);
            }
        }
    }
}
