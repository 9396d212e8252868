//! C ABI of the real-time corrector (header `include/trueaxis.h`): create a corrector from a machine
//! file and an error-values file, call it once per servo cycle with the axis positions, free it.
//! Every function catches panics; none unwinds into C.

use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use trueaxis::compensate::realtime::{RealtimeCorrector, RealtimeStatus};
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;

/// Copies `message` into the caller's buffer (NUL-terminated, truncated to fit).
unsafe fn write_message(message: &str, buffer: *mut c_char, len: usize) {
    if buffer.is_null() || len == 0 {
        return;
    }
    let bytes = message.as_bytes();
    let n = bytes.len().min(len - 1);
    std::ptr::copy_nonoverlapping(bytes.as_ptr(), buffer as *mut u8, n);
    *buffer.add(n) = 0;
}

fn load(machine_path: &CStr, errors_path: &CStr) -> Result<RealtimeCorrector, String> {
    let machine_path = machine_path.to_str().map_err(|_| "the machine path is not UTF-8".to_string())?;
    let errors_path = errors_path.to_str().map_err(|_| "the error-values path is not UTF-8".to_string())?;
    let machine = Machine::load(machine_path).map_err(|e| e.to_string())?;
    let errors = ErrorModel::load(errors_path, &machine).map_err(|e| e.to_string())?;
    RealtimeCorrector::new(machine, errors).map_err(|e| e.to_string())
}

/// Creates a corrector from a machine TOML and an error-values TOML. Returns NULL on failure and
/// writes the reason into `error` (at most `error_len` bytes, NUL-terminated) when it is not NULL.
///
/// # Safety
/// `machine_path` and `errors_path` must be NUL-terminated strings; `error` NULL or writable for
/// `error_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn trueaxis_corrector_new(
    machine_path: *const c_char,
    errors_path: *const c_char,
    error: *mut c_char,
    error_len: usize,
) -> *mut RealtimeCorrector {
    if machine_path.is_null() || errors_path.is_null() {
        write_message("a path is NULL", error, error_len);
        return std::ptr::null_mut();
    }
    let result = catch_unwind(|| load(CStr::from_ptr(machine_path), CStr::from_ptr(errors_path)));
    match result {
        Ok(Ok(c)) => Box::into_raw(Box::new(c)),
        Ok(Err(message)) => {
            write_message(&message, error, error_len);
            std::ptr::null_mut()
        }
        Err(_) => {
            write_message("internal error while loading", error, error_len);
            std::ptr::null_mut()
        }
    }
}

/// Frees a corrector (NULL is ignored).
///
/// # Safety
/// `corrector` must come from [`trueaxis_corrector_new`] and not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn trueaxis_corrector_free(corrector: *mut RealtimeCorrector) {
    if !corrector.is_null() {
        drop(Box::from_raw(corrector));
    }
}

/// Forgets the previous call: the next call starts cold (NULL is ignored).
///
/// # Safety
/// `corrector` must be NULL or a live corrector.
#[no_mangle]
pub unsafe extern "C" fn trueaxis_corrector_reset(corrector: *mut RealtimeCorrector) {
    if let Some(c) = corrector.as_mut() {
        c.reset();
    }
}

/// Number of axes (length of the position and correction arrays); -4 for NULL.
///
/// # Safety
/// `corrector` must be NULL or a live corrector.
#[no_mangle]
pub unsafe extern "C" fn trueaxis_corrector_axis_count(corrector: *const RealtimeCorrector) -> i32 {
    corrector.as_ref().map_or(RealtimeStatus::NullPointer as i32, |c| c.axis_count() as i32)
}

/// Number of temperatures a call expects; -4 for NULL.
///
/// # Safety
/// `corrector` must be NULL or a live corrector.
#[no_mangle]
pub unsafe extern "C" fn trueaxis_corrector_sensor_count(corrector: *const RealtimeCorrector) -> i32 {
    corrector.as_ref().map_or(RealtimeStatus::NullPointer as i32, |c| c.sensor_count() as i32)
}

/// Letter of axis `index` (canonical order X Y Z U V W A B C), or 0 when out of range.
///
/// # Safety
/// `corrector` must be NULL or a live corrector.
#[no_mangle]
pub unsafe extern "C" fn trueaxis_corrector_axis_letter(corrector: *const RealtimeCorrector, index: usize) -> c_char {
    corrector.as_ref().and_then(|c| c.machine().axes().get(index)).map_or(0, |a| a.letter as c_char)
}

/// Corrections (mm, deg; added to the set-points) for the axis positions `positions` (mm, deg).
/// `temperatures` (degC, one per sensor) and `directions` (+1, -1, 0 per axis) may be NULL (20 degC,
/// at rest). Returns 0, or a negative `RealtimeStatus` code; on every code but 0 the corrections are
/// all zero (when `corrector` and `corrections` are not NULL). Allocation-free.
///
/// # Safety
/// `positions` and `corrections` must hold `axis_count` doubles, `temperatures` `sensor_count`
/// doubles and `directions` `axis_count` bytes, when not NULL.
#[no_mangle]
pub unsafe extern "C" fn trueaxis_correct(
    corrector: *mut RealtimeCorrector,
    positions: *const f64,
    temperatures: *const f64,
    directions: *const i8,
    corrections: *mut f64,
) -> i32 {
    let Some(c) = corrector.as_mut() else { return RealtimeStatus::NullPointer as i32 };
    if corrections.is_null() {
        return RealtimeStatus::NullPointer as i32;
    }
    let n = c.axis_count();
    let out = std::slice::from_raw_parts_mut(corrections, n);
    if positions.is_null() {
        out.fill(0.0);
        return RealtimeStatus::NullPointer as i32;
    }
    let positions = std::slice::from_raw_parts(positions, n);
    let temperatures: &[f64] = if temperatures.is_null() { &[] } else { std::slice::from_raw_parts(temperatures, c.sensor_count()) };
    let directions: &[i8] = if directions.is_null() { &[] } else { std::slice::from_raw_parts(directions, n) };
    match catch_unwind(AssertUnwindSafe(|| c.correct(positions, temperatures, directions, out) as i32)) {
        Ok(status) => status,
        Err(_) => {
            c.reset();
            std::slice::from_raw_parts_mut(corrections, n).fill(0.0);
            RealtimeStatus::NotConverged as i32
        }
    }
}
