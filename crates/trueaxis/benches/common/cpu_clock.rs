//! CPU time from the Linux clocks (`clock_gettime`), shared by the benchmarks
//! (`common/servo.rs`) and the cost examples (`examples/kernel_cost.rs`, `examples/mc_cost.rs`):
//! on a machine shared with other processes the CPU time is what a computation costs, the wall
//! time includes the waits for a core.
#![allow(dead_code)]

/// `CLOCK_PROCESS_CPUTIME_ID`: all the threads of the process.
pub const PROCESS: i32 = 2;
/// `CLOCK_THREAD_CPUTIME_ID`: the calling thread.
pub const THREAD: i32 = 3;

/// CPU time (ns) of `clock` ([`PROCESS`] or [`THREAD`]); `None` off Linux or on an error.
#[cfg(target_os = "linux")]
pub fn cpu_ns(clock: i32) -> Option<f64> {
    #[repr(C)]
    struct Timespec {
        tv_sec: std::ffi::c_long,
        tv_nsec: std::ffi::c_long,
    }
    extern "C" {
        fn clock_gettime(clock: std::ffi::c_int, tp: *mut Timespec) -> std::ffi::c_int;
    }
    let mut t = Timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes one timespec into `t`
    let status = unsafe { clock_gettime(clock, &mut t) };
    (status == 0).then_some(t.tv_sec as f64 * 1e9 + t.tv_nsec as f64)
}

#[cfg(not(target_os = "linux"))]
pub fn cpu_ns(_clock: i32) -> Option<f64> {
    None
}
