//! What posted programs do that a strict reading refused (issue 31, classes 2, 3 and 6), each
//! checked against what the controller does: LinuxCNC's rs274 where it runs the program (the same
//! moves, or the same refusal), the Fanuc manuals' rules otherwise (canned cycles in group 09 leave
//! the group-01 mode as it was; a G00 beside G28 sets the mode only).

use trueaxis::compensate::nc::{correct_program, program_moves, Controller, Dialect, NcOptions};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

fn vmc3() -> (Machine, ErrorModel) {
    super::roundtrip::load("vmc3", "vmc3")
}

/// The end points (X Y Z, mm) of the moves trueaxis reads.
fn ends(m: &Machine, text: &str, dialect: Dialect) -> Vec<[f64; 3]> {
    let mut options = NcOptions::new(m);
    options.dialect = Some(dialect.into());
    program_moves(m, text, "p", &options)
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .iter()
        .map(|mv| [mv.end[0], mv.end[1], mv.end[2]])
        .collect()
}

/// rs274's end points of the same program (inch without an INI file: the program says G21).
fn rs274_ends(text: &str) -> Option<Result<Vec<[f64; 3]>, String>> {
    let rs = super::common::rs274::rs274()?;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("p.ngc"), text).unwrap();
    Some(rs.run(dir.path(), "p.ngc", None).map(|c| c.iter().map(|c| [c.end[0], c.end[1], c.end[2]]).collect()))
}

#[test]
fn modal_rules_are_those_of_the_controller() {
    let (m, _) = vmc3();
    // the first line of most Fanuc/Haas posts, in both dialects: G80 beside G00 (rs274 runs it too)
    let first = "G21\nG00 G17 G40 G49 G80 G90\nG0 X10 Y5 Z-20\nG81 G80 X12 Y6 Z-30 R-25 F100\nG1 G80 X15 F200\nM2\n";
    let got = ends(&m, first, Dialect::LinuxCnc);
    if let Some(rs) = rs274_ends(first) {
        // (G00 with no axis words moves to where it is, in both)
        let rs = rs.unwrap();
        assert_eq!(got.len(), rs.len(), "{got:?} {rs:?}");
        for (a, b) in got.iter().zip(&rs) {
            assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9), "{got:?} {rs:?}");
        }
    }
    // G81 G80 runs the cycle and retracts to R (G99 until G98, as rs274); G1 G80 moves in G1
    assert_eq!(got.last().unwrap(), &[15.0, 6.0, -25.0]);
    let fanuc =
        "%\nO1\nG00 G17 G40 G49 G80 G90\nG00 G91 G28 Z0.\nG90 G00 X10. Y5. Z-20.\nG98 G81 X12. Y6. Z-30. R-25. F100.\nG80\nX20.\nM30\n%\n";
    let got = ends(&m, fanuc, Dialect::Fanuc);
    // G28 G91 Z0: to Z0 (the reference position); after G80 the group-01 G00 of line 5 moves to X20
    assert_eq!(got[0], [0.0, 0.0, 0.0]);
    assert_eq!(got.last().unwrap(), &[20.0, 6.0, -20.0]);
    // LinuxCNC refuses G00 beside G28 and axis words after G80, as rs274 does
    let (m, e) = vmc3();
    let options = NcOptions::new(&m);
    for (text, rs274_message) in [
        ("G21\nG00 G91 G28 Z0\nM2\n", "Cannot use two g codes that both use axis values"),
        ("G21\nG81 X1 Y2 Z-1 R1 F100\nG80\nX5\nM2\n", "Cannot use axis values without a g code that uses them"),
    ] {
        assert!(correct_program(&Corrector::new(&m, &e), text, "p", &options, &[]).is_err(), "{text}");
        if let Some(rs) = rs274_ends(text) {
            assert!(rs.unwrap_err().contains(rs274_message), "{text}");
        }
    }
}

#[test]
fn unknown_codes_pass_through_with_a_warning_unless_they_have_axis_words() {
    let (m, e) = vmc3();
    let c = Corrector::new(&m, &e);
    let mut options = NcOptions::new(&m);
    options.dialect = Some(Dialect::Fanuc.into());
    // Haas G187 (smoothness), G103 (look-ahead) and a machine M code
    let text = "%\nO1\nG187 P1\nG103 P1\nG00 X10. Y5. Z-20.\nM45\nG103\nM30\n%\n";
    let r = correct_program(&c, text, "haas.nc", &options, &[]).unwrap();
    assert_eq!(r.moves, 1);
    assert_eq!(
        r.warnings,
        vec![
            "haas.nc: line 3: G187 is not a code of Fanuc 0i/30i (Custom Macro B): passed through unchanged, assumed to move nothing",
            "haas.nc: line 4: G103 is not a code of Fanuc 0i/30i (Custom Macro B): passed through unchanged, assumed to move nothing (and 1 more lines)",
        ]
    );
    assert!(r.text().contains("\nG187 P1\nG103 P1\n"));
    // detected as Haas (its G187, G103): codes of its own, passed through without a warning
    let haas = correct_program(&c, text, "haas.nc", &NcOptions::new(&m), &[]).unwrap();
    assert_eq!((haas.dialect, haas.moves, haas.warnings.len(), haas.text()), (Controller::Haas, 1, 0, r.text()));
    let err = correct_program(&c, "%\nO1\nG187 X10. Y5.\nM30\n%\n", "haas.nc", &options, &[]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "haas.nc: line 3: G187 is not a code of Fanuc 0i/30i (Custom Macro B): with axis words on its line it cannot be passed through"
    );
    // LinuxCNC: a user M code beyond M199 and a program without M2 (rs274 runs both moves and
    // then reports the missing end)
    let options = NcOptions::new(&m);
    let r = correct_program(&c, "G21\nG0 X10 Y5 Z-20\nM428\nG1 X20 F100\n", "p.ngc", &options, &[]).unwrap();
    assert_eq!(r.moves, 2);
    assert_eq!(r.warnings.len(), 2, "{:?}", r.warnings);
    assert!(r.warnings[1].starts_with("p.ngc: line 4: the program ends without M2"), "{:?}", r.warnings);
}

#[test]
fn without_a_tool_table_the_tool_length_is_assumed_and_its_error_stated() {
    let (m, e) = vmc3();
    let c = Corrector::new(&m, &e);
    let options = NcOptions::new(&m);
    let text = "G21 G90\nT1 M6\nG43 H1\nG0 X-200 Y-150 Z-100\nG1 Z-250 F500\nT2 M6\nG43 H2\nG1 X100 Y50\nM2\n";
    let r = correct_program(&c, text, "p.ngc", &options, &[]).unwrap();
    assert_eq!(r.assumed_tools, vec![1, 2]);
    // the orientation error left along the program (vmc3: about 38 urad) times 100 mm
    let per_100 = r.tool_length_um_per_100mm.unwrap();
    assert!((per_100 - r.max_uncorrectable_urad * 0.1).abs() < 1e-12 && per_100 > 1.0, "{per_100}");
    let stated = format!("100 mm of a real tool's length from that moves its corrected points by up to {per_100:.1} um)");
    assert!(r.text().lines().next().unwrap().ends_with(&stated), "{}", r.text());
    // the same program with a tool table of 0-length tools: the same corrected moves
    let mut table = NcOptions::new(&m);
    table.setup.tools = trueaxis::compensate::nc::ToolTable::parse("T1 P1 Z0\nT2 P2 Z0\n", "t.tbl").unwrap();
    let with = correct_program(&c, text, "p.ngc", &table, &[]).unwrap();
    assert!(with.assumed_tools.is_empty() && with.tool_length_um_per_100mm.is_none());
    assert_eq!(with.text(), r.text().split_once('\n').unwrap().1);
}

#[test]
fn haas_programs_with_their_macros_and_output_are_read() {
    let (m, e) = vmc3();
    let c = Corrector::new(&m, &e);
    let mut options = NcOptions::new(&m);
    options.dialect = Some(Controller::Haas);
    let text = "%\n:1001 (HAAS STYLE)\nG103 P1\nG00 G17 G40 G49 G80 G90\nG154 P1\n#3901 = #3901 + 1\nPOPEN\nDPRNT[PART*#3901[40]]\nPCLOS\n\
                IF [#3901 GT 1000] THEN #3000 = 1 (TOO MANY)\nT1 M06\nG43 H01 Z-10.\nG00 X10. Y5. Z-20.\n#3006 = 1 (CHECK PART)\nM30\n%\n";
    let r = correct_program(&c, text, "haas.nc", &options, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.moves, 2);
    assert_eq!(r.assumed_tools, vec![1]);
    // the program number `:1001` stays second, the output lines as they were
    let out = r.text();
    assert!(out.starts_with("%\n:1001 (HAAS STYLE)\n(TRUEAXIS: T1 NOT IN A TOOL TABLE"), "{out}");
    assert!(out.contains("\nPOPEN\nDPRNT[PART*#3901[40]]\nPCLOS\n"), "{out}");
    // G154 P1 reads its offsets from #7001... like G54.1 P1
    let mut offset = options.clone();
    offset.setup.parameters = vec![(7001, 5.0), (7002, -3.0)];
    let moves = program_moves(&m, text, "haas.nc", &offset).unwrap();
    assert_eq!((moves[1].end[0], moves[1].end[1]), (15.0, 2.0));
    // #3000 executed: the program stops with the alarm there
    let alarm = text.replace("GT 1000", "GT 0");
    let err = correct_program(&c, alarm, "haas.nc", &options, &[]).unwrap_err();
    assert_eq!(err.to_string(), "haas.nc: line 10: the program stops with alarm 1 here (#3000 = 1)");
}

/// Each dialect's own refusals (its table's data), with the line: grbl stops at a code it does not
/// know (error:20), LinuxCNC refuses Mach3's `M98`, a Haas `M97` needs its `N` block, a Fadal `E`
/// fixture offset is E0-E48; the same codes pass where the dialect knows them.
#[test]
fn dialects_refuse_what_their_controller_does_not_run() {
    let (m, e) = vmc3();
    let c = Corrector::new(&m, &e);
    let run = |text: &str, dialect: Controller| {
        let mut options = NcOptions::new(&m);
        options.dialect = Some(dialect);
        correct_program(&c, text, "p.nc", &options, &[]).map(|r| r.moves).map_err(|e| e.to_string())
    };
    let lines = "G21 G90\nG0 X10 Y10 Z-5\nT1 M6\nG1 Z-20 F100\nM2\n";
    assert_eq!(run(lines, Controller::LinuxCnc), Ok(2));
    assert_eq!(
        run(lines, Controller::Grbl),
        Err("p.nc: line 3: M6 is not a code of grbl 1.1: grbl 1.1 stops here with error:20 (unsupported or invalid g-code command)".into())
    );
    let sub = "G21 G90\nG0 X10 Y10 Z-5\nM98 P100 L2\nM30\nO100\nG91 G1 X1 F100\nG90 M99\n";
    assert!(run(sub, Controller::LinuxCnc).unwrap_err().starts_with("p.nc: line 3: M98 is a Fanuc subprogram call"));
    assert_eq!(run(sub, Controller::Mach3), Ok(3));
    let fadal = "%\nO1\nG0 G90 G21 E1 X10. Y10. Z-5.\nM30\n%\n";
    assert_eq!(run(fadal, Controller::Fanuc), Ok(1));
    assert_eq!(run(fadal, Controller::Fadal), Ok(1));
    assert_eq!(
        run(&fadal.replace("E1", "E49"), Controller::Fadal),
        Err("p.nc: line 3: E49: a Fadal fixture offset is E0 (none) or E1-E48".into())
    );
    let haas = "%\nO1\nG0 G90 G21 X10. Y10. Z-5.\nM97 P100\nM30\nN100 G91 G1 X1. F100.\nG90 M99\n%\n";
    assert_eq!(run(haas, Controller::Fanuc), Ok(1));
    assert_eq!(run(haas, Controller::Haas), Ok(2));
    assert_eq!(
        run(&haas.replace("P100", "P200"), Controller::Haas),
        Err("p.nc: line 4: M97 P200: no block N200 in this program (a local subprogram starts at its N number)".into())
    );
    // detection names the controller from its codes
    assert_eq!(Controller::detect(haas), Controller::Haas);
    assert_eq!(Controller::detect("%\nO1\n# V1 = 2\nG0 X1.\nM30\n%\n"), Controller::Fadal);
}

/// Mach3's `M98 P.. L..` with `O` subprograms after `M30` ("Using Mach3Mill", 10.7): rs274 runs the
/// program rewritten with O-word subroutines (`common/fanuc_to_ngc.rs`) and makes the moves trueaxis
/// reads (1e-6 mm); the corrected program, rewritten the same way and run by rs274, lands on them
/// through the erroneous machine within 0.05 um (5 decimals). The subprogram run three times is
/// expanded at its call, the one run once is corrected in place.
#[test]
fn mach3_subprograms_are_corrected_and_land_through_rs274() {
    let (m, e) = vmc3();
    let c = Corrector::new(&m, &e);
    let text = "%\n(SUBPROGRAMS)\nG21 G90 G94 G17\nG0 X10 Y10 Z-50\nM98 P1001 L3\nG0 X-20 Y30\nM98 P1002\nG0 Z-50\nM30\n\
                O1001 (STEP DOWN)\nG91 G1 Z-2 F300\nX40 F800\nY5\nX-40\nG90\nM99\nO1002 (SQUARE)\nG1 X60 Y60 F800\nY90\nM99\n%\n";
    let mut options = NcOptions::new(&m);
    options.dialect = Some(Controller::Mach3);
    let read = super::roundtrip::read(&m, text, &options);
    assert_eq!(read.len(), 1 + 3 * 4 + 1 + 2 + 1);
    let r = correct_program(&c, text, "p.tap", &options, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.expanded.len(), 1, "{:?}", r.expanded);
    assert!(r.expanded[0].contains("M98 P1001 (the subprogram runs 3 times)"), "{:?}", r.expanded);
    let Some(rs) = super::common::rs274::rs274() else { return };
    let dir = tempfile::tempdir().unwrap();
    let ngc = |t: &str| super::common::fanuc_to_ngc::mach_to_ngc(t).expect("rewritten");
    std::fs::write(dir.path().join("p.ngc"), ngc(text)).unwrap();
    std::fs::write(dir.path().join("c.ngc"), ngc(&r.text())).unwrap();
    let original = rs.run(dir.path(), "p.ngc", None).unwrap_or_else(|e| panic!("{e}\n{}", ngc(text)));
    assert_eq!(original.len(), read.len());
    for (a, b) in original.iter().zip(&read) {
        assert!(a.end.iter().zip(&b.end).all(|(x, y)| (x - y).abs() < 1e-6), "rs274 {a:?}, trueaxis {b:?}");
    }
    let corrected = rs.run(dir.path(), "c.ngc", None).unwrap_or_else(|e| panic!("{e}\n{}", ngc(&r.text())));
    let oracle = super::common::oracle::Oracle { machine: &m, errors: &e, temperatures: vec![] };
    let report = oracle
        .compare(&original, &corrected, &vec![0.0; m.axis_count()], 0.05, 1.05, &[])
        .unwrap_or_else(|err| panic!("{err}\n{}", r.text()));
    println!("Mach3 M98: {} moves within {:.4} um", report.moves, report.worst_end_um);
    assert_eq!(report.moves, read.len());
}

/// Haas's `M97 P<N> L<repeats>` (Haas mill operator's manual, "M97 Local Sub-Program Call"): trueaxis
/// reads the expansion written here (1e-9 mm); the corrected program, read again by the library,
/// lands on it through the erroneous machine within half the written increment (3 decimals:
/// sqrt 3 x 0.5 um).
#[test]
fn haas_local_subprograms_are_corrected() {
    let (m, e) = vmc3();
    let c = Corrector::new(&m, &e);
    let text =
        "%\nO01000 (M97 FACING)\nG00 G17 G40 G49 G80 G90\nG21\nG00 G54 X-50. Y20.;\nZ-40.;\nM97 P1000 L4; (FACE)\nG00 Z-30.;\nM30;\n\
                N1000; (ONE PASS)\nG91;\nG00 Z-0.5;\nG90;\nG01 X50. F900.;\nG00 Y-20.;\nG01 X-50.;\nG00 Y20.;\nM99;\n%\n";
    let mut options = NcOptions::new(&m);
    options.dialect = Some(Controller::Haas);
    let mut expected = vec![[-50.0, 20.0, 0.0], [-50.0, 20.0, -40.0]];
    for pass in 1..=4 {
        let z = -40.0 - 0.5 * pass as f64;
        expected.extend([[-50.0, 20.0, z], [50.0, 20.0, z], [50.0, -20.0, z], [-50.0, -20.0, z], [-50.0, 20.0, z]]);
    }
    expected.push([-50.0, 20.0, -30.0]);
    let read = super::fanuc::read(&m, text, &options);
    assert_eq!(read.len(), expected.len());
    for (a, b) in read.iter().zip(&expected) {
        assert!(a.end[..3].iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9), "read {a:?}, expected {b:?}");
    }
    let r = correct_program(&c, text, "p.nc", &options, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.expanded.len(), 1, "{:?}", r.expanded);
    let corrected = super::fanuc::read(&m, &r.text(), &options);
    let oracle = super::common::oracle::Oracle { machine: &m, errors: &e, temperatures: vec![] };
    let tolerance = 3f64.sqrt() * 0.5 + 0.01;
    let report = oracle
        .compare(&read, &corrected, &vec![0.0; m.axis_count()], tolerance, 1.0 + tolerance, &[])
        .unwrap_or_else(|err| panic!("{err}\n{}", r.text()));
    println!("Haas M97: {} moves within {:.4} um", report.moves, report.worst_end_um);
    assert_eq!(report.moves, expected.len());
}
