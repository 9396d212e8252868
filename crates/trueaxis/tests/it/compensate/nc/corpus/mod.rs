//! The corpus of posted and hand-written programs (issue 31's measure): 18 styles of CAM posts and
//! hand-writing for 8 controllers in 6 dialects ([`styles`]), 10 variants each, corrected as a user
//! would run them (`--dialect` of the controller, a tool table given; and again without one) for
//! the vmc3 example errors on a vmc3 with a 6 m travel.
//!
//! Each program must run in LinuxCNC's `rs274` (as it is when written for a LinuxCNC-compatible
//! controller: LinuxCNC, PathPilot, Mach3, grbl; rewritten as RS274/NGC by
//! [`super::common::fanuc_to_ngc`] when written for a Fanuc, Haas or Fadal (a Fadal one first by
//! `fadal_to_ngc`), by [`super::common::siemens_to_ngc`] when written for a SINUMERIK 840D), which must run the
//! corrected program too; its canonical moves, pushed through the erroneous machine, must land on
//! the original's within 0.05 um (path within 1.05 um: the 1 um split tolerance), as for LinuxCNC's
//! samples, or within half the last written increment on each axis for the Fanuc family (sqrt 3 x
//! 0.5 um in mm, sqrt 3 x 1.27 um in inch, + 0.01 um) and the SINUMERIK (4 decimals in mm, 5 in
//! inch). A program the rewriting does not take (Fanuc subprogram calls, `IF`/`GOTO`, tapping; a
//! SINUMERIK construct it does not know, in the original or in the corrected program) is read
//! again after correction by the library (a second run of the interpreter on the written text)
//! with the same bound. The share corrected or
//! refused by design (cutter radius compensation, probing, threading) must be at least 90 %, in all
//! and in every dialect; the outcome of every style and dialect is printed (docs/nc.md reports it).

pub(crate) mod styles;
mod writer;

use super::common::fanuc_to_ngc;
use super::common::oracle::Oracle;
use super::common::rs274::rs274;
use super::common::siemens_to_ngc::siemens_to_ngc;
use styles::{corpus, Sample, STYLES};
use trueaxis::compensate::nc::{correct_program, program_moves, Controller, Dialect, NcOptions, SearchPath, ToolTable};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// Variants of each style.
const PER_STYLE: usize = 10;

/// The holes kept as canned cycles: how many, the largest distance of an R point from its level
/// (um, read back), the largest lean and clearance reported.
#[derive(Clone, Copy, Default)]
struct Holes {
    count: usize,
    along_um: f64,
    lean_um: f64,
    clearance_um: f64,
}

impl Holes {
    fn of(holes: &[trueaxis::compensate::nc::write::HoleReport], along_um: f64) -> Holes {
        let max = |f: &dyn Fn(&trueaxis::compensate::nc::write::HoleReport) -> f64| holes.iter().map(f).fold(0.0, f64::max);
        Holes { count: holes.len(), along_um, lean_um: max(&|h| h.lean_um), clearance_um: max(&|h| h.clearance_um) }
    }

    fn add(&mut self, o: &Holes) {
        self.count += o.count;
        self.along_um = self.along_um.max(o.along_um);
        self.lean_um = self.lean_um.max(o.lean_um);
        self.clearance_um = self.clearance_um.max(o.clearance_um);
    }
}

enum Outcome {
    /// `rs274`: read back by rs274 (else by the library's second reading).
    Corrected {
        moves: usize,
        worst_um: f64,
        holes: Holes,
        rs274: bool,
    },
    ByDesign(String),
    Failed(String),
}

/// The Fanuc-dialect tool table (mm).
pub(crate) const FANUC_TOOLS: &str = "T1 P1 Z100\nT2 P2 Z120\nT3 P3 Z95\nT4 P4 Z110\n";

/// The refusals that are by design.
fn by_design(message: &str) -> bool {
    ["(probing)", "(spindle-synchronised motion)", "(cutter radius compensation)"].iter().any(|d| message.contains(d))
}

fn refused(message: String) -> Outcome {
    if by_design(&message) {
        Outcome::ByDesign(message)
    } else {
        Outcome::Failed(message)
    }
}

/// The program rs274 reads for `bytes`: a LinuxCNC-compatible program as it is (Mach3's `M98`
/// subprograms rewritten as O-word subroutines, grbl's `$` system commands as moves and comments), a Fanuc-family one rewritten as RS274/NGC
/// ([`fanuc_to_ngc`]; a Fadal one by `fadal_to_ngc`), a SINUMERIK one with its subprogram files too
/// ([`siemens_to_ngc`]); `None` when it uses what the rewriting does not take.
fn as_ngc(s: &Sample, bytes: &[u8]) -> Option<Vec<u8>> {
    if s.dialect == Controller::Siemens {
        siemens_to_ngc(&String::from_utf8_lossy(bytes), &styles::siemens_subprograms()).map(String::into_bytes)
    } else if s.dialect == Controller::Fadal {
        super::common::fadal_to_ngc::translate(&String::from_utf8_lossy(bytes)).map(String::into_bytes)
    } else if s.dialect.family() == Dialect::Fanuc {
        fanuc_to_ngc::translate(&String::from_utf8_lossy(bytes)).map(String::into_bytes)
    } else if let Some(mach) = std::str::from_utf8(bytes).ok().filter(|t| t.contains("M98")) {
        fanuc_to_ngc::mach_to_ngc(mach).map(String::into_bytes)
    } else if let Some(grbl) = std::str::from_utf8(bytes).ok().filter(|t| s.dialect == Controller::Grbl && t.contains('$')) {
        fanuc_to_ngc::grbl_to_ngc(grbl).map(String::into_bytes)
    } else {
        Some(bytes.to_vec())
    }
}

/// A program through rs274, before and after correction (a Fanuc-family program rewritten as
/// RS274/NGC): the corrected moves land on the original's within 0.05 um (5 decimals), or within
/// half the last written increment on each axis for a Fanuc-family program.
fn check_rs274(s: &Sample, machine: &Machine, corrector: &Corrector, errors: &ErrorModel) -> Outcome {
    let rs = rs274().expect("checked by the caller");
    let dir = tempfile::tempdir().unwrap();
    let tools = super::linuxcnc_samples::tool_table();
    std::fs::write(dir.path().join("tools.tbl"), &tools).unwrap();
    if s.dialect == Controller::Siemens {
        for (file, text) in styles::siemens_subprograms() {
            std::fs::write(dir.path().join(file), text).unwrap();
        }
    }
    let name = s.name.replace(".nc", ".ngc");
    let ngc = as_ngc(s, &s.bytes).expect("checked by the caller");
    if let Some(d) = std::env::var_os("TRUEAXIS_CORPUS_DIR") {
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(std::path::Path::new(&d).join(format!("{name}.rewritten")), &ngc).unwrap();
    }
    std::fs::write(dir.path().join(&name), ngc).unwrap();
    let original = rs
        .run(dir.path(), &name, Some("tools.tbl"))
        .unwrap_or_else(|e| panic!("{}: the corpus program does not run in rs274: {e}", s.name));
    let mut options = NcOptions::new(machine);
    options.dialect = Some(s.dialect);
    let siemens = s.dialect == Controller::Siemens;
    // rs274 reads its tool table in inch: the machine units of every correction (a SINUMERIK
    // `ATRANS` on such a machine once counted the shift so far 25.4 times too small)
    options.setup.machine_inch = true;
    // the SINUMERIK's rewriting changes the length on a line of its own after `M6`, where rs274
    // keeps the machine where it is (as the 840D does)
    options.setup.rs274_tool_change = !siemens;
    options.setup.tools = ToolTable::parse(&tools, "tools").unwrap();
    options.setup.search_path = SearchPath(vec![dir.path().to_path_buf()]);
    let result = match correct_program(corrector, &s.bytes, &s.name, &options, &[]) {
        Ok(r) => r,
        Err(e) => return refused(e.to_string()),
    };
    dump(s, &result.program);
    let Some(corrected) = as_ngc(s, &result.program) else {
        if s.dialect == Controller::Siemens {
            // the corrected program uses what the rewriting does not know (a kept cycle...)
            println!("  {}: the corrected program is not rewritten as RS274/NGC: the second reading", s.name);
            return check_fanuc(s, machine, corrector, errors);
        }
        return Outcome::Failed("the corrected program cannot be rewritten as RS274/NGC as the original was".into());
    };
    if let Some(d) = std::env::var_os("TRUEAXIS_CORPUS_DIR") {
        std::fs::write(std::path::Path::new(&d).join(format!("corrected_{name}.rewritten")), &corrected).unwrap();
    }
    std::fs::write(dir.path().join("corrected.ngc"), corrected).unwrap();
    let corrected = match rs.run(dir.path(), "corrected.ngc", Some("tools.tbl")) {
        Ok(m) => m,
        Err(e) => return Outcome::Failed(format!("the corrected program: {e}")),
    };
    let moves = program_moves(machine, &s.bytes, &s.name, &options).unwrap();
    let (count, homes) = super::common::canonical_homes(machine, &moves);
    if count != original.len() {
        return Outcome::Failed(format!("trueaxis reads {count} moves, rs274 {}", original.len()));
    }
    let slack = super::common::hole_slack(&moves, &result.holes);
    let tolerance = if s.dialect == Controller::Siemens {
        siemens_tolerance_um(&s.bytes)
    } else if s.dialect.family() == Dialect::Fanuc {
        fanuc_tolerance_um(&s.bytes)
    } else {
        0.05
    };
    let oracle = Oracle { machine, errors, temperatures: vec![] };
    match oracle.compare_with(&original, &corrected, &vec![0.0; machine.axis_count()], tolerance, 1.0 + tolerance, &homes, &slack) {
        Ok(r) => {
            Outcome::Corrected { moves: r.moves, worst_um: r.worst_end_um, holes: Holes::of(&result.holes, r.worst_along_um), rs274: true }
        }
        Err(e) => Outcome::Failed(e),
    }
}

/// With `TRUEAXIS_CORPUS_DIR` set, the program and its correction are written there to be looked at.
fn dump(s: &Sample, corrected: &[u8]) {
    if let Some(dir) = std::env::var_os("TRUEAXIS_CORPUS_DIR") {
        let dir = std::path::Path::new(&dir);
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join(&s.name), &s.bytes).unwrap();
        std::fs::write(dir.join(format!("corrected_{}", s.name)), corrected).unwrap();
    }
}

/// A Fanuc-dialect program, read again after correction.
fn check_fanuc(s: &Sample, machine: &Machine, corrector: &Corrector, errors: &ErrorModel) -> Outcome {
    let mut options = NcOptions::new(machine);
    options.dialect = Some(s.dialect);
    options.setup.tools = ToolTable::parse(FANUC_TOOLS, "tools").unwrap();
    let subprograms = subprogram_dir(s);
    options.setup.search_path = SearchPath(subprograms.iter().map(|d| d.path().to_path_buf()).collect());
    let text = String::from_utf8_lossy(&s.bytes).into_owned();
    let result = match correct_program(corrector, &s.bytes, &s.name, &options, &[]) {
        Ok(r) => r,
        Err(e) => return refused(e.to_string()),
    };
    dump(s, &result.program);
    if result.dialect.family() != Dialect::Fanuc && result.dialect != Controller::Siemens {
        return Outcome::Failed(format!("detected as {}", result.dialect));
    }
    let original = super::fanuc::read(machine, &text, &options);
    let corrected = super::fanuc::read(machine, &result.text(), &options);
    let tolerance = if s.dialect == Controller::Siemens { siemens_tolerance_um(&s.bytes) } else { fanuc_tolerance_um(&s.bytes) };
    let homes = super::fanuc::homes(machine, &text, &options);
    if let Some(dir) = std::env::var_os("TRUEAXIS_CORPUS_DIR") {
        let list = |c: &[super::common::rs274::Canon]| {
            c.iter().enumerate().map(|(i, m)| format!("{} {:?} {:?} {:?}\n", i + 1, m.kind, m.end, m.tool)).collect::<String>()
        };
        std::fs::write(
            std::path::Path::new(&dir).join(format!("{}.moves", s.name)),
            format!("{homes:?}\n{}\n{}", list(&original), list(&corrected)),
        )
        .unwrap();
    }
    let moves = program_moves(machine, &s.bytes, &s.name, &options).unwrap();
    let slack = super::common::hole_slack(&moves, &result.holes);
    let oracle = Oracle { machine, errors, temperatures: vec![] };
    match oracle.compare_with(&original, &corrected, &vec![0.0; machine.axis_count()], tolerance, 1.0 + tolerance, &homes, &slack) {
        Ok(r) => {
            Outcome::Corrected { moves: r.moves, worst_um: r.worst_end_um, holes: Holes::of(&result.holes, r.worst_along_um), rs274: false }
        }
        Err(e) => Outcome::Failed(e),
    }
}

/// The SINUMERIK subprogram files a SINUMERIK sample may call, in a directory of their own.
fn subprogram_dir(s: &Sample) -> Option<tempfile::TempDir> {
    if s.dialect != Controller::Siemens {
        return None;
    }
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in styles::siemens_subprograms() {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    Some(dir)
}

/// Where a corrected point of a Fanuc-family program may land: half the written increment on each
/// axis (3 decimals in mm, 4 in inch), plus the solve.
fn fanuc_tolerance_um(bytes: &[u8]) -> f64 {
    let inch = String::from_utf8_lossy(bytes).contains("G20");
    3f64.sqrt() * if inch { 1.27 } else { 0.5 } + 0.01
}

/// The same for a SINUMERIK program: 4 decimals in mm, 5 in inch (G70).
fn siemens_tolerance_um(bytes: &[u8]) -> f64 {
    let inch = String::from_utf8_lossy(bytes).contains("G70");
    3f64.sqrt() * if inch { 0.127 } else { 0.05 } + 0.01
}

/// Whether the program is corrected without a tool table (each tool at the assumed length).
fn corrected_without_tools(s: &Sample, machine: &Machine, corrector: &Corrector) -> bool {
    let mut options = NcOptions::new(machine);
    options.dialect = Some(s.dialect);
    options.setup.machine_inch = s.rs274;
    let subprograms = subprogram_dir(s);
    options.setup.search_path = SearchPath(subprograms.iter().map(|d| d.path().to_path_buf()).collect());
    correct_program(corrector, &s.bytes, &s.name, &options, &[]).is_ok()
}

#[test]
fn corpus_of_posts_and_controllers_is_corrected() {
    if rs274().is_none() {
        return;
    }
    let machine = super::linuxcnc_samples::mill();
    let errors = ErrorModel::load("../../examples/errors/vmc3.toml", &machine).unwrap();
    let corrector = Corrector::new(&machine, &errors);
    let samples = corpus(PER_STYLE);
    assert!(samples.len() >= 150);
    use rayon::prelude::*;
    let outcomes: Vec<(Outcome, bool)> = samples
        .par_iter()
        .map(|s| {
            let o = if as_ngc(s, &s.bytes).is_some() {
                check_rs274(s, &machine, &corrector, &errors)
            } else {
                check_fanuc(s, &machine, &corrector, &errors)
            };
            (o, corrected_without_tools(s, &machine, &corrector))
        })
        .collect();
    let (mut ok, mut design, mut no_table, mut moves, mut worst, mut by_rs274) = (0, 0, 0, 0, 0.0f64, 0);
    // SINUMERIK programs read back by rs274 through their rewriting, and their largest deviation
    let (mut siemens, mut siemens_worst) = (0, 0.0f64);
    // holes read back by rs274 on LinuxCNC-family programs, on Fanuc-family and SINUMERIK ones
    // rewritten, by the second reading
    let mut holes = [Holes::default(); 3];
    let mut failures = Vec::new();
    for (post, controller, _, _, _) in STYLES {
        let mine: Vec<_> = samples.iter().zip(&outcomes).filter(|(s, _)| s.post == post).collect();
        let corrected = mine.iter().filter(|(_, (o, _))| matches!(o, Outcome::Corrected { .. })).count();
        let refused = mine.iter().filter(|(_, (o, _))| matches!(o, Outcome::ByDesign(_))).count();
        let without = mine.iter().filter(|(_, (_, t))| *t).count();
        println!("| {post} | {controller} | {} | {corrected} | {refused} | {} | {without} |", mine.len(), mine.len() - corrected - refused);
        for (s, (o, t)) in &mine {
            no_table += usize::from(*t);
            match o {
                Outcome::Corrected { moves: m, worst_um, holes: hole_stats, rs274 } => {
                    ok += 1;
                    moves += m;
                    worst = worst.max(*worst_um);
                    by_rs274 += usize::from(*rs274);
                    if *rs274 && s.dialect == Controller::Siemens {
                        siemens += 1;
                        siemens_worst = siemens_worst.max(*worst_um);
                    }
                    let rewritten = s.dialect.family() == Dialect::Fanuc || s.dialect == Controller::Siemens;
                    holes[if !*rs274 { 2 } else { usize::from(rewritten) }].add(hole_stats);
                }
                Outcome::ByDesign(m) => {
                    design += 1;
                    println!("  refused by design: {}: {m}", s.name);
                }
                Outcome::Failed(m) => failures.push(format!("{} ({}): {m}", s.name, s.controller)),
            }
        }
    }
    let n = samples.len();
    println!(
        "{by_rs274} corrected programs read back by rs274 (the Fanuc-family and SINUMERIK ones rewritten as RS274/NGC), {} by the second reading",
        ok - by_rs274
    );
    println!(
        "{siemens} SINUMERIK programs read back by rs274 through their RS274/NGC rewriting, largest end deviation {siemens_worst:.4} um"
    );
    let share = (ok + design) as f64 / n as f64;
    println!(
        "{n} programs in {} styles: {ok} corrected, {design} refused by design, {} failed ({:.1} % corrected or refused by design); {no_table} corrected without a tool table ({:.1} %); {moves} moves, largest end deviation {worst:.4} um",
        STYLES.len(),
        failures.len(),
        100.0 * share,
        100.0 * no_table as f64 / n as f64
    );
    let readers = ["rs274", "rs274 (Fanuc-family and SINUMERIK programs rewritten as RS274/NGC)", "the second reading"];
    for (h, by) in holes.iter().zip(readers) {
        println!(
            "{} holes kept as canned cycles, read back by {by}: R points within {:.4} um of their level; lean reported up to {:.3} um, clearance points up to {:.3} um",
            h.count, h.along_um, h.lean_um, h.clearance_um
        );
    }
    assert!(holes[0].count >= 50 && holes[0].along_um <= 0.05, "R levels through rs274: {} um", holes[0].along_um);
    for f in &failures {
        println!("FAILED: {f}");
    }
    assert!(share >= 0.90, "{:.1} % corrected or refused by design, fewer than 90 %", 100.0 * share);
    by_dialect(&samples, &outcomes);
}

/// The outcome by dialect (each program corrected with its controller's `--dialect`), and how
/// often detection names that dialect: at least 90 % corrected or refused by design in every
/// dialect, and the family detected right in every program.
fn by_dialect(samples: &[Sample], outcomes: &[(Outcome, bool)]) {
    println!("| dialect | programs | corrected | read back by rs274 | refused by design | failed | detected as its own | detected in its family |");
    for dialect in Controller::ALL {
        let mine: Vec<_> = samples.iter().zip(outcomes).filter(|(s, _)| s.dialect == dialect).collect();
        if mine.is_empty() {
            continue;
        }
        let corrected = mine.iter().filter(|(_, (o, _))| matches!(o, Outcome::Corrected { .. })).count();
        let by_rs274 = mine.iter().filter(|(_, (o, _))| matches!(o, Outcome::Corrected { rs274: true, .. })).count();
        let design = mine.iter().filter(|(_, (o, _))| matches!(o, Outcome::ByDesign(_))).count();
        let detected: Vec<Controller> = mine.iter().map(|(s, _)| Controller::detect(&String::from_utf8_lossy(&s.bytes))).collect();
        let own = detected.iter().filter(|&&d| d == dialect).count();
        let family = detected.iter().filter(|d| d.family() == dialect.family()).count();
        let n = mine.len();
        println!("| {dialect} | {n} | {corrected} | {by_rs274} | {design} | {} | {own} | {family} |", n - corrected - design);
        assert!((corrected + design) * 10 >= n * 9, "{dialect}: {corrected} + {design} of {n}");
        assert_eq!(family, n, "{dialect}: detected in another family");
    }
}
