//! Reading any byte stream a controller takes (issue 38's NC items): line ends CR, LF and CR LF
//! alike, a byte-order mark, Latin-1 comments kept byte for byte, control bytes refused with the
//! line, characters named readably, double signs as each controller reads them, expressions too
//! deep or too long refused with the line instead of overflowing the stack. Each corrected program
//! is read back through the erroneous machine (the pocket's moves land on the original ones) and
//! zero errors leave it byte for byte.

use super::common::oracle::Oracle;
use super::roundtrip::{load, read};
use trueaxis::compensate::nc::{correct_program, program_moves, Dialect, NcOptions};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// A small program (vmc3: Z from -400 to 0) whose lines end in `eol`, with a comment `comment`.
fn program(eol: &str, comment: &[u8]) -> Vec<u8> {
    let mut p = Vec::new();
    for line in
        ["%", "O1000", "G21 G90 G17", "G0 X-200. Y-150. Z-100.", "G1 Z-250. F500.", "X100. Y50.", "G2 X200. Y-50. I0. J-100.", "M30", "%"]
    {
        p.extend_from_slice(line.as_bytes());
        if line == "O1000" {
            p.extend_from_slice(b" ");
            p.extend_from_slice(comment);
        }
        p.extend_from_slice(eol.as_bytes());
    }
    p
}

/// Corrects `bytes` for the vmc3 errors, checks the landing through the erroneous machine and that
/// zero errors give the bytes back; the corrected bytes.
fn corrected(bytes: &[u8], dialect: Dialect) -> Vec<u8> {
    let (m, e) = load("vmc3", "vmc3");
    let mut options = NcOptions::new(&m);
    options.dialect = Some(dialect.into());
    let r = correct_program(&Corrector::new(&m, &e), bytes, "t.nc", &options, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.moves, 4);
    let original = read(&m, &String::from_utf8_lossy(bytes), &options);
    let back = read(&m, &r.text(), &options);
    let oracle = Oracle { machine: &m, errors: &e, temperatures: Vec::new() };
    let report = oracle.compare(&original, &back, &options.setup.start, 0.876, 1.876, &[]).unwrap_or_else(|err| panic!("{err}"));
    assert_eq!(report.moves, 4);
    assert!(r.changed_lines >= 3, "{r:?}");
    let zero = ErrorModel::zero(&m);
    let same = correct_program(&Corrector::new(&m, &zero), bytes, "t.nc", &options, &[]).unwrap();
    assert_eq!(same.program, bytes);
    r.program
}

#[test]
fn line_ends_bom_and_latin1_comments_are_read_and_kept() {
    for eol in ["\n", "\r\n", "\r"] {
        let bytes = program(eol, b"(PART)");
        let out = corrected(&bytes, Dialect::Fanuc);
        // the corrected program has the input's line ends only
        let lines = out.split(|&b| b == b'\r' || b == b'\n').filter(|l| !l.is_empty()).count();
        assert_eq!(out.windows(eol.len()).filter(|w| *w == eol.as_bytes()).count(), lines, "{eol:?}");
        if eol == "\r" {
            assert!(!out.contains(&b'\n'));
        }
    }
    // a byte-order mark stays first
    let mut bom = b"\xEF\xBB\xBF".to_vec();
    bom.extend(program("\n", b"(PART)"));
    assert!(corrected(&bom, Dialect::Fanuc).starts_with(b"\xEF\xBB\xBF%\nO1000 (PART)\n"));
    // Latin-1 (Windows-1252) bytes of a comment come back as they were
    let latin1 = program("\r\n", b"(Fr\xE4se \xD810 Stra\xDFe)");
    let out = corrected(&latin1, Dialect::Fanuc);
    assert!(out.windows(18).any(|w| w == b"(Fr\xE4se \xD810 Stra\xDFe)"));
    // UTF-8 comments too
    let utf8 = program("\n", "(Fräse Ø10)".as_bytes());
    assert!(String::from_utf8(corrected(&utf8, Dialect::Fanuc)).unwrap().contains("O1000 (Fräse Ø10)\n"));
}

fn refusal(bytes: &[u8], dialect: Dialect) -> String {
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let zero = ErrorModel::zero(&m);
    let mut options = NcOptions::new(&m);
    options.dialect = Some(dialect.into());
    match correct_program(&Corrector::new(&m, &zero), bytes, "t.nc", &options, &[]) {
        Ok(r) => panic!("accepted: {}", r.text()),
        Err(e) => {
            assert_eq!(e.kind(), trueaxis::ErrorKind::Input);
            e.to_string()
        }
    }
}

#[test]
fn control_bytes_and_foreign_characters_are_refused_readably() {
    for dialect in [Dialect::LinuxCnc, Dialect::Fanuc] {
        let nul = refusal(b"G21 G90\nG0 X0 Y0 Z-10\nG1 F500 X3\x0000 Y50\nM30\n", dialect);
        assert_eq!(nul, "t.nc: line 3: control byte 0x00 (NUL) at column 11: program text holds none (a damaged or binary file?)");
        // a byte that is not UTF-8 outside a comment: named as a byte
        let byte = refusal(b"G21 G90\nG0 X\xD810 Y0\nM30\n", dialect);
        assert!(byte.starts_with("t.nc: line 2: ") && byte.contains("byte 0xD8"), "{byte}");
        // Arabic-Indic digits: the character and its code point, not its bytes as Latin-1
        let arabic = refusal("G21 G90\nG0 X\u{0661}\u{0660} Y0\nM30\n".as_bytes(), dialect);
        assert!(arabic.starts_with("t.nc: line 2: ") && arabic.contains("`\u{0661}` (U+0661)"), "{arabic}");
    }
}

#[test]
fn double_signs_are_read_as_each_controller_reads_them() {
    // LinuxCNC's rs274 2.9 reads `X+-5` as -5 and `X--5` as 5 (checked with rs274 -g); a Fanuc
    // reads one sign before a value
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let mut options = NcOptions::new(&m);
    options.dialect = Some(Dialect::LinuxCnc.into());
    let moves = program_moves(&m, "G21 G90\nG0 X+-5 Y--7 Z-10\nM2\n", "t.ngc", &options).unwrap();
    assert_eq!((moves[0].end[0], moves[0].end[1], moves[0].end[2]), (-5.0, 7.0, -10.0));
    if let Some(rs) = super::common::rs274::rs274() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("t.ngc"), "G21 G90\nG0 X+-5 Y--7 Z-10\nM2\n").unwrap();
        let canon = rs.run(dir.path(), "t.ngc", None).unwrap();
        let last = canon.last().unwrap();
        assert!((last.end[0] + 5.0).abs() < 1e-9 && (last.end[1] - 7.0).abs() < 1e-9, "{:?}", last.end);
    }
    let fanuc = refusal(b"%\nO1\nG21 G90\nG0 X+-5. Z-10.\nM30\n%\n", Dialect::Fanuc);
    assert_eq!(fanuc, "t.nc: line 4: two signs `+-` before a value");
}

#[test]
fn deep_and_long_expressions_are_refused_with_the_line() {
    let deep = format!("G21\nG0 X{}1{} Z-10\nM2\n", "[".repeat(12_000), "]".repeat(12_000));
    assert_eq!(
        refusal(deep.as_bytes(), Dialect::LinuxCnc),
        "t.nc: line 2: a line of 24010 characters: LinuxCNC reads at most 252 (rs274: Command too long)"
    );
    let deep = format!("%\nO1\nG0 X{}1{} Z-10.\nM30\n%\n", "[".repeat(12_000), "]".repeat(12_000));
    assert_eq!(refusal(deep.as_bytes(), Dialect::Fanuc), "t.nc: line 3: brackets nested more than 5 levels (a Fanuc raises alarm 118)");
    for (what, text) in [
        ("SIN[", format!("#1={}0{}", "SIN[".repeat(100_000), "]".repeat(100_000))),
        ("#[", format!("#1={}1{}", "#[".repeat(100_000), "]".repeat(100_000))),
        ("minus", format!("#1={}1", "-".repeat(100_000))),
        ("##", format!("#1={}1", "#".repeat(100_000))),
    ] {
        let program = format!("%\nO1\n{text}\nG0 X#1 Z-10.\nM30\n%\n");
        let e = refusal(program.as_bytes(), Dialect::Fanuc);
        assert!(e.starts_with("t.nc: line 3: "), "{what}: {e}");
        assert!(e.contains("nested more than") || e.contains("two signs"), "{what}: {e}");
    }
    let terms = format!("%\nO1\n#1=1{}\nG0 X#1 Z-10.\nM30\n%\n", "+1".repeat(50_000));
    assert_eq!(refusal(terms.as_bytes(), Dialect::Fanuc), "t.nc: line 3: more than 1000 terms in the expressions of one line");
}

#[test]
fn the_reported_residual_includes_the_rounding_of_the_written_numbers() {
    // with few decimals the written numbers, not the solve, decide where the machine goes: the
    // residual reported must cover what the written program leaves (read back through the
    // erroneous machine), and stay within the rounding of the solve's residual
    let (m, e) = load("vmc3", "vmc3");
    let text = "G21 G90\nG0 X-300 Y-200 Z-100\nG1 Z-250 F500\nX-0.3 Y-200.7\nX300 Y-150.1 Z-251.37\nY190.9\nX-251.21 Y199.99\nM2\n";
    for decimals in [0, 1, 2, 3, 5] {
        let mut options = NcOptions::new(&m);
        options.decimals = Some(decimals);
        let r = correct_program(&Corrector::new(&m, &e), text, "t.ngc", &options, &[]).unwrap();
        let original = read(&m, text, &options);
        let back = read(&m, &r.text(), &options);
        let oracle = Oracle { machine: &m, errors: &e, temperatures: Vec::new() };
        let half_um = 0.5 * 10f64.powi(-(decimals as i32)) * 1e3;
        let bound_um = 3f64.sqrt() * half_um + 0.01;
        let report = oracle.compare(&original, &back, &options.setup.start, bound_um, 1e9, &[]).unwrap_or_else(|e| panic!("{e}"));
        println!("{decimals} decimals: reported {:.4} um, left {:.4} um", r.max_residual_um, report.worst_end_um);
        assert!(r.max_residual_um >= report.worst_end_um - 1e-9, "{decimals}: {} < {}", r.max_residual_um, report.worst_end_um);
        assert!(r.max_residual_um <= bound_um, "{decimals}: {}", r.max_residual_um);
    }
}
