//! Progress on stderr while a long command runs: shown on a terminal, hidden with `--json` or when
//! stderr is not a terminal (piped, in a script), so that output stays clean (BENCHMARKS.md (targets)).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

fn hidden(json: bool) -> bool {
    json || !std::io::stderr().is_terminal()
}

/// A spinner with the elapsed time and a message, for work of unknown length.
pub fn spinner(json: bool) -> ProgressBar {
    if hidden(json) {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    bar.set_style(ProgressStyle::with_template("{spinner} {elapsed} {msg}").unwrap_or_else(|_| ProgressStyle::default_spinner()));
    bar
}

/// A bar of `count` steps with a message.
pub fn steps(count: usize, json: bool) -> ProgressBar {
    if hidden(json) {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(count as u64), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{pos}/{len} [{bar:20}] {msg}").unwrap_or_else(|_| ProgressStyle::default_bar()).progress_chars("=> "),
    );
    bar
}
