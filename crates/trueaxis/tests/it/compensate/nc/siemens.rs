//! The SINUMERIK 840D's own language (SINUMERIK 840D sl Programming Manual Fundamentals) on a
//! program written as shop programs for the 840D are written (`%_N_..._MPF` and `;$PATH=` header,
//! `MSG`, R parameters with arithmetic, `X=` values, `CR=` arcs of both signs and `I J` arcs,
//! `TRANS`/`ATRANS`/`TRANS`, `T1 D1`/`M6`, `G0 SUPA Z0 D0`), checked against its moves written
//! here from the manual: the `CR=` centres from the closed form (the centre on the left of the
//! chord for G3 and a positive CR, on the right for a negative one, at sqrt(CR^2 - c^2/4) from
//! the chord's middle), `TRANS` a shift of the program zero, `ATRANS` added to it. trueaxis reads
//! the program as those moves (1e-9 mm); the corrected program, read back, pushed through the
//! erroneous machine, lands on them within half the written increment (4 decimals: 0.1 um, each
//! axis within 0.05 um) and is written in the 840D's language (the header in `;` comments after
//! the file header, `CR=` arcs whose ends move rewritten with `I J`).

use super::common::oracle::Oracle;
use super::common::rs274::Kind;
use super::common::siemens_to_ngc::siemens_to_ngc;
use super::fanuc::{homes, read, Expansion, G54_Z, START_Z};
use trueaxis::compensate::nc::{correct_program, Controller, NcOptions, ToolTable};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// 4 decimals: each linear axis within half the 0.1 um increment, plus the solve (0.01 um).
const TOLERANCE_UM: f64 = 0.0866 + 0.01;

const PLATE: &str = "\
%_N_PLATE_MPF
;$PATH=/_N_WKS_DIR/_N_PLATE_WPD
; PLATE 1 - hand-written
N10 G17 G90 G40 G71 G94
N20 MSG(\"PLATE 1 (POCKET)\")
N30 T1 D1
N40 M6
N50 G54
N60 R1=40 R2=25 R3=-2.5
N70 R4=R1/2+SQRT(POT(3)+POT(4))-2*3 ; 19
N80 S3000 M3
N90 TRANS X10 Y5
N100 G0 X0 Y0 Z5
N110 G1 Z=R3 F=200
N120 X=R1 Y0
N130 G3 X=R1+10 Y10 CR=10
N140 G1 Y=R2
N150 G3 X40 Y=R2+10 I-10 J0
N160 G3 X30 Y45 CR=-10 ; over 180 degrees
N170 G2 X=R4+1 Y=R4+25 CR=10
N180 ATRANS X5 Y-5
N190 ATRANS Y2
N200 G1 X0 Y0
N210 G0 Z50
N220 TRANS
N230 G0 SUPA Z0 D0
N240 M30
";

/// PLATE's moves, from the manual: program zero at G54 + TRANS, the tool T1 100 mm long.
fn plate_expansion() -> Expansion {
    let mut e = Expansion::new();
    e.tool = 100.0;
    let t = |x: f64, y: f64, z: f64| [x + 10.0, y + 5.0, z];
    e.go(true, t(0.0, 0.0, 5.0));
    e.go(false, t(0.0, 0.0, -2.5));
    e.go(false, t(40.0, 0.0, -2.5));
    // G3 CR=10 from (40,0) to (50,10): centre (40,10), on the left of the chord
    e.arc(t(50.0, 10.0, -2.5), [50.0, 15.0], 1);
    e.go(false, t(50.0, 25.0, -2.5));
    e.arc(t(40.0, 35.0, -2.5), [50.0, 30.0], 1);
    // G3 CR=-10 from (40,35) to (30,45): the arc over 180 degrees, centre (40,45) on the right
    e.arc(t(30.0, 45.0, -2.5), [50.0, 50.0], 1);
    // G2 CR=10 from (30,45) to (20,44): the centre on the right of the chord
    let (s, f): ([f64; 2], [f64; 2]) = ([30.0, 45.0], [20.0, 44.0]);
    let (mx, my, dx, dy) = ((s[0] + f[0]) / 2.0, (s[1] + f[1]) / 2.0, f[0] - s[0], f[1] - s[1]);
    let c = (dx * dx + dy * dy).sqrt();
    let h = (100.0 - c * c / 4.0).sqrt();
    e.arc(t(20.0, 44.0, -2.5), [mx + h * dy / c + 10.0, my - h * dx / c + 5.0], -1);
    // ATRANS X5 Y-5, ATRANS Y2: the zero at (15, 2) from TRANS's
    e.go(false, t(5.0, -3.0, -2.5));
    e.go(true, t(5.0, -3.0, 50.0));
    // SUPA Z0 D0: machine Z 0, no tool length
    let last = e.moves.last().unwrap().end;
    e.tool = 0.0;
    e.machine([last[0], last[1], 0.0]);
    e
}

/// The same kind of move; arcs the same way round the same centre (1e-9 mm).
fn same_kind(a: &Kind, b: &Kind) -> bool {
    match (a, b) {
        (Kind::Arc { centre: c, turns: t, .. }, Kind::Arc { centre: d, turns: u, .. }) => {
            t == u && (c[0] - d[0]).abs() < 1e-9 && (c[1] - d[1]).abs() < 1e-9
        }
        (a, b) => a == b,
    }
}

fn options(m: &Machine) -> NcOptions {
    let mut options = NcOptions::new(m);
    options.setup.tools = ToolTable::parse("T1 Z100\nT2 Z120\n", "tools").unwrap();
    let mut offset = vec![0.0; m.axis_count()];
    offset[2] = G54_Z;
    options.setup.set_work_offset(&trueaxis::compensate::nc::machine_axes(m), 1, &offset);
    options.setup.start[2] = START_Z;
    options
}

/// Reads `text` (as the expansion, 1e-9 mm), corrects it, reads the correction back through the
/// erroneous machine (half the written increment); the corrected text.
fn check(name: &str, text: &str, expected: &Expansion) -> String {
    check_in(name, text, expected, &[])
}

/// [`check`] with subprogram files looked for in `search`.
fn check_in(name: &str, text: &str, expected: &Expansion, search: &[std::path::PathBuf]) -> String {
    check_with(name, text, expected, search, false)
}

/// [`check_in`], the canned cycles expanded with `expand_cycles`.
fn check_with(name: &str, text: &str, expected: &Expansion, search: &[std::path::PathBuf], expand_cycles: bool) -> String {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load("../../examples/errors/vmc3.toml", &m).unwrap();
    let mut options = options(&m);
    options.setup.expand_cycles = expand_cycles;
    options.setup.search_path = trueaxis::compensate::nc::SearchPath(search.to_vec());
    let id = |name: &str| trueaxis::compensate::nc::FileId::of(name, name.as_bytes());
    options.header = Some(trueaxis::compensate::nc::Header { machine: id("vmc3.toml"), errors: id("vmc3 errors") });
    let original = read(&m, text, &options);
    assert_eq!(original.len(), expected.moves.len(), "{name}: {original:#?}");
    for (i, (o, x)) in original.iter().zip(&expected.moves).enumerate() {
        let same = o.end.iter().zip(&x.end).all(|(a, b)| (a - b).abs() < 1e-9) && o.tool == x.tool && same_kind(&o.kind, &x.kind);
        assert!(same, "{name}: move {}: read {o:?}, expected {x:?}", i + 1);
    }
    let corrector = Corrector::new(&m, &e);
    let r = correct_program(&corrector, text, name, &options, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
    let corrected_text = r.text();
    assert_eq!(r.dialect, Controller::Siemens);
    // the file header first, the trueaxis header after it in `;` comments
    let lines: Vec<&str> = corrected_text.lines().collect();
    assert!(lines[0].starts_with("%_N_") && lines[1].starts_with(";$PATH=/_N_WKS_DIR/"), "{name}: {corrected_text}");
    assert!(lines[2].starts_with(";trueaxis ") && lines[5].starts_with(";trueaxis dialect siemens"), "{name}: {corrected_text}");
    let corrected = read(&m, &corrected_text, &options);
    let oracle = Oracle { machine: &m, errors: &e, temperatures: vec![] };
    let mut start = vec![0.0; m.axis_count()];
    start[2] = START_Z;
    // the holes kept as cycles: bottom exact, R exact along Z, the rest within what is reported
    let slack = super::common::hole_slack(&trueaxis::compensate::nc::program_moves(&m, text, name, &options).unwrap(), &r.holes);
    let report = oracle
        .compare_with(&expected.moves, &corrected, &start, TOLERANCE_UM, 1.0 + TOLERANCE_UM, &homes(&m, text, &options), &slack)
        .unwrap_or_else(|err| panic!("{name}: {err}\n{corrected_text}"));
    println!(
        "{name}: {} moves, {} pieces, ends within {:.4} um, path within {:.3} um\n{corrected_text}",
        report.moves, report.pieces, report.worst_end_um, report.worst_path_um
    );
    assert!(r.changed_lines >= 5);
    corrected_text.to_string()
}

#[test]
fn a_hand_written_840d_program_is_read_and_corrected_in_its_language() {
    let text = check("plate.mpf", PLATE, &plate_expansion());
    assert!(text.contains("N20 MSG(\"PLATE 1 (POCKET)\")\n") && text.contains("N70 R4=R1/2+SQRT(POT(3)+POT(4))-2*3 ; 19\n"));
    // CR= arcs whose ends move are written with their centres
    assert!(!text.contains("CR=10\n") && text.contains("CR=-10 ; over 180") == text.contains("N160 G3 X30 Y45 "), "{text}");
    for l in text.lines().filter(|l| !l.starts_with(';') && !l.contains("MSG(")) {
        assert!(!l.contains('(') || l.contains("POT("), "a parenthesis outside a comment or an expression: {l}");
    }
}

/// Drilling as the 840D's cycles do it: `MCALL CYCLE81` over three positions, a direct
/// `CYCLE82` whose DPR counts over its DP.
const DRILL: &str = "\
%_N_DRILL_MPF
;$PATH=/_N_WKS_DIR/_N_DRILL_WPD
N10 G17 G90 G40 G71 G94
N20 T2 D1
N30 M6
N40 G54 S2000 M3
N50 G0 X20 Y20 Z15
N60 F150
N70 MCALL CYCLE81(15, 0, 2, -12) ; holes
N80 X20 Y20
N90 X40
N100 Y40
N110 MCALL
N120 G0 X60 Y60
N130 CYCLE82(15, 0, 2, -30, 8, 0.5)
N140 G0 Z50
N150 M30
";

/// DRILL's moves from the manual's sequence: G0 to RFP + SDIS, G1 to the depth, G0 to RTP.
fn drill_expansion() -> Expansion {
    let mut e = Expansion::new();
    e.tool = 120.0;
    let hole = |e: &mut Expansion, x: f64, y: f64, depth: f64| {
        e.go(true, [x, y, 2.0]);
        e.go(false, [x, y, depth]);
        e.go(true, [x, y, 15.0]);
    };
    e.go(true, [20.0, 20.0, 15.0]);
    e.go(true, [20.0, 20.0, 15.0]);
    hole(&mut e, 20.0, 20.0, -12.0);
    e.go(true, [40.0, 20.0, 15.0]);
    hole(&mut e, 40.0, 20.0, -12.0);
    e.go(true, [40.0, 40.0, 15.0]);
    hole(&mut e, 40.0, 40.0, -12.0);
    e.go(true, [60.0, 60.0, 15.0]);
    hole(&mut e, 60.0, 60.0, -8.0);
    e.go(true, [60.0, 60.0, 50.0]);
    e
}

#[test]
fn drilling_cycles_expanded_with_expand_cycles_become_corrected_moves() {
    let text = check_with("drill.mpf", DRILL, &drill_expansion(), &[], true);
    // the calls are taken out (the SINUMERIK would drill again at the corrected moves)
    assert!(!text.contains("CYCLE8") && text.contains("\nN70 ; holes\n") && text.contains("\nG4 F0.5\n"), "{text}");
}

#[test]
fn g70_is_inch_and_g71_mm() {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let mut options = options(&m);
    options.dialect = Some(Controller::Siemens);
    let moves = read(&m, "N10 G17 G90 G70\nN20 G0 X1 Y2\nN30 G710 G1 X1 F100\nN40 G700 Y1\nN50 M30\n", &options);
    let xy: Vec<[f64; 2]> = moves.iter().map(|c| [c.end[0], c.end[1]]).collect();
    for (got, want) in xy.iter().zip([[25.4, 50.8], [1.0, 50.8], [1.0, 25.4]]) {
        assert!((got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9, "{xy:?}");
    }
    assert_eq!(xy.len(), 3);
}

/// Subprograms (Fundamentals, "Subprogram technique"): `L10 P3` runs the file L10.SPF three
/// times with the R parameters shared (R1 grows by R2 at each pass), `SLOT2` calls SLOT2.SPF by
/// its name (`PROC SLOT2` ... `RET`), `CALL "L10"` once more; M17 and RET return.
const GROOVES: &str = "\
%_N_GROOVES_MPF
;$PATH=/_N_WKS_DIR/_N_GROOVES_WPD
N10 G17 G90 G40 G71 G94
N20 T1 D1 M6
N40 G54 S3000 M3
N50 R1=0 R2=10
N60 G0 X0 Y0 Z5
N70 L10 P3 ; three grooves
N80 SLOT2
N90 CALL \"L10\"
N100 G0 Z50
N110 M30
";

const L10: &str = "%_N_L10_SPF\n;$PATH=/_N_SPF_DIR\nN10 R1=R1+R2\nN20 G0 X=R1 Y0\nN30 G1 Z-1 F200\nN40 G1 Y20\nN50 G0 Z5\nN60 M17\n";
const SLOT2: &str = "PROC SLOT2 ; by name\nN10 G0 X50 Y0\nN20 G1 Z-2 F150\nN30 G3 X60 Y10 CR=10\nN40 G0 Z5\nN50 RET\n";

/// GROOVES's moves: grooves at X 10, 20, 30 (and 40 after the CALL), the slot's G3 CR=10 from
/// (50, 0) to (60, 10) round (50, 10), on the left of the chord at sqrt(100 - 200/4) from its middle.
fn grooves_expansion() -> Expansion {
    let mut e = Expansion::new();
    e.tool = 100.0;
    let groove = |e: &mut Expansion, x: f64| {
        e.go(true, [x, 0.0, 5.0]);
        e.go(false, [x, 0.0, -1.0]);
        e.go(false, [x, 20.0, -1.0]);
        e.go(true, [x, 20.0, 5.0]);
    };
    e.go(true, [0.0, 0.0, 5.0]);
    for x in [10.0, 20.0, 30.0] {
        groove(&mut e, x);
    }
    e.go(true, [50.0, 0.0, 5.0]);
    e.go(false, [50.0, 0.0, -2.0]);
    e.arc([60.0, 10.0, -2.0], [50.0, 10.0], 1);
    e.go(true, [60.0, 10.0, 5.0]);
    groove(&mut e, 40.0);
    e.go(true, [40.0, 20.0, 50.0]);
    e
}

#[test]
fn subprogram_files_called_by_number_with_passes_and_by_name_are_expanded() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("L10.SPF"), L10).unwrap();
    std::fs::write(dir.path().join("SLOT2.spf"), SLOT2).unwrap();
    let text = check_in("grooves.mpf", GROOVES, &grooves_expansion(), &[dir.path().to_path_buf()]);
    // the corrected program is one file: the calls are expanded, their ends are not written
    // (an M17 or M30 in the main program would end it), R1 is set as the subprograms left it
    assert!(text.contains(";trueaxis: - line 8, L10, a subprogram file run 3 times\n"), "{text}");
    let blocks: String = text.lines().filter(|l| !l.starts_with(';')).collect::<Vec<_>>().join("\n");
    for gone in ["L10", "SLOT2", "CALL", "M17", "RET", "_SPF", "PROC"] {
        assert!(!blocks.contains(gone), "{gone}: {text}");
    }
    assert!(blocks.contains("\nR1=30\n") && blocks.contains("\nR1=40\n") && !text.contains('#'), "{text}");
    assert_eq!(text.matches("M30").count(), 1, "{text}");
}

#[test]
fn subprogram_calls_that_cannot_run_are_refused_with_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("L20.SPF"), "N10 G1 X5 F100\n").unwrap();
    std::fs::write(dir.path().join("L30.SPF"), "N10 L30\nM17\n").unwrap();
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let mut options = options(&m);
    options.dialect = Some(Controller::Siemens);
    options.setup.search_path = trueaxis::compensate::nc::SearchPath(vec![dir.path().to_path_buf()]);
    for (text, says) in [
        ("N10 G90 G71\nN20 L99\nM30\n", "main.mpf: line 2: subprogram L99 is not a file L99.SPF, L99.spf or _N_L99_SPF on the search path"),
        (
            "N10 G90 G71\nN20 L20 P2\nM30\n",
            "L20.SPF: line 1: the subroutine file ends inside a subroutine (no endsub / M99; SINUMERIK: M17, RET, M2 or M30)",
        ),
        ("N10 G90\nN20 RET\n", "main.mpf: line 2: RET outside a subprogram"),
        ("N10 G90\nN20 L30\nM30\n", "L30.SPF: line 1: more than 10 nested subroutine calls"),
    ] {
        let message = trueaxis::compensate::nc::run_program(&m, text, "main.mpf", &options).expect_err(text).to_string();
        assert!(message.contains(says), "{text}: {message}");
    }
}

/// `X=IC(..)`, `X=AC(..)` (Fundamentals, "Absolute dimensions (G90, AC)", "Incremental
/// dimensions (G91, IC)") and the absolute centre `I=AC(..)`, against the positions worked out by
/// hand: from (10, 10) in G90, `X=IC(5) Y=AC(3)` is (15, 3); in G91 `X=AC(20) Y=IC(1)` is (20, 4);
/// `G2 X30 Y4 I=AC(25) J=AC(4)` in G90 turns round (25, 4), `G3 X20 Y4 I=IC(-5) J0` round (25, 4).
#[test]
fn one_value_in_the_other_distance_mode_and_the_absolute_centre() {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let mut options = options(&m);
    options.dialect = Some(Controller::Siemens);
    let text = "N10 G17 G71 G90 G0 X10 Y10 Z0\nN20 G1 X=IC(5) Y=AC(3) F100\nN30 G91\nN40 X=AC(20) Y=IC(1)\nN50 G90\n\
                N60 G2 X30 Y4 I=AC(25) J=AC(4)\nN70 G3 X20 Y4 I=IC(-5) J0\nN80 M30\n";
    let moves = read(&m, text, &options);
    let xy: Vec<[f64; 2]> = moves.iter().map(|c| [c.end[0], c.end[1]]).collect();
    for (got, want) in xy.iter().zip([[10.0, 10.0], [15.0, 3.0], [20.0, 4.0], [30.0, 4.0], [20.0, 4.0]]) {
        assert!((got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9, "{xy:?}");
    }
    assert_eq!(xy.len(), 5);
    for c in &moves[3..] {
        let Kind::Arc { centre, .. } = c.kind else { panic!("an arc: {c:?}") };
        assert!((centre[0] - 25.0).abs() < 1e-9 && (centre[1] - 4.0).abs() < 1e-9, "{c:?}");
    }
}

/// Values in the other distance mode and absolute centres in a program to correct.
const VALUES: &str = "%_N_VALUES_MPF\n;$PATH=/_N_WKS_DIR/_N_VALUES_WPD\nN10 G17 G71 G90\nN20 T1 D1 M6\nN30 G0 X10 Y10 Z5\n\
                      N40 G1 X=IC(5) Y=AC(3) F100\nN50 G91\nN60 X=AC(20) Y=IC(1)\nN70 G90\nN80 G2 X30 Y4 I=AC(25) J=AC(4)\n\
                      N90 G3 X20 Y4 I=IC(-5) J0\nN100 G0 Z50\nN110 M30\n";

#[test]
fn values_in_the_other_distance_mode_are_corrected() {
    let text = VALUES;
    let mut e = Expansion::new();
    e.tool = 100.0;
    e.go(true, [10.0, 10.0, 5.0]);
    e.go(false, [15.0, 3.0, 5.0]);
    e.go(false, [20.0, 4.0, 5.0]);
    e.arc([30.0, 4.0, 5.0], [25.0, 4.0], -1);
    e.arc([20.0, 4.0, 5.0], [25.0, 4.0], 1);
    e.go(true, [20.0, 4.0, 50.0]);
    let corrected = check("values.mpf", text, &e);
    // a value counted from the current position is not kept as text: the correction moves it
    assert!(!corrected.contains("IC(") && !corrected.contains("AC("), "{corrected}");
}

/// The rs274 reading of the RS274/NGC rewriting of `text` ([`siemens_to_ngc`], `files` its
/// subprogram files) beside the library's reading, for a machine with `tools` (mm) and the G54 Z
/// offset of [`options`]: the same moves, ends and arc centres within 1e-6 mm, the same tool
/// offsets; the largest difference (mm).
fn rs274_reads_the_same(
    name: &str,
    text: &str,
    files: &[(&str, String)],
    m: &Machine,
    options: &NcOptions,
    tools: &str,
    g54_z: f64,
) -> Option<f64> {
    let rs = super::common::rs274::rs274()?;
    let ngc = siemens_to_ngc(text, files).unwrap_or_else(|| panic!("{name}: not rewritten"));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("p.ngc"), &ngc).unwrap();
    std::fs::write(dir.path().join("tools.tbl"), tools).unwrap();
    let params = format!("5221 0\n5222 0\n5223 {}\n", g54_z / 25.4);
    let seen = rs.run_with(dir.path(), "p.ngc", Some("tools.tbl"), Some(&params)).unwrap_or_else(|e| panic!("{name}: {e}\n{ngc}"));
    let read = read(m, text, options);
    assert_eq!(seen.len(), read.len(), "{name}: rs274 {seen:#?}\nlibrary {read:#?}\n{ngc}");
    let mut worst = 0.0f64;
    for (i, (a, b)) in seen.iter().zip(&read).enumerate() {
        let d = a.end.iter().zip(&b.end).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        let centre = match (&a.kind, &b.kind) {
            (Kind::Arc { centre: c, turns: t, .. }, Kind::Arc { centre: e, turns: u, .. }) if t == u => {
                (c[0] - e[0]).abs().max((c[1] - e[1]).abs())
            }
            (x, y) if x == y => 0.0,
            _ => f64::INFINITY,
        };
        let tool = (a.tool[2] - b.tool[2]).abs();
        worst = worst.max(d).max(centre).max(tool);
        assert!(d.max(centre).max(tool) < 1e-6, "{name}: move {}: rs274 {a:?}, library {b:?}\n{ngc}", i + 1);
    }
    Some(worst)
}

/// The hand-written programs above read by LinuxCNC's rs274 through their RS274/NGC rewriting
/// ([`siemens_to_ngc`], written from the Fundamentals and LinuxCNC's G-code manual, not from the
/// library's reader): the same moves as the library reads them, ends, arc centres and tool
/// lengths within 1e-6 mm (rs274 prints 10 decimals with the test's shim), on the tests' G54 and
/// tools (rs274's table in inch).
#[test]
fn rs274_reads_the_rewritten_programs_as_the_library_does() {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let mut options = options(&m);
    options.dialect = Some(Controller::Siemens);
    let files = vec![("L10.SPF", L10.to_string()), ("SLOT2.spf", SLOT2.to_string())];
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in &files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    options.setup.search_path = trueaxis::compensate::nc::SearchPath(vec![dir.path().to_path_buf()]);
    let tools = format!("T1 P1 Z{}\nT2 P2 Z{}\n", 100.0 / 25.4, 120.0 / 25.4);
    for (name, text) in [("plate.mpf", PLATE), ("drill.mpf", DRILL), ("grooves.mpf", GROOVES), ("values.mpf", VALUES)] {
        let Some(worst) = rs274_reads_the_same(name, text, &files, &m, &options, &tools, G54_Z) else { return };
        println!("{name}: rs274 reads the rewriting as the library reads the program, within {worst:.1e} mm");
    }
}

/// Arcs by their opening angle (Fundamentals, "Circular interpolation with opening angle and
/// center point / end point"): `AR=` with the end point (a quarter G3, a G2 of 270 degrees, an
/// angle from an R parameter), and with the centre `I J` (a helical half circle, a third of a turn).
const ARCS: &str = "\
%_N_ARCS_MPF
;$PATH=/_N_WKS_DIR/_N_ARCS_WPD
N10 G17 G90 G40 G71 G94
N20 T1 D1 M6
N30 G54 S2000 M3
N40 G0 X20 Y0 Z5
N50 G1 Z-1 F300
N60 G3 X40 Y20 AR=90 ; quarter
N70 G2 X60 Y20 AR=270
N80 G3 I-10 J0 AR=180 Z-2 ; centre and angle
N90 R1=30
N100 G3 X25 Y40 AR=R1*2
N110 G2 I0 J-10 AR=120
N120 G0 Z50
N130 M30
";

/// The centre of the arc that turns `start` into `end` through `degrees` (positive
/// counterclockwise): the fixed point of the rotation, (I - R) c = end - R start, a formulation
/// apart from the chord-and-angle one trueaxis uses.
fn rotation_centre(start: [f64; 2], end: [f64; 2], degrees: f64) -> [f64; 2] {
    let (s, c) = degrees.to_radians().sin_cos();
    // R start
    let rs = [c * start[0] - s * start[1], s * start[0] + c * start[1]];
    let rhs = [end[0] - rs[0], end[1] - rs[1]];
    // I - R = [[1 - c, s], [-s, 1 - c]], determinant (1 - c)^2 + s^2
    let det = (1.0 - c).powi(2) + s * s;
    [((1.0 - c) * rhs[0] - s * rhs[1]) / det, (s * rhs[0] + (1.0 - c) * rhs[1]) / det]
}

fn arcs_expansion() -> Expansion {
    let mut e = Expansion::new();
    e.tool = 100.0;
    e.go(true, [20.0, 0.0, 5.0]);
    e.go(false, [20.0, 0.0, -1.0]);
    e.arc([40.0, 20.0, -1.0], rotation_centre([20.0, 0.0], [40.0, 20.0], 90.0), 1);
    e.arc([60.0, 20.0, -1.0], rotation_centre([40.0, 20.0], [60.0, 20.0], -270.0), -1);
    // about (50, 20), half a turn: back to (40, 20), Z down 1 mm on the way
    e.arc([40.0, 20.0, -2.0], [50.0, 20.0], 1);
    e.arc([25.0, 40.0, -2.0], rotation_centre([40.0, 20.0], [25.0, 40.0], 60.0), 1);
    // about (25, 30) clockwise 120 degrees from (25, 40): the end at angle 90 - 120 = -30 degrees
    let t = (-30.0f64).to_radians();
    e.arc([25.0 + 10.0 * t.cos(), 30.0 + 10.0 * t.sin(), -2.0], [25.0, 30.0], -1);
    let last = e.moves.last().unwrap().end;
    e.go(true, [last[0], last[1], 50.0]);
    e
}

#[test]
fn ar_arcs_have_the_centres_of_the_closed_form_and_land() {
    // the closed form's numbers: the quarter's centre (20, 20), the 270-degree G2's (50, 30)
    let q = rotation_centre([20.0, 0.0], [40.0, 20.0], 90.0);
    assert!((q[0] - 20.0).abs() < 1e-12 && (q[1] - 20.0).abs() < 1e-12, "{q:?}");
    let g2 = rotation_centre([40.0, 20.0], [60.0, 20.0], -270.0);
    assert!((g2[0] - 50.0).abs() < 1e-12 && (g2[1] - 30.0).abs() < 1e-12, "{g2:?}");
    let text = check("arcs.mpf", ARCS, &arcs_expansion());
    // an arc to an end point whose ends move is written with its centre; one about a centre as
    // its move (G2/G3 X Y I J)
    let line = |n: &str| text.lines().find(|l| l.starts_with(n)).unwrap_or_else(|| panic!("{n}: {text}")).to_string();
    assert!(line("N60 ").contains(" I") && !line("N60 ").contains("AR=") && line("N60 ").ends_with("; quarter"), "{text}");
    assert!(!text.contains("AR=180") && !text.contains("AR=120"), "{text}");
    assert!(
        text.contains(";trueaxis: - line 13, SINUMERIK arc by its centre and opening angle AR=, written with its end point\n"),
        "{text}"
    );
    assert!(text.contains("N90 R1=30\n"), "{text}");
}

/// Control structures and local variables (Job Planning, "Flexible NC programming"): DEF
/// variables of the three types, a FOR loop over three grooves, a WHILE loop, IF-ELSE-ENDIF on a
/// BOOL, a LOOP left by a conditional GOTOF to a label on a block with a move, an INT that rounds
/// what it is given (0 + 1.4 is 1, 1 + 1.4 is 2, ...), REPEAT-UNTIL, a GOTOF over a block.
const FLOW: &str = "\
%_N_FLOW_MPF
;$PATH=/_N_WKS_DIR/_N_FLOW_WPD
DEF INT PASS=0, HOLES
DEF REAL DEPTH=-1.5, STEP=10 ; mm
DEF BOOL DEEP=FALSE
N10 G17 G90 G40 G71 G94
N20 T1 D1 M6
N30 G54 S3000 M3
N40 G0 X0 Y0 Z5
N50 FOR PASS=1 TO 3 ; three grooves
N60 G0 X=PASS*STEP Y0
N70 G1 Z=DEPTH F200
N80 G1 Y20
N90 G0 Z5
N100 ENDFOR
N110 R1=0
N120 WHILE R1 < 30
N130 R1=R1+12.5
N140 G1 X40 Y=R1 F300
N150 ENDWHILE
N160 IF DEEP
N170 G1 Z-5
N180 ELSE
N190 G1 Z=DEPTH*2
N200 ENDIF
N210 HOLES=0
N220 LOOP
N230 HOLES=HOLES+1.4
N240 G0 X=50+HOLES*5 Y10
N250 IF HOLES >= 3 GOTOF DONE
N260 ENDLOOP
N270 DONE: G0 Z20
N280 REPEAT
N290 R2=R2+1
N300 G1 X60 Y=R2*5 F100
N310 UNTIL (R2 == 2) OR (R2 > 5)
N320 GOTOF N340
N330 G0 X0 Y0 ; skipped
N340 G0 Z50
N350 M30
";

/// FLOW's moves, worked out by hand from the manual's rules.
fn flow_expansion() -> Expansion {
    let mut e = Expansion::new();
    e.tool = 100.0;
    e.go(true, [0.0, 0.0, 5.0]);
    for pass in 1..=3 {
        let x = 10.0 * f64::from(pass);
        e.go(true, [x, 0.0, 5.0]);
        e.go(false, [x, 0.0, -1.5]);
        e.go(false, [x, 20.0, -1.5]);
        e.go(true, [x, 20.0, 5.0]);
    }
    for y in [12.5, 25.0, 37.5] {
        e.go(false, [40.0, y, 5.0]);
    }
    // DEEP is FALSE: the ELSE branch, Z at twice DEPTH
    e.go(false, [40.0, 37.5, -3.0]);
    // HOLES 1, 2, 3 (the INT rounds 1.4, 2.4, 3.4), then the jump out at 3
    for holes in [1.0, 2.0, 3.0] {
        e.go(true, [50.0 + holes * 5.0, 10.0, -3.0]);
    }
    e.go(true, [65.0, 10.0, 20.0]);
    e.go(false, [60.0, 5.0, 20.0]);
    e.go(false, [60.0, 10.0, 20.0]);
    e.go(true, [60.0, 10.0, 50.0]);
    e
}

#[test]
fn jumps_loops_if_and_def_variables_run_as_the_manual_says_and_land() {
    let text = check("flow.mpf", FLOW, &flow_expansion());
    // the loops run more than once: expanded, the variables they leave set written after them
    // in the 840D's spelling; the IF ran once: kept, its ELSE branch corrected in place
    for note in ["lines 10-15, FOR loop", "lines 17-20, WHILE loop", "lines 27-31, LOOP: its blocks", "lines 33-36, REPEAT loop"] {
        assert!(text.contains(note), "{note}: {text}");
    }
    assert!(
        text.contains("\nPASS=4\n") && text.contains("\nR1=37.5\n") && text.contains("\nHOLES=3\n") && text.contains("\nR2=2\n"),
        "{text}"
    );
    assert!(
        text.contains("\nDEF INT PASS=0, HOLES\n") && text.contains("\nN160 IF DEEP\nN170 G1 Z-5\nN180 ELSE\nN190 G1 Z=-3.00"),
        "{text}"
    );
    assert!(text.contains("\nN320 GOTOF N340\nN330 G0 X0 Y0 ; skipped\n"), "{text}");
}

/// A backward conditional jump as shop programs write spirals (`IF R2<360 GOTOB METKA1`): the
/// whole program is expanded (the correction differs at each pass).
const SPIRAL: &str = "\
%_N_SPIRAL_MPF
;$PATH=/_N_WKS_DIR/_N_SPIRAL_WPD
N10 G17 G90 G71 T1 D1 M6
N20 G54 G0 X0 Y0 Z5
N30 R2=0
N40 METKA1:
N50 R2=R2+90
N60 G1 X=10*COS(R2) Y=10*SIN(R2) Z=-R2/90 F250
N70 IF R2<360 GOTOB METKA1
N80 G0 Z50
N90 M30
";

#[test]
fn a_backward_jump_expands_the_program_and_lands() {
    let mut e = Expansion::new();
    e.tool = 100.0;
    e.go(true, [0.0, 0.0, 5.0]);
    for (k, angle) in [90.0f64, 180.0, 270.0, 360.0].into_iter().enumerate() {
        let a = angle.to_radians();
        e.go(false, [10.0 * a.cos(), 10.0 * a.sin(), -(k as f64) - 1.0]);
    }
    e.go(true, [10.0, 0.0, 50.0]);
    let text = check("spiral.mpf", SPIRAL, &e);
    assert!(text.contains("the whole program: the program jumps backwards") && !text.contains("GOTOB"), "{text}");
}

/// What the 840D refuses, or trueaxis does not read, is refused with the file and line.
#[test]
fn flow_that_cannot_run_is_refused_with_the_line() {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load("../../examples/errors/vmc3.toml", &m).unwrap();
    let corrector = Corrector::new(&m, &e);
    let mut options = options(&m);
    options.dialect = Some(Controller::Siemens);
    options.setup.max_blocks = 10_000;
    let head = "N10 G17 G90 G71 T1 D1 M6\nN20 G54 G0 X0 Y0 Z5\n";
    for (body, line, says) in [
        ("N30 IF R1==0\nN40 G1 X1 F100\nM30\n", 3, "the IF is never closed (ENDIF)"),
        ("N30 WHILE R1<3\nN40 R1=R1+1\nN50 ENDIF\nM30\n", 5, "ENDIF closes the WHILE of line 3"),
        ("N30 GOTOF NOWHERE\nM30\n", 3, "GOTOF NOWHERE: no block NOWHERE after this block (the 840D stops with alarm 14080)"),
        ("N30 GOTOF INSIDE\nN40 FOR R1=1 TO 2\nINSIDE: G0 X1\nN60 ENDFOR\nM30\n", 3, "a jump into the FOR of lines 4-6"),
        ("N30 G0 X1\nDEF REAL LATE=1\nM30\n", 4, "DEF after the statements of line 1"),
        ("N30 OFFN=2\nM30\n", 3, "OFFN is neither a variable defined by DEF"),
        ("N30 REPEAT START END P=2\nM30\n", 3, "program section repetition"),
        ("N30 LOOP\nN40 R1=R1+1\nN50 ENDLOOP\nM30\n", 5, "an endless loop?"),
    ] {
        let text = format!("{head}{body}");
        let err = correct_program(&corrector, &text, "bad.mpf", &options, &[]).expect_err(&text).to_string();
        assert!(err.contains(&format!("bad.mpf: line {line}: ")) && err.contains(says), "{text}: {err}");
    }
}

/// Deep-hole drilling as the 840D's CYCLE83 does it (Programming Guide Cycles, "Deep-hole
/// drilling, CYCLE83"), in the parameter order Autodesk's 840D post writes (`MCALL CYCLE83(RTP, RFP, SDIS,
/// DP, , FDEP, , DAM, , , FRF, VARI, , _MDEP, _VRT, _DTD, _DIS1)`): chip breaking under `MCALL`
/// over two holes, swarf removal called directly with DPR, FDPR, DTS, `_DTD` and `_DIS1`.
const DEEP: &str = "\
%_N_DEEP_MPF
;$PATH=/_N_WKS_DIR/_N_DEEP_WPD
N10 G17 G90 G40 G71 G94
N20 T2 D1
N30 M6
N40 G54 S1800 M3 F120
N50 G0 X30 Y-20 Z20
N60 MCALL CYCLE83(20, 0, 2, -23, , -6, , 0, , , 1, 0, , 6, 0.8, 0, 0) ; chip breaking
N70 X30 Y-20
N80 X55
N90 MCALL
N100 G0 X80 Y-20
N110 CYCLE83(20, 1, 2, , 17, , 5, 0, 0, 0.3, 1, 1, , , , 0.5, 0.7) ; swarf removal
N120 G0 Z50
N130 M30
";

/// DEEP's moves worked out from the manual's sequences (program units, mm): chip breaking from
/// RFP 0 with the first infeed FDEP -6, so the drilling depths `d_k = -6 k` above DP -23 (-6, -12,
/// -18), each followed by a `G1` back by `_VRT` 0.8, the last infeed to -23, `G0` to RTP 20;
/// swarf removal from RFP 1 with FDPR 5 and DPR 17 (depth 1 - 17 = -16): depths -4, -9, -14, each
/// followed by `G0` out to RFP + SDIS = 3 and `G0` back to the depth plus `_DIS1` 0.7.
fn deep_expansion() -> Expansion {
    let mut e = Expansion::new();
    e.tool = 120.0;
    e.go(true, [30.0, -20.0, 20.0]);
    for x in [30.0, 55.0] {
        e.go(true, [x, -20.0, 20.0]);
        e.go(true, [x, -20.0, 2.0]);
        for k in 1..=3 {
            let d = -6.0 * f64::from(k);
            e.go(false, [x, -20.0, d]);
            e.go(false, [x, -20.0, d + 0.8]);
        }
        e.go(false, [x, -20.0, -23.0]);
        e.go(true, [x, -20.0, 20.0]);
    }
    e.go(true, [80.0, -20.0, 20.0]);
    e.go(true, [80.0, -20.0, 3.0]);
    for k in 1..=3 {
        let d = 1.0 - 5.0 * f64::from(k);
        e.go(false, [80.0, -20.0, d]);
        e.go(true, [80.0, -20.0, 3.0]);
        e.go(true, [80.0, -20.0, d + 0.7]);
    }
    e.go(false, [80.0, -20.0, -16.0]);
    e.go(true, [80.0, -20.0, 20.0]);
    e.go(true, [80.0, -20.0, 50.0]);
    e
}

/// Corrects `text` on vmc3 (its G54 and tools) with the errors of `errors`.
fn correct_on(text: &str, errors: &str, expand_cycles: bool) -> trueaxis::compensate::nc::NcResult {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let e = match errors {
        "zero" => ErrorModel::zero(&m),
        name => ErrorModel::load(format!("../../examples/errors/{name}.toml"), &m).unwrap(),
    };
    let mut options = options(&m);
    options.setup.expand_cycles = expand_cycles;
    correct_program(&Corrector::new(&m, &e), text, "holes.mpf", &options, &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// Each kept hole's lean, computed independently of the writer: the corrected program read back,
/// the erroneous machine's landing of the move nearest the original R point (RFP + SDIS at the
/// hole), its distance across Z from that point; along Z it lands within half the increment.
fn assert_leans(text: &str, r: &trueaxis::compensate::nc::NcResult) -> f64 {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let e = ErrorModel::load("../../examples/errors/vmc3.toml", &m).unwrap();
    let options = options(&m);
    let (original, corrected) = (read(&m, text, &options), read(&m, &r.text(), &options));
    let oracle = Oracle { machine: &m, errors: &e, temperatures: vec![] };
    let mut worst: f64 = 0.0;
    for h in &r.holes {
        let (target, _) = oracle.landing(&original[h.r_move as usize]).unwrap();
        let land =
            corrected.iter().map(|c| (oracle.landing(c).unwrap().1 - target) * 1e3).min_by(|a, b| a.norm().total_cmp(&b.norm())).unwrap();
        let across = land.x.hypot(land.y);
        assert!(land.z.abs() < 0.05 + 0.01, "line {}: R lands {:.4} um off along Z", h.line, land.z);
        assert!((across - h.lean_um).abs() < 0.02, "line {}: lean {:.4} um reported, {across:.4} um landed", h.line, h.lean_um);
        worst = worst.max((across - h.lean_um).abs());
    }
    worst
}

#[test]
fn deep_hole_drilling_is_read_as_the_manual_gives_it() {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let mut options = options(&m);
    options.dialect = Some(Controller::Siemens);
    let moves = read(&m, DEEP, &options);
    let expected = deep_expansion();
    assert_eq!(moves.len(), expected.moves.len(), "{moves:#?}");
    for (i, (o, x)) in moves.iter().zip(&expected.moves).enumerate() {
        assert!(o.end.iter().zip(&x.end).all(|(a, b)| (a - b).abs() < 1e-9) && o.kind == x.kind, "move {}: {o:?} vs {x:?}", i + 1);
    }
    // what is not confirmed from a published source is refused with the line
    for (call, says) in [
        ("CYCLE83(20, 0, 2, -23, , -6, , 2, , , 1, 0)", "degression DAM 2"),
        ("CYCLE83(20, 0, 2, -23, , -6, , 0, , , 1, 1, , , , , 0)", "give _DIS1"),
        ("CYCLE83(20, 0, 2, -23, , , , 0, , , 1, 0)", "without its first drilling depth"),
        ("CYCLE83(20, 0, 2, -23, , -6, , 0, , , 1, 2)", "VARI 2 is neither"),
    ] {
        let text = format!("N10 G17 G90 G71\nN20 T2 D1 M6\nN30 G0 X0 Y0 Z30\nN40 {call}\nN50 M30\n");
        let message = trueaxis::compensate::nc::run_program(&m, &text, "deep.mpf", &options).expect_err(call).to_string();
        assert!(message.contains("deep.mpf: line 4: ") && message.contains(says), "{call}: {message}");
    }
}

#[test]
fn drilling_cycles_stay_cycles_with_their_holes_and_levels_corrected() {
    for (name, text, expected, holes) in [("drill.mpf", DRILL, drill_expansion(), 4), ("deep.mpf", DEEP, deep_expansion(), 3)] {
        let corrected = check(name, text, &expected);
        let r = correct_on(text, "vmc3", false);
        assert_eq!(r.holes.len(), holes, "{name}: {:?}", r.holes);
        assert!(r.expanded.is_empty(), "{name}: {:?}", r.expanded);
        // the original calls stay; where a hole needs other parameters, the modal call is given again
        let blocks: Vec<&str> = corrected.lines().filter(|l| !l.starts_with(';')).collect();
        let first = if name == "drill.mpf" { "N70 MCALL CYCLE81(15, 0, 2, -12) ; holes" } else { "N60 MCALL CYCLE83(20, 0, 2, -23, , -6," };
        assert!(blocks.iter().any(|l| l.starts_with(first)), "{corrected}");
        assert!(blocks.iter().filter(|l| l.starts_with("MCALL CYCLE8")).count() >= 1, "{corrected}");
        assert!(blocks.iter().any(|l| l.starts_with("N90 MCALL") || l.starts_with("N110 MCALL")), "{corrected}");
        // lean and clearance reported per hole, and in the warnings where above 0.1 um
        let worst = assert_leans(text, &r);
        let (lean, clearance) = r.holes.iter().fold((0.0f64, 0.0f64), |(l, c), h| (l.max(h.lean_um), c.max(h.clearance_um)));
        let warned = r.warnings.iter().filter(|w| w.contains(" kept as a cycle")).count();
        assert_eq!(warned, r.holes.iter().filter(|h| h.lean_um.max(h.clearance_um) > 0.1).count(), "{:?}", r.warnings);
        assert!(r.warnings.iter().filter(|w| w.contains(" kept as a cycle")).all(|w| w.contains(": CYCLE8")), "{:?}", r.warnings);
        println!(
            "{name}: {holes} holes kept; lean up to {lean:.3} um (landed within {worst:.4} um of it), clearance up to {clearance:.3} um"
        );
    }
}

#[test]
fn zero_errors_leave_drilling_cycles_byte_for_byte() {
    for (text, holes) in [(DRILL, 4), (DEEP, 3)] {
        let r = correct_on(text, "zero", false);
        assert_eq!(r.text(), text);
        assert_eq!((r.changed_lines, r.inserted_lines, r.expanded.len(), r.holes.len()), (0, 0, 0, holes));
    }
}

#[test]
fn expand_cycles_writes_deep_hole_drilling_as_plain_moves() {
    let text = check_with("deep.mpf", DEEP, &deep_expansion(), &[], true);
    assert!(!text.contains("CYCLE8") && text.contains("\nG4 F0.3\n") && text.contains("\nG4 F0.5\n"), "{text}");
    let r = correct_on(DEEP, "vmc3", true);
    assert!(r.holes.is_empty() && r.expanded.len() == 4, "{:?}", r.expanded);
}
