//! The command line is consistent: every command and sub-command (found by walking `trueaxis --help`)
//! has `--help` with an example, `--json` where it prints results, and exit status 2 with a one-line
//! message naming the file (and the system's reason once) when its input file does not exist
//! (docs/design.md, Command line).

use crate::support::{trueaxis, trueaxis_in};

/// The sub-command names listed under `Commands:` of a help text (without `help`).
fn subcommands(help: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut inside = false;
    for line in help.lines() {
        if line.trim_end() == "Commands:" {
            inside = true;
            continue;
        }
        if inside {
            // entries are indented by two spaces; a blank or unindented line ends the list
            if !line.starts_with("  ") || line.trim().is_empty() {
                break;
            }
            if line.starts_with("   ") {
                continue; // a wrapped description
            }
            let name = line.split_whitespace().next().unwrap();
            if name != "help" {
                names.push(name.to_string());
            }
        }
    }
    names
}

/// Every command path (`["ballbar", "identify"]`, `["predict"]`, ...), parents included.
fn command_tree() -> Vec<Vec<String>> {
    let mut all = Vec::new();
    let mut stack: Vec<Vec<String>> = Vec::new();
    let top = trueaxis(&["--help"]);
    assert!(top.status.success());
    for name in subcommands(&String::from_utf8_lossy(&top.stdout)) {
        stack.push(vec![name]);
    }
    while let Some(path) = stack.pop() {
        let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
        args.push("--help");
        let out = trueaxis(&args);
        assert!(out.status.success(), "`trueaxis {}` failed", args.join(" "));
        for name in subcommands(&String::from_utf8_lossy(&out.stdout)) {
            let mut child = path.clone();
            child.push(name);
            stack.push(child);
        }
        all.push(path);
    }
    all.sort();
    all
}

fn help_of(path: &[String]) -> String {
    let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
    args.push("--help");
    let out = trueaxis(&args);
    assert!(out.status.success(), "`trueaxis {}` exits {:?}", args.join(" "), out.status.code());
    String::from_utf8(out.stdout).unwrap()
}

fn is_parent(path: &[String]) -> bool {
    !subcommands(&help_of(path)).is_empty()
}

#[test]
fn every_command_has_help_with_an_example() {
    let tree = command_tree();
    let names: Vec<String> = tree.iter().map(|p| p.join(" ")).collect();
    // the commands of docs/design.md, Command line that exist, and their sub-commands: the walk found them
    for expected in [
        "ballbar",
        "ballbar identify",
        "ballbar iso230-4",
        "ballbar simulate",
        "ballbar tmbb",
        "budget",
        "budget allocate",
        "budget analyse",
        "budget configurations",
        "budget miniaturisation",
        "compensate",
        "demo",
        "design",
        "design optimal",
        "design simulate",
        "design trajectory",
        "fit",
        "identify",
        "iso230-2",
        "nc",
        "predict",
        "report",
        "thermal",
        "thermal fit",
        "thermal modes",
        "thermal place",
        "thermal predict",
        "uncertainty",
    ] {
        assert!(names.iter().any(|n| n == expected), "`trueaxis {expected}` not found in the help tree {names:?}");
    }
    let mut missing = Vec::new();
    for path in &tree {
        let help = help_of(path);
        if !help.contains("Example") {
            missing.push(path.join(" "));
        }
        // the example names the command itself
        let line = format!("trueaxis {}", path.join(" "));
        assert!(help.contains(&line), "the help of `{}` has no example of it:\n{help}", path.join(" "));
    }
    assert!(missing.is_empty(), "--help without an example: {missing:?}");
    let top = String::from_utf8(trueaxis(&["--help"]).stdout).unwrap();
    assert!(top.contains("Example"), "{top}");
}

#[test]
fn every_command_that_prints_results_has_json() {
    // commands whose product is a data file for the next command (CSV to --out or stdout)
    let data_writers = ["ballbar simulate", "design trajectory", "design steady", "convert"];
    // a long-running process: its results go to its logs and status file (JSON lines, JSON)
    let processes = ["live"];
    let mut missing = Vec::new();
    for path in command_tree() {
        let name = path.join(" ");
        if is_parent(&path) || data_writers.contains(&name.as_str()) || processes.contains(&name.as_str()) {
            continue;
        }
        if !help_of(&path).contains("--json") {
            missing.push(name);
        }
    }
    assert!(missing.is_empty(), "commands without --json: {missing:?}");
}

/// An invocation of every leaf command whose first input file does not exist.
fn missing_input_invocation(name: &str) -> Option<Vec<&'static str>> {
    let m = "no_such_file.toml";
    let c = "no_such_file.csv";
    Some(match name {
        "predict" => vec!["predict", "--machine", m, "--errors", m, "--poses", c],
        "report" => vec!["report", "--machine", m, "--errors", m, "--out", "report.html"],
        "fit" => vec!["fit", "--data", c, "--parameter", "EXX"],
        "identify" => vec!["identify", "--machine", m, "--campaign", m],
        "iso230-2" => vec!["iso230-2", c],
        "reversal arbor" => vec!["reversal", "arbor", c],
        "reversal parallelism" => vec!["reversal", "parallelism", c, "--dz", "100"],
        "reversal disk" => vec!["reversal", "disk", c],
        "uncertainty" => vec!["uncertainty", "--design", c, "--sources", m],
        "compensate" => vec!["compensate", "--machine", m, "--errors", m, "--format", "csv", "--out", "no_such_dir"],
        "nc" => vec!["nc", "--machine", m, "--errors", m, "no_such_file.ngc"],
        "ballbar simulate" => vec!["ballbar", "simulate", "--machine", m, "--test", "a1"],
        "ballbar identify" => vec!["ballbar", "identify", "--machine", m, "--a1", c, "--a2", c, "--c1", c, "--c2", c],
        "ballbar iso230-4" => vec!["ballbar", "iso230-4", c, "--radius", "100"],
        "ballbar tmbb" => vec!["ballbar", "tmbb", "--short", c, "--long", c],
        "ballbar sensitivity" => vec!["ballbar", "sensitivity", "--machine", m],
        "design steady" => vec!["design", "steady", c, "--poses", c, "--rate", "100"],
        "budget analyse" => vec!["budget", "analyse", "--machine", m],
        "budget allocate" => vec!["budget", "allocate", "--machine", m, "--target-um", "10"],
        "design trajectory" => {
            vec!["design", "trajectory", "--machine", m, "--work-point", "0,0,0", "--sweep", "C=0:10", "--count", "3"]
        }
        "design simulate" => vec!["design", "simulate", "--machine", m, "--campaign", m, "--errors", m],
        "design optimal" => vec!["design", "optimal", "--machine", m, "--campaign", m, "--count", "3"],
        "thermal modes" => vec!["thermal", "modes", "--model", m],
        "thermal place" => vec!["thermal", "place", "--model", m],
        "thermal fit" => vec!["thermal", "fit", "--data", c, "--error", "dz"],
        "thermal predict" => vec!["thermal", "predict", "--model", m, "--data", c],
        "inspect" => vec!["inspect", c],
        "convert" => vec!["convert", c, "--to", "csv"],
        "thermal links" => vec!["thermal", "links", "--machine", m, "--links", m],
        "thermal beam" => vec!["thermal", "beam", "--machine", m, "--beam", m],
        "thermal temperatures" => vec!["thermal", "temperatures", "--data", c, "--inputs", "T:a", "--outputs", "T:b"],
        "thermal tune" => vec!["thermal", "tune", "--model", m, "--tau-min", "100", "--tune", "convection_w_m2k"],
        "verify" => vec!["verify", "--machine", m, "--errors", m, "--campaign", m],
        "live" => vec!["live", "--machine", m, "--thermal-model", m, "--source", "csv:no_such_file.csv", "--state", "state.json"],
        _ => return None,
    })
}

#[test]
fn a_missing_input_file_is_bad_input_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let mut unlisted = Vec::new();
    for path in command_tree() {
        let name = path.join(" ");
        if is_parent(&path) || ["demo", "ballbar tmbb-setup", "budget configurations", "budget miniaturisation"].contains(&name.as_str()) {
            continue; // these read no input file
        }
        let Some(args) = missing_input_invocation(&name) else {
            unlisted.push(name);
            continue;
        };
        let out = trueaxis_in(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "`trueaxis {}`: {stderr}", args.join(" "));
        assert!(stderr.starts_with("trueaxis: error: "), "`{name}`: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "`{name}`: one line expected: {stderr}");
        assert!(stderr.contains("no_such_file"), "`{name}`: the message does not name the file: {stderr}");
        assert!(stderr.matches("(os error").count() <= 1, "`{name}`: the system's reason repeated: {stderr}");
        assert!(out.stdout.is_empty(), "`{name}` printed on stdout");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "`{name}` wrote a file");
    }
    assert!(unlisted.is_empty(), "add these commands to missing_input_invocation: {unlisted:?}");
}

#[test]
fn a_usage_error_exits_2() {
    for args in [&["predict", "--no-such-option"][..], &["no-such-command"], &["ballbar", "simulate", "--test", "z9"]] {
        let out = trueaxis(args);
        assert_eq!(out.status.code(), Some(2), "`trueaxis {}`", args.join(" "));
    }
}
