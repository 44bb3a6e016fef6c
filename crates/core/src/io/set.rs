//! Outputs written as a set: all of them appear, or none.

use std::path::{Path, PathBuf};

use super::{check_writable, temp_path, track, untrack};
use crate::error::{CoreError, Result};

/// The files one run writes, staged under temporary names and renamed into
/// place together by [`commit`](OutputSet::commit).
///
/// A run that fails, panics or is dropped before `commit` leaves none of its
/// outputs and none of its temporary files behind, and never a new EXR beside
/// an old PNG. Every target is checked for writability when the set is made,
/// before any long computation.
///
/// ```
/// # fn main() -> natura_core::Result<()> {
/// let dir = std::env::temp_dir().join(format!("natura-doc-set-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let (png, txt) = (dir.join("a.png"), dir.join("a.txt"));
/// let set = natura_core::io::OutputSet::new([&png, &txt])?;
/// natura_core::io::write_bytes_atomic(set.stage(&txt)?, b"hello")?;
/// natura_core::io::write_bytes_atomic(set.stage(&png)?, b"not really a png")?;
/// assert!(!txt.exists(), "nothing appears before commit");
/// set.commit()?;
/// assert_eq!(std::fs::read(&txt).unwrap(), b"hello");
/// # Ok(()) }
/// ```
#[derive(Debug)]
pub struct OutputSet {
    /// (final path, staging path)
    entries: Vec<(PathBuf, PathBuf)>,
}

impl OutputSet {
    /// Declares the set's targets and checks that each can be written.
    ///
    /// # Errors
    ///
    /// Returns the errors of [`check_writable`] for the first target that
    /// cannot be written, and [`CoreError::Format`] if a target is named twice.
    pub fn new<P: AsRef<Path>>(targets: impl IntoIterator<Item = P>) -> Result<Self> {
        let mut entries: Vec<(PathBuf, PathBuf)> = Vec::new();
        for t in targets {
            let t = t.as_ref();
            if entries.iter().any(|(p, _)| p == t) {
                return Err(CoreError::format(t, "named twice in one output set"));
            }
            check_writable(t)?;
            let tmp = temp_path(t);
            track(&tmp);
            entries.push((t.to_path_buf(), tmp));
        }
        Ok(Self { entries })
    }

    /// The staging path to write `target` to (its file name ends like the
    /// target's, so encoders that look at the extension behave the same).
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Format`] naming `target` if it is not one of the
    /// set's targets.
    pub fn stage(&self, target: impl AsRef<Path>) -> Result<&Path> {
        let target = target.as_ref();
        self.entries
            .iter()
            .find(|(p, _)| p == target)
            .map(|(_, tmp)| tmp.as_path())
            .ok_or_else(|| CoreError::format(target, "not a target of this output set"))
    }

    /// The targets, in the order given.
    pub fn targets(&self) -> impl Iterator<Item = &Path> {
        self.entries.iter().map(|(p, _)| p.as_path())
    }

    /// Renames every staged file into place.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::Format`] naming the first target that was never
    /// written (then nothing is renamed), or [`CoreError::Io`] if a rename
    /// fails (the targets renamed before it stay; the rest are removed).
    pub fn commit(mut self) -> Result<()> {
        if let Some((p, _)) = self.entries.iter().find(|(_, tmp)| !tmp.is_file()) {
            return Err(CoreError::format(p, "was never written"));
        }
        let entries = std::mem::take(&mut self.entries);
        for (k, (p, tmp)) in entries.iter().enumerate() {
            let r = std::fs::rename(tmp, p);
            untrack(tmp);
            if let Err(e) = r {
                for (_, rest) in &entries[k..] {
                    let _ = std::fs::remove_file(rest);
                    untrack(rest);
                }
                return Err(CoreError::io(p, e));
            }
        }
        Ok(())
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        for (_, tmp) in &self.entries {
            let _ = std::fs::remove_file(tmp);
            untrack(tmp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("natura-core-set-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn leftovers(d: &Path) -> Vec<String> {
        std::fs::read_dir(d)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with(".natura-tmp"))
            .collect()
    }

    #[test]
    fn all_or_nothing() {
        let d = dir("all");
        let (a, b) = (d.join("a.exr"), d.join("a.png"));
        std::fs::write(&b, b"old png").unwrap();
        {
            let set = OutputSet::new([&a, &b]).unwrap();
            super::super::write_bytes_atomic(set.stage(&a).unwrap(), b"new exr").unwrap();
            // The run fails before the PNG: dropping the set keeps the old PNG
            // alone, with no new EXR beside it and no temporary files.
        }
        assert!(!a.exists());
        assert_eq!(std::fs::read(&b).unwrap(), b"old png");
        assert!(leftovers(&d).is_empty(), "{:?}", leftovers(&d));

        let set = OutputSet::new([&a, &b]).unwrap();
        super::super::write_bytes_atomic(set.stage(&a).unwrap(), b"exr").unwrap();
        // Committing before every file is written is refused, and cleans up.
        assert!(set.commit().unwrap_err().to_string().contains("a.png"));
        assert!(!a.exists() && leftovers(&d).is_empty());

        let set = OutputSet::new([&a, &b]).unwrap();
        super::super::write_bytes_atomic(set.stage(&a).unwrap(), b"exr").unwrap();
        super::super::write_bytes_atomic(set.stage(&b).unwrap(), b"png").unwrap();
        set.commit().unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), b"exr");
        assert_eq!(std::fs::read(&b).unwrap(), b"png");
        assert!(leftovers(&d).is_empty());
    }

    #[test]
    fn bad_targets_are_refused_up_front() {
        let d = dir("bad");
        let sub = d.join("x.png");
        std::fs::create_dir_all(&sub).unwrap();
        let e = OutputSet::new([&sub]).unwrap_err().to_string();
        assert!(e.contains("directory"), "{e}");
        let e = OutputSet::new([d.join("y"), d.join("y")])
            .unwrap_err()
            .to_string();
        assert!(e.contains("twice"), "{e}");
        assert!(OutputSet::new([Path::new("/nonexistent-natura/z.png")]).is_err());
        let set = OutputSet::new([d.join("ok.bin")]).unwrap();
        assert!(set.stage(d.join("other.bin")).is_err());
        drop(set);
        assert!(leftovers(&d).is_empty());
    }
}
