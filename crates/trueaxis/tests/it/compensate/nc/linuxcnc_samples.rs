//! LinuxCNC's own sample programs (every `.ngc` of the Debian package linuxcnc-uspace) as a corpus
//! of real programs: those that LinuxCNC's `rs274 -g` runs on a 3-axis mill (from their own
//! directory, subroutine files found there, a tool table T1-T20, no axis A B C moving) are corrected
//! for the vmc3 example errors on a vmc3 with a 6 m travel (the samples put their zeros anywhere);
//! rs274 must run each corrected program, and its canonical moves, pushed through the erroneous
//! machine, must land on the original program's canonical moves within 0.05 um (every point along
//! the corrected path within 1.05 um of the original path: the 1 um split tolerance).
//!
//! The share of the runnable programs that are corrected is measured; programs that use what the
//! corrector refuses by design (probing `G38.x`, spindle-synchronised `G33`/`G76`, cutter radius
//! compensation `G41`/`G42`) are listed apart. The share of the others must be at least 95 %; the
//! failures are printed.

use super::common::oracle::Oracle;
use super::common::rs274::rs274;
use std::path::Path;
use std::process::Command;
use trueaxis::compensate::nc::trace::flags;
use trueaxis::compensate::nc::{correct_program, run_program, Dialect, Move, NcOptions, SearchPath, ToolTable};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// The tool table given to rs274 and trueaxis (inch: rs274's machine units without an INI file).
pub(crate) fn tool_table() -> String {
    let mut t: String = (1..=20).map(|n| format!("T{n} P{n} Z{:.3} D{:.3} ;tool {n}\n", 0.25 * n as f64, 0.05 * n as f64)).collect();
    t.push_str("T99999 P123 Z0.1 ;big tool number\n");
    t
}

/// A 3-axis mill: vmc3 with a travel of +-3000 mm on every axis.
pub(crate) fn mill() -> Machine {
    let text = std::fs::read_to_string("../../examples/machines/vmc3.toml").unwrap();
    let text = text
        .replace("range = [-400, 400]", "range = [-3000, 3000]")
        .replace("range = [-250, 250]", "range = [-3000, 3000]")
        .replace("range = [-400, 0]", "range = [-3000, 3000]");
    Machine::from_toml_str(&text, "vmc3, 6 m travel").unwrap()
}

enum Outcome {
    /// rs274 cannot run it on a 3-axis mill.
    NotRunnable,
    Refused(String),
    Failed(String),
    Corrected {
        moves: usize,
        pieces: usize,
        expanded: usize,
        worst_um: f64,
    },
}

fn copy_dir(from: &Path, to: &Path) {
    for entry in std::fs::read_dir(from).unwrap().flatten() {
        let p = entry.path();
        if p.is_file() {
            let _ = std::fs::copy(&p, to.join(entry.file_name()));
        }
    }
}

fn check(path: &str, machine: &Machine, errors: &ErrorModel) -> Outcome {
    let rs = rs274().expect("checked by the caller");
    let dir = tempfile::tempdir().unwrap();
    let source = Path::new(path);
    copy_dir(source.parent().unwrap(), dir.path());
    let name = source.file_name().unwrap().to_string_lossy().to_string();
    let tools = tool_table();
    std::fs::write(dir.path().join("trueaxis-tools.tbl"), &tools).unwrap();
    let original = match rs.run(dir.path(), &name, Some("trueaxis-tools.tbl")) {
        Ok(m) => m,
        Err(_) => return Outcome::NotRunnable,
    };
    if original.iter().any(|c| c.end[3..].iter().any(|v| v.abs() > 1e-9)) {
        return Outcome::NotRunnable;
    }
    let text = std::fs::read_to_string(source).unwrap_or_default();
    let mut options = NcOptions::new(machine);
    options.dialect = Some(Dialect::LinuxCnc.into());
    options.setup.machine_inch = true;
    options.setup.rs274_tool_change = true;
    options.setup.tools = ToolTable::parse(&tools, "tools").unwrap();
    options.setup.search_path = SearchPath(vec![dir.path().to_path_buf()]);
    let corrector = Corrector::new(machine, errors);
    let result = match correct_program(&corrector, &text, &name, &options, &[]) {
        Ok(r) => r,
        Err(e) => {
            let m = e.to_string();
            let by_design = ["(probing)", "(spindle-synchronised motion)", "(cutter radius compensation)"];
            return if by_design.iter().any(|d| m.contains(d)) { Outcome::Refused(m) } else { Outcome::Failed(m) };
        }
    };
    std::fs::write(dir.path().join("trueaxis-corrected.ngc"), &result.program).unwrap();
    let corrected = match rs.run(dir.path(), "trueaxis-corrected.ngc", Some("trueaxis-tools.tbl")) {
        Ok(m) => m,
        Err(e) => return Outcome::Failed(format!("the corrected program: {e}")),
    };
    let oracle = Oracle { machine, errors, temperatures: vec![] };
    let Ok((trace, _)) = run_program(machine, &text, &name, &options) else { return Outcome::Failed("run again: differs".into()) };
    let moves = &trace.moves;
    // rs274 prints a spline as NURBS_FEED without its points: the moves around it are compared,
    // and the chords trueaxis reads (checked against the curve in splines.rs) stand for it
    let spline = |m: &Move| trace.steps[m.step as usize].has(flags::SPLINE);
    let plain: Vec<Move> = moves.iter().filter(|m| !spline(m)).copied().collect();
    let (count, _) = super::common::canonical_homes(machine, &plain);
    if count != original.len() {
        return Outcome::Failed(format!("trueaxis reads {count} moves, rs274 {}", original.len()));
    }
    let (_, homes) = super::common::canonical_homes(machine, moves);
    let original = if plain.len() < moves.len() { super::fanuc::read(machine, &text, &options) } else { original };
    let slack = super::common::hole_slack(moves, &result.holes);
    match oracle.compare_with(&original, &corrected, &vec![0.0; machine.axis_count()], 0.05, 1.05, &homes, &slack) {
        Ok(r) => Outcome::Corrected { moves: r.moves, pieces: r.pieces, expanded: result.expanded.len(), worst_um: r.worst_end_um },
        Err(e) => Outcome::Failed(e),
    }
}

#[test]
fn linuxcnc_sample_programs_are_corrected() {
    if rs274().is_none() {
        return;
    }
    let listing = Command::new("dpkg").args(["-L", "linuxcnc-uspace"]).output().expect("dpkg lists the package");
    let mut programs: Vec<String> =
        String::from_utf8_lossy(&listing.stdout).lines().filter(|l| l.ends_with(".ngc")).map(str::to_string).collect();
    programs.sort();
    assert!(programs.len() > 100, "{} sample programs", programs.len());
    let machine = mill();
    let errors = ErrorModel::load("../../examples/errors/vmc3.toml", &machine).unwrap();
    use rayon::prelude::*;
    let outcomes: Vec<(String, Outcome)> = programs.par_iter().map(|p| (p.clone(), check(p, &machine, &errors))).collect();
    let (mut runnable, mut corrected, mut refused, mut failed) = (0, 0, Vec::new(), Vec::new());
    let (mut moves, mut pieces, mut expanded, mut worst) = (0, 0, 0, 0.0f64);
    for (p, o) in &outcomes {
        match o {
            Outcome::NotRunnable => {}
            Outcome::Refused(m) => {
                runnable += 1;
                refused.push(format!("{p}: {m}"));
            }
            Outcome::Failed(m) => {
                runnable += 1;
                failed.push(format!("{p}: {m}"));
            }
            Outcome::Corrected { moves: m, pieces: n, expanded: e, worst_um } => {
                runnable += 1;
                corrected += 1;
                moves += m;
                pieces += n;
                expanded += usize::from(*e > 0);
                worst = worst.max(*worst_um);
            }
        }
    }
    let eligible = runnable - refused.len();
    let share = corrected as f64 / eligible as f64;
    println!(
        "{} sample programs; rs274 runs {runnable} on a 3-axis mill; {} use what is refused by design; {corrected} of the other {eligible} corrected ({:.1} %, {:.1} % of all runnable), {expanded} of them with expanded parts; {moves} canonical moves, {pieces} pieces, largest end deviation {worst:.4} um",
        programs.len(),
        refused.len(),
        100.0 * share,
        100.0 * corrected as f64 / runnable as f64
    );
    for r in &refused {
        println!("refused by design: {r}");
    }
    for f in &failed {
        println!("FAILED: {f}");
    }
    assert!(runnable > 150, "rs274 runs only {runnable} of the samples");
    assert!(share >= 0.95, "{:.1} % corrected, fewer than 95 %", 100.0 * share);
    assert!(worst <= 0.05);
}
