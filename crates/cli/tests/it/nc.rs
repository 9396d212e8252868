//! `trueaxis nc` end to end: the example programs of both dialects with a tool table, work offsets
//! and a subroutine file on the search path; the JSON summary; a parameter file; refusals (exit 2,
//! the file and line named, nothing written); correction limits; the start outside the travel; the
//! header naming the machine and error files with their SHA-256 (checked with `sha256sum`) and
//! the refusal to correct a corrected program again (`--force`).

use crate::support::{outcome, ROOT};
use std::process::Command;

/// `trueaxis nc --machine vmc3 --errors ERRORS REST...`
fn nc(errors: &str, rest: &[&str]) -> (i32, String, String) {
    let mut args = vec!["nc", "--machine", "examples/machines/vmc3.toml", "--errors", errors];
    args.extend(rest);
    outcome(&args)
}

#[test]
fn the_pocket_is_corrected_with_a_json_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pocket_corrected.ngc");
    let (code, stdout, stderr) = nc("examples/errors/vmc3.toml", &["examples/nc/pocket.ngc", "--out", out.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(doc["moves"], 12);
    assert_eq!(doc["dialect"], "linuxcnc");
    assert_eq!(doc["expanded"].as_array().unwrap().len(), 0);
    // the solve's residual and the rounding of the written numbers: N120 is in inch, written to 6
    // decimals (half a unit: 0.0127 um per axis, sqrt 3 x 0.0127 = 0.022 um)
    assert!((0.022..0.025).contains(&doc["max_residual_um"].as_f64().unwrap()), "{doc}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("N40 G1 Z-250.00") && text.contains("(plunge)"), "{text}");
}

#[test]
fn both_dialects_run_with_a_tool_table_offsets_and_a_subroutine_file() {
    let dir = tempfile::tempdir().unwrap();
    let setup = ["--tool-table", "examples/nc/tools.tbl", "--offset", "G54=X0,Y0,Z-300", "--start", "X0,Y0,Z-100"];
    let out = dir.path().join("features.ngc");
    let mut args = vec!["examples/nc/features.ngc", "--out", out.to_str().unwrap(), "--json"];
    args.extend(setup);
    let (code, stdout, stderr) = nc("examples/errors/vmc3_backlash.toml", &[&args[..], &["--temperature", "T:column=22"]].concat());
    assert_eq!(code, 0, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    // the loop and the three calls of hole.ngc (found beside the program) are expanded
    let expanded: Vec<String> = doc["expanded"].as_array().unwrap().iter().map(|v| v.as_str().unwrap().to_string()).collect();
    assert_eq!(expanded.len(), 4, "{expanded:?}");
    assert!(expanded[1].contains("o<hole> call (a subroutine file)"), "{expanded:?}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("(trueaxis 0.1.0: corrected program; do not correct it again)\n"), "{text}");
    assert!(
        text.contains(
            "sha256 ffd694b371bfcdcf26d5997bc30c6cf7255fbd5655ddb248b71d9867ffe1c84d)\n(trueaxis dialect linuxcnc: LinuxCNC 2.9 - detected from the program)\n(trueaxis: corrected program; expanded into plain moves"
        ),
        "{text}"
    );
    assert!(text.contains("#<pass>=3"), "the loop's counter is set after it: {text}");
    let out = dir.path().join("drilling.nc");
    let mut args = vec!["examples/nc/drilling.nc", "--out", out.to_str().unwrap(), "--json"];
    args.extend(setup);
    let (code, stdout, stderr) = nc("examples/errors/vmc3.toml", &args);
    assert_eq!(code, 0, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(doc["dialect"], "fanuc");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.starts_with("%\nO1001 (BRACKET - CAM POST STYLE)\n(TRUEAXIS 0.1.0: CORRECTED PROGRAM; DO NOT CORRECT IT AGAIN)\n"),
        "{text}"
    );
    assert!(text.contains("(TRUEAXIS: CORRECTED PROGRAM; EXPANDED INTO PLAIN MOVES"), "{text}");
    assert!(text.contains("N45 G00 X19.99") && text.contains("N95 M30"), "{text}");
    // the G83 pattern stays a cycle, its holes corrected; --expand-cycles writes its moves
    assert!(text.contains("N55 G98 G83 X19.99") && text.contains("\nN60 X39.99"), "{text}");
    assert_eq!(doc["expanded"].as_array().unwrap().len(), 1, "{doc}");
    // one report per hole kept as a cycle: the three of lines 13-15 (N55 N60 N65), drilled along Z
    let holes = doc["holes"].as_array().unwrap();
    let lines: Vec<u64> = holes.iter().map(|h| h["line"].as_u64().unwrap()).collect();
    assert_eq!(lines, [13, 14, 15], "{doc}");
    for h in holes {
        assert_eq!((h["cycle"].as_str(), h["axis"].as_str()), (Some("G83"), Some("Z")), "{h}");
        let (lean, clearance) = (h["lean_um"].as_f64().unwrap(), h["clearance_um"].as_f64().unwrap());
        assert!((0.0..1.0).contains(&lean) && (0.0..5.0).contains(&clearance), "{h}");
    }
    let (code, stdout, stderr) = nc("examples/errors/vmc3.toml", &[&args[..], &["--expand-cycles"]].concat());
    assert_eq!(code, 0, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(doc["holes"].as_array().map(Vec::len), Some(0), "no hole stays a cycle: {doc}");
    let expanded: Vec<&str> = doc["expanded"].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect();
    assert_eq!(expanded[..3], ["line 13, canned cycle", "line 14, canned cycle", "line 15, canned cycle"], "{doc}");
    // --dialect linuxcnc reads the Fanuc program as LinuxCNC: its O number is no O-word
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &[&["examples/nc/drilling.nc", "--dialect", "linuxcnc"][..], &setup].concat());
    assert_eq!(code, 2);
    assert!(stderr.contains("drilling.nc: line 2: `o1001` is not followed by sub"), "{stderr}");
}

#[test]
fn a_parameter_file_gives_the_work_offsets() {
    let dir = tempfile::tempdir().unwrap();
    let var = dir.path().join("sim.var");
    std::fs::write(&var, "5221\t10.0\n5222\t-20.0\n5223\t-200.0\n").unwrap();
    let program = dir.path().join("p.ngc");
    std::fs::write(&program, "G21 G90 G54\nG0 X0 Y0 Z0\nG1 X10 F500\nM2\n").unwrap();
    let (code, stdout, stderr) =
        nc("examples/errors/vmc3.toml", &[program.to_str().unwrap(), "--parameters", var.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let text = doc["program"].as_str().unwrap();
    // at machine X10 Y-20 Z-200 the correction is a few micrometres: X0 becomes ...
    let g0 = text.lines().find(|l| l.starts_with("G0")).unwrap();
    assert!(g0.starts_with("G0 X-0.00") || g0.starts_with("G0 X0.00"), "{text}");
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &[program.to_str().unwrap(), "--parameters", program.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(stderr.contains("p.ngc: line 1: `G21` is not a parameter number"), "{stderr}");
}

#[test]
fn refusals_name_the_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.ngc");
    let out = dir.path().join("out.ngc");
    for (text, message, extra) in [
        ("G21 G90\nG0 X1\nG38.2 Z-10 F100\nM2\n", "bad.ngc: line 3: G38.2 (probing) stops where the probe touches", None),
        ("G21 G90\nG0 X1\nG43 H1 Z-5\nM2\n", "bad.ngc: line 3: tool 1 is not in the tool table (--strict-tools)", Some("--strict-tools")),
        ("G21 G90\nG42 D1\nM2\n", "bad.ngc: line 2: G42 (cutter radius compensation)", None),
    ] {
        std::fs::write(&bad, text).unwrap();
        let mut args = vec![bad.to_str().unwrap(), "--out", out.to_str().unwrap()];
        args.extend(extra);
        let (code, _, stderr) = nc("examples/errors/vmc3.toml", &args);
        assert_eq!(code, 2, "{text}");
        assert!(stderr.contains(message), "{stderr}");
        assert!(!out.exists());
    }
    // without --strict-tools the tool takes the assumed length, and the header says what that costs
    std::fs::write(&bad, "G21 G90\nG0 X1 Z-200\nG43 H1 Z-250\nM2\n").unwrap();
    let (code, stdout, stderr) = nc("examples/errors/vmc3.toml", &[bad.to_str().unwrap(), "--tool-length", "120", "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(doc["assumed_tools"], serde_json::json!([1]));
    assert!(
        doc["program"]
            .as_str()
            .unwrap()
            .contains("(trueaxis: T1 not in a tool table, taken as 120 mm long from the machine file's tool point;"),
        "{doc}"
    );
    // with a work offset of 200 mm the program's X300 is X500 on the machine: beyond the travel
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &["examples/nc/pocket.ngc", "--offset", "G54=X200"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("line 7: the end point leaves the machine's travel: axis X at 500 mm"), "{stderr}");
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &["examples/nc/pocket.ngc", "--dialect", "heidenhain"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--dialect `heidenhain` is not one of linuxcnc|fanuc|haas|mach3|mach4|grbl|fadal|siemens"), "{stderr}");
    // a grbl program with a code grbl does not know: refused as grbl refuses it
    let grbl = dir.path().join("drill.gcode");
    std::fs::write(&grbl, "G21 G90\nG0 X10 Y10 Z-5\nG81 Z-20 R-10 F100\nM2\n").unwrap();
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &[grbl.to_str().unwrap(), "--dialect", "grbl"]);
    assert_eq!(code, 2);
    assert!(stderr.ends_with("drill.gcode: line 3: G81 is not a code of grbl 1.1: grbl 1.1 stops here with error:20 (unsupported or invalid g-code command)\n"), "{stderr}");
    // a Siemens program: read; a frame rotation refused with its line
    let siemens = dir.path().join("part.mpf");
    std::fs::write(&siemens, "; SINUMERIK 840D\nN10 G17 G90 G54\nN20 G0 X10 Y10\nN30 AROT Z30\nN40 G2 X20 Y20 CR=10\nM30\n").unwrap();
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &[siemens.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(stderr.contains("part.mpf: line 4: AROT (additive programmable rotation) is not supported"), "{stderr}");
}

#[test]
fn corrections_beyond_the_limit_and_a_start_outside_the_travel_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pocket.ngc");
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &["examples/nc/pocket.ngc", "--out", out.to_str().unwrap(), "--limit-um", "5"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("examples/nc/pocket.ngc: line 4: the correction of axis X is -5.151 um at the machine position X0 Y0 Z-10"),
        "{stderr}"
    );
    assert!(stderr.contains("beyond the limit of 5 um (given for this run)") && stderr.contains("nothing was written"), "{stderr}");
    assert!(!out.exists());
    let (code, stdout, stderr) =
        nc("examples/errors/vmc3.toml", &["examples/nc/pocket.ngc", "--out", out.to_str().unwrap(), "--limit-um", "50", "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert!(doc["max_correction_um"].as_f64().unwrap() < 50.0 && out.exists());
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &["examples/nc/pocket.ngc", "--start", "X500"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--start: the start point leaves the machine's travel: axis X at 500 mm"), "{stderr}");
}

/// `sha256sum FILE` (GNU coreutils): the digest an operator checks the header against.
fn sha256sum(path: &str) -> Option<String> {
    let out = Command::new("sha256sum").arg(path).current_dir(ROOT).output().ok()?;
    Some(String::from_utf8(out.stdout).ok()?.split_whitespace().next()?.to_string())
}

#[test]
fn a_corrected_program_names_its_files_and_is_not_corrected_twice() {
    let dir = tempfile::tempdir().unwrap();
    let drilling = ["--tool-table", "examples/nc/tools.tbl", "--offset", "G54=X0,Y0,Z-300", "--start", "X0,Y0,Z-100"];
    for (program, name, setup) in
        [("examples/nc/pocket.ngc", "pocket.ngc", &[][..]), ("examples/nc/drilling.nc", "drilling.nc", &drilling[..])]
    {
        let out = dir.path().join(name);
        let (code, _, stderr) = nc("examples/errors/vmc3.toml", &[&[program, "--out", out.to_str().unwrap()][..], setup].concat());
        assert_eq!(code, 0, "{stderr}");
        let text = std::fs::read_to_string(&out).unwrap();
        let upper = |s: &str| if name.ends_with(".nc") { s.to_uppercase() } else { s.to_string() };
        for file in ["examples/machines/vmc3.toml", "examples/errors/vmc3.toml"] {
            let digest = sha256sum(file).unwrap_or_else(|| {
                // without coreutils: the digest of the file computed in the library
                trueaxis::compensate::nc::FileId::of(file, &std::fs::read(format!("../../{file}")).unwrap()).sha256
            });
            assert!(text.contains(&upper(&format!("{file} sha256 {digest})"))), "{name}: {digest}\n{text}");
        }
        // the header comes after the tape start (and the program number of a Fanuc program)
        let first = text.lines().position(|l| l.to_lowercase().starts_with("(trueaxis")).unwrap();
        assert_eq!(first, if name.ends_with(".nc") { 2 } else { 1 }, "{text}");
        // corrected again: refused with the line, nothing written
        let again = dir.path().join(format!("again_{name}"));
        let (code, _, stderr) =
            nc("examples/errors/vmc3.toml", &[&[out.to_str().unwrap(), "--out", again.to_str().unwrap()][..], setup].concat());
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(&format!("line {}: this program was corrected by trueaxis already", first + 1)), "{stderr}");
        assert!(!again.exists());
        let (code, _, stderr) =
            nc("examples/errors/vmc3.toml", &[&[out.to_str().unwrap(), "--out", again.to_str().unwrap(), "--force"][..], setup].concat());
        assert_eq!(code, 0, "{stderr}");
        assert!(again.exists());
    }
}

/// A Fadal program (`E7` fixture offset): the offset given as `--offset E7=...` moves the program
/// on the machine, so its correction differs with the offset; `E49` is refused, on the
/// command line and in the program.
#[test]
fn a_fadal_fixture_offset_is_given_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("e7.nc");
    std::fs::write(&program, "%\nO1 (FADAL)\nG90 G21 G17\nG0 E7 X10. Y20.\nG0 Z5.\nG1 Z-1. F200.\nM30\n%\n").unwrap();
    let run = |offset: &str| {
        let (code, stdout, stderr) = nc("examples/errors/vmc3.toml", &[program.to_str().unwrap(), "--json", "--offset", offset]);
        assert_eq!(code, 0, "{stderr}");
        serde_json::from_str::<serde_json::Value>(&stdout).unwrap()
    };
    let shifted = run("E7=X100,Y50,Z-310");
    let other = run("E7=X0,Y0,Z-300");
    assert_eq!(shifted["dialect"], "fadal");
    assert_eq!(shifted["moves"], 3);
    let text = shifted["program"].as_str().unwrap();
    assert!(text.contains("G0 E7 X"), "{text}");
    assert_ne!(shifted["program"], other["program"], "the offset moves the points corrected");
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &[program.to_str().unwrap(), "--offset", "E49=X1"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--offset: `E49` is not one of G54 ... G59.3 or a Fadal fixture offset E1 ... E48"), "{stderr}");
    std::fs::write(&program, "%\nO1\nG90 G21\nG0 E49 X10.\nM30\n%\n").unwrap();
    let (code, _, stderr) = nc("examples/errors/vmc3.toml", &[program.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(stderr.contains("e7.nc: line 4: E49: a Fadal fixture offset is E0 (none) or E1-E48"), "{stderr}");
}
