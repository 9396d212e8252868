//! NC correction without an outside reader: the corrected programs read back by trueaxis land on
//! the original moves through the erroneous machine (the example programs of both dialects, the
//! five-axis program through the C600U's singularity); zero errors leave every program byte for
//! byte as it was, expansions included; the interpreter against closed forms (operator precedence
//! in both dialects, parallel assignments, Fanuc increments and vacant variables, offsets); the
//! tool length offset moves the tool point the correction is computed for; what cannot be
//! corrected is refused with the file, the line and the reason.

use super::common::oracle::Oracle;
use super::common::rs274::{Canon, Kind};
use trueaxis::compensate::nc::{correct_program, program_moves, run_program, Dialect, MoveKind, NcOptions, SearchPath, ToolTable};
use trueaxis::compensate::{CorrectionWorkspace, Corrector};
use trueaxis::error_model::{ErrorModel, MachineState};
use trueaxis::geometry::Vec3;
use trueaxis::machine::Machine;

pub(crate) use crate::support::examples::load;

/// The options of the example programs: the example tool table, G54 300 mm down, the examples
/// directory on the search path, the machine 100 mm below the top of its travel.
fn example_options(m: &Machine) -> NcOptions {
    let mut options = NcOptions::new(m);
    options.setup.tools = ToolTable::parse(&std::fs::read_to_string("../../examples/nc/tools.tbl").unwrap(), "tools.tbl").unwrap();
    let mut g54 = vec![0.0; m.axis_count()];
    g54[2] = -300.0;
    options.setup.set_work_offset(&trueaxis::compensate::nc::machine_axes(m), 1, &g54);
    options.setup.search_path = SearchPath(vec!["../../examples/nc".into()]);
    options.setup.start[2] = -100.0;
    options
}

/// The moves trueaxis reads, as canonical moves in machine positions.
pub(crate) fn read(m: &Machine, text: &str, options: &NcOptions) -> Vec<Canon> {
    let (trace, _) = run_program(m, text, "read", options).unwrap_or_else(|e| panic!("{e}"));
    trace
        .moves
        .iter()
        .map(|mv| {
            let frame = trace.frames[mv.frame as usize];
            let mut end = [0.0; 6];
            for (k, l) in ['X', 'Y', 'Z', 'A', 'B', 'C'].iter().enumerate() {
                if let Some(i) = m.axis_index(*l) {
                    end[k] = mv.end[i];
                }
            }
            let kind = match mv.kind {
                MoveKind::Rapid => Kind::Traverse,
                MoveKind::Feed => Kind::Feed,
                MoveKind::Arc { clockwise, centre, plane } => {
                    let axes = [plane.select.axes()[0], plane.select.axes()[1], plane.select.axes()[2]];
                    Kind::Arc { axes, centre, turns: if clockwise { -1 } else { 1 } }
                }
            };
            let s = frame.scale();
            Canon { kind, end, tool: [frame.tool[0] * s, frame.tool[1] * s, frame.tool[2] * s], inch: frame.inch }
        })
        .collect()
}

#[test]
fn corrected_examples_read_back_land_on_the_originals() {
    let cases = [
        ("vmc3", "vmc3_backlash", "pocket.ngc", &[24.0][..], false, 0.05),
        ("vmc3", "vmc3_backlash", "arcs.ngc", &[22.0][..], false, 0.05),
        ("c600u", "c600u", "five_axis.ngc", &[][..], false, 0.05),
        ("vmc3", "vmc3_backlash", "features.ngc", &[21.0][..], true, 0.05),
        // Fanuc: 3 decimals, each axis within half a micrometre
        ("vmc3", "vmc3_backlash", "drilling.nc", &[25.0][..], true, 0.876),
    ];
    for (machine, errors, file, temperatures, with_setup, end_um) in cases {
        let (m, e) = load(machine, errors);
        let options = if with_setup { example_options(&m) } else { NcOptions::new(&m) };
        let text = std::fs::read_to_string(format!("../../examples/nc/{file}")).unwrap();
        let r = correct_program(&Corrector::new(&m, &e), &text, file, &options, temperatures).unwrap_or_else(|e| panic!("{e}"));
        let original = read(&m, &text, &options);
        let corrected = read(&m, &r.text(), &options);
        let moves = program_moves(&m, &text, file, &options).unwrap();
        let (_, homes) = super::common::canonical_homes(&m, &moves);
        let oracle = Oracle { machine: &m, errors: &e, temperatures: temperatures.to_vec() };
        let report = oracle
            .compare(&original, &corrected, &options.setup.start, end_um, 1.0 + end_um, &homes)
            .unwrap_or_else(|err| panic!("{file}: {err}\n{}", r.text()));
        assert_eq!(report.moves, original.len());
        println!(
            "{file}: {} moves, {} pieces, ends within {:.4} um, expanded {:?}",
            report.moves, report.pieces, report.worst_end_um, r.expanded
        );
        if file == "five_axis.ngc" {
            // through the singularity at A = 0 the C correction fades in continuously
            assert!(report.pieces >= 20, "{}", report.pieces);
            // the residual includes the rounding to 5 decimals: sqrt 3 x 0.005 um of X Y Z, and A and C
            // by 0.000005 deg each at their levers (about 0.01 um each)
            assert!(
                r.max_residual_um < 0.04 && (r.max_uncorrectable_urad - 349.066).abs() < 1e-3,
                "{} {}",
                r.max_residual_um,
                r.max_uncorrectable_urad
            );
        }
    }
}

#[test]
fn zero_errors_leave_every_program_byte_for_byte() {
    for (machine, file, with_setup) in [
        ("vmc3", "pocket.ngc", false),
        ("vmc3", "arcs.ngc", false),
        ("c600u", "five_axis.ngc", false),
        ("vmc3", "features.ngc", true),
        ("vmc3", "drilling.nc", true),
    ] {
        let m = Machine::load(format!("../../examples/machines/{machine}.toml")).unwrap();
        let zero = ErrorModel::zero(&m);
        let options = if with_setup { example_options(&m) } else { NcOptions::new(&m) };
        let text = std::fs::read_to_string(format!("../../examples/nc/{file}")).unwrap();
        let r = correct_program(&Corrector::new(&m, &zero), &text, file, &options, &[]).unwrap();
        assert_eq!(r.program, text.as_bytes(), "{file}");
        assert_eq!((r.changed_lines, r.inserted_lines, r.expanded.len()), (0, 0, 0), "{file}");
        assert!(r.moves >= 5);
    }
}

fn assert_ends(got: Vec<[f64; 3]>, want: &[[f64; 3]]) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(g.iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-9), "{got:?} vs {want:?}");
    }
}

/// The end points (machine positions) trueaxis reads from a program on vmc3.
fn ends(text: &str, dialect: Dialect) -> Vec<[f64; 3]> {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let mut options = NcOptions::new(&m);
    options.dialect = Some(dialect.into());
    program_moves(&m, text, "t", &options).unwrap_or_else(|e| panic!("{e}")).iter().map(|mv| [mv.end[0], mv.end[1], mv.end[2]]).collect()
}

#[test]
fn the_interpreter_matches_closed_forms() {
    // LinuxCNC: ** before * / MOD before + -; 3 * 4 ** 2 MOD 5 = 48 MOD 5 = 3, + 2
    assert_ends(ends("#1 = [2 + 3 * 4 ** 2 MOD 5]\nG0 X#1\nM2\n", Dialect::LinuxCnc), &[[5.0, 0.0, 0.0]]);
    // Fanuc: no brackets needed on the right of `=`, * before +
    assert_ends(ends("O1\n#1=2+3*4\nG0 X#1\nM30\n", Dialect::Fanuc), &[[14.0, 0.0, 0.0]]);
    // LinuxCNC assigns in parallel: #2 gets the #1 before the line
    assert_ends(ends("#1 = 1\n#1 = 2 #2 = #1\nG0 X#2 Y#1\nM2\n", Dialect::LinuxCnc), &[[1.0, 2.0, 0.0]]);
    // Fanuc: a dimension word without a decimal point counts in 0.001 mm; a vacant variable's word
    // is ignored
    assert_ends(ends("O1\nG0 X100 Y1.\n#1=#0\nG0 X#1 Y2.\nM30\n", Dialect::Fanuc), &[[0.1, 1.0, 0.0], [0.1, 2.0, 0.0]]);
    // G92 shifts the coordinates of the current point, G92.1 removes it
    assert_ends(
        ends("G0 X10\nG92 X0\nG0 X5\nG92.1\nG0 X5\nM2\n", Dialect::LinuxCnc),
        &[[10.0, 0.0, 0.0], [15.0, 0.0, 0.0], [5.0, 0.0, 0.0]],
    );
    // G10 L20 P1 X0: the current point becomes X0 of G54; G10 L2 with a 90 deg rotation
    assert_ends(ends("G0 X7\nG10 L20 P1 X0\nG0 X1\nM2\n", Dialect::LinuxCnc), &[[7.0, 0.0, 0.0], [8.0, 0.0, 0.0]]);
    let r = ends("G10 L2 P1 X10 R90\nG0 X5 Y0\nM2\n", Dialect::LinuxCnc);
    assert!((r[0][0] - 10.0).abs() < 1e-12 && (r[0][1] - 5.0).abs() < 1e-12, "{r:?}");
    // inch: 1 inch is 25.4 mm; G91 increments
    assert_ends(ends("G20 G0 X1\nG91 X0.5\nM2\n", Dialect::LinuxCnc), &[[25.4, 0.0, 0.0], [38.1, 0.0, 0.0]]);
    // a G81 hole from Z-10 with R-18 to Z-25 (G98): over the hole, down to R, feed, back up
    assert_ends(
        ends("G0 X0 Y0 Z-10\nG98 G81 X5 Y5 Z-25 R-18 F100\nG80\nM2\n", Dialect::LinuxCnc),
        &[[0.0, 0.0, -10.0], [5.0, 5.0, -10.0], [5.0, 5.0, -18.0], [5.0, 5.0, -25.0], [5.0, 5.0, -10.0]],
    );
}

#[test]
fn a_tool_length_offset_moves_the_tool_point_of_the_correction() {
    // vmc3's tool point is the controlled point without offset; with G43 H1 (100 mm) the tool tip
    // is 100 mm lower, where the pitch and yaw errors act with a shorter lever: the corrected end
    // is the correction computed directly for that tool point
    let (m, e) = load("vmc3", "vmc3");
    let mut options = NcOptions::new(&m);
    options.setup.tools = ToolTable::parse("T1 Z100\n", "t").unwrap();
    options.decimals = Some(7);
    let text = "G21 G90\nG43 H1\nG0 X100 Y50 Z-250\nM2\n";
    let r = correct_program(&Corrector::new(&m, &e), text, "t", &options, &[]).unwrap();
    let corrected = program_moves(&m, &r.program, "t", &options).unwrap();
    let q_mm = [100.0, 50.0, -150.0];
    let mut corrector = Corrector::new(&m, &e);
    corrector.setup.tool_point -= Vec3::new(0.0, 0.0, 100.0);
    let mut ws = CorrectionWorkspace::new(&m);
    let mut q = vec![0.0; 3];
    m.pose_to_internal(&q_mm, &mut q);
    let c = corrector.correct_state(&q, &MachineState::default(), &mut ws).dq_user(&m);
    let without = Corrector::new(&m, &e).correct_state(&q, &MachineState::default(), &mut ws).dq_user(&m);
    let last = corrected.last().unwrap();
    for k in 0..3 {
        assert!((last.end[k] - q_mm[k] - c[k]).abs() < 1e-6, "axis {k}: {} vs {}", last.end[k] - q_mm[k], c[k]);
    }
    assert!((c[0] - without[0]).abs() > 1e-3, "the tool length changes the correction: {c:?} {without:?}");
}

#[test]
fn what_cannot_be_corrected_is_refused_with_the_line() {
    let (m, e) = load("vmc3", "vmc3");
    let corrector = Corrector::new(&m, &e);
    let options = NcOptions::new(&m);
    for (text, needle) in [
        ("G0 X1\nG38.2 Z-10 F100\nM2\n", "line 2: G38.2 (probing)"),
        ("G0 X1\nG33 Z-10 K1.5\nM2\n", "line 2: G33 (spindle-synchronised motion)"),
        ("G0 X1\nG76 P1 Z-10 I-1 J0.1 K0.8\nM2\n", "line 2: G76 (spindle-synchronised motion)"),
        ("G0 X1\nG41 D1 G1 X10 F100\nM2\n", "line 2: G41 (cutter radius compensation)"),
        ("G0 G1 X2\nM2\n", "line 1: G0 and G1 on one line are in the same modal group"),
        ("G1 X1 X2 F100\nM2\n", "line 1: two X words on one line"),
        ("G0 X0 Y0\nG2 X20 Y10 I10 J10 F100\nM2\n", "line 2: the radius to the end of the arc"),
        ("G0 X0 Y0\nG2 X10 Y0 R2 F100\nM2\n", "line 2: no arc of radius 2"),
        ("G1 X1\nM2\n", "line 1: a feed move with zero feed rate"),
        ("G1 X#<depth> F100\nM2\n", "line 1: named parameter #<depth> is not defined"),
        ("#1 = [1/0]\nM2\n", "line 1: division by zero"),
        ("o1 while [1]\nG0 X1\nM2\n", "line 1: `o1 while` is never closed"),
        ("G0 X1\nG0 A10\nM2\n", "line 2: axis A is not an axis of machine"),
        ("G0 X1000\nM2\n", "line 1: the end point leaves the machine's travel"),
        ("F100\nG5.2 X1 Y1 P1 L3\nX2 Y0 P1\nM2\n", "line 2: the G5.2 NURBS is not ended by G5.3"),
        ("F100\nG5.2 X1 Y1 P1\nG1 X2\nM2\n", "line 3: a G5.2 NURBS must be ended by G5.3 before another motion"),
        ("F100\nG5.2 X1 Y1 P1\nG5.3\nM2\n", "line 3: the NURBS of line 2 has 2 control points, fewer than its order L = 3"),
        ("F100\nG5.2 X1 Y1\nM2\n", "line 2: every NURBS control point needs its weight P"),
        ("F100\nG5.2 X1 Y1 Z1 P1\nM2\n", "line 2: a NURBS (G5.2) moves X and Y only"),
        ("F100\nG5.3\nM2\n", "line 2: G5.3 without a G5.2 NURBS before it"),
        ("o1 sub\no1 endsub\nM98 P100\nM2\n", "line 3: M98 is a Fanuc subprogram call"),
        ("o<nowhere> call\nM2\n", "line 1: subroutine `o<nowhere>` is neither in the program nor a file nowhere.ngc"),
        ("(abort, tool broken)\nM2\n", "line 1: the program aborts here: tool broken"),
        ("%\nO1\nG91 G84 X0 Y0 Z-5 R-2 F100\nM30\n%\n", "line 3: G84 in G91 (incremental) or with polar words: a tapping cycle"),
        ("%\nO1\nG68 X0 Y0 R30.\nM30\n%\n", "line 3: G68 (coordinate rotation"),
        ("%\nO1\nM99\n%\n", "line 3: M99 in the main program restarts it endlessly"),
        ("%\nO1\nGOTO 20\nM30\n%\n", "line 3: GOTO 20: no block N20"),
        // calls nested deeper than the controllers' 10 levels (a program that calls itself)
        ("o<r> sub\nG0 X1\no<r> call\no<r> endsub\no<r> call\nM2\n", "line 3: more than 10 nested subroutine calls"),
        ("%\nO1001\nG0 X1\nM98 P2001001\nM30\n%\n", "line 4: more than 10 nested subroutine calls"),
    ] {
        let err = correct_program(&corrector, text, "bad.ngc", &options, &[]).unwrap_err();
        assert_eq!(err.kind(), trueaxis::ErrorKind::Input, "{text}");
        assert!(err.to_string().starts_with("bad.ngc: ") && err.to_string().contains(needle), "{text}: {err}");
    }
    // --strict-tools: a tool the table lacks is refused
    let mut strict = NcOptions::new(&m);
    strict.setup.unknown_tools = trueaxis::compensate::nc::UnknownTools::Refuse;
    let err = correct_program(&corrector, "G43 H7\nM2\n", "bad.ngc", &strict, &[]).unwrap_err();
    assert_eq!(err.to_string(), "bad.ngc: line 1: tool 7 is not in the tool table (--strict-tools)");
}
