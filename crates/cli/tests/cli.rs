//! The command line end to end: `predict` on all five example machines (CSV and JSON agree with the
//! library), exit status 2 with a one-line message for bad input, `demo` output files.

use std::path::Path;
use std::process::{Command, Output};
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::model::{Frame, Predictor};
use trueaxis::poses::read_poses;

const EXAMPLES: [&str; 5] = ["vmc3", "lathe2", "c600u", "kx8five", "head5"];

fn trueaxis(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_trueaxis")).args(args).current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).output().unwrap()
}

fn example(kind: &str, name: &str, ext: &str) -> String {
    format!("examples/{kind}/{name}.{ext}")
}

fn predict(name: &str, extra: &[&str]) -> Output {
    let (m, e, p) = (example("machines", name, "toml"), example("errors", name, "toml"), example("poses", name, "csv"));
    let mut args = vec!["predict", "--machine", &m, "--errors", &e, "--poses", &p];
    args.extend_from_slice(extra);
    trueaxis(&args)
}

#[test]
fn predict_answers_for_every_example_machine_and_matches_the_library() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    for name in EXAMPLES {
        let out = predict(name, &["--json"]);
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(doc["frame"], "workpiece");
        assert_eq!(doc["units"]["dx"], "um");
        assert_eq!(doc["units"]["drx"], "urad");

        let machine = Machine::load(root.join(example("machines", name, "toml"))).unwrap();
        let errors = ErrorModel::load(root.join(example("errors", name, "toml")), &machine).unwrap();
        let poses = read_poses(root.join(example("poses", name, "csv")), &machine).unwrap();
        let expected = Predictor::new(&machine, &errors).predict_batch(&poses.internal(&machine));
        let rows = doc["poses"].as_array().unwrap();
        assert_eq!(rows.len(), expected.len(), "{name}");
        let mut largest: f64 = 0.0;
        for (row, e) in rows.iter().zip(&expected) {
            for ((key, _), v) in trueaxis::poses::PREDICTION_COLUMNS.iter().zip(e.to_user_units()) {
                let got = row[*key].as_f64().unwrap();
                // JSON values are rounded to 1e-4 um / urad
                assert!((got - v).abs() <= 0.6e-4, "{name} {key}: {got} vs {v}");
                largest = largest.max(v.abs());
            }
        }
        assert!(largest > 1.0, "{name}: the example errors should give a visible prediction (largest {largest})");

        // the CSV carries the same numbers
        let csv = predict(name, &[]);
        assert!(csv.status.success());
        let text = String::from_utf8(csv.stdout).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(&header[header.len() - 7..], &["dx", "dy", "dz", "drx", "dry", "drz", "dL"]);
        for (line, e) in lines.zip(&expected) {
            let fields: Vec<f64> = line.split(',').map(|f| f.parse().unwrap()).collect();
            for (got, v) in fields[fields.len() - 7..].iter().zip(e.to_user_units()) {
                assert!((got - v).abs() <= 0.6e-4, "{name} csv: {got} vs {v}");
            }
        }
    }
}

#[test]
fn machine_frame_rotates_the_vector_and_keeps_its_length() {
    let wp: serde_json::Value = serde_json::from_slice(&predict("kx8five", &["--json"]).stdout).unwrap();
    let mf: serde_json::Value = serde_json::from_slice(&predict("kx8five", &["--json", "--frame", "machine"]).stdout).unwrap();
    assert_eq!(mf["frame"], "machine");
    let norm = |r: &serde_json::Value, k: [&str; 3]| k.iter().map(|c| r[*c].as_f64().unwrap().powi(2)).sum::<f64>().sqrt();
    let mut rotated = false;
    for (a, b) in wp["poses"].as_array().unwrap().iter().zip(mf["poses"].as_array().unwrap()) {
        assert!((norm(a, ["dx", "dy", "dz"]) - norm(b, ["dx", "dy", "dz"])).abs() < 1e-3);
        assert!((norm(a, ["drx", "dry", "drz"]) - norm(b, ["drx", "dry", "drz"])).abs() < 1e-3);
        assert_eq!(a["dL"], b["dL"]);
        rotated |= (a["dx"].as_f64().unwrap() - b["dx"].as_f64().unwrap()).abs() > 1e-2;
    }
    assert!(rotated, "poses with rotary axes away from zero must differ between frames");
}

#[test]
fn tool_and_work_points_change_the_lever_arms() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let out = predict("vmc3", &["--json", "--tool-point", "0,0,500", "--work-point", "-10,20,5"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let machine = Machine::load(root.join("examples/machines/vmc3.toml")).unwrap();
    let errors = ErrorModel::load(root.join("examples/errors/vmc3.toml"), &machine).unwrap();
    let mut p = Predictor::new(&machine, &errors);
    p.setup.tool_point = nalgebra::Vector3::new(0.0, 0.0, 500.0);
    p.setup.work_point = nalgebra::Vector3::new(-10.0, 20.0, 5.0);
    p.frame = Frame::Workpiece;
    let e = p.predict(&[400.0, 250.0, -400.0]).to_user_units();
    let row = &doc["poses"][2];
    assert!((row["dx"].as_f64().unwrap() - e[0]).abs() < 1e-4);
    assert!((row["dL"].as_f64().unwrap() - e[6]).abs() < 1e-4);
}

fn assert_bad_input(out: &Output, fragments: &[&str]) {
    assert_eq!(out.status.code(), Some(2), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    for f in fragments {
        assert!(err.contains(f), "expected `{f}` in: {err}");
    }
    assert!(out.stdout.is_empty(), "nothing on stdout for a failed command");
}

#[test]
fn bad_input_exits_with_status_2_and_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad_machine = dir.path().join("bad.toml");
    std::fs::write(&bad_machine, "name = \"x\"\nstructure = \"wXbt\"\n[axes]\nX = { kind = \"linear\", direction = [0, 0, 0], range = [0, 1] }\n[tool]\npoint = [0, 0, 0]\n").unwrap();
    let bad = bad_machine.to_str().unwrap();
    let out = trueaxis(&["predict", "--machine", bad, "--errors", "examples/errors/vmc3.toml", "--poses", "examples/poses/vmc3.csv"]);
    assert_bad_input(&out, &["bad.toml", "zero vector"]);

    let out = trueaxis(&[
        "predict",
        "--machine",
        "examples/machines/vmc3.toml",
        "--errors",
        "examples/errors/kx8five.toml",
        "--poses",
        "examples/poses/vmc3.csv",
    ]);
    assert_bad_input(&out, &["examples/errors/kx8five.toml", "axis C"]);

    let out = trueaxis(&[
        "predict",
        "--machine",
        "examples/machines/kx8five.toml",
        "--errors",
        "examples/errors/kx8five.toml",
        "--poses",
        "examples/poses/vmc3.csv",
    ]);
    assert_bad_input(&out, &["examples/poses/vmc3.csv", "missing column `A`"]);

    let out =
        trueaxis(&["predict", "--machine", "missing.toml", "--errors", "examples/errors/vmc3.toml", "--poses", "examples/poses/vmc3.csv"]);
    assert_bad_input(&out, &["missing.toml", "cannot read"]);

    let out = predict("vmc3", &["--tool-point", "1,2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a point x,y,z"));
}

#[test]
fn out_file_is_written_whole_and_not_on_failure() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("pred.csv");
    let t = target.to_str().unwrap();
    let ok = predict("head5", &["--out", t]);
    assert!(ok.status.success());
    let text = std::fs::read_to_string(&target).unwrap();
    assert_eq!(text.lines().count(), 5, "header + 4 poses");
    let failed = trueaxis(&[
        "predict",
        "--machine",
        "examples/machines/head5.toml",
        "--errors",
        "examples/errors/head5.toml",
        "--poses",
        "examples/poses/vmc3.csv",
        "--out",
        t,
    ]);
    assert_eq!(failed.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&target).unwrap(), text, "a failed run leaves the previous file untouched");
    let leftovers: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(leftovers.len(), 1, "no temporary files left behind");
}

#[test]
fn every_command_has_help_with_an_example() {
    for cmd in [vec!["--help"], vec!["demo", "--help"], vec!["predict", "--help"], vec!["fit", "--help"]] {
        let out = trueaxis(&cmd);
        assert!(out.status.success());
        assert!(String::from_utf8_lossy(&out.stdout).contains("Example"), "{cmd:?}");
    }
}

/// Runs trueaxis with its stdout a pipe whose reader takes `keep` bytes (0: closes it at once) and
/// then closes it, as `| head -c N` does: (status, stderr).
#[cfg(unix)]
fn with_closed_pipe(args: &[&str], dir: &Path, keep: usize) -> (std::process::ExitStatus, String) {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_trueaxis"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let mut head = vec![0u8; keep];
    stdout.read_exact(&mut head).unwrap();
    drop(stdout);
    let out = child.wait_with_output().unwrap();
    (out.status, String::from_utf8_lossy(&out.stderr).into_owned())
}

/// A closed pipe ends the process quietly (SIGPIPE, as other Unix tools), never with a panic (exit
/// 101); files written before are whole and no temporary file is left.
#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_the_command_quietly() {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    // 20000 poses: far more output than a pipe holds, so the writer meets the closed pipe
    let mut poses = String::from("X,Y,Z\n");
    for i in 0..20000 {
        poses.push_str(&format!("{},{},{}\n", (i % 800) as f64 - 400.0, (i % 500) as f64 - 250.0, -((i % 400) as f64)));
    }
    std::fs::write(dir.path().join("poses.csv"), poses).unwrap();
    let machine = root.join("examples/machines/vmc3.toml");
    let errors = root.join("examples/errors/vmc3.toml");
    let (m, e) = (machine.to_str().unwrap(), errors.to_str().unwrap());
    let quiet = |status: std::process::ExitStatus, stderr: &str, what: &str| {
        assert!(!stderr.contains("panicked") && !stderr.contains("Broken pipe"), "{what}: {stderr}");
        assert_ne!(status.code(), Some(101), "{what}");
        assert!(status.success() || status.signal() == Some(13), "{what}: {status:?}");
    };
    let (status, stderr) = with_closed_pipe(&["predict", "--machine", m, "--errors", e, "--poses", "poses.csv"], dir.path(), 100);
    quiet(status, &stderr, "predict | head -c 100");
    assert_eq!(status.signal(), Some(13), "predict ended by SIGPIPE");
    let (status, stderr) =
        with_closed_pipe(&["compensate", "--machine", m, "--errors", e, "--format", "csv", "--out", "comp"], dir.path(), 0);
    quiet(status, &stderr, "compensate | head -0");
    let (status, stderr) = with_closed_pipe(&["demo", "--out", "demo"], dir.path(), 0);
    quiet(status, &stderr, "demo | head -0");
    // everything was written before the output: whole files, no temporary files
    let report = std::fs::read_to_string(dir.path().join("demo/report.html")).unwrap();
    assert!(report.trim_end().ends_with("</html>"));
    let tables = std::fs::read_to_string(dir.path().join("comp/tables.csv")).unwrap();
    assert!(tables.lines().count() > 40);
    for folder in ["demo", "demo/compensation", "comp"] {
        for entry in std::fs::read_dir(dir.path().join(folder)).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            assert!(!name.starts_with(".tmp"), "temporary file {folder}/{name} left behind");
        }
    }
}

/// Output files get the usual mode (0666 minus the umask, what `touch` gives) and a replaced file
/// keeps its own.
#[cfg(unix)]
#[test]
fn output_files_have_the_usual_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    // what this process's umask makes of 0666 (the child inherits it)
    let probe = dir.path().join("probe");
    std::fs::File::create(&probe).unwrap();
    let usual = mode(&probe);
    let target = dir.path().join("pred.csv");
    assert!(predict("vmc3", &["--out", target.to_str().unwrap()]).status.success());
    assert_eq!(mode(&target), usual, "a new file: {:o} vs {:o}", mode(&target), usual);
    std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o640)).unwrap();
    assert!(predict("vmc3", &["--out", target.to_str().unwrap()]).status.success());
    assert_eq!(mode(&target), 0o640, "a replaced file keeps its mode");
}

/// Each message says the system's reason once, and never the name of a temporary file.
#[test]
fn error_messages_name_the_cause_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = trueaxis(&[
        "predict",
        "--machine",
        "/nonexistent.toml",
        "--errors",
        "examples/errors/vmc3.toml",
        "--poses",
        "examples/poses/vmc3.csv",
    ]);
    assert_bad_input(&out, &["/nonexistent.toml: cannot read machine file: "]);
    assert_eq!(String::from_utf8_lossy(&out.stderr).matches("(os error 2)").count(), 1, "{}", String::from_utf8_lossy(&out.stderr));

    let missing = dir.path().join("no/folder/pred.csv");
    let out = predict("vmc3", &["--out", missing.to_str().unwrap()]);
    assert_bad_input(&out, &["no/folder/pred.csv: cannot write: "]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("at path") && err.matches("(os error 2)").count() == 1, "no temporary file named: {err}");

    let afile = dir.path().join("afile");
    std::fs::write(&afile, "x").unwrap();
    let out = trueaxis(&["demo", "--out", afile.to_str().unwrap()]);
    assert_bad_input(&out, &["afile: exists and is not a directory; give the path of a directory; nothing was written"]);
}
