//! Progress reports of long calls, forwarded to a Python callable: natura's
//! [`Progress`] sink (the one the examples bind to an `indicatif` bar)
//! calling `callback(stage, done, total)` with the GIL taken for the call.

use std::sync::Mutex;

use natura_core::Progress;
use pyo3::prelude::*;

/// The stage being reported and the units done in it.
#[derive(Debug, Default)]
struct State {
    stage: String,
    total: u64,
    done: u64,
    /// The first exception the callback raised (later reports are dropped).
    error: Option<PyErr>,
}

/// A [`Progress`] that calls a Python `callback(stage, done, total)` on
/// every report: once when a stage starts (`done` 0), after each unit of
/// work (rows, tiles, slices, steps: whatever the Rust stage counts), and
/// once when it finishes (`done == total`). Reports from several threads
/// are serialised, so `done` never goes backwards within a stage. An
/// exception raised by the callback stops further reports and is raised
/// by [`PyProgress::finish_call`] once the Rust work has returned (the work
/// itself cannot be interrupted halfway).
#[derive(Debug)]
pub struct PyProgress {
    callback: Option<Py<PyAny>>,
    state: Mutex<State>,
}

impl PyProgress {
    /// Reports to `callback`, or nowhere when it is `None`.
    #[must_use]
    pub fn new(callback: Option<Py<PyAny>>) -> Self {
        Self {
            callback,
            state: Mutex::new(State::default()),
        }
    }

    fn report(&self, update: impl FnOnce(&mut State)) {
        let Some(cb) = &self.callback else { return };
        // The lock is taken before the GIL, never the other way round: a
        // thread holding the GIL never waits for this lock.
        let Ok(mut s) = self.state.lock() else { return };
        update(&mut s);
        if s.error.is_some() {
            return;
        }
        let (stage, done, total) = (s.stage.clone(), s.done, s.total);
        let result = Python::attach(|py| cb.call1(py, (stage, done, total)).map(drop));
        if let Err(e) = result {
            s.error = Some(e);
        }
    }

    /// The exception the callback raised, if any, else `result`.
    ///
    /// # Errors
    /// The callback's first exception, or `result`'s error.
    pub fn finish_call<T>(self, result: PyResult<T>) -> PyResult<T> {
        let state = self.state.into_inner().unwrap_or_default();
        match state.error {
            Some(e) => Err(e),
            None => result,
        }
    }
}

impl Progress for PyProgress {
    fn start(&self, stage: &str, total: u64) {
        self.report(|s| {
            stage.clone_into(&mut s.stage);
            s.total = total;
            s.done = 0;
        });
    }

    fn advance(&self, n: u64) {
        self.report(|s| s.done = s.done.saturating_add(n));
    }

    fn finish(&self) {
        self.report(|s| s.done = s.done.max(s.total));
    }
}
