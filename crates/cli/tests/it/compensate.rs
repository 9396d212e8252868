//! `trueaxis compensate` end to end: files written, JSON summaries, exit codes (`trueaxis nc`: nc.rs).

use crate::support::{arg, identify_c600u, json_of, outcome, read, vmc3, VMC3};
use serde_json::Value;
use std::path::Path;

/// `trueaxis compensate --machine examples/machines/vmc3.toml --errors ERRORS REST...`
fn on_vmc3(errors: &str, rest: &[&str]) -> (i32, String, String) {
    outcome(&vmc3(&["compensate"], &[&["--errors", errors][..], rest].concat()))
}

/// `trueaxis compensate --machine MACHINE --errors ERRORS --format FORMAT --out OUT REST... --json`,
/// which must succeed: its summary.
fn compensate_json(machine: &str, errors: &str, format: &str, out: &Path, rest: &[&str]) -> Value {
    json_of(
        &[&["compensate", "--machine", machine, "--errors", errors, "--format", format, "--out", arg(out)][..], rest, &["--json"]].concat(),
    )
}

/// The files of a five-axis machine leave at most a tenth of the error before.
fn leave_a_tenth(doc: &Value) {
    let r = &doc["format_residual"];
    assert!(r["worst_um"].as_f64().unwrap() < 0.1 * r["worst_error_um"].as_f64().unwrap(), "{r}");
}

#[test]
fn compensate_writes_every_format_and_refuses_beyond_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    for (format, files) in [
        ("linuxcnc", vec!["X.comp", "Y.comp", "Z.comp", "linuxcnc-comp.ini"]),
        ("linuxcnc-hal", vec!["trueaxis_comp.comp", "trueaxis_comp.hal", "trueaxis_comp.ini"]),
        ("isg", vec!["volcomp.csv", "volcomp1.lis"]),
        ("heidenhain", vec!["X.COM", "COMP.CMA"]),
        ("siemens", vec!["AX_EEC.INI", "NC_CEC.INI"]),
        ("fanuc", vec!["pitch_error.nc"]),
        ("lattice", vec!["lattice3d.txt"]),
        ("fanuc3d", vec!["lattice3d.txt"]),
        ("csv", vec!["tables.csv", "grid.csv"]),
        ("json", vec!["compensation.json"]),
    ] {
        let out = dir.path().join(format);
        // --force: LinuxCNC's own-axis joint files leave more than half of this model's error (they
        // are refused without it: files_that_leave_more_than_they_remove_are_refused)
        let rest = ["--points", "21", "--grid", "5,5,3", "--temperature", "T:column=22", "--force"];
        let doc = compensate_json(VMC3, "examples/errors/vmc3_backlash.toml", format, &out, &rest);
        assert_eq!(doc["tables"], 9);
        assert!(doc["max_correction_um"].as_f64().unwrap() > 1.0);
        assert!(doc["worst_residual_um"].as_f64().unwrap() < 0.01);
        // controller formats: the error they leave over the travel, at most the error before at that
        // pose plus what they add; data formats (csv, json) have none
        let residual = &doc["format_residual"];
        if matches!(format, "csv" | "json") {
            assert!(residual.is_null(), "{format}");
        } else {
            let worst = residual["worst_um"].as_f64().unwrap();
            assert!(worst > 0.0 && worst < residual["worst_error_um"].as_f64().unwrap(), "{format}: {residual}");
            assert!(residual["rms_um"].as_f64().unwrap() <= worst && residual["worst_pose"]["X"].is_number());
            assert!(doc["left_out"].is_array());
        }
        for f in files {
            assert!(out.join(f).metadata().unwrap().len() > 0, "{format}: {f}");
        }
    }
    // a 5-axis machine with per-pose corrections
    let out = dir.path().join("c600u");
    let (machine, errors) = ("examples/machines/c600u.toml", "examples/errors/c600u.toml");
    let doc = compensate_json(machine, errors, "csv", &out, &["--poses", "examples/poses/c600u.csv"]);
    assert!(doc["poses"]["max_residual_um"].as_f64().unwrap() < 0.01);
    let csv = std::fs::read_to_string(out.join("corrections.csv")).unwrap();
    assert!(csv.starts_with("X,Y,Z,A,C,dX,dY,dZ,dA,dC,error_um,residual_um,uncorrectable_urad\n"));
    // beyond the user's limit: refused, exit 2, nothing written
    let out = dir.path().join("limited");
    let (code, _, stderr) = on_vmc3("examples/errors/vmc3.toml", &["--format", "linuxcnc", "--limit-um", "5", "--out", arg(&out)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("beyond the limit of 5 um"), "{stderr}");
    assert!(!out.exists());
    let (code, _, stderr) = on_vmc3("examples/errors/vmc3.toml", &["--format", "csv", "--reference", "Q=1", "--out", arg(&out)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("no axis Q"), "{stderr}");
}

#[test]
fn the_summary_covers_what_is_written() {
    // fanuc3d writes only the lattice: its largest correction is the summary's (the own-axis tables
    // along the axis lines through home are smaller, 13.4 um)
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fanuc");
    let doc = compensate_json(VMC3, "examples/errors/vmc3.toml", "fanuc3d", &out, &[]);
    let lattice = std::fs::read_to_string(out.join("lattice3d.txt")).unwrap();
    let written = lattice
        .lines()
        .filter(|l| !l.starts_with(';') && l.split_whitespace().count() == 6)
        .flat_map(|l| l.split_whitespace().skip(3).map(|v| v.parse::<f64>().unwrap().abs()).collect::<Vec<_>>())
        .fold(0.0, f64::max);
    let summary = doc["max_correction_um"].as_f64().unwrap();
    assert!(written > 14.0 && (summary - written).abs() <= 0.0006, "summary {summary} um, lattice {written} um");
}

#[test]
fn an_output_directory_with_other_files_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("comp");
    let run = |format: &str| on_vmc3("examples/errors/vmc3.toml", &["--format", format, "--out", arg(&out)]);
    assert_eq!(run("heidenhain").0, 0);
    // the same run again overwrites its own files
    assert_eq!(run("heidenhain").0, 0);
    // another format would mix its tables with the Heidenhain ones: refused, nothing written
    let (code, _, stderr) = run("csv");
    assert_eq!(code, 2);
    assert!(stderr.contains("holds files this run does not write (COMP.CMA X.COM Y.COM Z.COM)"), "{stderr}");
    assert!(!out.join("tables.csv").exists());
}

/// A G-T error model: vmc3_backlash (bidirectional EXX, sensor T:column) plus a thermal term of EZZ
/// on the sensor T:p1, both sensors in examples/thermal/poses_with_T.csv.
fn gt_model(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("vmc3_gt.toml");
    let base = read("examples/errors/vmc3_backlash.toml");
    std::fs::write(&path, base + "\n[[term.EZZ]]\ncoefficient = 1.5e-2\nfactors = { Z = 1, \"T:p1\" = 1 }\n").unwrap();
    path
}

#[test]
fn compensate_poses_uses_the_temperature_columns_and_cancels_what_predict_reports() {
    let dir = tempfile::tempdir().unwrap();
    let errors = gt_model(dir.path());
    let poses = "examples/thermal/poses_with_T.csv";
    let errors = arg(&errors);
    let predicted = json_of(&vmc3(&["predict"], &["--errors", errors, "--poses", poses, "--json"]));
    let out = dir.path().join("comp");
    let doc = compensate_json(VMC3, errors, "csv", &out, &["--poses", poses]);
    assert!(doc["poses"]["max_residual_um"].as_f64().unwrap() < 0.01);
    let csv = std::fs::read_to_string(out.join("corrections.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    let predicted = predicted["poses"].as_array().unwrap();
    assert_eq!(rows.len(), predicted.len());
    for (row, p) in rows.iter().zip(predicted) {
        let d = ["dx", "dy", "dz"].map(|k| p[k].as_f64().unwrap());
        // the error before correction is the one predict reports for the same row (4 decimals)
        let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        // columns X Y Z dX dY dZ error_um residual_um uncorrectable_urad
        assert!((row[6] - norm).abs() < 1e-3, "error {} um vs predict {norm} um", row[6]);
        // vmc3: the joint Jacobian of the relative position is the identity, so the correction is
        // minus the error to first order (second-order remainder ~ 1e-4 x 10 um)
        for k in 0..3 {
            assert!((row[3 + k] + d[k]).abs() < 0.01, "axis {k}: correction {} um, error {} um", row[3 + k], d[k]);
        }
        assert!(row[7] < 0.01, "residual {} um", row[7]);
    }
    // the same file with T:p1 at 20 degC: row 3 (Z -200 mm, T:p1 24.5 degC) loses the thermal term
    // 0.015 um/(mm K) x -200 mm x 4.5 K = -13.5 um of EZZ, so its Z correction drops by 13.5 um
    let cold = dir.path().join("poses_p1_20.csv");
    let text = read(poses);
    let rewritten: Vec<String> = text
        .lines()
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            if !l.starts_with('#') && !l.starts_with('X') && f.len() == 7 {
                f[4] = "20.0";
            }
            f.join(",")
        })
        .collect();
    std::fs::write(&cold, rewritten.join("\n") + "\n").unwrap();
    let out_cold = dir.path().join("comp_cold");
    let (code, _, stderr) = on_vmc3(errors, &["--poses", arg(&cold), "--format", "csv", "--out", arg(&out_cold)]);
    assert_eq!(code, 0, "{stderr}");
    let csv = std::fs::read_to_string(out_cold.join("corrections.csv")).unwrap();
    let dz_cold: f64 = csv.lines().nth(3).unwrap().split(',').nth(5).unwrap().parse().unwrap();
    assert!((rows[2][5] - dz_cold - 13.5).abs() < 0.01, "{} vs {dz_cold}", rows[2][5]);
}

#[test]
fn compensate_poses_without_a_needed_temperature_column_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("comp");
    let mut args = vec!["--poses", "examples/poses/vmc3.csv", "--format", "csv", "--out", arg(&out)];
    let (code, _, stderr) = on_vmc3("examples/errors/vmc3_backlash.toml", &args);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("examples/poses/vmc3.csv: missing column `T:column` (degC) needed by the error model; add it or give --temperature T:column=degC"),
        "{stderr}"
    );
    assert!(!out.exists());
    // a temperature given on the command line serves every pose
    args.extend(["--temperature", "T:column=22"]);
    let (code, _, stderr) = on_vmc3("examples/errors/vmc3_backlash.toml", &args);
    assert_eq!(code, 0, "{stderr}");
}

#[test]
fn files_that_leave_more_than_they_remove_are_refused() {
    // vmc3's squareness errors are more than half of its error: LinuxCNC's own-axis joint files
    // would leave more than they remove (docs/compensation.md, "Never worse")
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("joint");
    let (code, _, stderr) = on_vmc3("examples/errors/vmc3.toml", &["--format", "linuxcnc", "--out", arg(&out)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("more than they remove") && stderr.contains("--format linuxcnc-hal") && stderr.contains("nothing was written"),
        "{stderr}"
    );
    assert!(!out.exists());
    let doc = compensate_json(VMC3, "examples/errors/vmc3.toml", "linuxcnc", &out, &["--force"]);
    let r = &doc["format_residual"];
    assert_eq!(r["leaves_more_than_it_removes"], true);
    assert!(r["worst_um"].as_f64().unwrap() > 0.5 * r["worst_error_um"].as_f64().unwrap(), "{r}");
    assert!(out.join("X.comp").exists());
    // a five-axis machine: the kinematic description and tables leave at most a tenth
    let five = dir.path().join("c600u");
    let doc = compensate_json("examples/machines/c600u.toml", "examples/errors/c600u.toml", "siemens", &five, &[]);
    leave_a_tenth(&doc);
    assert!(doc["kinematics"]["axes"]["C"]["tilt_urad"].is_array() && five.join("TC_CARR.INI").exists(), "{doc}");
}

#[test]
fn ballbar_identify_writes_error_values_that_compensate_reads_with_their_uncertainty() {
    let dir = tempfile::tempdir().unwrap();
    let piges = dir.path().join("piges.toml");
    let doc = json_of(&identify_c600u(&["--out", arg(&piges), "--json"]));
    let text = std::fs::read_to_string(&piges).unwrap();
    let file: toml::Table = text.parse().unwrap();
    for (name, p) in doc["parameters"].as_object().unwrap() {
        let value = file["constant"][name.as_str()].as_float().unwrap();
        let u = file["uncertainty"][name.as_str()].as_float().unwrap();
        assert!((value - p["value"].as_f64().unwrap()).abs() < 1e-4, "{name}: {value} vs {p}");
        assert!((u - p["std_uncertainty"].as_f64().unwrap()).abs() < 1e-4, "{name}: {u} vs {p}");
    }
    let out = dir.path().join("comp");
    let doc = compensate_json("examples/machines/c600u.toml", arg(&piges), "heidenhain", &out, &[]);
    leave_a_tenth(&doc);
    let u = &doc["error_left_uncertainty"];
    assert!(u["expanded_um"].as_f64().unwrap() > 0.1 && u["parameters"] == 8 && u["coverage_factor"] == 2, "{u}");
}
