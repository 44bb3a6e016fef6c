//! What an interrupt handler does: remove the temporary files of the writes
//! and output sets in flight. (A test binary of its own, so no other test's
//! temporary files are in flight at the same time.)

use natura_core::io::{OutputSet, remove_temp_files, write_bytes_atomic};

#[test]
fn interrupted_runs_can_remove_their_temporary_files() {
    let d = std::env::temp_dir().join(format!("natura-core-interrupt-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let temps = || {
        std::fs::read_dir(&d)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with(".natura-tmp"))
            .count()
    };
    let set = OutputSet::new([d.join("a.exr"), d.join("a.png")]).unwrap();
    write_bytes_atomic(set.stage(d.join("a.exr")).unwrap(), b"x").unwrap();
    assert_eq!(temps(), 1);
    // The interrupt arrives: the handler removes what is in flight and exits.
    assert_eq!(remove_temp_files(), 1);
    assert_eq!(temps(), 0);
    assert!(!d.join("a.exr").exists() && !d.join("a.png").exists());
    std::mem::forget(set);
}
