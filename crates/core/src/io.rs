//! Crash-safe file writing: write to a temporary name beside the target, then rename.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{CoreError, Result};

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Temporary files currently being written or staged by this process, so an
/// interrupted run can remove them ([`remove_temp_files`]).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Records `tmp` as a live temporary file.
pub(crate) fn track(tmp: &Path) {
    live().push(tmp.to_path_buf());
}

/// Forgets `tmp` (renamed into place or removed).
pub(crate) fn untrack(tmp: &Path) {
    let mut l = live();
    if let Some(i) = l.iter().position(|p| p == tmp) {
        l.swap_remove(i);
    }
}

/// Removes every temporary file this process is writing or has staged in an
/// uncommitted [`OutputSet`], and returns how many it removed.
///
/// Call it from an interrupt handler (for example one installed with the
/// `ctrlc` crate) before exiting, so a run stopped with Ctrl-C leaves no
/// `.natura-tmp-…` files behind. Files already renamed into place are kept.
pub fn remove_temp_files() -> usize {
    let mut l = live();
    let n = l.iter().filter(|p| std::fs::remove_file(p).is_ok()).count();
    l.clear();
    n
}

/// The temporary path used while writing `path`: a hidden sibling in the same
/// directory (so the final rename never crosses file systems).
fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(
        ".natura-tmp-{}-{unique}-{name}",
        std::process::id()
    ))
}

/// Writes a file through `write`, atomically: the bytes go to a temporary file
/// beside `path`, which is flushed, synced and renamed over `path` only if
/// `write` succeeds. On any error the temporary file is removed and `path` is
/// untouched, so a crash or a failed encode never leaves a half-written file.
///
/// `write` returns a problem description on failure; it is reported as
/// [`CoreError::Format`] naming `path` (or [`CoreError::Io`] for OS errors).
///
/// # Errors
///
/// Returns [`CoreError::Format`] naming `path` if it is not a file path or is
/// an existing directory, or if `write` reports an encoding problem;
/// [`CoreError::Io`] naming it if the OS refuses to create, write, sync or
/// rename the file.
pub fn write_atomic<F>(path: impl AsRef<Path>, write: F) -> Result<()>
where
    F: FnOnce(&mut BufWriter<File>) -> std::result::Result<(), WriteError>,
{
    write_atomic_impl(path.as_ref(), Box::new(write))
}

/// The encoder a [`write_atomic`] call runs, as a trait object.
type Encoder<'a> =
    Box<dyn FnOnce(&mut BufWriter<File>) -> std::result::Result<(), WriteError> + 'a>;

/// The body of [`write_atomic`]: not generic, so it is compiled once, here,
/// and not again for every path type and encoder of every crate that calls it.
fn write_atomic_impl(path: &Path, write: Encoder<'_>) -> Result<()> {
    if path.file_name().is_none() {
        return Err(CoreError::format(path, "not a file path"));
    }
    refuse_directory(path)?;
    let tmp = temp_path(path);
    track(&tmp);
    let result = (|| {
        let file = File::create(&tmp).map_err(|e| CoreError::io(path, e))?;
        let mut w = BufWriter::new(file);
        write(&mut w).map_err(|e| match e {
            WriteError::Io(e) => CoreError::io(path, e),
            WriteError::Encode(m) => CoreError::format(path, m),
        })?;
        let file = w
            .into_inner()
            .map_err(|e| CoreError::io(path, e.into_error()))?;
        file.sync_all().map_err(|e| CoreError::io(path, e))?;
        std::fs::rename(&tmp, path).map_err(|e| CoreError::io(path, e))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    untrack(&tmp);
    result
}

/// Refuses a target that exists as a directory (a rename over it would fail
/// only after all the work).
fn refuse_directory(path: &Path) -> Result<()> {
    if path.is_dir() {
        return Err(CoreError::format(path, "is a directory, not a file"));
    }
    Ok(())
}

/// Writes `bytes` to `path` atomically (see [`write_atomic`]).
///
/// # Errors
///
/// As [`write_atomic`].
pub fn write_bytes_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<()> {
    write_atomic(path, |w| w.write_all(bytes).map_err(WriteError::Io))
}

/// Checks, before any long computation, that a file can be created at `path`:
/// the parent directory exists and is writable, and `path` is not a
/// directory. Nothing is left behind.
///
/// # Errors
///
/// Returns [`CoreError::Format`] naming `path` if it is a directory, and
/// [`CoreError::Io`] naming it if a file cannot be created beside it.
pub fn check_writable(path: impl AsRef<Path>) -> Result<()> {
    let path = path.as_ref();
    if path.file_name().is_none() {
        return Err(CoreError::format(path, "not a file path"));
    }
    refuse_directory(path)?;
    let tmp = temp_path(path);
    match File::create(&tmp) {
        Ok(_) => {
            let _ = std::fs::remove_file(&tmp);
            Ok(())
        }
        Err(e) => Err(CoreError::io(path, e)),
    }
}

/// Failure inside a [`write_atomic`] callback.
#[derive(Debug)]
pub enum WriteError {
    /// The OS refused a write.
    Io(std::io::Error),
    /// An encoder refused the data (reason given).
    Encode(String),
}

impl From<std::io::Error> for WriteError {
    fn from(e: std::io::Error) -> Self {
        WriteError::Io(e)
    }
}

/// Reads a whole file, mapping OS errors to [`CoreError::Io`] naming the file.
///
/// # Errors
///
/// Returns [`CoreError::Io`] naming `path` if it cannot be opened or read.
pub fn read_file(path: impl AsRef<Path>) -> Result<Vec<u8>> {
    let path = path.as_ref();
    std::fs::read(path).map_err(|e| CoreError::io(path, e))
}

/// Reads at most `limit` bytes of a file (or stream) from its start, so an
/// endless or oversized input cannot exhaust memory; compare the length with
/// what was expected to detect a longer file.
///
/// # Errors
///
/// Returns [`CoreError::Io`] naming `path` if it cannot be opened or read.
pub fn read_file_at_most(path: impl AsRef<Path>, limit: u64) -> Result<Vec<u8>> {
    use std::io::Read;
    let path = path.as_ref();
    let file = File::open(path).map_err(|e| CoreError::io(path, e))?;
    let mut bytes = Vec::new();
    file.take(limit)
        .read_to_end(&mut bytes)
        .map_err(|e| CoreError::io(path, e))?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("natura-core-io-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn failed_write_leaves_nothing() {
        let p = scratch("fail.bin");
        std::fs::write(&p, b"old").unwrap();
        let err = write_atomic(&p, |w| {
            w.write_all(b"partial")?;
            Err(WriteError::Encode("encoder refused".into()))
        })
        .unwrap_err();
        assert!(err.to_string().contains("encoder refused"));
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        let dir = p.parent().unwrap();
        let leftovers: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with(".natura-tmp"))
            .collect();
        assert!(leftovers.is_empty());
    }

    #[test]
    fn successful_write_replaces() {
        let p = scratch("ok.bin");
        write_bytes_atomic(&p, b"new").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
    }

    #[test]
    fn unwritable_directory_is_reported() {
        let p = Path::new("/nonexistent-natura-dir/x.png");
        let err = check_writable(p).unwrap_err();
        assert!(
            err.to_string().contains("/nonexistent-natura-dir/x.png"),
            "{err}"
        );
        assert!(write_bytes_atomic(p, b"x").is_err());
    }
}

pub mod exr;
pub mod glb;

/// The 64-bit FNV-1a hash of `bytes`, the checksum natura's own file
/// formats carry over their contents (the EXR files' pixels and text
/// attributes, the render crate's prepared cloud sky).
///
/// Each step (xor a byte in, multiply by an odd prime modulo 2⁶⁴) is a
/// bijection of the state, so two inputs of one length that differ in a
/// single byte always hash differently: every one-byte corruption of a
/// file whose length is checked is found.
///
/// ```
/// use natura_core::io::checksum;
/// // The published FNV-1a test vectors.
/// assert_eq!(checksum(*b""), 0xcbf2_9ce4_8422_2325);
/// assert_eq!(checksum(*b"a"), 0xaf63_dc4c_8601_ec8c);
/// assert_ne!(checksum(*b"natura"), checksum(*b"naturb"));
/// ```
#[must_use]
pub fn checksum(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xCBF2_9CE4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01B3)
    })
}
mod set;

pub use set::OutputSet;
