//! Fadal format 2 programs (`--dialect fadal`): a CAM program as the Autodesk post for Fadal
//! (`fadal.cps`) writes it, with the fixture offsets `E1` and `E7` and the cycle's R plane written
//! `R0+3.000`, and a hand-written program with macro statements (`# V1 = ..`, a loop made of `#
//! IF .. THEN GOTO :STEP` back to `#:STEP`, a jump forward, `# PRINT`, `# CLEAR`), `E0` and `E2`.
//! trueaxis reads each as the moves worked out here by hand from the Fadal manual (machine
//! position = program position + the fixture offset selected + the tool length; 1e-9 mm); LinuxCNC's
//! rs274 runs each rewritten as RS274/NGC (`common/fadal_to_ngc.rs`, the fixture offsets given to
//! it as G54/G55/G59.1 in a parameter file) and makes the same moves (1e-6 mm); the corrected
//! program, read back by the library and by rs274 through the same rewriting, lands on them through
//! the erroneous machine within half the 3-decimal increment (sqrt 3 x 0.5 um + the solve).

use super::common::fadal_to_ngc;
use super::common::oracle::Oracle;
use super::common::rs274::{rs274, Canon, Kind};
use trueaxis::compensate::nc::{correct_program, program_moves, run_program, Controller, MoveKind, NcOptions, NcResult, ToolTable};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// Where a corrected point may land with 3 decimals (mm): half the increment on each linear axis.
const TOLERANCE_UM: f64 = 0.866 + 0.01;
/// The tool lengths H1 100 mm and H2 120 mm, in inch (rs274 without an INI file works in inch).
const TOOLS_INCH: &str = "T1 P1 Z3.9370078740\nT2 P2 Z4.7244094488\n";
const TOOL: [f64; 3] = [0.0, 100.0, 120.0];
/// The fixture offsets of the tests (mm): E1 (G54), E2 (G55), E7.
const E1: [f64; 3] = [0.0, 0.0, -300.0];
const E2: [f64; 3] = [-50.0, 20.0, -280.0];
const E7: [f64; 3] = [100.0, 50.0, -310.0];

/// As the Autodesk post for Fadal writes a program in format 2 with `E` numbers for the work
/// offsets: `%`, `O1001 (NAME)`, the tool list, `G90 G94 G17`, `G21`, `T1 M6`, the dwell of three
/// spindle turns `G4 P36` (ms), `G90 G0 E1 X.. Y..`, `G0 G43 Z.. H1`, a rapid of two axes as
/// `G1 .. F5000.`, `G17 G94 G3 X.. Y.. I.. J..`, `G28 G91 Z0.`, a `G0` alone before the cycle,
/// `G98 G90 G81 .. R0+3.000 F..`, `G80`, `G90 G0` then `G53 X0. Y0.`, `M30`.
const POST: &str = "\
%
O1001 (FADAL BRACKET)
(T1  D=10. CR=0. - ZMIN=-2. - FLAT END MILL)
(T2  D=5. CR=0. TAPER=118DEG - ZMIN=-8. - DRILL)
N10 G90 G94 G17
N15 G21

(CONTOUR)
N20 T1 M6
N25 S5000 M3
N30 G4 P36
N35 G17
N40 G90 G0 E1 X-20. Y0.
N45 G0 G43 Z15. H1
N50 M8
N55 G0 Z5.
N60 G94 G1 Z-2. F300.
N65 G1 X40. F1000.
N70 G17 G94 G3 X50. Y10. I0. J10.
N75 G1 Y30.
N80 G1 X0. Y40. Z5. F5000.
N85 G0 Z15.
N90 G17
N95 M9
N100 G28 G91 Z0.
N105 G90

(DRILL)
N110 M1
N115 T2 M6
N120 S3000 M3
N125 G17
N130 G90 G0 E7 X10. Y20.
N135 G0 G43 Z15. H2
N140 M8
N145 G0
N150 G98 G90 G81 X10. Y20. Z-8. R0+3.000 F150.
N155 X30.
N160 Y40.
N165 G80
N170 G17
N175 M9
N180 G28 G91 Z0.
N185 G90
N190 G90 G0
N195 G53 X0. Y0.
N200 M30
%
";

/// A hand-written Fadal program with macro statements: `E0` (machine coordinates) and `E2`, three
/// passes of an incremental step-down square made a loop by `# IF V1 LT 3 THEN GOTO :STEP`, a jump
/// forward over two blocks, `# CLEAR`, `# PRINT`, `# R1 = ..`.
const MACROS: &str = "\
%
O2002 (FADAL STEPS)
N1 G90 G80 G40 G17 G21
N2 M6 T1
N3 G0 E0 Z-50.
N4 G0 E2 X10. Y10. S4000 M3
N5 G43 H1 Z10. M8
# CLEAR
# V1 = 0
# V2 = 1.5
# R1 = V2 * 2 + SQR(16)
#:STEP
G91 G1 Z-1.5 F200.
X30. F600.
Y20.
X-30.
Y-20.
G90
# V1 = V1 + 1
# IF V1 LT 3 THEN GOTO :STEP
# IF V1 GE 3 AND R1 EQ 7 THEN GOTO :DONE
G0 X-100. Y-100.
G0 Z-20.
#:DONE
# PRINT \"STEPS: \", V1
G0 Z10.
X50. Y10.
G0 G91 G28 Z0.
G90
M30
%
";

/// Moves in machine positions (mm), built from the program's points.
struct Moves {
    out: Vec<Canon>,
    offset: [f64; 3],
    tool: f64,
}

impl Moves {
    fn new() -> Moves {
        Moves { out: Vec::new(), offset: [0.0; 3], tool: 0.0 }
    }

    fn last(&self) -> [f64; 6] {
        self.out.last().map_or([0.0; 6], |c| c.end)
    }

    /// To machine position `m` (X Y Z).
    fn machine(&mut self, kind: Kind, m: [f64; 3]) {
        self.out.push(Canon { kind, end: [m[0], m[1], m[2], 0.0, 0.0, 0.0], tool: [0.0, 0.0, self.tool], inch: false });
    }

    /// To program point `p`: p + the fixture offset + the tool length along Z; `None` keeps the
    /// axis where the machine is.
    fn go(&mut self, kind: Kind, p: [Option<f64>; 3]) {
        let last = self.last();
        let m = std::array::from_fn(|k| p[k].map_or(last[k], |v| v + self.offset[k] + if k == 2 { self.tool } else { 0.0 }));
        self.machine(kind, m);
    }

    fn rapid(&mut self, x: f64, y: f64, z: f64) {
        self.go(Kind::Traverse, [Some(x), Some(y), Some(z)]);
    }

    fn feed(&mut self, x: f64, y: f64, z: f64) {
        self.go(Kind::Feed, [Some(x), Some(y), Some(z)]);
    }

    /// `G28 G91 Z0.`: the intermediate point where the machine is, then Z to the reference (0).
    fn reference_z(&mut self) {
        let l = self.last();
        self.machine(Kind::Traverse, [l[0], l[1], l[2]]);
        self.machine(Kind::Traverse, [l[0], l[1], 0.0]);
    }

    /// A `G81` hole in `G98` from the initial level: to the hole, down to R, feed to the bottom,
    /// back to the initial level (Fadal manual, fixed cycles; as a Fanuc's).
    fn g81(&mut self, x: f64, y: f64, initial: f64, r: f64, bottom: f64) {
        self.rapid(x, y, initial);
        self.rapid(x, y, r);
        self.feed(x, y, bottom);
        self.rapid(x, y, initial);
    }
}

fn post_moves() -> Vec<Canon> {
    let mut e = Moves::new();
    e.offset = E1;
    e.go(Kind::Traverse, [Some(-20.0), Some(0.0), None]);
    e.tool = TOOL[1];
    e.rapid(-20.0, 0.0, 15.0);
    e.rapid(-20.0, 0.0, 5.0);
    e.feed(-20.0, 0.0, -2.0);
    e.feed(40.0, 0.0, -2.0);
    // G3 X50. Y10. I0. J10. from (40, 0): centre (40, 10), counterclockwise
    e.go(Kind::Arc { axes: [0, 1, 2], centre: [40.0, 10.0], turns: 1 }, [Some(50.0), Some(10.0), Some(-2.0)]);
    e.feed(50.0, 30.0, -2.0);
    e.feed(0.0, 40.0, 5.0);
    e.rapid(0.0, 40.0, 15.0);
    e.reference_z();
    e.offset = E7;
    e.go(Kind::Traverse, [Some(10.0), Some(20.0), None]);
    e.tool = TOOL[2];
    e.rapid(10.0, 20.0, 15.0);
    for (x, y) in [(10.0, 20.0), (30.0, 20.0), (30.0, 40.0)] {
        e.g81(x, y, 15.0, 3.0, -8.0);
    }
    e.reference_z();
    // G53 X0. Y0.: machine coordinates
    e.machine(Kind::Traverse, [0.0, 0.0, 0.0]);
    e.out
}

fn macro_moves() -> Vec<Canon> {
    let mut e = Moves::new();
    // E0: no fixture offset
    e.go(Kind::Traverse, [None, None, Some(-50.0)]);
    e.offset = E2;
    e.go(Kind::Traverse, [Some(10.0), Some(10.0), None]);
    e.tool = TOOL[1];
    e.rapid(10.0, 10.0, 10.0);
    for pass in 1..=3 {
        let z = 10.0 - 1.5 * f64::from(pass);
        for (x, y) in [(10.0, 10.0), (40.0, 10.0), (40.0, 30.0), (10.0, 30.0), (10.0, 10.0)] {
            e.feed(x, y, z);
        }
    }
    // the jump forward skips X-100. Y-100. and Z-20.
    e.rapid(10.0, 10.0, 10.0);
    e.rapid(50.0, 10.0, 10.0);
    e.reference_z();
    e.out
}

fn setup() -> (Machine, ErrorModel, NcOptions) {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load("../../examples/errors/vmc3.toml", &m).unwrap();
    let mut options = NcOptions::new(&m);
    options.dialect = Some(Controller::Fadal);
    options.setup.machine_inch = true;
    options.setup.rs274_tool_change = true;
    options.setup.tools = ToolTable::parse(TOOLS_INCH, "tools").unwrap();
    // E1 and E2 are the offsets of G54 and G55; E7 is kept where G54.1 P7 is
    let axes = trueaxis::compensate::nc::machine_axes(&m);
    for (system, offset) in [(1, E1), (2, E2), (16, E7)] {
        options.setup.set_work_offset(&axes, system, &offset);
    }
    (m, e, options)
}

/// A parameter file (inch) with the X Y Z of each offset from its first parameter.
fn var_file(offsets: &[(u32, [f64; 3])]) -> String {
    offsets.iter().flat_map(|&(n, v)| (0..3).map(move |k| format!("{}\t{:.10}\n", n + k, v[k as usize] / 25.4))).collect()
}

/// The moves trueaxis reads, as canonical moves.
fn read(machine: &Machine, text: &str, options: &NcOptions) -> Vec<Canon> {
    let (trace, _) = run_program(machine, text, "fadal.nc", options).unwrap_or_else(|e| panic!("{e}"));
    trace
        .moves
        .iter()
        .map(|m| {
            let frame = trace.frames[m.frame as usize];
            let kind = match m.kind {
                MoveKind::Rapid => Kind::Traverse,
                MoveKind::Feed => Kind::Feed,
                MoveKind::Arc { clockwise, centre, .. } => Kind::Arc { axes: [0, 1, 2], centre, turns: if clockwise { -1 } else { 1 } },
            };
            Canon { kind, end: [m.end[0], m.end[1], m.end[2], 0.0, 0.0, 0.0], tool: [0.0, 0.0, frame.tool[2] * frame.scale()], inch: false }
        })
        .collect()
}

fn same(name: &str, what: &str, got: &[Canon], expected: &[Canon], tolerance_mm: f64) {
    assert_eq!(got.len(), expected.len(), "{name}, {what}: {got:#?}");
    for (i, (g, x)) in got.iter().zip(expected).enumerate() {
        let near = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(p, q)| (p - q).abs() < tolerance_mm);
        assert!(near(&g.end, &x.end) && near(&g.tool, &x.tool), "{name}, {what}: move {}: {g:?}, expected {x:?}", i + 1);
        match (&g.kind, &x.kind) {
            (Kind::Arc { centre: a, turns: ta, .. }, Kind::Arc { centre: b, turns: tb, .. }) => {
                assert!(ta == tb && near(a, b), "{name}, {what}: arc {}: {a:?} vs {b:?}", i + 1)
            }
            (a, b) => assert_eq!(a, b, "{name}, {what}: move {}", i + 1),
        }
    }
}

/// Every number of an axis, centre or R word has a decimal point and at most 3 decimals; an R
/// word stands as the R0 plane with its sign (`R0+3.002`).
fn check_numbers(text: &str) {
    for line in text.lines().filter(|l| !l.trim_start().starts_with('#')) {
        let code = line.split('(').next().unwrap_or("");
        for (i, c) in code.char_indices().filter(|(i, c)| "XYZIJKR".contains(*c) && (*i == 0 || code.as_bytes()[i - 1] == b' ')) {
            let mut value = &code[i + 1..];
            if c == 'R' {
                value = value
                    .strip_prefix('0')
                    .filter(|v| v.starts_with(['+', '-']))
                    .unwrap_or_else(|| panic!("`R` not as R0+/R0- in `{line}`"));
            }
            let number: String = value.chars().take_while(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | '+')).collect();
            let (_, frac) = number.split_once('.').unwrap_or_else(|| panic!("`{c}{number}` without a decimal point in `{line}`"));
            assert!(frac.len() <= 3, "`{c}{number}` with more than 3 decimals in `{line}`");
        }
    }
}

/// rs274's moves of a Fadal program rewritten as RS274/NGC, with the fixture offsets in its
/// parameter file (E1 as G54, E2 as G55, E7 as G59.1).
fn through_rs274(text: &str, what: &str) -> Option<Vec<Canon>> {
    let rs = rs274()?;
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tools.tbl"), TOOLS_INCH).unwrap();
    let ngc = fadal_to_ngc::translate(text).unwrap_or_else(|| panic!("{what}: not rewritten as RS274/NGC:\n{text}"));
    std::fs::write(dir.path().join("p.ngc"), &ngc).unwrap();
    let var = var_file(&[(5221, E1), (5241, E2), (5341, E7)]);
    Some(rs.run_with(dir.path(), "p.ngc", Some("tools.tbl"), Some(&var)).unwrap_or_else(|e| panic!("{what}: {e}\n{ngc}")))
}

/// Reads, corrects and checks a program: the moves trueaxis and rs274 read against `expected`,
/// the corrected program read back by both, through the erroneous machine.
fn check(name: &str, text: &str, expected: &[Canon]) -> NcResult {
    let (m, e, options) = setup();
    same(name, "read by trueaxis", &read(&m, text, &options), expected, 1e-9);
    let corrector = Corrector::new(&m, &e);
    let r = correct_program(&corrector, text, name, &options, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(r.dialect, Controller::Fadal);
    check_numbers(&r.text());
    assert!(r.text().starts_with("%\nO"), "{name}: the tape start and program number stay first:\n{}", r.text());
    let moves = program_moves(&m, text, name, &options).unwrap();
    let (_, homes) = super::common::canonical_homes(&m, &moves);
    let slack = super::common::hole_slack(&moves, &r.holes);
    let oracle = Oracle { machine: &m, errors: &e, temperatures: vec![] };
    let start = vec![0.0; m.axis_count()];
    let readback = read(&m, &r.text(), &options);
    let report = oracle
        .compare_with(expected, &readback, &start, TOLERANCE_UM, 1.0 + TOLERANCE_UM, &homes, &slack)
        .unwrap_or_else(|err| panic!("{name}, read back: {err}\n{}", r.text()));
    println!("{name}: read back by trueaxis: {} moves, ends within {:.3} um", report.moves, report.worst_end_um);
    if let Some(original) = through_rs274(text, name) {
        same(name, "read by rs274", &original, expected, 1e-6);
        let corrected = through_rs274(&r.text(), name).unwrap();
        let report = oracle
            .compare_with(&original, &corrected, &start, TOLERANCE_UM, 1.0 + TOLERANCE_UM, &homes, &slack)
            .unwrap_or_else(|err| panic!("{name}, through rs274: {err}\n{}", r.text()));
        println!("{name}: read back by rs274: {} moves, ends within {:.3} um", report.moves, report.worst_end_um);
    }
    r
}

#[test]
fn post_with_fixture_offsets_and_r0_plane_is_corrected() {
    let r = check("fadal_post", POST, &post_moves());
    let text = r.text();
    // the E words, the cycle and its R0 plane stay, each hole corrected in place
    assert!(text.contains(" E1 X-") && text.contains(" E7 X"), "{text}");
    let cycle = text.lines().find(|l| l.contains("G98 G90 G81 X")).unwrap_or_else(|| panic!("the cycle stays: {text}"));
    let r0: f64 = cycle.split(" R0").nth(1).and_then(|v| v.split(' ').next()).and_then(|v| v.parse().ok()).unwrap();
    assert!((r0 - 3.0).abs() < 0.01 && cycle.contains(" R0+"), "the R plane as R0+: {cycle}");
    assert_eq!(r.holes.len(), 3, "{:?}", r.holes);
    assert!(r.expanded.is_empty(), "{:?}", r.expanded);
}

#[test]
fn macro_loop_and_jumps_are_expanded() {
    let r = check("fadal_macros", MACROS, &macro_moves());
    // a jump back: the whole program expanded into plain moves, the fixture offsets written back
    assert_eq!(r.expanded.len(), 1, "{:?}", r.expanded);
    let text = r.text();
    assert!(text.contains("E0") && text.contains("E2"), "{text}");
    assert!(text.lines().all(|l| !l.starts_with('#')), "no macro statement left: {text}");
}
