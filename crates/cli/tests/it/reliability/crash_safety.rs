//! Outputs survive `kill -9` (docs/reliability.md): a command killed at any point leaves at its
//! output paths the complete old set or the complete new set, never a mix and never a partial file;
//! the temporaries it leaves are ignored by the next run, which succeeds and removes them; a set
//! whose last output cannot be written writes nothing.

use crate::support::{alone, arg, root, utf8, vmc3, Run};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// `trueaxis ARGS` to spawn and kill, its stdout discarded.
fn command(args: &[&str]) -> Command {
    let mut c = Run::new(args).command();
    c.stdout(Stdio::null()).stderr(Stdio::piped());
    c
}

fn run(args: &[&str]) -> (i32, String) {
    let out = Run::new(args).output();
    (out.status.code().unwrap_or(-1), utf8(&out.stderr))
}

/// Every file below `dir` (relative path -> bytes).
fn contents(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for e in entries.map(Result::unwrap) {
            if e.file_type().unwrap().is_dir() {
                stack.push(e.path());
            } else {
                files.insert(e.path().strip_prefix(dir).unwrap().display().to_string(), std::fs::read(e.path()).unwrap());
            }
        }
    }
    files
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// vmc3 with its example squareness and X positioning errors scaled by `factor` (so that the old and
/// new sets differ in every file).
fn scaled_errors(dir: &Path, factor: f64) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/errors/vmc3.toml")).unwrap();
    let mut scaled = text
        .replace("EC0X = 12.0", &format!("EC0X = {:.1}", 12.0 * factor))
        .replace("EA0Z = -20.0", &format!("EA0Z = {:.1}", -20.0 * factor))
        .replace("EB0Z = 15.0", &format!("EB0Z = {:.1}", 15.0 * factor));
    let values: Vec<String> = [-5.0, -2.0, 0.0, 3.0, 6.5].iter().map(|v: &f64| format!("{:.1}", v * factor)).collect();
    scaled = scaled.replace("value    = [-5.0, -2.0, 0.0, 3.0, 6.5]", &format!("value    = [{}]", values.join(", ")));
    assert!(scaled.matches(&format!("{:.1}", 6.5 * factor)).count() == 1, "the example errors changed");
    let path = dir.join(format!("errors_{factor}.toml"));
    std::fs::write(&path, scaled).unwrap();
    path
}

fn compensate_args<'a>(errors: &'a str, out: &'a str) -> Vec<&'a str> {
    vec![
        "compensate",
        "--machine",
        "examples/machines/vmc3.toml",
        "--errors",
        errors,
        "--format",
        "csv",
        "--grid",
        "31,31,31",
        "--points",
        "1001",
        "--out",
        out,
    ]
}

/// Kills `child` with SIGKILL and reaps it.
fn kill(mut child: Child) {
    let _ = child.kill();
    let _ = child.wait();
}

/// Spawns `args` and kills it as soon as an entry whose name starts with `prefix` appears in
/// `parent` (the temporaries of its output), plus `after`; false when the run ended first.
fn kill_while_writing(args: &[&str], parent: &Path, prefix: &str, after: Duration) -> bool {
    let mut child = command(args).spawn().unwrap();
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        let seen = std::fs::read_dir(parent).unwrap().flatten().any(|e| e.file_name().to_string_lossy().starts_with(prefix));
        if seen {
            std::thread::sleep(after);
            kill(child);
            return true;
        }
        assert!(start.elapsed() < Duration::from_secs(300), "the run did not reach its write phase");
    }
}

#[test]
fn a_killed_compensate_leaves_the_old_or_the_new_tables_and_the_next_run_succeeds() {
    // kill points timed from a measured run: on a machine not shared with the other tests
    let _alone = alone();
    let tmp = tempfile::tempdir().unwrap();
    let old_errors = scaled_errors(tmp.path(), 1.0);
    let new_errors = scaled_errors(tmp.path(), 2.0);
    let (old_errors, new_errors) = (arg(&old_errors), arg(&new_errors));
    let parent = tmp.path().join("cell");
    std::fs::create_dir(&parent).unwrap();
    let out = parent.join("comp");
    let out_s = arg(&out);
    // the complete new set, written once into another directory
    let reference = tmp.path().join("reference");
    let (code, err) = run(&compensate_args(new_errors, arg(&reference)));
    assert_eq!(code, 0, "{err}");
    let new_set = contents(&reference);
    let start = Instant::now();
    let (code, err) = run(&compensate_args(old_errors, out_s));
    let duration = start.elapsed();
    assert_eq!(code, 0, "{err}");
    let old_set = contents(&out);
    assert_eq!(old_set.keys().collect::<Vec<_>>(), ["grid.csv", "tables.csv"]);
    assert!(old_set["grid.csv"].len() > 500_000, "a grid large enough to take a while to write");
    assert!(old_set.iter().all(|(k, v)| new_set[k] != *v), "the old and new sets differ in every file");

    let mut outcomes = BTreeMap::new();
    // kill points: through the computation (fractions of a whole run), and in the write phase (as
    // soon as the temporary directory appears, and 0.2, 1, 5 ms later)
    let fractions = [0.05, 0.3, 0.6, 0.9, 1.1];
    let writing = [0u64, 200, 1000, 5000];
    for point in 0..fractions.len() + writing.len() {
        let args = compensate_args(new_errors, out_s);
        if point < fractions.len() {
            let child = command(&args).spawn().unwrap();
            std::thread::sleep(duration.mul_f64(fractions[point]));
            kill(child);
        } else {
            let after = Duration::from_micros(writing[point - fractions.len()]);
            // a loaded machine can deschedule the watcher past the whole write phase: try again (a
            // run that ended first is an ordinary complete run, checked like any other below)
            let caught = (0..20).any(|_| kill_while_writing(&args, &parent, ".comp.trueaxis-", after));
            assert!(caught, "kill point {point}: the run ended first 20 times");
        }
        // the output directory holds one complete set; nothing else is there but temporaries
        let now = contents(&out);
        let which = if now == old_set {
            "old"
        } else if now == new_set {
            "new"
        } else {
            panic!("kill point {point}: the output directory holds a mix: {:?}", now.keys().collect::<Vec<_>>())
        };
        *outcomes.entry(which).or_insert(0) += 1;
        for name in names_in(&parent) {
            assert!(name == "comp" || name.starts_with(".comp.trueaxis-"), "kill point {point}: {name} left in the parent");
        }
        // the next run succeeds, writes the new set, and removes the killed run's temporaries
        let (code, err) = run(&compensate_args(new_errors, out_s));
        assert_eq!(code, 0, "kill point {point}: {err}");
        assert!(contents(&out) == new_set, "kill point {point}");
        assert_eq!(names_in(&parent), ["comp"], "kill point {point}: temporaries left after the next run");
        // back to the old set for the next kill point
        let (code, err) = run(&compensate_args(old_errors, out_s));
        assert_eq!(code, 0, "{err}");
        assert!(contents(&out) == old_set);
    }
    assert!(outcomes.get("old").copied().unwrap_or(0) >= 4, "{outcomes:?}");
}

#[test]
fn a_killed_single_file_output_is_the_old_or_the_new_file() {
    // kills timed into a write phase: on a machine not shared with the other tests
    let _alone = alone();
    let tmp = tempfile::tempdir().unwrap();
    // 40 000 poses of vmc3: a prediction table of a few MB
    let mut poses = String::from("X,Y,Z\n");
    for k in 0..40_000 {
        poses += &format!("{},{},{}\n", (k % 400) as f64 - 200.0, (k % 250) as f64 - 125.0, -((k % 300) as f64));
    }
    let poses_path = tmp.path().join("poses.csv");
    std::fs::write(&poses_path, poses).unwrap();
    let errors = [scaled_errors(tmp.path(), 1.0), scaled_errors(tmp.path(), 3.0)];
    let out = tmp.path().join("out").join("prediction.csv");
    std::fs::create_dir(out.parent().unwrap()).unwrap();
    let (poses_s, out_s) = (arg(&poses_path), arg(&out));
    let args =
        |e: &'static str| vec!["predict", "--machine", "examples/machines/vmc3.toml", "--errors", e, "--poses", poses_s, "--out", out_s];
    let leak = |p: &Path| -> &'static str { Box::leak(p.display().to_string().into_boxed_str()) };
    let (old_args, new_args) = (args(leak(&errors[0])), args(leak(&errors[1])));
    assert_eq!(run(&new_args).0, 0);
    let new_file = std::fs::read(&out).unwrap();
    assert_eq!(run(&old_args).0, 0);
    let old_file = std::fs::read(&out).unwrap();
    assert!(old_file.len() > 1_000_000 && old_file != new_file);
    let mut killed = 0;
    for after in [0u64, 100, 500, 2000] {
        if !kill_while_writing(&new_args, out.parent().unwrap(), ".prediction.csv.trueaxis-", Duration::from_micros(after)) {
            continue;
        }
        killed += 1;
        let now = std::fs::read(&out).unwrap();
        assert!(now == old_file || now == new_file, "a partial file after a kill {after} us into the write");
        assert_eq!(run(&new_args).0, 0);
        assert_eq!(std::fs::read(&out).unwrap(), new_file);
        assert_eq!(names_in(out.parent().unwrap()), ["prediction.csv"], "temporaries left after the next run");
        assert_eq!(run(&old_args).0, 0);
    }
    assert!(killed >= 2, "only {killed} kills landed in the write phase");
}

#[test]
fn identify_writes_nothing_when_the_residuals_cannot_be_written() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("ok.toml");
    let (code, err) = run(&vmc3(
        &["identify"],
        &["--campaign", "examples/campaigns/vmc3_tracer/campaign.toml", "--out", arg(&out), "--residuals", "/nonexistent/r.csv"],
    ));
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("/nonexistent/r.csv") && err.contains("nothing was written"), "{err}");
    assert!(!out.exists(), "the error file was written although the residuals were not");
    assert_eq!(names_in(tmp.path()), Vec::<String>::new(), "temporaries left behind");
}

#[test]
fn temporaries_in_the_output_directory_do_not_block_the_next_run() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("comp");
    let with_out =
        || vmc3(&["compensate"], &["--errors", "examples/errors/vmc3.toml", "--format", "linuxcnc", "--force", "--out", arg(&out)]);
    assert_eq!(run(&with_out()).0, 0);
    // what a killed earlier version left (`tempfile`'s name) and a killed run of this one left
    std::fs::write(out.join(".tmpAb12Cd"), "partial").unwrap();
    std::fs::write(out.join(".X.comp.trueaxis-99999999-abcdef.tmp"), "partial").unwrap();
    let (code, err) = run(&with_out());
    assert_eq!(code, 0, "{err}");
    assert_eq!(names_in(&out), ["X.comp", "Y.comp", "Z.comp", "linuxcnc-comp.ini"], "the old directory went whole");
    // a user's file is still refused, and nothing is written
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let before = contents(&out);
    let (code, err) = run(&with_out());
    assert_eq!(code, 2);
    assert!(err.contains("holds files this run does not write (notes.txt)") && err.contains("nothing was written"), "{err}");
    assert!(contents(&out) == before);
    assert_eq!(names_in(tmp.path()), ["comp"]);
}

#[test]
fn a_symbolic_link_to_the_output_directory_stays_a_link() {
    let tmp = tempfile::tempdir().unwrap();
    let real = tmp.path().join("real");
    std::fs::create_dir(&real).unwrap();
    let link = tmp.path().join("link");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let (code, err) =
        run(&vmc3(&["compensate"], &["--errors", "examples/errors/vmc3.toml", "--format", "fanuc", "--force", "--out", arg(&link)]));
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    assert_eq!(names_in(&real), ["pitch_error.nc"]);
}
