//! A program corrected in parts (`compensate::nc::stream`: read, run, corrected and written a few
//! lines at a time, for programs of any length) is the program corrected whole: the same bytes
//! and the same summary (every field of `NcResult`: counts, largest correction and residual,
//! warnings with their lines, holes with their lines and moves), for parts of 1, 3 and 16 lines,
//! through the spool in memory and in a temporary file. Checked on the programs of the corpus,
//! the shipped examples and two long generated programs written to cross part boundaries
//! everywhere (arcs, incremental moves, canned cycles kept as cycles, tool changes, an unknown
//! tool, a backlash model whose direction state goes on across parts, CR LF and CR line ends, a
//! byte-order mark, `%` lines, a last line without its end). A program that needs its whole text
//! (control flow) falls back to it; the straight ones must be corrected in parts.

use super::corpus::styles::corpus;
use trueaxis::compensate::nc::stream::{correct_streamed, Spool, Streamed};
use trueaxis::compensate::nc::{correct_whole, Controller, Dialect, NcOptions, NcResult, ToolTable};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// How a program went in parts.
#[derive(Debug, PartialEq)]
pub(crate) enum Went {
    InParts,
    Whole(String),
    Refused(String),
}

/// Corrects `bytes` whole and in parts of 1, 3 and 16 lines; asserts that every run in parts that
/// did not fall back gives the whole run's bytes and summary, and that a refusal is the same. (A
/// part of comments only falls back: where the notes go depends on the first line that is not a
/// comment, which the default parts of 20,000 lines hold.)
pub(crate) fn compare(corrector: &Corrector, bytes: &[u8], name: &str, options: &NcOptions) -> Vec<Went> {
    let whole = correct_whole(corrector, bytes, name, options, &[]);
    let detected = options.dialect.unwrap_or_else(|| Controller::detect(&String::from_utf8_lossy(bytes)));
    let dialect = whole.as_ref().map_or(detected, |w| w.dialect);
    let mut went = Vec::new();
    for (part_lines, in_file) in [(1, false), (3, false), (16, true)] {
        let options = NcOptions { part_lines, dialect: Some(dialect), ..options.clone() };
        let spool = if in_file { Spool::file().unwrap() } else { Spool::Memory(Vec::new()) };
        let mut out = Vec::new();
        let streamed = correct_streamed(corrector, bytes, name, &options, &[], spool, &mut out);
        went.push(match (streamed, &whole) {
            (Ok(Streamed::Done(r)), Ok(w)) => {
                let parts = NcResult { program: out, ..*r };
                if parts.program != w.program {
                    let at = parts.program.iter().zip(&w.program).position(|(a, b)| a != b).unwrap_or(0);
                    let show = |p: &[u8]| String::from_utf8_lossy(&p[at.saturating_sub(80)..(at + 80).min(p.len())]).into_owned();
                    panic!(
                        "{name} in parts of {part_lines} lines differs at byte {at}:\n{}\n--- whole:\n{}",
                        show(&parts.program),
                        show(&w.program)
                    );
                }
                assert_eq!(parts, *w, "{name} in parts of {part_lines} lines");
                Went::InParts
            }
            (Ok(Streamed::NeedsWhole(why)), _) => Went::Whole(why),
            (Err(e), Err(w)) => {
                assert_eq!(e.to_string(), w.to_string(), "{name} in parts of {part_lines} lines");
                Went::Refused(e.to_string())
            }
            (Ok(Streamed::Done(_)), Err(w)) => panic!("{name}: corrected in parts of {part_lines} lines, refused whole: {w}"),
            (Err(e), Ok(_)) => panic!("{name}: refused in parts of {part_lines} lines ({e}), corrected whole"),
        });
    }
    went
}

/// A long straight LinuxCNC program that crosses part boundaries with every kind of state.
fn long_linuxcnc(lines: usize, eol: &str) -> Vec<u8> {
    let mut p = String::from("\u{FEFF}%\n(generated: parts)\nG21 G90 G17 G94 G40 G49\nT1 M6 G43 H1\nG0 X-300 Y-200 Z-100\nF800\n");
    for k in 0..lines {
        let x = -300.0 + (k * 37 % 600) as f64;
        let y = -200.0 + (k * 53 % 400) as f64;
        p += &match k % 11 {
            0 => format!("G1 X{x:.3} Y{y:.3} Z-{:.2} (pass {k})", 100.0 + (k % 7) as f64),
            1 => "G91 G2 X20 Y0 I10 J0\nG90".to_string(),
            2 => "G91 G1 X5 Y-3\nX-5 Y3\nG90".to_string(),
            3 => format!("G98 G81 X{x:.2} Y{y:.2} Z-150 R-120\nX{:.2}\nY{:.2}\nG80", x + 10.0, y + 10.0),
            4 => format!("T{} M6 G43 H{}", 1 + k % 3, 1 + k % 3),
            5 => format!("N{k} G0 X{y:.1} Y{x:.1}"),
            6 => format!("G1 Z-{:.1}\nZ-100", 120.0 + (k % 5) as f64),
            _ => format!("G1 X{x:.4} Y{y:.4}"),
        };
        p.push('\n');
    }
    p += "M2\n%\n(after the end)";
    p.replace('\n', eol).into_bytes()
}

/// A long straight Fanuc program (program number, sequence numbers, decimal points, cycles).
fn long_fanuc(lines: usize) -> Vec<u8> {
    let mut p = String::from("%\rO1234 (PARTS)\rG21 G90 G17 G40 G49 G80\rT1 M06\rG43 Z50. H01\r");
    for k in 0..lines {
        let x = -250.0 + (k * 29 % 500) as f64;
        p += &match k % 5 {
            0 => format!("N{k} G01 X{x:.3} Y{:.3} F600.", (k % 90) as f64 - 45.0),
            1 => format!("G99 G83 X{x:.3} Y20. Z-180. R-140. Q5.\rY30.\rG80"),
            2 => "G91 G02 X30. Y0. R15.\rG90 G01".to_string(),
            3 if k % 50 == 3 => format!("T{0} M06\rG43 H0{0} Z50.", 1 + k % 100 / 50),
            _ => format!("X{x:.3}"),
        };
        p.push('\r');
    }
    p += "M30\r%\r";
    p.into_bytes()
}

#[test]
fn programs_corrected_in_parts_are_those_corrected_whole() {
    let machine = super::linuxcnc_samples::mill();
    let errors = ErrorModel::load("../../examples/errors/vmc3_backlash.toml", &machine).unwrap();
    let corrector = Corrector::new(&machine, &errors);
    let (mut in_parts, mut whole) = (0, 0);
    let mut count = |went: Went| match went {
        Went::InParts => in_parts += 1,
        Went::Whole(_) => whole += 1,
        Went::Refused(_) => {}
    };
    for s in corpus(10) {
        let mut options = NcOptions::new(&machine);
        options.setup.machine_inch = s.rs274;
        let tools = if s.rs274 { super::linuxcnc_samples::tool_table() } else { super::corpus::FANUC_TOOLS.to_string() };
        options.setup.tools = ToolTable::parse(&tools, "tools").unwrap();
        count(compare(&corrector, &s.bytes, &s.name, &options).pop().unwrap());
    }
    println!("corpus: {in_parts} programs corrected in parts, {whole} need their whole text");
    assert!(in_parts >= 60, "{in_parts} corrected in parts");
    let vmc3 = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let vmc3_errors = ErrorModel::load("../../examples/errors/vmc3_backlash.toml", &vmc3).unwrap();
    let examples = Corrector::new(&vmc3, &vmc3_errors);
    for name in ["pocket.ngc", "arcs.ngc", "features.ngc", "drilling.nc"] {
        let bytes = std::fs::read(format!("../../examples/nc/{name}")).unwrap();
        let mut options = NcOptions::new(&vmc3);
        options.setup.tools = ToolTable::parse(&std::fs::read_to_string("../../examples/nc/tools.tbl").unwrap(), "tools").unwrap();
        options.setup.set_work_offset(&trueaxis::compensate::nc::machine_axes(&vmc3), 1, &[0.0, 0.0, -300.0]);
        options.setup.start = vec![0.0, 0.0, -100.0];
        options.setup.search_path = trueaxis::compensate::nc::SearchPath(vec!["../../examples/nc".into()]);
        compare(&examples, &bytes, name, &options);
    }
    let mut options = NcOptions::new(&machine);
    options.setup.tools = ToolTable::parse("T1 P1 Z100\nT3 P3 Z80\n", "tools").unwrap();
    for (name, bytes, dialect) in [
        ("long.ngc", long_linuxcnc(600, "\n"), Dialect::LinuxCnc),
        ("long_crlf.ngc", long_linuxcnc(300, "\r\n"), Dialect::LinuxCnc),
        ("long.nc", long_fanuc(500), Dialect::Fanuc),
    ] {
        let options = NcOptions { dialect: Some(dialect.into()), ..options.clone() };
        assert_eq!(compare(&corrector, &bytes, name, &options), [Went::InParts, Went::InParts, Went::InParts], "{name}");
        let r = correct_whole(&corrector, &bytes, name, &options, &[]).unwrap();
        assert!(r.holes.len() > 50 && r.assumed_tools == [2], "{name}: {} holes, {:?}", r.holes.len(), r.assumed_tools);
    }
}
