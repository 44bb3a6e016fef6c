//! Shared helpers for the example programs: command lines (`clap` derive,
//! through [`parse`], [`in_range`] and [`out_dir`]), the clean-up of
//! their outputs on every way out ([`run`], [`Exit`]), an `indicatif`
//! binding of `natura_core::Progress`, and demo data ([`scene`]).
//! Algorithms never live here.
//!
//! A program's files are staged under temporary names (natura-core's
//! `OutputSet` and atomic writes, which register them) and renamed into
//! place at the end. Whatever ends the program — an error returned through
//! [`run`], [`fail`], Ctrl-C or SIGTERM — removes every staged or
//! half-written file first, so nothing is left behind. A closed stdout
//! (`… | head`) ends the program normally.
#![allow(dead_code)]

#[cfg(feature = "volume")]
pub mod cloudshot;
#[cfg(feature = "core")]
pub mod figures;
#[cfg(feature = "core")]
pub mod plot;
#[cfg(feature = "core")]
pub mod scene;
#[cfg(all(feature = "core", feature = "terrain"))]
pub mod tiles;
// The `natura` binary's progress bar, so the examples and the binary show
// the same bars with one implementation.
#[path = "../../cli/progress.rs"]
mod progress;
#[allow(unused_imports)] // not every example shows progress
pub use progress::Bar;

use std::path::PathBuf;
use std::process::ExitCode;
use std::str::FromStr;

/// Why a program stops early: the message for stderr (none for a quiet
/// stop) and the exit status. Any error converts into one with status 2,
/// so a program's body uses `?`.
#[derive(Debug)]
pub struct Exit {
    code: u8,
    message: String,
}

impl Exit {
    /// A stop with `message` and status `code`.
    pub fn new(code: u8, message: impl Into<String>) -> Self {
        Self {
            code,
            message: message.into(),
        }
    }

    /// A normal, silent end (a reader closed stdout).
    pub fn quiet() -> Self {
        Self::new(0, "")
    }
}

impl<E: std::fmt::Display> From<E> for Exit {
    fn from(e: E) -> Self {
        Self::new(2, e.to_string())
    }
}

/// The result of a program's body.
pub type Run = Result<(), Exit>;

/// Removes every file this process has staged or is writing (natura-core's
/// registry of temporary files) and returns how many.
pub fn remove_staged() -> usize {
    natura::core::io::remove_temp_files()
}

/// Installs, once, the interrupt handler: on Ctrl-C or SIGTERM the staged
/// and half-written files are removed and the program exits with status
/// 130.
pub fn install_interrupt_cleanup() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            let n = remove_staged();
            eprintln!("\ninterrupted: removed {n} temporary file(s), outputs left as they were");
            std::process::exit(130);
        });
    });
}

/// Runs a program's body as `fn main() -> ExitCode { common::run(body) }`:
/// with the interrupt clean-up installed; on an error, the staged files
/// are removed, the message printed and its status returned.
pub fn run(body: impl FnOnce() -> Run) -> ExitCode {
    install_interrupt_cleanup();
    let result = body();
    // Every output was committed or dropped (which removes its staging);
    // anything still registered was left by an error path.
    remove_staged();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            if !e.message.is_empty() {
                eprintln!("error: {}", e.message);
            }
            ExitCode::from(e.code)
        }
    }
}

/// Writes `text` to stdout; a closed stdout (`… | head`) is a quiet,
/// normal end ([`Exit::quiet`]), any other failure an error.
pub fn out(text: impl std::fmt::Display) -> Run {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match write!(stdout, "{text}").and_then(|()| stdout.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(Exit::quiet()),
        Err(e) => Err(Exit::new(2, format!("cannot write to stdout: {e}"))),
    }
}

/// [`out`] with a newline.
pub fn outln(text: impl std::fmt::Display) -> Run {
    out(format_args!("{text}\n"))
}

/// Parses the command line into `T` (a `clap` derive): `--help` and
/// `--version` print and exit 0; an unknown flag, a missing value or one
/// that does not parse prints clap's message, which names the flag and the
/// value as typed, and exits 2. Also installs the interrupt clean-up
/// ([`install_interrupt_cleanup`]).
pub fn parse<T: clap::Parser>() -> T {
    install_interrupt_cleanup();
    T::parse()
}

/// A clap value parser for a number in `lo..=hi` (NaN never is): the value
/// is parsed as `T`, and one outside the range is refused with a message
/// clap prints after the flag and the value as the user typed it.
pub fn in_range<T>(
    lo: T,
    hi: T,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: FromStr + PartialOrd + std::fmt::Display + Copy + Send + Sync + 'static,
    T::Err: std::fmt::Display,
{
    move |s: &str| {
        let v: T = s.trim().parse().map_err(|e: T::Err| e.to_string())?;
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(format!("must be in {lo}..={hi}"))
        }
    }
}

/// A clap value parser for `LO,HI`: two numbers (the height-map loader
/// checks that they make a range).
pub fn parse_range(s: &str) -> Result<(f32, f32), String> {
    let v = s
        .split(',')
        .map(|p| p.trim().parse::<f32>().map_err(|e| e.to_string()))
        .collect::<Result<Vec<f32>, String>>()?;
    match v[..] {
        [lo, hi] => Ok((lo, hi)),
        _ => Err("needs LO,HI".to_owned()),
    }
}

/// Creates the output directory given by `--out` (with its parents) and
/// proves it can be written by creating and removing a probe file, before
/// any work starts.
///
/// # Errors
///
/// An [`Exit`] with status 2 naming `--out` and the path when the directory
/// cannot be created or written; nothing is left behind.
pub fn out_dir(dir: &std::path::Path) -> Result<PathBuf, Exit> {
    let refuse = |e: std::io::Error| Exit::new(2, format!("--out {}: {e}", dir.display()));
    std::fs::create_dir_all(dir).map_err(refuse)?;
    let probe = dir.join(format!(".natura-probe-{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(|e| {
            Exit::new(
                2,
                format!(
                    "--out {}: the directory cannot be written: {e}",
                    dir.display()
                ),
            )
        })?;
    std::fs::remove_file(&probe).map_err(refuse)?;
    Ok(dir.to_path_buf())
}

/// A number as a person reads it: plain from 1e-4 to 1e6, otherwise in
/// exponent form (`-1e300`, not three hundred digits).
pub fn short<T>(v: T) -> String
where
    T: std::fmt::Display + std::fmt::LowerExp + Copy + Into<f64>,
{
    let a = v.into().abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e6).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Removes the staged files, prints `msg` to stderr and exits with status
/// 2, for an error where `?` cannot reach (inside a per-pixel closure); a
/// program's body returns an [`Exit`] through [`run`] instead.
pub fn fail(msg: &str) -> ! {
    remove_staged();
    eprintln!("error: {msg}");
    std::process::exit(2);
}

/// Unwraps a result or exits with its error message (removing the staged
/// files first, as [`fail`]).
pub fn check<T, E: std::fmt::Display>(r: Result<T, E>) -> T {
    r.unwrap_or_else(|e| fail(&e.to_string()))
}
