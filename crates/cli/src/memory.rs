//! Memory that cannot be had ends the run with a message and status 3 (`exit::ENVIRONMENT`),
//! not with an abort (status 134, no word): the global allocator is the system's, watched. When
//! an allocation fails (a limit such as `ulimit -v`, or a system without overcommit), it releases
//! a reserve kept for the purpose, removes the run's temporaries (`trueaxis::data::temporaries`,
//! unless the failing thread holds their registry), prints what was asked for, and exits.
//! A system that overcommits memory (Linux by default) may instead stop the process with SIGKILL
//! (the kernel's out-of-memory killer), which nothing can catch; its temporaries are then removed
//! by the next run (docs/reliability.md).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicPtr, Ordering};

/// The system allocator, with a report instead of an abort when it fails.
pub struct Watched;

/// The reserve released to report a failure (enough for the clean-up and the message).
const RESERVE: usize = 4 << 20;
static RESERVED: AtomicPtr<u8> = AtomicPtr::new(std::ptr::null_mut());

fn reserve_layout() -> Layout {
    Layout::from_size_align(RESERVE, 16).expect("a valid layout")
}

/// Sets the reserve aside; called first thing in `main`.
pub fn reserve() {
    // SAFETY: a non-zero size and a valid alignment
    let p = unsafe { System.alloc(reserve_layout()) };
    RESERVED.store(p, Ordering::SeqCst);
}

/// The report of a failed allocation of `size` bytes; never returns.
#[cold]
fn out_of_memory(size: usize) -> ! {
    let reserve = RESERVED.swap(std::ptr::null_mut(), Ordering::SeqCst);
    if !reserve.is_null() {
        // SAFETY: allocated by `reserve` with this layout and released once (swapped out above)
        unsafe { System.dealloc(reserve, reserve_layout()) };
    }
    let removed = trueaxis::data::temporaries::try_remove_live();
    let mut buffer = [0u8; 400];
    let mut text = &mut buffer[..];
    let mib = size as f64 / (1u64 << 20) as f64;
    let cleaned = match removed {
        Some(_) => "its temporary files were removed",
        None => "its temporary files are removed by the next run",
    };
    use std::io::Write;
    let _ = writeln!(
        text,
        "trueaxis: error: out of memory: {mib:.1} MiB more could not be allocated (the limit of this process, `ulimit -v`, or the memory of the machine); the run stopped, {cleaned}"
    );
    let len = 400 - text.len();
    // SAFETY: writes `len` initialised bytes of `buffer` to stderr, then ends the process without
    // running anything else (no allocation, no lock)
    unsafe {
        libc::write(2, buffer.as_ptr().cast(), len);
        libc::_exit(crate::exit::ENVIRONMENT.into())
    }
}

// SAFETY: every call is forwarded to the system allocator unchanged; only a failed allocation (a
// null pointer) is turned into the report above, which does not return.
unsafe impl GlobalAlloc for Watched {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(layout);
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = System.realloc(ptr, layout, new_size);
        if p.is_null() {
            out_of_memory(new_size);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}
