//! Progress reporting for long-running library functions.

/// A sink for progress reports from long-running work.
///
/// Library functions that may take more than a moment take a `&dyn Progress`
/// and call [`start`](Progress::start) once per stage, then
/// [`advance`](Progress::advance) as units of work complete (possibly from
/// several threads at once), then [`finish`](Progress::finish). Reports never
/// influence results. Examples bind this to an `indicatif` bar; pass
/// [`NoProgress`] when you do not care.
pub trait Progress: Sync {
    /// A stage named `stage` begins, with `total` units of work (0 if unknown).
    fn start(&self, stage: &str, total: u64);
    /// `n` more units of the current stage are done.
    fn advance(&self, n: u64);
    /// The current stage is complete.
    fn finish(&self);
}

/// A [`Progress`] that ignores every report.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    #[inline]
    fn start(&self, _stage: &str, _total: u64) {}
    #[inline]
    fn advance(&self, _n: u64) {}
    #[inline]
    fn finish(&self) {}
}

/// A [`Progress`] that counts what it is told; useful in tests and for logging.
#[derive(Debug, Default)]
pub struct CountingProgress {
    stages: std::sync::Mutex<Vec<(String, u64)>>,
    done: std::sync::atomic::AtomicU64,
    finished: std::sync::atomic::AtomicU64,
}

impl CountingProgress {
    /// A fresh counter.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The `(stage, total)` pairs started so far, in order.
    #[must_use]
    pub fn stages(&self) -> Vec<(String, u64)> {
        self.stages.lock().map(|s| s.clone()).unwrap_or_default()
    }

    /// Total units advanced over all stages.
    #[must_use]
    pub fn advanced(&self) -> u64 {
        self.done.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Number of stages finished.
    #[must_use]
    pub fn finished(&self) -> u64 {
        self.finished.load(std::sync::atomic::Ordering::Relaxed)
    }
}

impl Progress for CountingProgress {
    fn start(&self, stage: &str, total: u64) {
        if let Ok(mut s) = self.stages.lock() {
            s.push((stage.to_owned(), total));
        }
    }
    fn advance(&self, n: u64) {
        self.done.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
    }
    fn finish(&self) {
        self.finished
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }
}
