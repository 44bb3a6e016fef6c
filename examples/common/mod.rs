//! Shared helpers for the example programs: flag parsing, an `indicatif`
//! binding of `natura_core::Progress`, and demo data ([`scene`]). Algorithms
//! never live here.
#![allow(dead_code)]

#[cfg(feature = "core")]
pub mod scene;
#[cfg(all(feature = "core", feature = "terrain"))]
pub mod tiles;

use std::path::PathBuf;
use std::str::FromStr;
use std::sync::Mutex;

/// A minimal `--flag value` / `--switch` parser that refuses unknown flags.
pub struct Args {
    program: String,
    rest: Vec<String>,
    known: Vec<(&'static str, &'static str)>,
}

impl Args {
    /// Captures the process arguments. `usage` lines are printed for `--help`.
    ///
    /// Also installs the interrupt handler: on Ctrl-C or SIGTERM the files
    /// being written are removed (none is left half-written or as a
    /// temporary) and the program exits with status 130.
    pub fn from_env() -> Self {
        #[cfg(feature = "core")]
        let _ = ctrlc::set_handler(|| {
            let n = natura::core::io::remove_temp_files();
            eprintln!("\ninterrupted: removed {n} temporary file(s), outputs left as they were");
            std::process::exit(130);
        });
        let mut it = std::env::args();
        let program = it.next().unwrap_or_default();
        Self {
            program,
            rest: it.collect(),
            known: vec![("--help", "print this help")],
        }
    }

    /// Returns whether the switch `name` was given.
    pub fn switch(&mut self, name: &'static str, help: &'static str) -> bool {
        self.known.push((name, help));
        if let Some(i) = self.rest.iter().position(|a| a == name) {
            self.rest.remove(i);
            true
        } else {
            false
        }
    }

    /// Returns the parsed value of `name`, or `default` if absent. Exits with a
    /// message if the value is missing or does not parse.
    pub fn value<T: FromStr>(&mut self, name: &'static str, default: T, help: &'static str) -> T
    where
        T::Err: std::fmt::Display,
    {
        self.optional(name, help).unwrap_or(default)
    }

    /// Returns the parsed value of `name` (or `default`), exiting with a
    /// message naming the flag unless it lies in `range` (NaN never does).
    pub fn ranged<T>(
        &mut self,
        name: &'static str,
        default: T,
        range: std::ops::RangeInclusive<T>,
        help: &'static str,
    ) -> T
    where
        T: FromStr + PartialOrd + std::fmt::Display,
        T::Err: std::fmt::Display,
    {
        let v = self.value(name, default, help);
        if !range.contains(&v) {
            fail(&format!(
                "{name} {v}: must be in {}..={}",
                range.start(),
                range.end()
            ));
        }
        v
    }

    /// Returns the parsed value of `name` if given.
    pub fn optional<T: FromStr>(&mut self, name: &'static str, help: &'static str) -> Option<T>
    where
        T::Err: std::fmt::Display,
    {
        self.known.push((name, help));
        let i = self.rest.iter().position(|a| a == name)?;
        if i + 1 >= self.rest.len() {
            fail(&format!("{name} needs a value"));
        }
        let v = self.rest.remove(i + 1);
        self.rest.remove(i);
        match v.parse() {
            Ok(x) => Some(x),
            Err(e) => fail(&format!("{name} {v}: {e}")),
        }
    }

    /// Returns the first argument that is not a flag (call after reading
    /// every flag, so flag values are already taken).
    pub fn positional(&mut self) -> Option<String> {
        let i = self.rest.iter().position(|a| !a.starts_with('-'))?;
        Some(self.rest.remove(i))
    }

    /// The output directory (`--out`, default `default`), created if needed.
    pub fn out_dir(&mut self, default: &str) -> PathBuf {
        let dir: PathBuf = self.value("--out", PathBuf::from(default), "output directory");
        if let Err(e) = std::fs::create_dir_all(&dir) {
            fail(&format!(
                "cannot create output directory {}: {e}",
                dir.display()
            ));
        }
        dir
    }

    /// Call after reading every flag: prints help or refuses leftovers.
    pub fn finish(self) {
        if self.rest.iter().any(|a| a == "--help" || a == "-h") {
            println!("usage: {} [flags]", self.program);
            for (k, h) in &self.known {
                println!("  {k:<14} {h}");
            }
            std::process::exit(0);
        }
        if let Some(a) = self.rest.first() {
            fail(&format!("unknown argument `{a}` (try --help)"));
        }
    }
}

/// Prints `msg` to stderr and exits with status 2.
pub fn fail(msg: &str) -> ! {
    eprintln!("error: {msg}");
    std::process::exit(2);
}

/// Unwraps a result or exits with its error message.
pub fn check<T, E: std::fmt::Display>(r: Result<T, E>) -> T {
    r.unwrap_or_else(|e| fail(&e.to_string()))
}

/// A `natura_core::Progress` shown as an `indicatif` bar per stage.
pub struct Bar {
    bar: Mutex<Option<indicatif::ProgressBar>>,
}

impl Bar {
    pub fn new() -> Self {
        Self {
            bar: Mutex::new(None),
        }
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
        if let Ok(b) = self.bar.lock() {
            if let Some(b) = b.as_ref() {
                b.inc(n);
            }
        }
    }

    fn finish(&self) {
        if let Ok(mut b) = self.bar.lock() {
            if let Some(b) = b.take() {
                b.finish();
            }
        }
    }
}
