//! Inputs (items 6, 10, 18, 19): each refused as bad input (exit 2) with one line naming the file,
//! the line or the option, and nothing written.

use super::{example, run, vmc3_compensate};
use crate::support::arg;

/// `(what, file name, contents, arguments with {f} for the file and {out} for the output, what
/// the message must hold)`.
type Case = (&'static str, &'static str, String, Vec<&'static str>, Vec<&'static str>);

fn cases() -> Vec<Case> {
    let machine = std::fs::read_to_string(example("examples/machines/vmc3.toml")).unwrap();
    let errors = std::fs::read_to_string(example("examples/errors/vmc3.toml")).unwrap();
    let predict_poses = vec![
        "predict",
        "--machine",
        "examples/machines/vmc3.toml",
        "--errors",
        "examples/errors/vmc3.toml",
        "--poses",
        "{f}",
        "--out",
        "{out}",
    ];
    let predict_machine = vec![
        "predict",
        "--machine",
        "{f}",
        "--errors",
        "examples/errors/vmc3.toml",
        "--poses",
        "examples/poses/vmc3.csv",
        "--out",
        "{out}",
    ];
    let predict_errors = vec![
        "predict",
        "--machine",
        "examples/machines/vmc3.toml",
        "--errors",
        "{f}",
        "--poses",
        "examples/poses/vmc3.csv",
        "--out",
        "{out}",
    ];
    let compensate_poses = vmc3_compensate(&["--poses", "{f}", "--out", "{out}"]);
    let with = |from: &str, to: &str, text: &str| {
        assert!(text.contains(from), "the example lacks `{from}`");
        text.replacen(from, to, 1)
    };
    vec![
        // item 6: a pose column of an axis the machine lacks
        (
            "pose column A on a 3-axis machine",
            "p.csv",
            "X,Y,Z,A\n0,0,0,30\n".into(),
            predict_poses.clone(),
            vec!["column `A`: axis A is not an axis of machine", "(axes: XYZ)"],
        ),
        (
            "dir:C on a 3-axis machine",
            "p.csv",
            "X,Y,Z,dir:C\n0,0,0,+\n".into(),
            compensate_poses,
            vec!["column `dir:C`: axis C is not an axis of machine"],
        ),
        // item 10: parallel or dependent linear axes refused at load
        (
            "parallel linear axes",
            "m.toml",
            with("Y = { kind = \"linear\", direction = [0, -1, 0]", "Y = { kind = \"linear\", direction = [-1, 0, 0]", &machine),
            predict_machine.clone(),
            vec!["linear axes X and Y are parallel (0.00 deg apart)"],
        ),
        (
            "a fourth linear axis",
            "m.toml",
            with("structure = \"wXYbZt\"", "structure = \"wXYbZWt\"", &machine)
                + "\n[axes.W]\nkind = \"linear\"\ndirection = [0, 0, 1]\nrange = [-50, 0]\n",
            predict_machine.clone(),
            vec!["4 linear axes (X Y Z W): at most three can move in independent directions"],
        ),
        // item 18: limits bounded, in the machine file too
        (
            "[limits] 1e308",
            "m.toml",
            machine.clone() + "\n[limits]\ncorrection_um = 1e308\n",
            predict_machine,
            vec!["[limits] correction_um = 1e308 um is more than the 10000 um"],
        ),
        // item 19: a number that underflows to zero, and a table position out of range
        (
            "1e-400 in an error file",
            "e.toml",
            with("EC0X = 12.0", "EC0X = 1e-400", &errors),
            predict_errors.clone(),
            vec!["line", "`1e-400` is below the smallest number"],
        ),
        (
            "1e-400 in a pose file",
            "p.csv",
            "X,Y,Z\n0,0,-1e-400\n".into(),
            predict_poses,
            vec!["line 2: column Z: axis Z at `-1e-400` is below the smallest number"],
        ),
        (
            "a table position of 1e300 mm",
            "e.toml",
            "[table.EXX]\nposition = [-400, 1e300]\nvalue = [0, 1]\n".into(),
            predict_errors,
            vec!["[table.EXX] EXX: line 1: position, entry 2: 1e300 mm is outside the physical range"],
        ),
    ]
}

#[test]
fn bad_inputs_of_round_two_are_refused_with_their_place() {
    let mut failures = Vec::new();
    for (what, name, text, args, expect) in cases() {
        let dir = tempfile::tempdir().unwrap();
        let (file, out) = (dir.path().join(name), dir.path().join("out"));
        std::fs::write(&file, text).unwrap();
        let args: Vec<String> = args.iter().map(|a| a.replace("{f}", arg(&file)).replace("{out}", arg(&out))).collect();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, _, err) = run(&args);
        let ok = code == Some(2) && err.lines().count() == 1 && err.contains(arg(&file)) && expect.iter().all(|e| err.contains(e));
        if !ok || out.exists() {
            failures.push(format!("{what}: exit {code:?}, output written {}: {err}", out.exists()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn correction_limits_beyond_ten_times_the_default_are_refused() {
    for (option, value, expect) in [
        ("--limit-um", "1e308", "--limit-um = 1e308 um is more than the 10000 um"),
        ("--limit-urad", "200000", "--limit-urad = 200000 urad is more than the 100000 urad"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("comp");
        let (code, _, err) = run(&vmc3_compensate(&[option, value, "--out", arg(&out)]));
        assert!(code == Some(2) && err.contains(expect), "{option} {value}: {code:?} {err}");
        assert!(!out.exists());
    }
    // the bound itself is allowed
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("comp");
    let (code, _, err) = run(&vmc3_compensate(&["--limit-um", "10000", "--out", arg(&out)]));
    assert_eq!(code, Some(0), "{err}");
}
