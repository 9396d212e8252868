//! Progress of long runs (the exchange algorithm of an optimal design, an adaptive Monte Carlo
//! budget): a Python callable `progress(done, total)` called from the computation between its
//! steps, e.g. `bar = tqdm(total=...)` with `lambda done, total: bar.update(done - bar.n)`.
//!
//! The computation runs without the GIL; each call takes it for the call only. An exception raised
//! by the callable (or a KeyboardInterrupt, checked at each call) is kept, no further calls are
//! made, and the exception is raised when the run returns: a run split into steps (exchange
//! starts) stops at the next step, one that is not (a Monte Carlo stage) finishes its stage first.

use pyo3::prelude::*;
use std::sync::Mutex;

/// A progress callable and the first exception it raised.
pub struct Progress {
    callable: Option<Py<PyAny>>,
    failure: Mutex<Option<PyErr>>,
}

impl Progress {
    /// From the `progress=` argument (None: no progress).
    pub fn new(callable: Option<&Bound<'_, PyAny>>) -> PyResult<Progress> {
        if let Some(c) = callable {
            if !c.is_callable() {
                return Err(crate::exceptions::input_msg(format!(
                    "progress: expected a callable progress(done, total), got a {}",
                    c.get_type().name()?
                )));
            }
        }
        Ok(Progress { callable: callable.map(|c| c.clone().unbind()), failure: Mutex::new(None) })
    }

    /// True when there is a callable to report to.
    pub fn wanted(&self) -> bool {
        self.callable.is_some()
    }

    /// True once the callable raised (the run should stop at its next step).
    pub fn failed(&self) -> bool {
        self.failure.lock().map(|f| f.is_some()).unwrap_or(true)
    }

    /// Calls `progress(done, total)` (taking the GIL), unless a call already raised.
    pub fn report(&self, done: usize, total: usize) {
        let Some(callable) = &self.callable else { return };
        if self.failed() {
            return;
        }
        let outcome = Python::attach(|py| py.check_signals().and_then(|()| callable.call1(py, (done, total)).map(drop)));
        if let (Err(e), Ok(mut failure)) = (outcome, self.failure.lock()) {
            failure.get_or_insert(e);
        }
    }

    /// The exception a call raised, if any: to be raised once the run has returned.
    pub fn finish(self) -> PyResult<()> {
        match self.failure.into_inner() {
            Ok(Some(e)) => Err(e),
            _ => Ok(()),
        }
    }
}
