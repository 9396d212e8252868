//! The real-time corrector: no allocation per call (counted by a global allocator), the same result
//! as the pose corrector, status codes for bad input, and the C ABI called from a C program built
//! with gcc against `include/trueaxis.h` and the cdylib.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};
use trueaxis::compensate::realtime::RealtimeStatus;
use trueaxis::compensate::{CorrectionWorkspace, Corrector, RealtimeCorrector};
use trueaxis::errors::ErrorModel;
use trueaxis::machine::{AxisKind, Machine};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(|c| c.get()) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn load(machine: &str, errors: &str) -> (Machine, ErrorModel) {
    let m = Machine::load(format!("examples/machines/{machine}.toml")).unwrap();
    let e = ErrorModel::load(format!("examples/errors/{errors}.toml"), &m).unwrap();
    (m, e)
}

fn poses(n: usize, count: usize) -> Vec<Vec<f64>> {
    (0..count).map(|i| (0..n).map(|k| (((i * 7 + k * 13) % 17) as f64 - 8.0) * [30.0, 25.0, 20.0, 5.0, 40.0][k % 5]).collect()).collect()
}

#[test]
fn a_call_allocates_nothing_and_matches_the_pose_corrector() {
    for (machine, errors, sensors) in [("c600u", "c600u", 0), ("vmc3", "vmc3_backlash", 1), ("kx8five", "kx8five", 0)] {
        let (m, e) = load(machine, errors);
        let mut rt = RealtimeCorrector::new(m.clone(), e.clone()).unwrap();
        assert_eq!(rt.sensor_count(), sensors);
        let n = m.axis_count();
        let mut out = vec![0.0; n];
        let temperatures = vec![22.5; sensors];
        let directions = vec![1i8; n];
        let corrector = Corrector::new(&m, &e);
        let mut ws = CorrectionWorkspace::new(&m);
        let all = poses(n, 50);
        let mut valid = Vec::new();
        for p in &all {
            let mut p = p.clone();
            for (k, a) in m.axes().iter().enumerate() {
                if let Some([lo, hi]) = a.range {
                    p[k] = p[k].clamp(lo, hi);
                }
            }
            valid.push(p);
        }
        // warm up (the workspace is allocated at construction), then count
        rt.correct(&valid[0], &temperatures, &directions, &mut out);
        let mut statuses = Vec::with_capacity(valid.len());
        let mut results = Vec::with_capacity(valid.len() * n);
        COUNTING.with(|c| c.set(true));
        for p in &valid {
            statuses.push(rt.correct(p, &temperatures, &directions, &mut out));
            results.extend_from_slice(&out);
        }
        COUNTING.with(|c| c.set(false));
        assert_eq!(ALLOCATIONS.load(Ordering::Relaxed), 0, "{machine}: allocations during real-time calls");
        assert!(statuses.iter().all(|s| *s == RealtimeStatus::Ok), "{machine}: {statuses:?}");
        for (p, r) in valid.iter().zip(results.chunks(n)) {
            let mut q = vec![0.0; n];
            m.pose_to_internal(p, &mut q);
            let dirs = vec![Some(trueaxis::errors::Direction::Positive); n];
            let c = corrector.correct_state(
                &q,
                &trueaxis::errors::MachineState { directions: Some(&dirs), temperatures: &temperatures },
                &mut ws,
            );
            // the real-time call starts from the previous one (warm start); both stop within the
            // step tolerances of the same fixed point: 0.01 um of a linear axis, 0.1 urad of a
            // rotary one
            for ((a, b), axis) in c.dq_user(&m).iter().zip(r).zip(m.axes()) {
                let tolerance = match axis.kind {
                    AxisKind::Linear => 2e-5,
                    AxisKind::Rotary => 2e-7f64.to_degrees(),
                };
                assert!((a - b).abs() < tolerance, "{machine}: {a} vs {b}");
            }
            assert!(c.residual_position.norm() < 1e-5);
        }
    }
}

#[test]
fn bad_calls_return_status_codes() {
    let (m, e) = load("vmc3", "vmc3_backlash");
    let mut rt = RealtimeCorrector::new(m, e).unwrap();
    let mut out = [0.0; 3];
    assert_eq!(rt.correct(&[0.0, 0.0], &[], &[], &mut out), RealtimeStatus::BadLength);
    assert_eq!(rt.correct(&[0.0, 0.0, 0.0], &[20.0, 21.0], &[], &mut out), RealtimeStatus::BadLength);
    assert_eq!(rt.correct(&[0.0, f64::NAN, 0.0], &[], &[], &mut out), RealtimeStatus::NotFinite);
    assert_eq!(rt.correct(&[10.0, 20.0, -30.0], &[], &[], &mut out), RealtimeStatus::Ok);
    assert!(out.iter().any(|v| v.abs() > 1e-4));
}

#[test]
fn the_c_abi_works_from_c() {
    let gcc_ok = std::process::Command::new("gcc").arg("--version").output().is_ok_and(|o| o.status.success());
    let exe = std::path::PathBuf::from(env!("CARGO_BIN_EXE_trueaxis"));
    // `cargo test` leaves the cdylib in target/<profile>/deps, `cargo build` also in target/<profile>
    let dir = [exe.parent().unwrap().join("deps"), exe.parent().unwrap().to_path_buf()]
        .into_iter()
        .find(|d| d.join("libtrueaxis.so").exists())
        .unwrap_or_else(|| exe.parent().unwrap().to_path_buf());
    if !gcc_ok || !dir.join("libtrueaxis.so").exists() {
        println!("SKIPPED: gcc or {}/libtrueaxis.so not available", dir.display());
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let bin = tmp.path().join("realtime");
    let status = std::process::Command::new("gcc")
        .args(["-std=c99", "-Wall", "-Werror", "-Iinclude", "tests/c/realtime.c", "-o"])
        .arg(&bin)
        .arg(format!("-L{}", dir.display()))
        .arg(format!("-Wl,-rpath,{}", dir.display()))
        .arg("-ltrueaxis")
        .status()
        .unwrap();
    assert!(status.success(), "gcc failed");
    let run = |machine: &str, errors: &str, input: &str| {
        use std::io::Write;
        let mut child = std::process::Command::new(&bin)
            .args([machine, errors])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        child.stdin.take().unwrap().write_all(input.as_bytes()).unwrap();
        let out = child.wait_with_output().unwrap();
        (out.status.code(), String::from_utf8(out.stdout).unwrap())
    };
    let (code, text) = run("examples/machines/c600u.toml", "examples/errors/c600u.toml", "10 20 -30 30 45\n-100 50 -200 -10 270\n");
    assert_eq!(code, Some(0), "{text}");
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "axes 5 sensors 0 first X");
    let (m, e) = load("c600u", "c600u");
    let mut rt = RealtimeCorrector::new(m, e).unwrap();
    for (line, pose) in lines.zip([[10.0, 20.0, -30.0, 30.0, 45.0], [-100.0, 50.0, -200.0, -10.0, 270.0]]) {
        let values: Vec<f64> = line.split_whitespace().skip(2).map(|v| v.parse().unwrap()).collect();
        assert!(line.starts_with("rc 0 "), "{line}");
        let mut out = [0.0; 5];
        assert_eq!(rt.correct(&pose, &[], &[0; 5], &mut out), RealtimeStatus::Ok);
        for (a, b) in values.iter().zip(&out) {
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-9), "{a} vs {b}");
        }
    }
    let (code, text) = run("examples/machines/missing.toml", "examples/errors/c600u.toml", "");
    assert_eq!(code, Some(1));
    assert!(text.starts_with("error: examples/machines/missing.toml: cannot read"), "{text}");
}
