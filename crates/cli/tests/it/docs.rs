//! Every shell example of the documentation runs: the ```sh blocks of `docs/*.md` and `README.md`.
//!
//! How a block is run:
//! - Each Markdown file gets its own temporary directory holding a copy of `examples/`; its blocks run
//!   there in document order, each command with that directory as the current directory. So the
//!   commands read the shipped example files by their documented relative paths (`examples/...`),
//!   every relative output lands in the temporary directory (the repository is never written), and a
//!   walkthrough may use the outputs of its earlier steps.
//! - A command is a line, joined with the next while it ends in `\`; `#` starts a comment. `trueaxis`
//!   is the binary under test (a symlink to it is first on `PATH`), `cargo run --release --` is
//!   replaced by it, and other `cargo` commands (`cargo build`, `cargo test`) are skipped. The rest is
//!   run by `sh -c`, so `cp`, `mkdir` and `>` work as written.
//! - The command must exit with status 0, or with the status of a trailing comment `# exit N` (the
//!   documented failure examples).
//! - Every file or directory it claims to write must exist and be non-empty (a directory: at least one
//!   file, none empty): the values of `--out`, `--plot`, `--plots`, `--plot-dir`, `--errors-out`,
//!   `--terms-out`, `--residuals` and the target of `>`; or, when a trailing comment `# writes A B`
//!   lists the files (e.g. `fit --direction both --plot exx.svg` writes `exx_plus.svg` and
//!   `exx_minus.svg`), those.
//!
//! - With `--json`, what it prints on stdout must be one JSON document.
//!
//! Blocks that are not meant to run (file excerpts, outputs) use other fence languages (`toml`, `csv`,
//! `text`, `json`, `c`); a fence without a language is refused.

#![cfg(unix)]

use crate::support::{BIN, ROOT};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Options whose value is a file or directory the command writes.
const OUTPUT_OPTIONS: [&str; 7] = ["--out", "--plot", "--plots", "--plot-dir", "--errors-out", "--terms-out", "--residuals"];
/// Longest a single documented command may take in the test profile.
const TIMEOUT: Duration = Duration::from_secs(120);

/// One command of a ```sh block.
#[derive(Debug)]
struct Example {
    file: PathBuf,
    line: usize,
    command: String,
    exit: i32,
    writes: Vec<String>,
}

/// A fenced block: the line number of its opening fence, its language, its body lines with their numbers.
type Block = (usize, String, Vec<(usize, String)>);

/// The fences of a Markdown file.
fn fenced_blocks(text: &str) -> Vec<Block> {
    let mut blocks = Vec::new();
    let mut open: Option<Block> = None;
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        if let Some(rest) = trimmed.strip_prefix("```") {
            match open.take() {
                Some(block) => blocks.push(block),
                None => open = Some((i + 1, rest.trim().to_string(), Vec::new())),
            }
        } else if let Some((_, _, body)) = open.as_mut() {
            body.push((i + 1, trimmed.to_string()));
        }
    }
    assert!(open.is_none(), "unclosed code fence");
    blocks
}

/// The commands of the ```sh blocks of one file.
fn examples_of(file: &Path) -> Vec<Example> {
    let text = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let mut out = Vec::new();
    for (_, lang, body) in fenced_blocks(&text) {
        if lang != "sh" {
            continue;
        }
        let mut pending: Option<(usize, String)> = None;
        for (number, line) in body {
            let (start, mut joined) = pending.take().unwrap_or((number, String::new()));
            let continued = line.trim_end().ends_with('\\');
            joined.push_str(line.trim_end().trim_end_matches('\\'));
            joined.push(' ');
            if continued {
                pending = Some((start, joined));
                continue;
            }
            if let Some(example) = parse_command(file, start, &joined) {
                out.push(example);
            }
        }
        assert!(pending.is_none(), "{}: a ```sh block ends with a continuation line", file.display());
    }
    out
}

/// One logical command line: comments stripped, annotations read; None for blank lines and skipped commands.
fn parse_command(file: &Path, line: usize, text: &str) -> Option<Example> {
    let (code, comment) = match text.find('#').filter(|&i| i == 0 || text[..i].ends_with(char::is_whitespace)) {
        Some(i) => (&text[..i], &text[i + 1..]),
        None => (text, ""),
    };
    let mut command = code.split_whitespace().collect::<Vec<_>>().join(" ");
    if command.is_empty() {
        return None;
    }
    if let Some(rest) = command.strip_prefix("cargo run --release --") {
        command = format!("trueaxis{rest}");
    } else if command.starts_with("cargo ") {
        return None; // `cargo build`, `cargo test`: the build itself
    }
    let words: Vec<&str> = comment.split(|c: char| c.is_whitespace() || c == ',').filter(|w| !w.is_empty()).collect();
    let mut exit = 0;
    let mut writes = Vec::new();
    for (i, w) in words.iter().enumerate() {
        if *w == "exit" {
            exit = words.get(i + 1).and_then(|n| n.parse().ok()).unwrap_or_else(|| panic!("{}:{line}: `# exit N`", file.display()));
        }
        if *w == "writes" {
            writes.extend(words[i + 1..].iter().filter(|w| **w != "and").map(|w| w.to_string()));
            break;
        }
    }
    let listed = !writes.is_empty();
    let tokens: Vec<&str> = command.split_whitespace().collect();
    for (i, t) in tokens.iter().enumerate() {
        if !listed && (OUTPUT_OPTIONS.contains(t) || *t == ">") {
            writes.push(tokens.get(i + 1).unwrap_or_else(|| panic!("{}:{line}: {t} without a value", file.display())).to_string());
        }
    }
    Some(Example { file: file.to_path_buf(), line, command, exit, writes })
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}

/// Runs a command with a time limit; (exit status, stdout, stderr).
fn run(command: &str, dir: &Path, path: &str) -> Result<(Option<i32>, String, String), String> {
    let mut child = Command::new("sh")
        .args(["-c", command])
        .current_dir(dir)
        .env("PATH", path)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start sh: {e}"))?;
    // drain the pipes in threads so that a large output cannot block the child
    let mut stdout = child.stdout.take().unwrap();
    let mut stderr = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut stdout, &mut s).ok();
        s
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut stderr, &mut s).ok();
        s
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if start.elapsed() > TIMEOUT {
            child.kill().ok();
            child.wait().ok();
            return Err(format!("took longer than {} s", TIMEOUT.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    Ok((status.code(), out.join().unwrap(), err.join().unwrap()))
}

/// A written path is non-empty: a file with bytes, or a directory with files that all have bytes.
fn non_empty(path: &Path) -> Result<(), String> {
    let meta = std::fs::metadata(path).map_err(|_| format!("{} was not written", path.display()))?;
    if meta.is_dir() {
        let entries: Vec<_> = std::fs::read_dir(path).unwrap().map(|e| e.unwrap().path()).collect();
        if entries.is_empty() {
            return Err(format!("directory {} is empty", path.display()));
        }
        return entries.iter().try_for_each(|p| non_empty(p));
    }
    if meta.len() == 0 {
        return Err(format!("{} is empty", path.display()));
    }
    Ok(())
}

/// Runs the examples of one file in their own directory; the failures as messages.
fn run_file(examples: &[Example], root: &Path) -> Vec<String> {
    let work = tempfile::tempdir().unwrap();
    copy_dir(&root.join("examples"), &work.path().join("examples"));
    let bin_dir = work.path().join(".bin");
    std::fs::create_dir(&bin_dir).unwrap();
    std::os::unix::fs::symlink(BIN, bin_dir.join("trueaxis")).unwrap();
    let path = format!("{}:{}", bin_dir.display(), std::env::var("PATH").unwrap_or_default());
    let mut failures = Vec::new();
    for ex in examples {
        let place = format!("{}:{}: `{}`", ex.file.display(), ex.line, ex.command);
        match run(&ex.command, work.path(), &path) {
            Err(e) => failures.push(format!("{place}: {e}")),
            Ok((code, _, stderr)) if code != Some(ex.exit) => {
                failures.push(format!("{place}: exit status {code:?}, documented {}; stderr:\n{stderr}", ex.exit))
            }
            Ok((_, stdout, _)) if ex.exit == 0 => {
                let json = ex.command.split_whitespace().any(|w| w == "--json");
                if json && !stdout.trim().is_empty() && serde_json::from_str::<serde_json::Value>(&stdout).is_err() {
                    failures.push(format!("{place}: --json did not print one JSON document:\n{stdout}"));
                }
                for w in &ex.writes {
                    if let Err(e) = non_empty(&work.path().join(w)) {
                        failures.push(format!("{place}: {e}"));
                    }
                }
            }
            Ok(_) => {}
        }
    }
    failures
}

fn documentation_files(root: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    files.sort();
    files.push(root.join("README.md"));
    files
}

#[test]
fn every_shell_example_of_the_documentation_runs() {
    let root = Path::new(ROOT);
    let files = documentation_files(root);
    let per_file: Vec<Vec<Example>> = files.iter().map(|f| examples_of(f)).collect();
    for (f, ex) in files.iter().zip(&per_file) {
        assert!(ex.iter().any(|e| e.command.starts_with("trueaxis ")), "{} has no runnable trueaxis example in a ```sh block", f.display());
    }
    let total: usize = per_file.iter().map(Vec::len).sum();
    assert!(total >= 40, "only {total} documented commands found");
    // two files at a time: the machine is shared
    let failures: Vec<String> = std::thread::scope(|s| {
        let handles: Vec<_> = per_file
            .chunks(per_file.len().div_ceil(2))
            .map(|chunk| s.spawn(move || chunk.iter().flat_map(|ex| run_file(ex, root)).collect::<Vec<_>>()))
            .collect();
        handles.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    assert!(failures.is_empty(), "{} of {total} documented commands failed:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn every_code_fence_names_its_language() {
    let root = Path::new(ROOT);
    let mut bare = Vec::new();
    for file in documentation_files(root) {
        let text = std::fs::read_to_string(&file).unwrap();
        for (line, lang, _) in fenced_blocks(&text) {
            if lang.is_empty() {
                bare.push(format!("{}:{line}", file.display()));
            }
        }
    }
    assert!(bare.is_empty(), "fences without a language (use sh for commands that run, text/toml/csv/json otherwise): {bare:?}");
}

#[test]
fn commands_are_parsed_as_documented() {
    let f = Path::new("x.md");
    let e = parse_command(f, 1, "trueaxis compensate --out comp   # exit 2 ").unwrap();
    assert_eq!((e.command.as_str(), e.exit), ("trueaxis compensate --out comp", 2));
    assert_eq!(e.writes, ["comp"]);
    let e = parse_command(f, 1, "cargo run --release -- demo --out d # writes d/a.csv, d/b.svg").unwrap();
    assert_eq!(e.command, "trueaxis demo --out d");
    assert_eq!(e.writes, ["d/a.csv", "d/b.svg"]);
    let e = parse_command(f, 1, "trueaxis x --plot p.svg --out o.csv > log.txt").unwrap();
    assert_eq!(e.writes, ["p.svg", "o.csv", "log.txt"]);
    assert!(parse_command(f, 1, "cargo test   # the tests").is_none());
    assert!(parse_command(f, 1, "# only a comment").is_none());
    let blocks = fenced_blocks("text\n```sh\na \\\n  b\n```\n  ```toml\nx = 1\n  ```\n");
    assert_eq!(blocks.len(), 2);
    assert_eq!((blocks[0].1.as_str(), blocks[1].1.as_str()), ("sh", "toml"));
}

/// GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens.
fn slug(heading: &str) -> String {
    let kept: String = heading.to_lowercase().chars().filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_').collect();
    kept.trim().replace(' ', "-")
}

fn anchors(text: &str) -> Vec<String> {
    let mut inside = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            inside = !inside;
        } else if !inside && line.starts_with('#') {
            out.push(slug(line.trim_start_matches('#')));
        }
    }
    out
}

#[test]
fn every_link_between_the_pages_resolves() {
    let root = Path::new(ROOT);
    let mut broken = Vec::new();
    for file in documentation_files(root) {
        let text = std::fs::read_to_string(&file).unwrap();
        let dir = file.parent().unwrap();
        let mut rest = text.as_str();
        while let Some(i) = rest.find("](") {
            rest = &rest[i + 2..];
            let Some(end) = rest.find(')') else { break };
            let target = &rest[..end];
            if target.starts_with("http") || target.contains(' ') {
                continue;
            }
            let (path, anchor) = target.split_once('#').unwrap_or((target, ""));
            let linked = if path.is_empty() { file.clone() } else { dir.join(path) };
            if !linked.exists() {
                broken.push(format!("{}: {target}: no such file", file.display()));
                continue;
            }
            if !anchor.is_empty() && linked.extension().is_some_and(|x| x == "md") {
                let headings = anchors(&std::fs::read_to_string(&linked).unwrap());
                if !headings.iter().any(|h| h == anchor) {
                    broken.push(format!("{}: {target}: no such heading", file.display()));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
    assert_eq!(slug("## `trueaxis predict`"), "trueaxis-predict");
    assert_eq!(
        slug(" Scale temperature: correction to 20 degC (Soons 1993 §3.2.4, §5.1.1; ISO 1)"),
        "scale-temperature-correction-to-20-degc-soons-1993-324-511-iso-1"
    );
}
