//! SIGINT (Ctrl-C), SIGTERM and SIGHUP end a run cleanly: the temporaries it holds are removed
//! (`trueaxis::data::temporaries::remove_live`, which waits for a commit in progress so that a set
//! is never left half renamed), a line says so on stderr, and the process exits with status 3
//! (`exit::ENVIRONMENT`: interrupted). A service (`trueaxis live`), whose normal end is a stop by
//! its supervisor (systemd and containers stop with SIGTERM), says that it stopped and exits with
//! 0 instead. The signals are received by a thread of their own
//! (signal-hook's iterator: the handler only writes to a pipe), so that the clean-up may allocate
//! and lock like any other code. SIGKILL cannot be caught: what it leaves is removed by the next
//! run (docs/reliability.md).

/// Installs the handler; `service`: a stop ends the run normally (status 0).
#[cfg(unix)]
pub fn install(service: bool) {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        // without the handler the signals keep their default action (the run ends; its temporaries
        // are removed by the next run)
        return;
    };
    let _ = std::thread::Builder::new().name("signals".into()).spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let removed = trueaxis::data::temporaries::remove_live();
            let name = match signal {
                SIGINT => "SIGINT",
                SIGTERM => "SIGTERM",
                _ => "SIGHUP",
            };
            let what = match removed {
                0 => "no temporary file to remove".to_string(),
                1 => "removed its temporary file".to_string(),
                n => format!("removed its {n} temporary files"),
            };
            if service {
                eprintln!("trueaxis: stopped by {name}, {what}");
                std::process::exit(0);
            }
            eprintln!("trueaxis: error: interrupted by {name}: stopped, {what}; outputs not yet renamed into place were not written");
            std::process::exit(crate::exit::ENVIRONMENT.into());
        }
    });
}

#[cfg(not(unix))]
pub fn install(_service: bool) {}
