//! NC validity as LinuxCNC's: programs that LinuxCNC's interpreter `rs274` refuses are refused by
//! `trueaxis nc` too, with the line, and a valid program next to each is accepted by both (so
//! that the refusal is the defect, not the program around it). rs274 is the independent reader
//! (Debian linuxcnc-uspace; skipped with a reason when missing, required when
//! `TRUEAXIS_REQUIRE_RS274` is set, as CI does).
//!
//! Tolerances of the arc checks: LinuxCNC `interp_internal.hh`, `CENTER_ARC_RADIUS_TOLERANCE_MM`
//! = 2 * 0.01 * sqrt 2 mm and `SPIRAL_RELATIVE_TOLERANCE` = 0.001, used by `arc_data_ijk` in
//! `interp_arc.cc` (crates/nc/src/arcs.rs).

use trueaxis::compensate::nc::{correct_program, NcOptions};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

#[test]
fn programs_rs274_refuses_are_refused_with_the_line() {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load("../../examples/errors/vmc3.toml", &m).unwrap();
    let corrector = Corrector::new(&m, &e);
    let options = NcOptions::new(&m);
    // (bad program, its valid neighbour, the line trueaxis names)
    let cases = [
        // start radius 1, end radius 9 (the program); the neighbour ends on the circle
        ("G21 G90 G17\nG0 X0 Y0 Z-10\nG2 X10 Y0 I1 J0 F100\nM2\n", "G21 G90 G17\nG0 X0 Y0 Z-10\nG2 X2 Y0 I1 J0 F100\nM2\n", "line 3"),
        // 0.05 mm mismatch on a 10 mm radius: beyond 0.0283 mm and 0.1 %
        (
            "G21 G90 G17\nG0 X10 Y0 Z-10\nG3 X0 Y10.05 I-10 J0 F100\nM2\n",
            "G21 G90 G17\nG0 X10 Y0 Z-10\nG3 X0 Y10.02 I-10 J0 F100\nM2\n",
            "line 3",
        ),
        // two motion codes, two codes of the units, distance, plane, work-offset groups
        ("G21 G90\nG0 G1 X10 F100\nM2\n", "G21 G90\nG1 X10 F100\nM2\n", "line 2"),
        ("G21 G90\nG20 G21 X10\nM2\n", "G21 G90\nG21 G0 X10\nM2\n", "line 2"),
        ("G21 G90\nG90 G91 X10\nM2\n", "G21 G90\nG91 G0 X10\nM2\n", "line 2"),
        ("G21 G90\nG17 G18 G0 X10\nM2\n", "G21 G90\nG18 G0 X10\nM2\n", "line 2"),
        ("G21 G90\nG54 G55 G0 X10\nM2\n", "G21 G90\nG55 G0 X10\nM2\n", "line 2"),
        // two M codes of the spindle group
        ("G21 G90\nM3 M5 S100\nM2\n", "G21 G90\nM3 S100\nM2\n", "line 2"),
        // a word twice, a feed move without feed rate, an R arc too short for its chord
        ("G21 G90\nG1 X10 X20 F100\nM2\n", "G21 G90\nG1 X20 F100\nM2\n", "line 2"),
        ("G21 G90\nG1 X10\nM2\n", "G21 G90\nG1 X10 F50\nM2\n", "line 2"),
        ("G21 G90 G17\nG0 X0 Y0\nG2 X10 Y0 R2 F100\nM2\n", "G21 G90 G17\nG0 X0 Y0\nG2 X10 Y0 R5 F100\nM2\n", "line 3"),
        // an exponent: `X1e200` is X1 and an E word nothing uses
        ("G21 G90\nG1 X1e200 F100\nM2\n", "G21 G90\nG1 X100 F100\nM2\n", "line 2"),
    ];
    let dir = tempfile::tempdir().unwrap();
    let rs274 = super::common::rs274::rs274();
    for (bad, good, line) in cases {
        let err = correct_program(&corrector, bad, "bad.ngc", &options, &[]).expect_err(bad).to_string();
        assert!(err.contains(&format!("bad.ngc: {line}:")), "{bad:?}: {err}");
        assert!(correct_program(&corrector, good, "good.ngc", &options, &[]).is_ok(), "{good:?}");
        if let Some(r) = rs274 {
            std::fs::write(dir.path().join("bad.ngc"), bad).unwrap();
            std::fs::write(dir.path().join("good.ngc"), good).unwrap();
            assert!(r.run(dir.path(), "bad.ngc", None).is_err(), "rs274 runs {bad:?}");
            let ran = r.run(dir.path(), "good.ngc", None);
            assert!(ran.is_ok(), "rs274 refuses {good:?}: {ran:?}");
        }
    }
}

/// Fadal programs with what the Fadal reader refuses (docs/nc.md, "Fadal format 2"): each refused
/// with its line and the reason, and the same program with that line written as it is read
/// corrected.
#[test]
fn fadal_constructs_not_read_are_refused_with_the_line() {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load("../../examples/errors/vmc3.toml", &m).unwrap();
    let corrector = Corrector::new(&m, &e);
    let mut options = NcOptions::new(&m);
    options.dialect = Some(trueaxis::compensate::nc::Controller::Fadal);
    let program = |line: &str| format!("%\nO1 (FADAL)\nG90 G21 G17\n# V1 = 1\n{line}\nG0 E1 X10. Y10. Z-5.\n#:END\nM30\n%\n");
    // (the line, what is said about it)
    let cases = [
        ("# INPUT V2", "`# INPUT` waits for a value typed at the machine"),
        ("# V2 = AZ", "`AZ` is not read in a Fadal expression"),
        ("# V2 = SIN(30)", "`SIN( )` is not read in a Fadal expression"),
        ("# V101 = 2", "V101: the variables read are V1-V100 and R0-R9"),
        ("# IF V1 GT 0 THEN GOTO :NOWHERE", "GOTO :NOWHERE: no label `#:NOWHERE` in this program"),
        ("# IF V1 GT 0 GOTO :END", "is read as `# IF <condition> THEN GOTO :LABEL`"),
        ("# DPRNT", "`# DPRNT` is not a Fadal macro statement read here"),
        ("G1 X+R1 F100.", "`X+R1`: R parameters in words are not read yet"),
        ("L9101 R1+1.", "`R1+1.` sets the R parameter R1"),
        ("L0102", "L words alone (Fadal subroutines"),
        ("M17", "M17 (end of a Fadal subroutine) is not read yet"),
        ("G0 E49 X1.", "E49: a Fadal fixture offset is E0 (none) or E1-E48"),
        ("G98 G84.1 X1. Y1. Z-5. R0+2. F100.", "G84.1 (Fadal rigid tapping) is not read yet"),
        ("G47 X5.", "G47 (tool offset single/double expansion or reduction)"),
    ];
    for (line, why) in cases {
        let err = correct_program(&corrector, program(line), "fadal.nc", &options, &[]).expect_err(line).to_string();
        assert!(err.starts_with("fadal.nc: line 5: ") && err.contains(why), "{line}: {err}");
    }
    for good in ["# V2 = 2", "# IF V1 GT 0 THEN GOTO :END", "G0 X1. Y1.", "# PRINT \"START\"", "G0 E0 Z-1."] {
        let r = correct_program(&corrector, program(good), "fadal.nc", &options, &[]);
        assert!(r.is_ok(), "{good}: {r:?}");
    }
}
