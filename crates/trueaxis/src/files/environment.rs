//! Errors of the environment rather than of the input: a full disk or quota, a permission, a
//! read-only file system, a failing device, memory, an interrupted call. The command line exits
//! with status 3 for them (2 for bad input, 1 for a failed computation) and the Python package
//! raises its own exception, so that a script can tell "fix the input" from "fix the machine it
//! runs on" (docs/reliability.md).

use std::io::ErrorKind;

/// `EIO`: an input/output error of the device (the same number on Linux, macOS and the BSDs).
const EIO: i32 = 5;

/// Whether a system error comes from the environment (module documentation).
pub fn is_environment(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        ErrorKind::PermissionDenied
            | ErrorKind::ReadOnlyFilesystem
            | ErrorKind::StorageFull
            | ErrorKind::QuotaExceeded
            | ErrorKind::FileTooLarge
            | ErrorKind::OutOfMemory
            | ErrorKind::Interrupted
            | ErrorKind::ResourceBusy
            | ErrorKind::StaleNetworkFileHandle
            | ErrorKind::TimedOut
    ) || e.raw_os_error() == Some(EIO)
}

/// The first system error of the environment in the chain of `error` (itself, then its sources).
pub fn environment_cause<'a>(error: &'a (dyn std::error::Error + 'static)) -> Option<&'a std::io::Error> {
    let mut next = Some(error);
    while let Some(e) = next {
        if let Some(io) = e.downcast_ref::<std::io::Error>().filter(|io| is_environment(io)) {
            return Some(io);
        }
        next = e.source();
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn environment_errors_are_found_in_a_chain() {
        let full = crate::data::DataError::Write { path: "t.csv".into(), source: std::io::Error::from(ErrorKind::StorageFull) };
        assert!(environment_cause(&full).is_some());
        let missing = crate::data::DataError::Write { path: "d/t.csv".into(), source: std::io::Error::from(ErrorKind::NotFound) };
        assert!(environment_cause(&missing).is_none());
        assert!(is_environment(&std::io::Error::from_raw_os_error(EIO)));
        assert!(!is_environment(&std::io::Error::from(ErrorKind::InvalidData)));
    }
}
