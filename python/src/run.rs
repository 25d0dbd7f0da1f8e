//! Running heavy work without the GIL: on a thread pool of the requested size, while
//! the calling thread watches for Ctrl-C.
//!
//! The work runs on a thread of its own (which hands it to rayon); the calling
//! thread, detached from the interpreter, waits for it and every [`POLL`] takes the
//! GIL back just long enough to run Python's signal handlers. A `KeyboardInterrupt`
//! (or any exception a handler raises) sets the cancel flag that the renderer polls
//! between rows, and comes back out once the work has stopped. Off the main thread
//! the signal check does nothing, and the work simply runs to completion.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use nffrt::limits::MAX_THREADS;
use nffrt::render::Observer;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rayon::ThreadPool;

/// How often the waiting thread checks for signals.
const POLL: Duration = Duration::from_millis(50);
/// The renderer's observer: cancelled once a signal handler raised.
pub struct Cancel(AtomicBool);

impl Cancel {
    /// The flag itself, for the loader's cancellable parse.
    pub fn flag(&self) -> &AtomicBool {
        &self.0
    }
}

impl Observer for Cancel {
    fn cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// A pool of `threads` workers, or `None` for rayon's global pool (one per core).
pub fn pool(threads: Option<usize>) -> PyResult<Option<ThreadPool>> {
    let Some(n) = threads else {
        return Ok(None);
    };
    if !(1..=MAX_THREADS as usize).contains(&n) {
        return Err(PyValueError::new_err(format!(
            "threads={n}: the count goes from 1 to {MAX_THREADS}"
        )));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map(Some)
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start {n} threads: {e}")))
}

/// Runs `work` on `pool` without the GIL, cancelling it through its observer when
/// a signal handler raises; that exception is returned once the work has stopped.
pub fn without_gil<T: Send>(
    py: Python<'_>,
    pool: Option<&ThreadPool>,
    work: impl FnOnce(&Cancel) -> T + Send,
) -> PyResult<T> {
    let cancel = Cancel(AtomicBool::new(false));
    let cancel = &cancel;
    py.detach(|| {
        std::thread::scope(|s| {
            let (done, finished) = mpsc::channel();
            let worker = s.spawn(move || {
                let out = match pool {
                    Some(p) => p.install(|| work(cancel)),
                    None => work(cancel),
                };
                // The receiver outlives this thread (it joins it below).
                let _ = done.send(());
                out
            });
            let mut raised = None;
            while let Err(mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(POLL) {
                if raised.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        cancel.0.store(true, Ordering::Relaxed);
                        raised = Some(e);
                    }
                }
            }
            let out = worker.join().map_err(|panic| {
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                PyRuntimeError::new_err(format!("internal error in nffrt: {what}"))
            })?;
            match raised {
                Some(e) => Err(e),
                None => Ok(out),
            }
        })
    })
}
