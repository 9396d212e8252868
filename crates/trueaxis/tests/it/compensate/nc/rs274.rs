//! LinuxCNC's standalone interpreter `rs274 -g` as the independent reader of a corpus of varied
//! programs: parameters and expressions, every O-word construct, subroutines called once and
//! several times, canned cycles in the three planes with G98/G99, L repeats and G91, tool length
//! offsets, G92, G10 L2/L20 with a rotated coordinate system, G28/G30 with stored positions, G53,
//! G52, inch and mm, absolute arc centres, R-format and multi-turn arcs in every plane, polar
//! coordinates, inverse-time feed, M70/M72, a program that reads the current position, the pocket
//! with backlash and a thermal term, and a five-axis program through the C600U's singularity.
//!
//! Each program is run by rs274 before and after correction (with its tool table and parameter
//! file); the canonical moves of the corrected program, pushed through the erroneous machine, must
//! land on those of the original within 0.05 um with the default 5 decimals (6 in inch) and within
//! 0.01 um with one digit more, and every point of the corrected path within the 1 um split
//! tolerance of the original path (the length of the vector of the linear axes; rapids: their ends
//! only). Skipped, with the reason printed, only when rs274 is not installed.

use super::common::oracle::{Oracle, Report};
use super::common::rs274::rs274;
use trueaxis::compensate::nc::{correct_program, program_moves, Dialect, NcOptions, NcResult, SearchPath, ToolTable};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// Tool table (inch, rs274's machine units without an INI file).
const TOOLS: &str = "T1 P1 Z2.0 D0.25 ;drill\nT2 P2 Z3.5 D0.5 ;end mill\nT3 P3 Z1.25 X0.1 D0.125\n";

struct Case<'a> {
    name: &'a str,
    machine: &'a str,
    errors: &'a str,
    temperatures: &'a [f64],
    program: &'a str,
    /// Parameters (number, value in mm or deg) written to the parameter file in inch.
    parameters: &'a [(u32, f64)],
    /// Parts expanded into plain moves.
    expanded: usize,
    /// Text the corrected program keeps (constructs that run once stay as they are).
    keeps: &'a [&'a str],
}

fn machine(name: &str) -> Machine {
    Machine::load(format!("../../examples/machines/{name}.toml")).unwrap()
}

/// The parameter file: lengths in inch (#5161-#5163, #5181-#5183, #5211-#5213 and the X Y Z of the
/// coordinate systems), angles in deg.
fn var_file(parameters: &[(u32, f64)]) -> String {
    let linear = |n: u32| matches!(n, 5161..=5163 | 5181..=5183 | 5211..=5213) || (5221..=5390).contains(&n) && (n - 5201) % 20 <= 2;
    parameters.iter().map(|&(n, v)| format!("{n}\t{:.10}\n", if linear(n) { v / 25.4 } else { v })).collect()
}

/// Corrects a case with `decimals` (None: the default) and checks it with rs274: the result and
/// the comparison.
fn check(case: &Case, decimals: Option<usize>, end_um: f64) -> (NcResult, Report) {
    let rs = rs274().expect("checked by the caller");
    let m = machine(case.machine);
    let e = ErrorModel::load(format!("../../examples/errors/{}.toml", case.errors), &m).unwrap();
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tools.tbl"), TOOLS).unwrap();
    let var = var_file(case.parameters);
    let mut options = NcOptions::new(&m);
    options.dialect = Some(Dialect::LinuxCnc.into());
    options.decimals = decimals;
    options.setup.machine_inch = true;
    options.setup.rs274_tool_change = true;
    options.setup.tools = ToolTable::parse(TOOLS, "tools.tbl").unwrap();
    options.setup.parameters = trueaxis::compensate::nc::params::read_parameter_file(&var, "var").unwrap();
    options.setup.search_path = SearchPath(vec![dir.path().to_path_buf()]);
    options.setup.expand_cycles = case.name.ends_with("_expanded");
    let corrector = Corrector::new(&m, &e);
    let result =
        correct_program(&corrector, case.program, case.name, &options, case.temperatures).unwrap_or_else(|e| panic!("{}: {e}", case.name));
    std::fs::write(dir.path().join("original.ngc"), case.program).unwrap();
    std::fs::write(dir.path().join("corrected.ngc"), &result.program).unwrap();
    let original =
        rs.run_with(dir.path(), "original.ngc", Some("tools.tbl"), Some(&var)).unwrap_or_else(|e| panic!("{}: original: {e}", case.name));
    let corrected = rs
        .run_with(dir.path(), "corrected.ngc", Some("tools.tbl"), Some(&var))
        .unwrap_or_else(|e| panic!("{}: corrected: {e}\n{}", case.name, result.text()));
    let oracle = Oracle { machine: &m, errors: &e, temperatures: case.temperatures.to_vec() };
    // trueaxis reads the same moves as rs274; the returns to the G28/G30 positions stay as they are
    let moves = program_moves(&m, case.program, case.name, &options).unwrap();
    let (count, homes) = super::common::canonical_homes(&m, &moves);
    assert_eq!(count, original.len(), "{}: moves read by trueaxis and by rs274", case.name);
    let report = oracle
        .compare_with(
            &original,
            &corrected,
            &vec![0.0; m.axis_count()],
            end_um,
            1.05,
            &homes,
            &super::common::hole_slack(&moves, &result.holes),
        )
        .unwrap_or_else(|err| panic!("{} ({decimals:?} decimals): {err}\n{}", case.name, result.text()));
    assert_eq!(report.moves, original.len(), "{}", case.name);
    (result, report)
}

const PARAMETERS_AND_LOOPS: &str = "\
G21 G90 G17 G94
#<depth> = 2
#<step> = [#<depth> / 4]
#1 = 0
F800
G0 X0 Y0 Z5
o100 while [#1 LT 4]
  G1 X[10 * #1] Y[5 * SIN[#1 * 30]] Z[-#<step> * #1]
  #1 = [#1 + 1]
o100 endwhile
o101 repeat [3]
  G91 G1 X5 Y-2
o101 endrepeat
G90
#2 = 6
o102 do
  #2 = [#2 - 1]
  o103 if [#2 EQ 2]
    o102 continue
  o103 elseif [[#2 MOD 4] EQ 1 AND #2 GT 4]
    G1 X[ATAN[1]/[1]] Y[2 ** 3]
  o103 else
    G1 X[#2 * 3] Y[FIX[#2 / 2]]
  o103 endif
o102 while [#2 GT 0]
o104 if [EXISTS[#<depth>]]
  G1 X[ROUND[#<depth> * 1.6]] Y[ABS[-4]] (kept: runs once)
o104 endif
G0 Z5
G1 X[#1 + #2 + #<depth>] F500
M2
";

const SUBROUTINES: &str = "\
G21 G90 G17
o<hole> sub
  G0 X#1 Y#2
  G1 Z-3 F200
  G0 Z2
o<hole> endsub
o<once> sub
  #<local> = [#1 * 2]
  G1 X50 Y50 Z-1 F300
  G2 X60 Y40 R10
  G1 Y[#<local>]
o<once> endsub
G0 Z5
o<hole> call [10] [10]
o<hole> call [20] [10]
o<hole> call [30] [15]
o<once> call [12]
G0 Z10
M2
";

const CYCLES: &str = "\
G21 G90 G17 G94
T1 M6 G43 H1
S1000 M3
G0 X0 Y0 Z10
G99 G81 X10 Y10 Z-5 R2 F100
X20
G98 G83 X30 Y10 Z-12 R2 Q3 F80
G73 X40 Z-7 R1 Q2
G82 X50 Z-4 R1 P0.5
G85 X60 Z-4 R1
G86 X70 Z-4 R1 P0.2
G89 X80 Z-4 R1 P0.2
G99 G84 X90 Z-6 R1 P0.3
X95
G91 G81 X5 Y3 Z-4 R-8 L3
G90 G80
G0 X0 Y-20 Z10
G18 G81 X10 Z5 Y-25 R-15 F100
G80
G19 G0 X10 Y0 Z0
G81 Y10 Z5 X2 R8
G17 G80
M5
G0 Z20
M2
";

const OFFSETS: &str = "\
G21 G90 G17
G0 X0 Y0 Z20
G10 L2 P2 X10 Y20 Z-150 R30
G55 G0 X5 Y5 Z10
G1 X20 Y0 F300
G2 X30 Y10 I5 J5
G92 X0 Y0
G1 X10 Y10
G92.1
G10 L20 P1 X0 Y0 Z0
G54 G1 X10 Y-5
G91 G28 Z0
G90 G53 G0 X-20 Y-10
G28.1
G0 X15 Y15
G30 X5 Y5
G52 X3 Y4
G1 X0 Y0 Z-2
G52 X0 Y0 Z0
G59.3 G0 X1 Y1
G28
M2
";

const UNITS_AND_ARCS: &str = "\
G21 G90 G17 G94 F400
G0 X0 Y0 Z0
G20 G1 X1 Y0.5
G91 G1 X0.25 Y-0.125
G90 G21
G0 X0 Y0
G90.1 G2 X40 Y0 I20 J0
G91.1 G3 X20 Y20 R-20
G2 X30 Y10 R10.5
G18 G2 X50 Z0 I10 K0
G19 G3 Y30 Z0 J10 K0
G17 G2 X40 Y30 I-5 J0 Z-6 P3
G1 @30 ^45
G91 G1 @2 ^-10
G90 G7 G1 X60
G8
G93 G1 X-100 Y-50 F2
G2 X-80 Y-30 R20 F30
G94 F300
G95 S1200 M3 G1 X0 Y0 F0.2
M5 G94
M2
";

const TOOL_LENGTH: &str = "\
G21 G90 G17 F300
T2 M6
G43 H2
G0 X10 Y10 Z5
G1 Z-2
G43.1 Z30 X1
G1 X20
G43.2 H3
G1 Y20
G49
G1 X0 Y0
T3 M6
G43
G1 X5 Z-1
G49
M2
";

const MODES: &str = "\
G21 G90 G17 F500
o<inch> sub
  M73
  G20 G91
  G1 X0.5 Y0.25
o<inch> endsub
G0 X0 Y0 Z0
M70
G20 G91
G1 X1
M72
G1 X10 Y10
o<inch> call
o<inch> call
G1 X20
M2
";

const READS_POSITION: &str = "\
G21 G90 G17 F300
G0 X0 Y0 Z0
G1 X12.5 Y3
#1 = #5420
o1 if [#1 GT 12.5]
  G1 X0
o1 else
  G1 Y0
o1 endif
G1 X[#<_x> + 1]
M2
";

#[test]
fn rs274_sees_every_corrected_move_on_the_original() {
    if rs274().is_none() {
        return;
    }
    let work = [(5221, 0.0), (5222, 0.0), (5223, -150.0)];
    let pocket = std::fs::read_to_string("../../examples/nc/pocket.ngc").unwrap();
    let arcs = std::fs::read_to_string("../../examples/nc/arcs.ngc").unwrap();
    let five = std::fs::read_to_string("../../examples/nc/five_axis.ngc").unwrap();
    let mut offsets = vec![(5161, 10.0), (5162, -20.0), (5163, -5.0), (5181, -30.0), (5182, 40.0), (5183, -10.0)];
    offsets.extend(work);
    offsets.extend([(5381, 7.0), (5382, -3.0), (5383, -160.0)]);
    let cases = [
        Case {
            name: "pocket",
            machine: "vmc3",
            errors: "vmc3_backlash",
            temperatures: &[24.0],
            program: &pocket,
            parameters: &[],
            expanded: 0,
            keeps: &[],
        },
        Case {
            name: "arcs",
            machine: "vmc3",
            errors: "vmc3_backlash",
            temperatures: &[22.0],
            program: &arcs,
            parameters: &[],
            expanded: 0,
            keeps: &[],
        },
        Case {
            name: "five_axis",
            machine: "c600u",
            errors: "c600u",
            temperatures: &[],
            program: &five,
            parameters: &[],
            expanded: 0,
            keeps: &[],
        },
        Case {
            name: "parameters_and_loops",
            machine: "vmc3",
            errors: "vmc3",
            temperatures: &[],
            program: PARAMETERS_AND_LOOPS,
            parameters: &work,
            expanded: 3,
            keeps: &["o104 if [EXISTS[#<depth>]]", "o104 endif", "#<depth> = 2"],
        },
        Case {
            name: "subroutines",
            machine: "vmc3",
            errors: "vmc3_backlash",
            temperatures: &[21.0],
            program: SUBROUTINES,
            parameters: &work,
            expanded: 3,
            keeps: &["o<once> call [12]", "o<hole> sub", "#<local> = [#1 * 2]"],
        },
        Case {
            name: "cycles",
            machine: "vmc3",
            errors: "vmc3_backlash",
            temperatures: &[20.0],
            program: CYCLES,
            parameters: &work,
            // the G83 after a G99 hole at R (its corrected R below the level the controller
            // stands at would drop the rise to the initial level), and the G91 cycle
            expanded: 2,
            keeps: &["T1 M6 G43 H1", "G90 G80", "G99 G81 X9.9", "G73 X39.9", "G82 X49.9", "G99 G84 X89.9", "G18 G81 X9.9", "G81 Y9.9"],
        },
        Case {
            name: "cycles_expanded",
            machine: "vmc3",
            errors: "vmc3_backlash",
            temperatures: &[20.0],
            program: CYCLES,
            parameters: &work,
            // every drilling and boring block; the two tapping blocks stay cycles
            expanded: 11,
            keeps: &["T1 M6 G43 H1", "G90 G80", "G99 G84 X89.9"],
        },
        Case {
            name: "offsets",
            machine: "vmc3",
            errors: "vmc3",
            temperatures: &[],
            program: OFFSETS,
            parameters: &offsets,
            expanded: 0,
            keeps: &["G10 L2 P2 X10 Y20 Z-150 R30", "G92.1", "G91 G28 Z0", "G28.1"],
        },
        Case {
            name: "units_and_arcs",
            machine: "vmc3",
            errors: "vmc3_backlash",
            temperatures: &[23.0],
            program: UNITS_AND_ARCS,
            parameters: &work,
            expanded: 1,
            keeps: &["G90.1 G2 X", "G93 G1 X"],
        },
        Case {
            name: "tool_length",
            machine: "vmc3",
            errors: "vmc3",
            temperatures: &[],
            program: TOOL_LENGTH,
            parameters: &work,
            expanded: 0,
            keeps: &["G43 H2", "G43.2 H3"],
        },
        Case {
            name: "modes",
            machine: "vmc3",
            errors: "vmc3",
            temperatures: &[],
            program: MODES,
            parameters: &work,
            expanded: 2,
            keeps: &["M70", "M72", "o<inch> sub"],
        },
        Case {
            name: "reads_position",
            machine: "vmc3",
            errors: "vmc3",
            temperatures: &[],
            program: READS_POSITION,
            parameters: &work,
            expanded: 1,
            keeps: &["G17 G21 G90 F300", "(trueaxis: - the whole program: line 4 reads the current position"],
        },
    ];
    let mut total = Report::default();
    for case in &cases {
        let (result, report) = check(case, None, 0.05);
        assert_eq!(result.expanded.len(), case.expanded, "{}: {:?}", case.name, result.expanded);
        for keep in case.keeps {
            assert!(result.text().contains(keep), "{}: `{keep}` is not kept:\n{}", case.name, result.text());
        }
        assert!(result.changed_lines > 0, "{}", case.name);
        // the holes kept as cycles: bottoms exact (within 0.05 um), R levels exact along Z, the
        // lean and the clearance points within what is reported (checked by the comparison)
        let holes = match case.name {
            "cycles" => 11,
            "cycles_expanded" => 2,
            _ => 0,
        };
        assert_eq!(result.holes.len(), holes, "{}: {:?}", case.name, result.holes);
        assert_eq!(report.holes > 0, holes > 0, "{}", case.name);
        assert!(report.worst_along_um <= 0.05, "{}: R {} um off its level", case.name, report.worst_along_um);
        let warned = result.warnings.iter().filter(|w| w.contains("kept as a cycle")).count();
        assert_eq!(warned, result.holes.iter().filter(|h| h.lean_um.max(h.clearance_um) > 0.01).count(), "{:?}", result.warnings);
        if holes > 0 {
            let (lean, clearance) = result.holes.iter().fold((0.0f64, 0.0f64), |(l, c), h| (l.max(h.lean_um), c.max(h.clearance_um)));
            println!(
                "{}: {holes} holes kept, R within {:.4} um along Z; lean up to {lean:.3} um, clearance points up to {clearance:.3} um",
                case.name, report.worst_along_um
            );
        }
        let (_, finer) = check(case, Some(6), 0.01);
        println!(
            "{}: {} moves, {} pieces, ends within {:.4} um (5 decimals) / {:.4} um (6 decimals), path within {:.3} um; expanded: {:?}",
            case.name, report.moves, report.pieces, report.worst_end_um, finer.worst_end_um, report.worst_path_um, result.expanded
        );
        total.moves += report.moves;
        total.pieces += report.pieces;
    }
    assert!(total.moves > 150 && total.pieces > 100, "{total:?}");
}
