//! The Fanuc dialect on programs written the way CAM posts write them for Fanuc controls
//! (Fusion 360 / HSMWorks-like: `%`, `O` number, `G28 G91 Z0.`, `G43 Z.. H..`, canned cycles with
//! R and Q; Mastercam-like: `M98 P.. L..` subprograms with incremental moves; Custom Macro B:
//! `WHILE [...] DO`, `G65` calls with arguments, `IF [...] GOTO`), each checked against an
//! expansion written here independently (closed forms of the hole patterns, the peck depths of
//! G83 from the Fanuc description, the arcs): trueaxis reads the original program as those moves
//! (1e-9 mm), and the corrected program, read back, pushed through the erroneous machine, lands on
//! them within 0.5 um (3 decimals: the IS-B increment 1 um, half of it from rounding) with every
//! dimension word written with a decimal point and at most 3 decimals.

use super::common::oracle::Oracle;
use super::common::rs274::{Canon, Kind};
use trueaxis::compensate::nc::{correct_program, program_moves, run_program, Dialect, MoveKind, NcOptions, ToolTable};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// G54 of the tests: program zero 300 mm below the spindle's home on vmc3; the machine starts
/// 100 mm below the top of its travel (program Z 200).
pub(crate) const G54_Z: f64 = -300.0;
pub(crate) const START_Z: f64 = -100.0;
/// Where a corrected point may land with 3 decimals: each linear axis within half the 1 um
/// increment (sqrt 3 x 0.5 um), plus the solve (0.01 um).
const TOLERANCE_UM: f64 = 0.866 + 0.01;
/// Tool lengths (mm, H1 and H2).
const TOOLS: &str = "T1 Z100\nT2 Z120\n";

/// Canonical moves of an expansion: machine positions X Y Z (A C for c600u in the A B C slots).
pub(crate) struct Expansion {
    pub(crate) moves: Vec<Canon>,
    pub(crate) tool: f64,
}

impl Expansion {
    pub(crate) fn new() -> Self {
        Expansion { moves: Vec::new(), tool: 0.0 }
    }

    fn at(&self, p: [f64; 3], rotary: [f64; 2]) -> [f64; 6] {
        [p[0], p[1], p[2] + G54_Z + self.tool, rotary[0], 0.0, rotary[1]]
    }

    fn last(&self) -> [f64; 6] {
        self.moves.last().map_or([0.0, 0.0, START_Z, 0.0, 0.0, 0.0], |c| c.end)
    }

    /// A straight move to program point `p` (G54, tool offset in force).
    pub(crate) fn go(&mut self, rapid: bool, p: [f64; 3]) {
        self.go5(rapid, p, [self.last()[3], self.last()[5]]);
    }

    fn go5(&mut self, rapid: bool, p: [f64; 3], rotary: [f64; 2]) {
        let end = self.at(p, rotary);
        self.moves.push(Canon { kind: if rapid { Kind::Traverse } else { Kind::Feed }, end, tool: [0.0, 0.0, self.tool], inch: false });
    }

    /// A move in machine coordinates (the return to the reference position).
    pub(crate) fn machine(&mut self, end: [f64; 3]) {
        let mut e = self.last();
        e[..3].copy_from_slice(&end);
        self.moves.push(Canon { kind: Kind::Traverse, end: e, tool: [0.0, 0.0, self.tool], inch: false });
    }

    /// An XY arc to `p` around program centre `c` (+1 counterclockwise).
    pub(crate) fn arc(&mut self, p: [f64; 3], c: [f64; 2], turns: i32) {
        let end = self.at(p, [self.last()[3], self.last()[5]]);
        self.moves.push(Canon { kind: Kind::Arc { axes: [0, 1, 2], centre: c, turns }, end, tool: [0.0, 0.0, self.tool], inch: false });
    }

    /// `G28 G91 Z0.`: no intermediate motion, Z to the reference position (machine 0).
    fn reference_z(&mut self) {
        let now = self.last();
        self.machine([now[0], now[1], now[2]]);
        self.machine([now[0], now[1], 0.0]);
    }

    /// A G83 hole as the Fanuc manual describes it: to R, pecks of Q each followed by a rapid
    /// back to R and down to `d` above the last depth, the last feed to the bottom, back to the
    /// initial level (G98).
    pub(crate) fn g83(&mut self, xy: [f64; 2], initial: f64, r: f64, bottom: f64, q: f64, d: f64) {
        self.go(true, [xy[0], xy[1], initial]);
        self.go(true, [xy[0], xy[1], r]);
        let mut depth = r - q;
        while depth > bottom {
            self.go(false, [xy[0], xy[1], depth]);
            self.go(true, [xy[0], xy[1], r]);
            self.go(true, [xy[0], xy[1], depth + d]);
            depth -= q;
        }
        self.go(false, [xy[0], xy[1], bottom]);
        self.go(true, [xy[0], xy[1], initial]);
    }

    /// A G84 rigid tapping hole as the Fanuc manual describes it: to R, feed to the bottom, the
    /// spindle reversed, feed back to R, with G98 a rapid to the initial level.
    fn g84(&mut self, xy: [f64; 2], level: f64, r: f64, bottom: f64, initial: Option<f64>) {
        self.go(true, [xy[0], xy[1], level]);
        if level > r {
            self.go(true, [xy[0], xy[1], r]);
        }
        self.go(false, [xy[0], xy[1], bottom]);
        self.go(false, [xy[0], xy[1], r]);
        if let Some(i) = initial {
            self.go(true, [xy[0], xy[1], i]);
        }
    }

    /// A G81 hole with G99 or G98 retraction.
    pub(crate) fn g81(&mut self, xy: [f64; 2], level: f64, r: f64, bottom: f64, retract: f64) {
        self.go(true, [xy[0], xy[1], level]);
        if level > r {
            self.go(true, [xy[0], xy[1], r]);
        }
        self.go(false, [xy[0], xy[1], bottom]);
        self.go(true, [xy[0], xy[1], retract]);
    }
}

/// Fusion 360-like output: facing pass with arcs, then a G83 peck-drilled pattern.
const FUSION: &str = "\
%
O1001 (PART1)
(T1  D=10. CR=0. - ZMIN=-5. - FLAT END MILL)
N10 G90 G94 G17 G49 G40 G80
N15 G21
N20 G28 G91 Z0.
N25 G90
(FACE1)
N30 T1 M06
N35 S5000 M03
N40 G54
N45 G00 X-20. Y0.
N50 G43 Z15. H01
N55 G00 Z5.
N60 G01 Z0. F1000.
N65 X100.
N70 G02 X110. Y10. I0. J10.
N75 G01 Y50.
N80 G03 X100. Y60. R10.
N85 G00 Z15.
(DRILL1)
N90 M05
N95 G28 G91 Z0.
N100 G90
N105 T2 M06
N110 S3000 M03
N115 G54
N120 G00 X20. Y20.
N125 G43 Z15. H02
N130 G98 G83 X20. Y20. Z-12. R3. Q2. F200.
N135 X40.
N140 Y40.
N145 G80
N150 G00 Z15.
N155 M05
N160 G28 G91 Z0.
N165 G28 G91 X0. Y0.
N170 M30
%
";

fn fusion_expansion() -> Expansion {
    let mut e = Expansion::new();
    e.reference_z();
    e.go(true, [-20.0, 0.0, -G54_Z]);
    e.tool = 100.0;
    e.go(true, [-20.0, 0.0, 15.0]);
    e.go(true, [-20.0, 0.0, 5.0]);
    e.go(false, [-20.0, 0.0, 0.0]);
    e.go(false, [100.0, 0.0, 0.0]);
    e.arc([110.0, 10.0, 0.0], [100.0, 10.0], -1);
    e.go(false, [110.0, 50.0, 0.0]);
    e.arc([100.0, 60.0, 0.0], [100.0, 50.0], 1);
    e.go(true, [100.0, 60.0, 15.0]);
    e.reference_z();
    // Z at the reference position with H1 still in force, then H2
    e.go(true, [20.0, 20.0, -G54_Z - 100.0]);
    e.tool = 120.0;
    e.go(true, [20.0, 20.0, 15.0]);
    for xy in [[20.0, 20.0], [40.0, 20.0], [40.0, 40.0]] {
        e.g83(xy, 15.0, 3.0, -12.0, 2.0, 0.254);
    }
    e.go(true, [40.0, 40.0, 15.0]);
    e.reference_z();
    let now = e.last();
    e.machine([now[0], now[1], now[2]]);
    e.machine([0.0, 0.0, now[2]]);
    e
}

/// Mastercam-like output: a pocket subprogram of incremental moves called three times.
const MASTERCAM: &str = "\
%
O1002 (MASTERCAM SUB)
G21
G0 G17 G40 G49 G80 G90
T1 M6
G0 G90 G54 X10. Y10. S8000 M3
G43 H1 Z10.
M98 P2000 L3
G90 G0 Z10.
M5
G91 G28 Z0.
M30
O2000 (POCKET)
G91 G1 Z-12. F300.
X20.
Y5.
X-20.
G0 Z12.
X25.
M99
%
";

/// Custom Macro B: a bolt circle with WHILE ... DO and G81, a G65 macro call with arguments, an
/// IF [...] GOTO loop that jumps back, a dimension word without a decimal point (increments).
const MACRO_B: &str = "\
%
O1003 (BOLT CIRCLE)
G21 G90 G17 G54
T2 M6
S2500 M3
G43 H2 Z20.
#100=6 (HOLES)
#101=40. (RADIUS)
#102=0
WHILE [#102 LT #100] DO 1
#103=#102*360/#100
G0 X[#101*COS[#103]] Y[#101*SIN[#103]]
G99 G81 Z-5. R2. F150.
G80
#102=#102+1
END 1
G65 P9100 A10. B-5.
#1=0
N50 IF [#1 GE 3] GOTO 80
G91 G1 X5. F300.
#1=#1+1
GOTO 50
N80 G90 G1 Y10000
G0 Z20.
M30
O9100 (A=X B=DEPTH)
G1 X#1 F200.
G1 Z#2
G0 Z20.
M99
%
";

fn macro_b_expansion() -> Expansion {
    let mut e = Expansion::new();
    e.tool = 120.0;
    e.go(true, [0.0, 0.0, 20.0]);
    let mut z = 20.0;
    for k in 0..6 {
        let a = (k as f64 * 60.0).to_radians();
        let xy = [40.0 * a.cos(), 40.0 * a.sin()];
        e.go(true, [xy[0], xy[1], z]);
        // G99: down to R 2 (from the initial level 20 the first time), drill, back to R
        e.g81(xy, z, 2.0, -5.0, 2.0);
        z = 2.0;
    }
    let last = e.last();
    let y = last[1];
    e.go(false, [10.0, y, 2.0]);
    e.go(false, [10.0, y, -5.0]);
    e.go(true, [10.0, y, 20.0]);
    for k in 1..=3 {
        e.go(false, [10.0 + 5.0 * k as f64, y, 20.0]);
    }
    // Y10000 without a decimal point: 10 mm in the IS-B increment of 0.001 mm
    e.go(false, [25.0, 10.0, 20.0]);
    e.go(true, [25.0, 10.0, 20.0]);
    e
}

/// A 3+2 program on the five-axis C600U: A and C positioned, then a face pass and a hole.
const FIVE_AXIS: &str = "\
%
O1004 (3+2)
G21 G90 G17 G54
G0 A30. C45.
G0 X-50. Y20. Z10.
G1 Z-2. F500.
X50.
G0 Z10.
G0 A0. C90.
G98 G81 X0. Y0. Z-8. R2. F100.
G80
G0 Z30.
M30
%
";

fn five_axis_expansion() -> Expansion {
    let mut e = Expansion::new();
    let z0 = START_Z - G54_Z;
    e.go5(true, [0.0, 0.0, z0], [30.0, 45.0]);
    e.go5(true, [-50.0, 20.0, 10.0], [30.0, 45.0]);
    e.go(false, [-50.0, 20.0, -2.0]);
    e.go(false, [50.0, 20.0, -2.0]);
    e.go(true, [50.0, 20.0, 10.0]);
    e.go5(true, [50.0, 20.0, 10.0], [0.0, 90.0]);
    e.g81([0.0, 0.0], 10.0, 2.0, -8.0, 10.0);
    e.go(true, [0.0, 0.0, 30.0]);
    e
}

/// The moves trueaxis reads, as canonical moves.
pub(crate) fn read(machine: &Machine, text: &str, options: &NcOptions) -> Vec<Canon> {
    let (trace, _) = run_program(machine, text, "fanuc", options).unwrap_or_else(|e| panic!("{e}"));
    let letters = ['X', 'Y', 'Z', 'A', 'B', 'C'];
    trace
        .moves
        .iter()
        .map(|m| {
            let frame = trace.frames[m.frame as usize];
            let mut end = [0.0; 6];
            for (k, l) in letters.iter().enumerate() {
                if let Some(i) = machine.axis_index(*l) {
                    end[k] = m.end[i];
                }
            }
            let kind = match m.kind {
                MoveKind::Rapid => Kind::Traverse,
                MoveKind::Feed => Kind::Feed,
                MoveKind::Arc { clockwise, centre, .. } => Kind::Arc { axes: [0, 1, 2], centre, turns: if clockwise { -1 } else { 1 } },
            };
            Canon { kind, end, tool: [0.0, 0.0, frame.tool[2] * frame.scale()], inch: frame.inch }
        })
        .collect()
}

pub(crate) fn homes(machine: &Machine, text: &str, options: &NcOptions) -> Vec<usize> {
    let (trace, _) = run_program(machine, text, "fanuc", options).unwrap();
    super::common::canonical_homes(machine, &trace.moves).1
}

/// Every dimension word has a decimal point and at most `decimals` digits after it.
fn check_numbers(text: &str, decimals: usize) {
    for line in text.lines() {
        let code: String = line.split('(').next().unwrap_or("").to_string();
        let b = code.as_bytes();
        for (i, &c) in b.iter().enumerate() {
            if !b"XYZABCIJKRQ".contains(&c) || i > 0 && b[i - 1].is_ascii_alphabetic() {
                continue;
            }
            let number: String = code[i + 1..].chars().take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-').collect();
            if number.is_empty() || number.starts_with('#') {
                continue;
            }
            let (_, frac) = number.split_once('.').unwrap_or_else(|| panic!("`{}{number}` without a decimal point in `{line}`", c as char));
            assert!(frac.len() <= decimals, "`{}{number}` has more than {decimals} decimals in `{line}`", c as char);
        }
    }
}

fn check(name: &str, machine_name: &str, errors: &str, text: &str, expected: &Expansion, expanded: usize) {
    let m = Machine::load(format!("../../examples/machines/{machine_name}.toml")).unwrap();
    let e = ErrorModel::load(format!("../../examples/errors/{errors}.toml"), &m).unwrap();
    let mut options = NcOptions::new(&m);
    options.setup.tools = ToolTable::parse(TOOLS, "tools").unwrap();
    let mut offset = vec![0.0; m.axis_count()];
    offset[2] = G54_Z;
    options.setup.set_work_offset(&trueaxis::compensate::nc::machine_axes(&m), 1, &offset);
    options.setup.start[2] = START_Z;
    // the original, read by trueaxis, is the independent expansion
    let original = read(&m, text, &options);
    assert_eq!(original.len(), expected.moves.len(), "{name}: {original:#?}");
    for (i, (o, x)) in original.iter().zip(&expected.moves).enumerate() {
        let same = o.end.iter().zip(&x.end).all(|(a, b)| (a - b).abs() < 1e-9) && o.tool == x.tool;
        assert!(same, "{name}: move {}: read {:?}, expected {:?}", i + 1, o, x);
        match (&o.kind, &x.kind) {
            (Kind::Arc { centre: a, turns: ta, .. }, Kind::Arc { centre: b, turns: tb, .. }) => {
                let c = [b[0], b[1] + 0.0];
                assert!(ta == tb && (a[0] - c[0]).abs() < 1e-9 && (a[1] - c[1]).abs() < 1e-9, "{name}: arc {}: {a:?} vs {c:?}", i + 1)
            }
            (a, b) => assert_eq!(a, b, "{name}: move {}", i + 1),
        }
    }
    // corrected, read back, through the erroneous machine
    let corrector = Corrector::new(&m, &e);
    let r = correct_program(&corrector, text, name, &options, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(r.dialect.family(), Dialect::Fanuc);
    assert_eq!(r.expanded.len(), expanded, "{name}: {:?}\n{}", r.expanded, r.text());
    check_numbers(&r.text(), 3);
    assert!(r.text().starts_with("%\nO100"), "{name}: the tape start and program number stay first:\n{}", r.text());
    let corrected = read(&m, &r.text(), &options);
    let oracle = Oracle { machine: &m, errors: &e, temperatures: vec![] };
    let mut start = vec![0.0; m.axis_count()];
    start[2] = START_Z;
    let report = oracle
        .compare_with(
            &expected.moves,
            &corrected,
            &start,
            TOLERANCE_UM,
            1.0 + TOLERANCE_UM,
            &homes(&m, text, &options),
            &super::common::hole_slack(&program_moves(&m, text, name, &options).unwrap(), &r.holes),
        )
        .unwrap_or_else(|err| panic!("{name}: {err}\n{}", r.text()));
    println!(
        "{name}: {} moves, {} pieces, ends within {:.3} um, path within {:.3} um; expanded {:?}",
        report.moves, report.pieces, report.worst_end_um, report.worst_path_um, r.expanded
    );
    assert!(r.changed_lines > 0);
}

#[test]
fn fusion_like_output_is_corrected() {
    check("fusion", "vmc3", "vmc3", FUSION, &fusion_expansion(), 0);
}

/// Rigid tapping as Fanuc and Haas posts write it: `M29 S..` before the cycle, G98 then G99.
const RIGID_TAP: &str = "\
%
O1005 (RIGID TAP M8)
G21 G90 G17 G40 G49 G80
T2 M06
G54 G00 X30. Y-20.
G43 Z20. H02
M29 S400
G98 G84 X30. Y-20. Z-15. R5. F500.
X60.
G99 Y-50.
G80
G00 Z20.
M30
%
";

#[test]
fn rigid_tapping_stays_a_cycle_corrected_at_its_holes() {
    let mut e = Expansion::new();
    e.go(true, [30.0, -20.0, START_Z - G54_Z]);
    e.tool = 120.0;
    e.go(true, [30.0, -20.0, 20.0]);
    e.g84([30.0, -20.0], 20.0, 5.0, -15.0, Some(20.0));
    e.g84([60.0, -20.0], 20.0, 5.0, -15.0, Some(20.0));
    e.g84([60.0, -50.0], 20.0, 5.0, -15.0, None);
    e.go(true, [60.0, -50.0, 20.0]);
    check("rigid_tap", "vmc3", "vmc3", RIGID_TAP, &e, 0);
    // the cycle and its rigid-tapping mode stay as written, each hole block corrected
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let errors = ErrorModel::load("../../examples/errors/vmc3.toml", &m).unwrap();
    let mut options = NcOptions::new(&m);
    options.setup.tools = ToolTable::parse(TOOLS, "tools").unwrap();
    options.setup.start[2] = START_Z;
    options.setup.set_work_offset(&trueaxis::compensate::nc::machine_axes(&m), 1, &[0.0, 0.0, G54_Z]);
    let r = correct_program(&Corrector::new(&m, &errors), RIGID_TAP, "tap.nc", &options, &[]).unwrap();
    let text = r.text();
    assert!(text.contains("\nM29 S400\n") && text.contains("G98 G84 X29.99") && text.contains("\nG80\n"), "{text}");
    assert_eq!(r.holes.len(), 3, "{:?}", r.holes);
    assert!(r.warnings.iter().all(|w| !w.contains("M29")), "{:?}", r.warnings);
    assert!(r.holes.iter().all(|h| h.code == 840 && h.lean_um < 5.0), "{:?}", r.holes);
    // with --expand-cycles too: a tap follows the spindle
    options.setup.expand_cycles = true;
    let expanded = correct_program(&Corrector::new(&m, &errors), RIGID_TAP, "tap.nc", &options, &[]).unwrap();
    assert_eq!(expanded.text(), text);
}

#[test]
fn mastercam_like_subprograms_are_expanded() {
    let mut e = Expansion::new();
    e.go(true, [10.0, 10.0, START_Z - G54_Z]);
    e.tool = 100.0;
    e.go(true, [10.0, 10.0, 10.0]);
    let (mut x, mut y) = (10.0, 10.0);
    for _ in 0..3 {
        e.go(false, [x, y, -2.0]);
        e.go(false, [x + 20.0, y, -2.0]);
        e.go(false, [x + 20.0, y + 5.0, -2.0]);
        e.go(false, [x, y + 5.0, -2.0]);
        e.go(true, [x, y + 5.0, 10.0]);
        e.go(true, [x + 25.0, y + 5.0, 10.0]);
        x += 25.0;
        y += 5.0;
    }
    e.go(true, [x, y, 10.0]);
    e.reference_z();
    check("mastercam", "vmc3", "vmc3_backlash", MASTERCAM, &e, 1);
}

#[test]
fn macro_b_loops_calls_and_jumps_are_expanded() {
    check("macro_b", "vmc3", "vmc3", MACRO_B, &macro_b_expansion(), 1);
}

#[test]
fn five_axis_positioning_is_corrected_on_the_machine_chain() {
    check("five_axis", "c600u", "c600u", FIVE_AXIS, &five_axis_expansion(), 0);
}

/// `G43 H..` and `G49` on blocks without a move (as hand-written programs have them), each followed
/// by a move to the X Y the machine is at: a Fanuc applies a tool length offset by moving, its
/// program position staying, so that move takes Z to the new offset (LinuxCNC instead keeps the
/// machine where it is: rs274 reads the rewriting of `fanuc_to_ngc`). Inside a loop (expanded, each
/// pass at its own correction) and in the main program (corrected in place).
const TOOL_OFFSET_ALONE: &str = "\
%
O1006 (G43 WITHOUT A MOVE)
G21 G90 G17 G40 G49 G80
G54 G0 X0. Y0. Z50.
#1=0
WHILE [#1 LT 2] DO 1
G0 X[#1*30.] Y0.
G43 H02
G0 X[#1*30.] Y0.
G1 X[#1*30.+20.] F500.
G49
G0 Y10.
Z50.
#1=#1+1
END 1
G43 H01
G0 X0. Y0.
G1 Y20. F500.
M30
%
";

fn tool_offset_alone_expansion() -> Expansion {
    let mut e = Expansion::new();
    e.go(true, [0.0, 0.0, 50.0]);
    for x in [0.0, 30.0] {
        e.go(true, [x, 0.0, 50.0]);
        // the rapid to the X Y the machine is at takes Z to the offset of H02
        e.tool = 120.0;
        e.go(true, [x, 0.0, 50.0]);
        e.go(false, [x + 20.0, 0.0, 50.0]);
        e.tool = 0.0;
        e.go(true, [x + 20.0, 10.0, 50.0]);
        e.go(true, [x + 20.0, 10.0, 50.0]);
    }
    e.tool = 100.0;
    e.go(true, [0.0, 0.0, 50.0]);
    e.go(false, [0.0, 20.0, 50.0]);
    e
}

#[test]
fn tool_length_offset_without_a_move_is_applied_by_the_next_move() {
    let expected = tool_offset_alone_expansion();
    check("tool_offset_alone", "vmc3", "vmc3", TOOL_OFFSET_ALONE, &expected, 1);
    // rs274 on the rewriting (inch machine units: the tool table and G54 in inch)
    let Some(rs) = super::common::rs274::rs274() else { return };
    let dir = tempfile::tempdir().unwrap();
    let inch = |mm: f64| format!("{:.12}", mm / 25.4);
    let tools = format!("T1 P1 Z{}\nT2 P2 Z{}\n", inch(100.0), inch(120.0));
    let parameters = format!("5223\t{}\n", inch(G54_Z));
    let ngc = super::common::fanuc_to_ngc::translate(TOOL_OFFSET_ALONE).expect("rewritten as RS274/NGC");
    std::fs::write(dir.path().join("tools.tbl"), &tools).unwrap();
    std::fs::write(dir.path().join("original.ngc"), &ngc).unwrap();
    let original = rs.run_with(dir.path(), "original.ngc", Some("tools.tbl"), Some(&parameters)).unwrap_or_else(|e| panic!("{e}\n{ngc}"));
    assert_eq!(original.len(), expected.moves.len(), "{original:#?}\n{ngc}");
    for (i, (o, x)) in original.iter().zip(&expected.moves).enumerate() {
        let off = o.end.iter().zip(&x.end).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(off < 1e-6 && (o.tool[2] - x.tool[2]).abs() < 1e-6, "move {}: rs274 {o:?}, expected {x:?}\n{ngc}", i + 1);
    }
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let errors = ErrorModel::load("../../examples/errors/vmc3.toml", &m).unwrap();
    let mut options = NcOptions::new(&m);
    options.setup.machine_inch = true;
    options.setup.tools = ToolTable::parse(&tools, "tools").unwrap();
    options.setup.set_work_offset(&trueaxis::compensate::nc::machine_axes(&m), 1, &[0.0, 0.0, G54_Z]);
    let r = correct_program(&Corrector::new(&m, &errors), TOOL_OFFSET_ALONE, "alone.nc", &options, &[]).unwrap();
    let corrected_ngc = super::common::fanuc_to_ngc::translate(&r.text()).expect("the corrected program rewritten");
    std::fs::write(dir.path().join("corrected.ngc"), &corrected_ngc).unwrap();
    let corrected = rs.run_with(dir.path(), "corrected.ngc", Some("tools.tbl"), Some(&parameters)).unwrap();
    // every rapid after a G43/G49 line is written, with the Z the new offset gives (moves of zero
    // length elsewhere may be left out: the oracle allows it)
    let text = r.text();
    let lines: Vec<&str> = text.lines().collect();
    let after: Vec<&str> = lines.windows(2).filter(|w| w[0].starts_with("G43") || w[0] == "G49").map(|w| w[1]).collect();
    assert_eq!(after.len(), 5, "{text}");
    assert!(after.iter().all(|l| l.starts_with("G0 X") && l.contains(" Z")), "{text}");
    let oracle = Oracle { machine: &m, errors: &errors, temperatures: vec![] };
    let report = oracle
        .compare_with(&original, &corrected, &[0.0, 0.0, 0.0], TOLERANCE_UM, 1.0 + TOLERANCE_UM, &[], &[])
        .unwrap_or_else(|err| panic!("{err}\n{}", r.text()));
    println!("tool_offset_alone through rs274: {} moves, ends within {:.3} um", report.moves, report.worst_end_um);
}
