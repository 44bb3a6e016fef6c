//! Progress on standard error: a `natura_core::Progress` shown as an
//! `indicatif` bar per stage (the examples include this file for theirs,
//! so both look alike). `indicatif` hides the bars when standard error is not a
//! terminal, so farm logs, output files and standard output are unchanged.

use std::sync::Mutex;

/// A `natura_core::Progress` shown as an `indicatif` bar per stage.
#[derive(Default)]
pub struct Bar {
    bar: Mutex<Option<indicatif::ProgressBar>>,
}

impl Bar {
    /// A bar that shows nothing until a stage starts.
    pub fn new() -> Self {
        Self::default()
    }
}

impl natura::core::Progress for Bar {
    fn start(&self, stage: &str, total: u64) {
        let bar = indicatif::ProgressBar::new(total);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{msg:>12} [{bar:40}] {pos}/{len} {elapsed_precise}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_message(stage.to_owned());
        if let Ok(mut b) = self.bar.lock() {
            *b = Some(bar);
        }
    }

    fn advance(&self, n: u64) {
        if let Ok(b) = self.bar.lock()
            && let Some(b) = b.as_ref()
        {
            b.inc(n);
        }
    }

    fn finish(&self) {
        if let Ok(mut b) = self.bar.lock()
            && let Some(b) = b.take()
        {
            b.finish();
        }
    }
}
