//! Outputs (issue 38 items 1, 3, 9, 11, 13, 14 and the exit status of the environment).

use super::{example, full_device, is_root, make_device, names, run, trueaxis, vmc3_compensate, vmc3_in, Mount, ROOT};
use crate::support::vmc3;
use std::process::{Command, Stdio};

fn predict_args<'a>(dir: &'a str, out: &'a str) -> Vec<String> {
    [
        "predict",
        "--machine",
        &format!("{dir}/m.toml"),
        "--errors",
        &format!("{dir}/e.toml"),
        "--poses",
        &format!("{dir}/p.csv"),
        "--out",
        out,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

fn run_owned(args: &[String]) -> (Option<i32>, Vec<u8>, String) {
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    run(&a)
}

/// Item 1: a device, a FIFO or a link to one is written in place and stays what it is; `-` and
/// `/dev/stdout` are standard output.
#[cfg(unix)]
#[test]
fn devices_fifos_and_links_to_them_are_written_in_place() {
    use std::os::unix::fs::FileTypeExt;
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    vmc3_in(d);
    let dir = d.to_str().unwrap();
    let (code, table, err) = run_owned(&predict_args(dir, "-"));
    assert_eq!(code, Some(0), "{err}");
    let poses = std::fs::read_to_string(d.join("p.csv")).unwrap().lines().filter(|l| !l.starts_with('#') && !l.trim().is_empty()).count();
    assert_eq!(String::from_utf8_lossy(&table).lines().count(), poses, "the header and a row per pose");
    // a FIFO: the reader gets the whole table, and the FIFO stays
    let fifo = d.join("fifo");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    let (code, _, err) = run_owned(&predict_args(dir, fifo.to_str().unwrap()));
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(reader.join().unwrap(), table);
    assert!(std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
    // a link to /dev/null stays a link
    let link = d.join("null");
    std::os::unix::fs::symlink("/dev/null", &link).unwrap();
    assert_eq!(run_owned(&predict_args(dir, link.to_str().unwrap())).0, Some(0));
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    // a link to standard output's descriptor (as /dev/stdout is) into a pipe: the table arrives
    // there and the link stays; as root a private link, so that a regression could never replace
    // the system's /dev/stdout
    let stdout = d.join("stdout");
    std::os::unix::fs::symlink("/proc/self/fd/1", &stdout).unwrap();
    let mut links = vec![stdout.to_str().unwrap().to_string()];
    if !is_root() {
        links.push("/dev/stdout".into());
    }
    for link in links {
        let (code, out, err) = run_owned(&predict_args(dir, &link));
        assert_eq!((code, out), (Some(0), table.clone()), "{link}: {err}");
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "{link}");
    }
    // `-` for an output of a command that also prints: the output alone on stdout, the rest on stderr
    let (code, out, err) = run(&vmc3(&["identify"], &["--campaign", "examples/campaigns/vmc3_tracer/campaign.toml", "--out", "-"]));
    assert_eq!(code, Some(0), "{err}");
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("[constant]") && !text.contains("Identification:"), "{text}");
    assert!(err.contains("Identification:"), "the report went to stderr: {err}");
    if !is_root() {
        println!("skipped the device made with mknod: needs root");
        return;
    }
    let device = d.join("null-copy");
    if !make_device(&device, 1, 3) {
        return;
    }
    assert_eq!(run_owned(&predict_args(dir, device.to_str().unwrap())).0, Some(0));
    std::fs::write(d.join("p.ngc"), "G21 G90\nG0 X-100 Y-100 Z-100\nG1 X-50 F500\nM2\n").unwrap();
    let nc = [
        "nc",
        "--machine",
        &format!("{dir}/m.toml"),
        "--errors",
        &format!("{dir}/e.toml"),
        &format!("{dir}/p.ngc"),
        "--out",
        device.to_str().unwrap(),
    ];
    let (code, _, err) = run(&nc);
    assert_eq!(code, Some(0), "{err}");
    let kind = std::fs::symlink_metadata(&device).unwrap().file_type();
    assert!(kind.is_char_device(), "the device was replaced: {kind:?}");
}

/// Items 3 and 9: for every command with an output, that output naming one of its inputs is
/// refused before anything runs (exit 2), and the input is left as it was. The table must cover
/// every output option the commands' help lists.
#[test]
fn an_output_that_is_an_input_is_refused_for_every_command() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let f = d.join("input.dat");
    std::fs::write(&f, "the input\n").unwrap();
    let f = f.to_str().unwrap();
    // (command, output option, arguments with `F` for the input file)
    let cases: &[(&str, &str, &[&str])] = &[
        ("ballbar simulate", "--out", &["ballbar", "simulate", "--machine", "F", "--test", "c1", "--out", "F"]),
        (
            "ballbar identify",
            "--plot-dir",
            &["ballbar", "identify", "--machine", "F", "--a1", "F", "--a2", "F", "--c1", "F", "--c2", "F", "--plot-dir", "F"],
        ),
        (
            "ballbar identify",
            "--out",
            &["ballbar", "identify", "--machine", "F", "--a1", "F", "--a2", "F", "--c1", "F", "--c2", "F", "--out", "F"],
        ),
        ("ballbar iso230-4", "--plot", &["ballbar", "iso230-4", "F", "--plot", "F"]),
        ("budget analyse", "--out", &["budget", "analyse", "--machine", "F", "--out", "F"]),
        ("budget analyse", "--sensitivity", &["budget", "analyse", "--machine", "F", "--sensitivity", "F"]),
        ("budget analyse", "--plots", &["budget", "analyse", "--machine", "F", "--plots", "F"]),
        ("budget analyse", "--report", &["budget", "analyse", "--machine", "F", "--report", "F"]),
        ("budget allocate", "--out", &["budget", "allocate", "--machine", "F", "--target-um", "10", "--out", "F"]),
        (
            "design trajectory",
            "--out",
            &["design", "trajectory", "--machine", "F", "--work-point", "0,0,0", "--sweep", "C=0:90", "--count", "5", "--out", "F"],
        ),
        ("design steady", "--out", &["design", "steady", "--poses", "F", "F", "--out", "F"]),
        ("design optimal", "--out", &["design", "optimal", "--machine", "F", "--campaign", "F", "--count", "5", "--out", "F"]),
        ("fit", "--errors-out", &["fit", "--data", "F", "--parameter", "EXX", "--errors-out", "F"]),
        ("fit", "--plot", &["fit", "--data", "F", "--parameter", "EXX", "--plot", "F"]),
        ("identify", "--out", &["identify", "--machine", "F", "--campaign", "F", "--out", "F"]),
        ("identify", "--residuals", &["identify", "--machine", "F", "--campaign", "F", "--residuals", "F"]),
        ("convert", "--out", &["convert", "F", "--to", "csv", "--out", "F"]),
        ("iso230-2", "--plot", &["iso230-2", "F", "--plot", "F"]),
        ("predict", "--out", &["predict", "--machine", "F", "--errors", "F", "--poses", "F", "--out", "F"]),
        ("reversal arbor", "--plot", &["reversal", "arbor", "F", "--plot", "F"]),
        ("reversal disk", "--plot", &["reversal", "disk", "F", "--plot", "F"]),
        ("report", "--out", &["report", "--machine", "F", "--errors", "F", "--out", "F"]),
        ("report", "--pdf", &["report", "--machine", "F", "--errors", "F", "--out", "new.html", "--pdf", "F"]),
        ("uncertainty", "--plots", &["uncertainty", "--design", "F", "--sources", "F", "--plots", "F"]),
        ("compensate", "--out", &["compensate", "--machine", "F", "--errors", "F", "--format", "csv", "--out", "F"]),
        ("nc", "--out", &["nc", "--machine", "F", "--errors", "F", "F", "--out", "F"]),
        ("thermal modes", "--plot", &["thermal", "modes", "--model", "F", "--plot", "F"]),
        ("thermal place", "--plot", &["thermal", "place", "--model", "F", "--plot", "F"]),
        ("thermal fit", "--out", &["thermal", "fit", "--data", "F", "--error", "dz", "--out", "F"]),
        ("thermal fit", "--terms-out", &["thermal", "fit", "--data", "F", "--error", "dz", "--parameter", "EZZ", "--terms-out", "F"]),
        ("thermal fit", "--plot", &["thermal", "fit", "--data", "F", "--error", "dz", "--plot", "F"]),
        ("thermal predict", "--out", &["thermal", "predict", "--model", "F", "--data", "F", "--out", "F"]),
        ("thermal predict", "--plot", &["thermal", "predict", "--model", "F", "--data", "F", "--plot", "F"]),
        ("thermal links", "--out", &["thermal", "links", "--machine", "F", "--links", "F", "--out", "F"]),
        ("thermal temperatures", "--out", &["thermal", "temperatures", "--data", "F", "--model", "F", "--out", "F"]),
        ("thermal tune", "--out", &["thermal", "tune", "--model", "F", "--tau-min", "10", "--tune", "convection_w_m2k", "--out", "F"]),
        ("thermal beam", "--out", &["thermal", "beam", "--machine", "F", "--beam", "F", "--out", "F"]),
        ("verify", "--residuals", &["verify", "--machine", "F", "--errors", "F", "--campaign", "F", "--residuals", "F"]),
    ];
    // outputs of commands that read no file: nothing to overwrite
    let without_inputs = [("demo", "--out"), ("budget configurations", "--plots"), ("budget miniaturisation", "--plots")];
    let mut failures = Vec::new();
    for (command, option, args) in cases {
        let args: Vec<&str> = args.iter().map(|a| if *a == "F" { f } else { a }).collect();
        let (code, _, err) = run(&args);
        let refused = code == Some(2) && err.contains(&format!("{option} is the same file as the input")) && err.lines().count() == 1;
        if !refused || std::fs::read_to_string(f).unwrap() != "the input\n" {
            failures.push(format!("{command} {option}: exit {code:?}: {err}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // every output option of every command is in one of the two lists
    for (command, option) in output_options() {
        let listed =
            cases.iter().any(|(c, o, _)| *c == command && *o == option) || without_inputs.contains(&(command.as_str(), option.as_str()));
        assert!(listed, "`{command} {option}` is an output option without a case here");
    }
    // a directory replaced whole must not hold an input
    let poses = d.join("comp/p.csv");
    std::fs::create_dir(d.join("comp")).unwrap();
    std::fs::copy(example("examples/poses/vmc3.csv"), &poses).unwrap();
    let (code, _, err) = run(&vmc3_compensate(&["--poses", poses.to_str().unwrap(), "--out", d.join("comp").to_str().unwrap()]));
    assert!(code == Some(2) && err.contains("--out is a directory this run replaces whole, and it holds the input --poses"), "{err}");
    assert!(poses.exists());
}

/// (command, option) of every output option in the commands' help.
fn output_options() -> Vec<(String, String)> {
    let help = |args: &[&str]| String::from_utf8(trueaxis(&[args, &["--help"]].concat()).output().unwrap().stdout).unwrap();
    let commands = |text: &str| -> Vec<String> {
        text.split("Commands:").nth(1).map_or(Vec::new(), |rest| {
            rest.lines()
                .skip(1)
                .take_while(|l| !l.trim().is_empty())
                .filter_map(|l| l.split_whitespace().next().map(String::from))
                .filter(|c| c != "help")
                .collect()
        })
    };
    let outputs =
        ["--out", "--plot", "--plots", "--plot-dir", "--residuals", "--errors-out", "--terms-out", "--pdf", "--report", "--sensitivity"];
    let mut found = Vec::new();
    for c in commands(&help(&[])) {
        let subs = commands(&help(&[&c]));
        let paths: Vec<Vec<String>> =
            if subs.is_empty() { vec![vec![c.clone()]] } else { subs.iter().map(|s| vec![c.clone(), s.clone()]).collect() };
        for path in paths {
            let args: Vec<&str> = path.iter().map(String::as_str).collect();
            let text = help(&args);
            for option in outputs {
                if text.lines().any(|l| l.trim_start().starts_with(&format!("{option} "))) {
                    found.push((path.join(" "), option.to_string()));
                }
            }
        }
    }
    assert!(found.len() > 30, "the help of the commands lists the outputs: {found:?}");
    found
}

/// Item 9: a file named inside an input (a campaign's data file) is an input too.
#[test]
fn a_file_named_inside_an_input_is_not_overwritten() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    for f in ["campaign.toml", "station1.csv", "station2.csv", "station3.csv", "station4.csv"] {
        std::fs::copy(example("examples/campaigns/vmc3_tracer").join(f), d.join(f)).unwrap();
    }
    let before = std::fs::read(d.join("station1.csv")).unwrap();
    let campaign = d.join("campaign.toml");
    let residuals = d.join("station1.csv");
    let (code, _, err) = run(&vmc3(&["identify"], &["--campaign", campaign.to_str().unwrap(), "--residuals", residuals.to_str().unwrap()]));
    assert!(code == Some(2) && err.contains("is the input") && err.contains("station1.csv of this run"), "{err}");
    assert_eq!(std::fs::read(d.join("station1.csv")).unwrap(), before);
}

/// Item 13: a read-only file, or one of another user in a directory this user may write, is not
/// replaced (exit 3: a permission); root may replace any file.
#[cfg(unix)]
#[test]
fn a_file_this_user_may_not_write_is_not_replaced() {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    vmc3_in(d);
    std::fs::set_permissions(d, std::fs::Permissions::from_mode(0o777)).unwrap();
    for f in ["m.toml", "e.toml", "p.csv"] {
        std::fs::set_permissions(d.join(f), std::fs::Permissions::from_mode(0o644)).unwrap();
    }
    let target = d.join("table.csv");
    std::fs::write(&target, "not yours\n").unwrap();
    std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o444)).unwrap();
    let args = predict_args(d.to_str().unwrap(), target.to_str().unwrap());
    if !is_root() {
        // the user's own read-only file
        let (code, _, err) = run_owned(&args);
        assert!(code == Some(3) && err.contains("this user may not write it (mode 0444"), "{code:?} {err}");
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "not yours\n");
        println!("skipped another user's file: needs root to run as another user");
        return;
    }
    // root owns the file; the run is of another user (uid 65534) in the directory open to all
    let as_other = |args: &[String]| {
        let mut c = Command::new("setpriv");
        c.args(["--reuid=65534", "--regid=65534", "--clear-groups", crate::support::BIN]).args(args).current_dir(ROOT);
        c.output()
    };
    match as_other(&["--version".to_string()]) {
        Ok(o) if o.status.success() => {}
        other => {
            println!("skipped another user's file: uid 65534 cannot run {} here ({other:?})", crate::support::BIN);
            return;
        }
    }
    let out = as_other(&args).unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.code() == Some(3) && err.contains("this user may not write it (mode 0444, owner uid 0)"), "{:?} {err}", out.status);
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "not yours\n");
    assert_eq!(std::fs::metadata(&target).unwrap().uid(), 0);
    assert_eq!(names(d), ["e.toml", "m.toml", "p.csv", "table.csv"], "no temporary left");
    // root replaces it, keeping its mode
    let (code, _, err) = run_owned(&args);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(std::fs::metadata(&target).unwrap().mode() & 0o777, 0o444);
}

/// Item 11: several runs making the same new output directory at once all succeed, and the
/// directory holds one run's set, whole.
#[test]
fn runs_making_the_same_new_directory_at_once_all_succeed() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("new/comp");
    let children: Vec<_> = (0..6)
        .map(|_| {
            trueaxis(&vmc3_compensate(&["--grid", "5,5,5", "--points", "11", "--out", out.to_str().unwrap()]))
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for child in children {
        let o = child.wait_with_output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert_eq!(names(&out), ["grid.csv", "tables.csv"]);
    assert_eq!(names(out.parent().unwrap()), ["comp"], "no temporary left");
}

/// The environment exits 3 (not 2 as bad input): a full device, a full disk (a small tmpfs), a
/// read-only file system; item 14: `demo` on a full disk says that nothing was written and leaves
/// nothing.
#[test]
fn a_full_disk_and_a_read_only_file_system_exit_3() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    vmc3_in(d);
    let full = full_device(d);
    let (code, _, err) = run_owned(&predict_args(d.to_str().unwrap(), full.to_str().unwrap()));
    assert!(code == Some(3) && err.contains(": cannot write: No space left on device"), "{code:?} {err}");
    if !is_root() {
        println!("skipped the full and read-only file systems: mounting a tmpfs needs root");
        return;
    }
    let Some(mount) = Mount::tmpfs(&d.join("full"), "size=256k") else { return };
    std::fs::write(d.join("full/filler"), vec![0u8; 200 << 10]).unwrap();
    let out = d.join("full/table.csv");
    // poses enough for a table larger than what is left
    let mut poses = String::from("X,Y,Z\n");
    for k in 0..2000 {
        poses += &format!("{},{},{}\n", -(k % 400) as f64, -(k % 250) as f64, -(k % 300) as f64);
    }
    std::fs::write(d.join("p.csv"), poses).unwrap();
    let (code, _, err) = run_owned(&predict_args(d.to_str().unwrap(), out.to_str().unwrap()));
    assert!(code == Some(3) && err.contains("No space left on device"), "{code:?} {err}");
    assert_eq!(names(&d.join("full")), ["filler"], "no partial table, no temporary");
    std::fs::remove_file(d.join("full/filler")).unwrap();
    let demo = d.join("full/demo");
    let (code, _, err) = run(&["demo", "--out", demo.to_str().unwrap()]);
    assert!(
        code == Some(3) && err.contains("No space left on device") && err.trim_end().ends_with("nothing was written"),
        "{code:?} {err}"
    );
    assert_eq!(names(&d.join("full")), Vec::<String>::new(), "the demo left nothing");
    drop(mount);
    let Some(_read_only) = Mount::tmpfs(&d.join("ro"), "ro,size=64k") else { return };
    let (code, _, err) = run_owned(&predict_args(d.to_str().unwrap(), d.join("ro/table.csv").to_str().unwrap()));
    assert!(code == Some(3) && err.contains("Read-only file system"), "{code:?} {err}");
}
