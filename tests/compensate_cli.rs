//! `trueaxis compensate` and `trueaxis nc` end to end: files written, JSON summaries, exit codes.

use std::process::Command;

fn trueaxis(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_trueaxis")).args(args).output().unwrap();
    (out.status.code().unwrap(), String::from_utf8(out.stdout).unwrap(), String::from_utf8(out.stderr).unwrap())
}

#[test]
fn compensate_writes_every_format_and_refuses_beyond_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    for (format, files) in [
        ("linuxcnc", vec!["X.comp", "Y.comp", "Z.comp", "linuxcnc-comp.ini"]),
        ("isg", vec!["volcomp.csv"]),
        ("heidenhain", vec!["X.COM", "COMP.CMA"]),
        ("fanuc3d", vec!["lattice3d.txt"]),
        ("csv", vec!["tables.csv", "grid.csv"]),
        ("json", vec!["compensation.json"]),
    ] {
        let out = dir.path().join(format);
        let (code, stdout, stderr) = trueaxis(&[
            "compensate",
            "--machine",
            "examples/machines/vmc3.toml",
            "--errors",
            "examples/errors/vmc3_backlash.toml",
            "--format",
            format,
            "--out",
            out.to_str().unwrap(),
            "--points",
            "21",
            "--grid",
            "5,5,3",
            "--temperature",
            "T:column=22",
            "--json",
        ]);
        assert_eq!(code, 0, "{format}: {stderr}");
        let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(doc["tables"], 9);
        assert!(doc["max_correction_um"].as_f64().unwrap() > 1.0);
        assert!(doc["worst_residual_um"].as_f64().unwrap() < 0.01);
        for f in files {
            assert!(out.join(f).metadata().unwrap().len() > 0, "{format}: {f}");
        }
    }
    // a 5-axis machine with per-pose corrections
    let out = dir.path().join("c600u");
    let (code, stdout, stderr) = trueaxis(&[
        "compensate",
        "--machine",
        "examples/machines/c600u.toml",
        "--errors",
        "examples/errors/c600u.toml",
        "--format",
        "csv",
        "--poses",
        "examples/poses/c600u.csv",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert!(doc["poses"]["max_residual_um"].as_f64().unwrap() < 0.01);
    let csv = std::fs::read_to_string(out.join("corrections.csv")).unwrap();
    assert!(csv.starts_with("X,Y,Z,A,C,dX,dY,dZ,dA,dC,error_um,residual_um,uncorrectable_urad\n"));
    // beyond the user's limit: refused, exit 2, nothing written
    let out = dir.path().join("limited");
    let (code, _, stderr) = trueaxis(&[
        "compensate",
        "--machine",
        "examples/machines/vmc3.toml",
        "--errors",
        "examples/errors/vmc3.toml",
        "--format",
        "linuxcnc",
        "--limit-um",
        "5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("beyond the limit of 5 um"), "{stderr}");
    assert!(!out.exists());
    let (code, _, stderr) = trueaxis(&[
        "compensate",
        "--machine",
        "examples/machines/vmc3.toml",
        "--errors",
        "examples/errors/vmc3.toml",
        "--format",
        "csv",
        "--reference",
        "Q=1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("no axis Q"), "{stderr}");
}

#[test]
fn nc_corrects_a_program_and_names_bad_lines() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pocket_corrected.ngc");
    let (code, stdout, stderr) = trueaxis(&[
        "nc",
        "--machine",
        "examples/machines/vmc3.toml",
        "--errors",
        "examples/errors/vmc3.toml",
        "examples/nc/pocket.ngc",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(doc["moves"], 12);
    assert!(doc["max_residual_um"].as_f64().unwrap() < 0.01);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("N40 G1 Z-250.") && text.contains("(plunge)"));
    let bad = dir.path().join("bad.ngc");
    std::fs::write(&bad, "G21 G90\nG0 X1\nG43 H1 Z5\n").unwrap();
    let (code, _, stderr) =
        trueaxis(&["nc", "--machine", "examples/machines/vmc3.toml", "--errors", "examples/errors/vmc3.toml", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(stderr.contains("bad.ngc: line 3: tool length compensation"), "{stderr}");
    // with a work offset of 200 mm the program's X300 is X500 on the machine: beyond the travel
    let (code, _, stderr) = trueaxis(&[
        "nc",
        "--machine",
        "examples/machines/vmc3.toml",
        "--errors",
        "examples/errors/vmc3.toml",
        "examples/nc/pocket.ngc",
        "--offset",
        "G54=X200",
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("line 7: the end point leaves the machine's travel: axis X at 500 mm"), "{stderr}");
}
