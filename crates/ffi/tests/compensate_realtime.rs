//! The real-time corrector: no allocation per call (counted by a global allocator), the same result
//! as the pose corrector, status codes for bad input, and the C ABI called from a C program built
//! with gcc against `include/trueaxis.h` and the cdylib.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};
use trueaxis::compensate::realtime::RealtimeStatus;
use trueaxis::compensate::{CorrectionWorkspace, Corrector, RealtimeCorrector};
use trueaxis::error_model::ErrorModel;
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
    let m = Machine::load(format!("../../examples/machines/{machine}.toml")).unwrap();
    let e = ErrorModel::load(format!("../../examples/errors/{errors}.toml"), &m).unwrap();
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
            let dirs = vec![Some(trueaxis::error_model::Direction::Positive); n];
            let c = corrector.correct_state(
                &q,
                &trueaxis::error_model::MachineState { directions: Some(&dirs), temperatures: &temperatures },
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
fn bad_calls_return_status_codes_and_leave_zeros() {
    let (m, e) = load("vmc3", "vmc3_backlash");
    let mut rt = RealtimeCorrector::new(m, e).unwrap();
    let mut out = [0.0; 3];
    // every failing status leaves zeros, never the previous call's corrections
    let mut after_a_good_call = |rt: &mut RealtimeCorrector, positions: &[f64], temperatures: &[f64]| {
        assert_eq!(rt.correct(&[10.0, 20.0, -30.0], &[], &[], &mut out), RealtimeStatus::Ok);
        assert!(out.iter().any(|v| v.abs() > 1e-4));
        let status = rt.correct(positions, temperatures, &[], &mut out);
        assert_eq!(out, [0.0; 3], "{status:?}");
        status
    };
    assert_eq!(after_a_good_call(&mut rt, &[0.0, 0.0, 0.0], &[20.0, 21.0]), RealtimeStatus::BadLength);
    assert_eq!(after_a_good_call(&mut rt, &[0.0, f64::NAN, 0.0], &[]), RealtimeStatus::NotFinite);
    assert_eq!(after_a_good_call(&mut rt, &[0.0, 0.0, 0.0], &[f64::INFINITY]), RealtimeStatus::NotFinite);
    // a pose the solve cannot reach within the iterations: 1 iteration for a 12 um error
    let (m, e) = load("vmc3", "vmc3");
    let options = trueaxis::compensate::CorrectionOptions { max_iterations: 0, ..Default::default() };
    let mut rt = RealtimeCorrector::new(m, e).unwrap().with_options(options);
    out = [1.0; 3];
    assert_eq!(rt.correct(&[-400.0, 0.0, -100.0], &[], &[], &mut out), RealtimeStatus::NotConverged);
    assert_eq!(out, [0.0; 3]);
    // a correction beyond the machine's limit: refused with zeros, never clipped; within it, Ok
    let (m, e) = load("vmc3", "vmc3");
    // the corner's X correction is 12.2 um, the origin's corrections at most 8.0 um
    let limits = trueaxis::compensate::export::Limits::with_overrides(&m, Some(10.0), None).unwrap();
    let mut rt = RealtimeCorrector::new(m, e).unwrap().with_limits(limits);
    out = [1.0; 3];
    assert_eq!(rt.correct(&[-400.0, 0.0, -100.0], &[], &[], &mut out), RealtimeStatus::BeyondLimit);
    assert_eq!(out, [0.0; 3]);
    assert_eq!(rt.correct(&[0.0, 0.0, 0.0], &[], &[], &mut out), RealtimeStatus::Ok);
    assert!(out.iter().all(|v| v.abs() * 1e3 <= 10.0) && out.iter().any(|v| v.abs() * 1e3 > 5.0), "{out:?}");
    // through the C ABI, called from Rust: the same
    use std::ffi::CString;
    use trueaxis_rt::{trueaxis_correct, trueaxis_corrector_free, trueaxis_corrector_new};
    let (mp, ep) = (CString::new("../../examples/machines/vmc3.toml").unwrap(), CString::new("../../examples/errors/vmc3.toml").unwrap());
    unsafe {
        let c = trueaxis_corrector_new(mp.as_ptr(), ep.as_ptr(), std::ptr::null_mut(), 0);
        assert!(!c.is_null());
        let mut corrections = [0.0f64; 3];
        let good = [10.0, 20.0, -30.0];
        assert_eq!(trueaxis_correct(c, good.as_ptr(), std::ptr::null(), std::ptr::null(), corrections.as_mut_ptr()), 0);
        assert!(corrections.iter().any(|v| v.abs() > 1e-4));
        let bad = [10.0, f64::NAN, -30.0];
        assert_eq!(trueaxis_correct(c, bad.as_ptr(), std::ptr::null(), std::ptr::null(), corrections.as_mut_ptr()), -2);
        assert_eq!(corrections, [0.0; 3]);
        assert_eq!(trueaxis_correct(c, good.as_ptr(), std::ptr::null(), std::ptr::null(), corrections.as_mut_ptr()), 0);
        assert_eq!(trueaxis_correct(c, std::ptr::null(), std::ptr::null(), std::ptr::null(), corrections.as_mut_ptr()), -4);
        assert_eq!(corrections, [0.0; 3]);
        trueaxis_corrector_free(c);
    }
    // the machine file's [limits] reaches the C ABI: vmc3 with a 5 um limit refuses the 12 um corner
    let dir = std::env::temp_dir().join(format!("trueaxis-rt-limits-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string("../../examples/machines/vmc3.toml").unwrap() + "\n[limits]\ncorrection_um = 5\n";
    std::fs::write(dir.join("m.toml"), text).unwrap();
    let mp = CString::new(dir.join("m.toml").to_str().unwrap()).unwrap();
    unsafe {
        let c = trueaxis_corrector_new(mp.as_ptr(), ep.as_ptr(), std::ptr::null_mut(), 0);
        assert!(!c.is_null());
        let mut corrections = [1.0f64; 3];
        let corner = [-400.0, 0.0, -100.0];
        assert_eq!(trueaxis_correct(c, corner.as_ptr(), std::ptr::null(), std::ptr::null(), corrections.as_mut_ptr()), -5);
        assert_eq!(corrections, [0.0; 3]);
        trueaxis_corrector_free(c);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn along_a_servo_path_a_call_costs_one_exact_chain_evaluation() {
    // poses 1 ms apart at 100 mm/s and 30 deg/s: each call starts from the previous correction,
    // extrapolated along the path, and stops when the exact residual there is below 0.01 um and the
    // next step below the tolerances; a cold solve needs the error and a check (2), 3 on a 5-axis
    // machine whose large rotary corrections leave a second-order residual after the first step
    for (machine, errors, servo_mean, cold_max) in [("vmc3", "vmc3", 1.001, 2), ("c600u", "c600u", 1.3, 3), ("kx8five", "kx8five", 1.05, 3)]
    {
        let (m, e) = load(machine, errors);
        let n = m.axis_count();
        let mut rt = RealtimeCorrector::new(m.clone(), e.clone()).unwrap();
        let corrector = Corrector::new(&m, &e);
        let mut ws = CorrectionWorkspace::new(&m);
        let mut out = vec![0.0; n];
        let (mut calls, mut evaluations, mut cold_worst) = (0, 0, 0);
        for i in 0..4000 {
            let pose: Vec<f64> = m
                .axes()
                .iter()
                .enumerate()
                .map(|(k, a)| {
                    let [lo, hi] = a.range.unwrap_or([0.0, 360.0]);
                    let speed = if a.kind == AxisKind::Rotary { 0.03 } else { 0.1 };
                    let s = (i as f64 * speed / (hi - lo) + 0.3 * k as f64).rem_euclid(2.0);
                    lo + (hi - lo) * if s < 1.0 { s } else { 2.0 - s }
                })
                .collect();
            assert_eq!(rt.correct(&pose, &[], &[], &mut out), RealtimeStatus::Ok);
            let c = rt.last().unwrap();
            assert!(c.residual_position.norm() < 1e-5);
            calls += 1;
            evaluations += c.evaluations;
            if i % 40 == 0 {
                let mut q = vec![0.0; n];
                m.pose_to_internal(&pose, &mut q);
                cold_worst = cold_worst.max(corrector.correct(&q, &mut ws).evaluations);
            }
        }
        let mean = evaluations as f64 / calls as f64;
        eprintln!("{machine}: {mean:.3} exact-chain evaluations per call along the path, cold at most {cold_worst}");
        assert!(mean <= servo_mean, "{machine}: {mean} evaluations per call");
        assert!(cold_worst <= cold_max, "{machine}: {cold_worst}");
    }
}

#[test]
fn the_c_abi_works_from_c() {
    let gcc_ok = std::process::Command::new("gcc").arg("--version").output().is_ok_and(|o| o.status.success());
    // `cargo test` builds the cdylib beside this test's executable (target/<profile>/deps)
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().unwrap().to_path_buf();
    if !gcc_ok || !dir.join("libtrueaxis_rt.so").exists() {
        println!("SKIPPED: gcc or {}/libtrueaxis_rt.so not available", dir.display());
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let bin = tmp.path().join("realtime");
    let status = std::process::Command::new("gcc")
        .args(["-std=c99", "-Wall", "-Werror", "-Iinclude", "tests/c/realtime.c", "-o"])
        .arg(&bin)
        .arg(format!("-L{}", dir.display()))
        .arg(format!("-Wl,-rpath,{}", dir.display()))
        .arg("-ltrueaxis_rt")
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
    let (code, text) =
        run("../../examples/machines/c600u.toml", "../../examples/errors/c600u.toml", "10 20 -30 30 45\n-100 50 -200 -10 270\n");
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
    let (code, text) = run("../../examples/machines/missing.toml", "../../examples/errors/c600u.toml", "");
    assert_eq!(code, Some(1));
    assert!(text.starts_with("error: ../../examples/machines/missing.toml: cannot read"), "{text}");
}
