//! Item 8: memory is bounded by the run, not by its input. `predict` and `compensate --poses` run
//! under `ulimit -v` (the address space of the process) on a pose stream ten times that limit, `nc`
//! on a program whose correction held whole would need ten times it, and an allocation that cannot
//! be met ends the run with a message and exit status 3, not an abort.

use super::trueaxis;
use crate::support::arg;
use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};

/// The address space the runs get (KiB): what `trueaxis` maps to start (its code, as large as the
/// executable file, and its threads' stacks) plus 40 MiB to work in. The executable grows with the
/// commands it has (the OPC UA client of `live` added 15 MB), so the limit follows it.
fn limit_kib() -> u64 {
    let code = std::fs::metadata(crate::support::BIN).map(|m| m.len()).unwrap_or(0) >> 10;
    code + (40 << 10)
}

/// A pose row of about 1000 bytes: X Y Z (vmc3's travel) and a note the reader skips, as the
/// exports of measuring software carry comments beside the positions (long rows keep the number
/// of poses, and so the time of the test, down for a given size).
fn row(k: u64) -> String {
    let note = format!("run {k:08} of the night shift; ").repeat(26);
    let at = |step: u64, span: u64| -(((k * step) % span) as f64);
    format!("{},{},{},{note}\n", 0.5 * at(7, 800), 0.5 * at(13, 500), at(11, 400))
}

/// What a run under the limit gave: exit status, stderr, the first lines of stdout, how many lines
/// it had, and how many rows were fed.
struct Limited {
    code: Option<i32>,
    err: String,
    head: Vec<String>,
    lines: u64,
    rows: u64,
}

/// Runs `args` (which read the poses from /dev/stdin) under the limit, feeding it rows until
/// `bytes` were written.
fn under_limit(args: &[&str], bytes: u64) -> Limited {
    let command = format!("ulimit -v {}; exec \"$0\" \"$@\"", limit_kib());
    let mut child = Command::new("sh")
        .args(["-c", &command, crate::support::BIN])
        .args(args)
        .current_dir(super::ROOT)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let feeder = std::thread::spawn(move || {
        let (mut sent, mut rows) = (0u64, 0u64);
        let mut block = String::from("X,Y,Z,note\n");
        while sent < bytes {
            while block.len() < 1 << 16 {
                block += &row(rows);
                rows += 1;
            }
            if stdin.write_all(block.as_bytes()).is_err() {
                break;
            }
            sent += block.len() as u64;
            block.clear();
        }
        rows
    });
    let (mut head, mut lines) = (Vec::new(), 0);
    for line in BufReader::new(child.stdout.take().unwrap()).lines() {
        if head.len() < 4 {
            head.push(line.unwrap());
        }
        lines += 1;
    }
    let rows = feeder.join().unwrap();
    let o = child.wait_with_output().unwrap();
    Limited { code: o.status.code(), err: String::from_utf8_lossy(&o.stderr).into_owned(), head, lines, rows }
}

#[cfg(unix)]
#[test]
fn predict_and_compensate_poses_run_on_ten_times_their_memory() {
    let ten_times = 10 * limit_kib() * 1024;
    let machine = ["--machine", "examples/machines/vmc3.toml", "--errors", "examples/errors/vmc3.toml"];
    let predict = [&["predict"][..], &machine, &["--poses", "/dev/stdin", "--out", "-"]].concat();
    let run = under_limit(&predict, ten_times);
    assert_eq!(run.code, Some(0), "{}", run.err);
    assert!(run.rows * 1000 > ten_times - (1 << 17), "{} rows", run.rows);
    assert_eq!(run.lines, run.rows + 1, "a row per pose and the header");
    // the table begins as the one of the same rows read whole from a file, without a limit
    let dir = tempfile::tempdir().unwrap();
    let few = dir.path().join("few.csv");
    std::fs::write(&few, ["X,Y,Z,note\n".to_string(), (0..3).map(row).collect()].concat()).unwrap();
    let whole = trueaxis(&[&["predict"][..], &machine, &["--poses", arg(&few)]].concat()).output().unwrap();
    assert_eq!(String::from_utf8(whole.stdout).unwrap().lines().collect::<Vec<_>>(), run.head);
    // compensate --poses streams corrections.csv into its output directory
    let out = dir.path().join("comp");
    let compensate = super::vmc3_compensate(&["--grid", "3,3,3", "--points", "5", "--poses", "/dev/stdin", "--out", arg(&out)]);
    let run = under_limit(&compensate, ten_times);
    assert_eq!(run.code, Some(0), "{}", run.err);
    let corrections = BufReader::new(std::fs::File::open(out.join("corrections.csv")).unwrap()).lines().count() as u64;
    assert_eq!(corrections, run.rows + 1);
}

#[cfg(unix)]
#[test]
fn an_allocation_that_cannot_be_met_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("grid");
    // a grid of 10^6 nodes needs more than the limit
    let command = format!("ulimit -v {}; exec \"$0\" \"$@\"", 3 * limit_kib());
    let o = Command::new("sh")
        .args(["-c", &command, crate::support::BIN])
        .args(super::vmc3_compensate(&["--grid", "100,100,100", "--points", "2", "--out", arg(&out)]))
        .current_dir(super::ROOT)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(
        err.starts_with("trueaxis: error: out of memory: ") && err.contains("MiB more could not be allocated") && err.lines().count() == 1,
        "{err}"
    );
    assert_eq!(super::names(dir.path()), Vec::<String>::new(), "nothing written, no temporary");
}

/// The raster of `bench/nc_memory.py`: `lines` G1 moves across vmc3's travel, and the control
/// flow of an `o1 if` before `M2` when `whole` (a program the correction holds whole).
fn raster(lines: usize, whole: bool) -> String {
    let mut text = String::from("(raster)\nG21 G90 G17 G94\n");
    for i in 0..lines {
        let t = (i as f64 / 200.0).fract();
        let u = if t < 0.5 { 2.0 * t } else { 2.0 - 2.0 * t };
        let (x, y, z) = (-400.0 + 800.0 * u, -250.0 + 500.0 * (i / 200 % 100) as f64 / 99.0, -280.0 + 80.0 * (i / 200 % 3) as f64);
        text += &format!("G1 X{x:.3} Y{y:.3} Z{z:.3} F3000\n");
    }
    if whole {
        text += "o1 if [1]\no1 endif\n";
    }
    text + "M2\n"
}

/// `nc` under the limit: a straight program whose correction held whole would need ten times the
/// memory the run gets to work in (about 1.6 kB per line whole: 164 MiB for 10^5 lines,
/// bench/nc_memory.py; 40 MiB x 10 / 1.6 kB = 260,000 lines) is corrected in parts under the limit,
/// line for line; the same program with control flow at its end, which the correction holds whole,
/// ends with the out-of-memory report and exit status 3, nothing written, no temporary left.
#[cfg(unix)]
#[test]
fn nc_corrects_a_program_of_ten_times_its_memory() {
    let dir = tempfile::tempdir().unwrap();
    let lines = 260_000;
    let command = format!("ulimit -v {}; exec \"$0\" \"$@\"", limit_kib());
    let machine = ["--machine", "examples/machines/vmc3.toml", "--errors", "examples/errors/vmc3.toml"];
    let run = |whole: bool| {
        let name = if whole { "whole" } else { "straight" };
        let program = dir.path().join(format!("{name}.ngc"));
        std::fs::write(&program, raster(lines, whole)).unwrap();
        let out = dir.path().join(format!("{name}_corrected.ngc"));
        let o = Command::new("sh")
            .args(["-c", &command, crate::support::BIN, "nc"])
            .args(machine)
            .args([arg(&program), "--out", arg(&out)])
            .current_dir(super::ROOT)
            .output()
            .unwrap();
        (o.status.code(), String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned(), out)
    };
    let (code, summary, err, out) = run(false);
    assert_eq!(code, Some(0), "{err}");
    assert!(summary.contains(&format!("{lines} moves corrected")), "{summary}");
    let added: usize = summary.split(" lines added").next().and_then(|s| s.rsplit(' ').next()).and_then(|n| n.parse().ok()).unwrap();
    let written = BufReader::new(std::fs::File::open(&out).unwrap()).lines().count();
    assert_eq!(written, lines + 3 + 4 + added, "the program, its 4 header lines (files, dialect) and the lines added");
    let (code, _, err, _) = run(true);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.starts_with("trueaxis: error: out of memory: ") && err.lines().count() == 1, "{err}");
    assert_eq!(super::names(dir.path()), ["straight.ngc", "straight_corrected.ngc", "whole.ngc"], "nothing written, no temporary");
}
