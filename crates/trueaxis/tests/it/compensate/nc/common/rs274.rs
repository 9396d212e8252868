//! LinuxCNC's standalone interpreter `rs274 -g` (Debian package linuxcnc-uspace) as the independent
//! reader of NC programs: it runs a program and prints the canonical moves, which are turned here
//! into machine positions (mm, deg) with the offsets it prints (`SET_G5X_OFFSET`, `SET_G92_OFFSET`,
//! `SET_XY_ROTATION`, `USE_TOOL_LENGTH_OFFSET`, each in the units in force when printed):
//! machine = rotate(program + G92) + work offset + tool offset (LinuxCNC `emccanon.cc`).
//!
//! rs274 prints coordinates with 4 decimals (0.1 um in mm); the tests preload `rs274_digits.c`
//! (built with gcc) so that it prints 10 and corrections can be checked to 0.05 um.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// rs274 and the preloaded printing shim.
pub struct Rs274 {
    shim: PathBuf,
}

/// rs274, or `None` (the reason printed) when it is not installed; when `TRUEAXIS_REQUIRE_RS274`
/// is set (CI installs LinuxCNC), a missing rs274 or gcc fails the test.
pub fn rs274() -> Option<&'static Rs274> {
    static R: OnceLock<Option<Rs274>> = OnceLock::new();
    R.get_or_init(|| {
        let required = std::env::var_os("TRUEAXIS_REQUIRE_RS274").is_some();
        if Command::new("rs274").arg("-g").arg("/dev/null").output().is_err() {
            assert!(!required, "TRUEAXIS_REQUIRE_RS274 is set but `rs274` cannot be run");
            println!("SKIPPED: `rs274` (LinuxCNC, Debian package linuxcnc-uspace) is not installed; install it to run this test");
            return None;
        }
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rs274_digits");
        std::fs::create_dir_all(&dir).unwrap();
        let shim = dir.join("rs274_digits.so");
        let source = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/it/compensate/nc/common/rs274_digits.c");
        let partial = dir.join(format!("rs274_digits.{}.so", std::process::id()));
        let status = Command::new("gcc").args(["-shared", "-fPIC", "-O2", "-o"]).arg(&partial).arg(source).status();
        match status {
            Ok(s) if s.success() => std::fs::rename(&partial, &shim).unwrap(),
            _ => {
                assert!(!required, "gcc is needed to build the rs274 printing shim");
                println!("SKIPPED: gcc is not installed (it builds the rs274 printing shim)");
                return None;
            }
        }
        Some(Rs274 { shim })
    })
    .as_ref()
}

/// A canonical move in machine positions.
#[derive(Clone, Debug, PartialEq)]
pub struct Canon {
    pub kind: Kind,
    /// X Y Z (mm) A B C (deg).
    pub end: [f64; 6],
    /// Tool length offset in force (X Y Z, mm).
    pub tool: [f64; 3],
    /// Printed in inch.
    pub inch: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    Traverse,
    Feed,
    /// Plane axes (first, second, normal; 0 1 2 = X Y Z), centre (machine mm), turns (+
    /// counterclockwise).
    Arc {
        axes: [usize; 3],
        centre: [f64; 2],
        turns: i32,
    },
}

impl Rs274 {
    /// Runs `rs274 -g` on `program` in `dir` (its subroutine files found there through an INI file
    /// with `SUBROUTINE_PATH = .`), with `tools` as the tool table; the canonical moves, or the
    /// error rs274 printed.
    pub fn run(&self, dir: &Path, program: &str, tools: Option<&str>) -> Result<Vec<Canon>, String> {
        self.run_with(dir, program, tools, None)
    }

    /// The same with a parameter file (its text; rewritten before the run, since rs274 saves the
    /// parameters into it when it ends).
    pub fn run_with(&self, dir: &Path, program: &str, tools: Option<&str>, parameters: Option<&str>) -> Result<Vec<Canon>, String> {
        std::fs::write(dir.join("trueaxis-rs274.ini"), "[RS274NGC]\nSUBROUTINE_PATH = .\n").unwrap();
        // rs274 keeps its tool table in shared memory: one run at a time
        static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());
        let _guard = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
        let mut cmd = Command::new("rs274");
        cmd.current_dir(dir).env("LD_PRELOAD", &self.shim).arg("-i").arg("trueaxis-rs274.ini");
        if let Some(t) = tools {
            cmd.arg("-t").arg(t);
        }
        if let Some(p) = parameters {
            std::fs::write(dir.join("trueaxis-rs274.var"), p).unwrap();
            cmd.arg("-v").arg("trueaxis-rs274.var");
        }
        let out = cmd.arg("-g").arg(program).stdin(std::process::Stdio::null()).output().map_err(|e| e.to_string())?;
        let stderr = String::from_utf8_lossy(&out.stderr);
        let complaint: Vec<&str> = stderr.lines().map(str::trim).filter(|l| !l.is_empty() && *l != "executing").collect();
        if !out.status.success() || !complaint.is_empty() {
            return Err(format!("rs274 ({}): {}", out.status, complaint.join(" / ")));
        }
        Ok(parse(&String::from_utf8_lossy(&out.stdout)))
    }
}

/// The canonical moves of rs274's output in machine positions.
pub fn parse(output: &str) -> Vec<Canon> {
    let mut inch = false;
    let (mut g5x, mut g92, mut tool) = ([0.0; 6], [0.0; 6], [0.0; 6]);
    let mut rotation: f64 = 0.0;
    let mut plane = [0usize, 1, 2];
    let mut moves = Vec::new();
    for line in output.lines() {
        let Some(open) = line.find('(') else { continue };
        let name = line[..open].split_whitespace().last().unwrap_or("");
        let inside = &line[open + 1..line.rfind(')').unwrap_or(line.len())];
        let numbers: Vec<f64> = inside.split([',', ' ']).filter_map(|a| a.trim().parse().ok()).collect();
        let scale = if inch { 25.4 } else { 1.0 };
        let to_mm = |v: &[f64]| -> [f64; 6] { std::array::from_fn(|k| v.get(k).copied().unwrap_or(0.0) * if k < 3 { scale } else { 1.0 }) };
        let machine = |p: [f64; 6], g5x: &[f64; 6], g92: &[f64; 6], tool: &[f64; 6], rotation: f64| -> [f64; 6] {
            let mut m: [f64; 6] = std::array::from_fn(|k| p[k] * if k < 3 { scale } else { 1.0 } + g92[k]);
            let (s, c) = rotation.to_radians().sin_cos();
            let (x, y) = (m[0], m[1]);
            m[0] = x * c - y * s;
            m[1] = x * s + y * c;
            std::array::from_fn(|k| m[k] + g5x[k] + tool[k])
        };
        match name {
            "USE_LENGTH_UNITS" => inch = inside.contains("INCHES"),
            "SELECT_PLANE" => {
                plane = match inside {
                    "CANON_PLANE_XZ" => [2, 0, 1],
                    "CANON_PLANE_YZ" => [1, 2, 0],
                    _ => [0, 1, 2],
                }
            }
            "SET_G5X_OFFSET" => g5x = to_mm(&numbers[1..]),
            "SET_G92_OFFSET" => g92 = to_mm(&numbers),
            "SET_XY_ROTATION" => rotation = numbers[0],
            "USE_TOOL_LENGTH_OFFSET" => tool = to_mm(&numbers),
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" => {
                let p: [f64; 6] = std::array::from_fn(|k| numbers[k]);
                let kind = if name == "STRAIGHT_TRAVERSE" { Kind::Traverse } else { Kind::Feed };
                moves.push(Canon { kind, end: machine(p, &g5x, &g92, &tool, rotation), tool: [tool[0], tool[1], tool[2]], inch });
            }
            "ARC_FEED" => {
                // first end, second end, first centre, second centre, turns, normal end, a, b, c
                let mut p = [0.0; 6];
                p[plane[0]] = numbers[0];
                p[plane[1]] = numbers[1];
                p[plane[2]] = numbers[5];
                p[3..6].copy_from_slice(&numbers[6..9]);
                let mut c = p;
                c[plane[0]] = numbers[2];
                c[plane[1]] = numbers[3];
                let centre = machine(c, &g5x, &g92, &tool, rotation);
                let kind = Kind::Arc { axes: plane, centre: [centre[plane[0]], centre[plane[1]]], turns: numbers[4] as i32 };
                moves.push(Canon { kind, end: machine(p, &g5x, &g92, &tool, rotation), tool: [tool[0], tool[1], tool[2]], inch });
            }
            _ => {}
        }
    }
    moves
}
