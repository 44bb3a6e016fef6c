//! The examples' clean-up guard (`examples/common`): whatever ends a program
//! after it has staged its outputs — an error returned through `run`, an
//! error that exits through `fail`, SIGTERM — leaves no staged or
//! half-written file behind. The exits run in a child process (this test
//! binary, re-run on one ignored test), so the guard is tested as the
//! examples use it.

#[path = "../examples/common/mod.rs"]
#[allow(unused_imports)]
mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use natura::core::io::{OutputSet, WriteError, write_atomic, write_bytes_atomic};

/// The variable naming the child's directory and way out.
const CHILD: &str = "NATURA_CLEANUP_CHILD";

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("natura-cleanup-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every file left in `dir`.
fn left(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect()
}

/// A landscape-like run: both outputs staged, the PNG written, then the
/// EXR's write fails as on a full disk.
fn stage_then_fail(dir: &Path) -> Result<OutputSet, common::Exit> {
    let (png, exr) = (dir.join("a.png"), dir.join("a.exr"));
    let set = OutputSet::new([&png, &exr])?;
    write_bytes_atomic(set.stage(&png)?, b"png")?;
    write_atomic(set.stage(&exr)?, |w| {
        use std::io::Write;
        w.write_all(b"half an exr")?;
        Err(WriteError::Io(std::io::Error::other(
            "No space left on device",
        )))
    })?;
    Ok(set)
}

#[test]
fn an_error_returned_through_run_leaves_nothing() {
    let dir = scratch("run");
    let code = common::run(|| {
        let set = stage_then_fail(&dir)?;
        set.commit()?;
        Ok(())
    });
    assert_eq!(code, std::process::ExitCode::from(2));
    assert_eq!(left(&dir), Vec::<String>::new());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs this binary's `child` test with `way` out, and returns its exit
/// status and the files it left.
fn run_child(way: &str) -> (Option<i32>, Vec<String>) {
    let dir = scratch(way);
    let status = Command::new(std::env::current_exe().unwrap())
        .args([
            "child",
            "--exact",
            "--ignored",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD, format!("{way}:{}", dir.display()))
        .status()
        .unwrap();
    let files = left(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    (status.code(), files)
}

#[test]
fn an_exit_through_fail_leaves_nothing() {
    let (code, files) = run_child("fail");
    assert_eq!(code, Some(2));
    assert_eq!(files, Vec::<String>::new());
}

#[test]
fn a_term_signal_leaves_nothing() {
    let (code, files) = run_child("term");
    assert_eq!(code, Some(130));
    assert_eq!(files, Vec::<String>::new());
}

/// The child: stages and writes an output, then leaves by the way its
/// parent asked for.
#[test]
#[ignore = "run by the tests above in a child process"]
fn child() {
    let Ok(spec) = std::env::var(CHILD) else {
        return;
    };
    let (way, dir) = spec.split_once(':').unwrap();
    let dir = PathBuf::from(dir);
    common::install_interrupt_cleanup();
    let png = dir.join("b.png");
    let set = OutputSet::new([&png]).unwrap();
    write_bytes_atomic(set.stage(&png).unwrap(), b"png").unwrap();
    assert_eq!(left(&dir).len(), 1, "the staged file exists");
    match way {
        "fail" => common::fail("No space left on device"),
        "term" => {
            let pid = std::process::id().to_string();
            Command::new("kill").args(["-TERM", &pid]).status().unwrap();
            // The handler exits; a child still here after a minute fails.
            std::thread::sleep(std::time::Duration::from_secs(60));
            std::mem::forget(set);
            std::process::exit(3);
        }
        _ => unreachable!("{way}"),
    }
}

/// Flag errors print numbers as a person reads them, never three hundred
/// digits for a 1e300 the user typed.
#[test]
fn numbers_in_flag_errors_are_short() {
    assert_eq!(common::short(1e300f64), "1e300");
    assert_eq!(common::short(-1e30f32), "-1e30");
    assert_eq!(common::short(2.5f64), "2.5");
    assert_eq!(common::short(1.5e-7f64), "1.5e-7");
    assert_eq!(common::short(0.0f32), "0");
}
