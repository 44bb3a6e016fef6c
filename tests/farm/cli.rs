//! The command line itself: help and version, usage errors that name the
//! flag, one meaning of `--out`, the commands of docs/farm.md run as
//! written, clean exits on signals and on a closed pipe.

use std::path::Path;
use std::process::{Command, Stdio};

use super::{SCENE, natura, ok, s, scratch};

/// Status code and standard error of a run.
fn status(args: &[&str]) -> (Option<i32>, String) {
    let o = natura(1, args);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn every_command_explains_itself() {
    let help = ok(1, &["--help"]);
    for cmd in ["render", "assemble", "prepare", "farm", "print-scene"] {
        assert!(help.contains(cmd), "{help}");
    }
    let version = ok(1, &["--version"]);
    assert_eq!(
        version.trim(),
        format!("natura {}", env!("CARGO_PKG_VERSION"))
    );
    for (args, want) in [
        (&["render", "--help"][..], "[default: 0]"),
        (&["assemble", "--help"], "--frame"),
        (&["prepare", "--help"], "--frames"),
        (&["farm", "--help"], "openjd"),
        (&["farm", "slurm", "--help"], "[default: 2]"),
        (&["farm", "openjd", "--help"], "--job-dir"),
        (&["print-scene", "--help"], "animation"),
    ] {
        let text = ok(1, args);
        assert!(
            text.contains(want) && text.contains("Usage"),
            "{args:?}: {text}"
        );
    }
    // A bare call prints the usage and fails with status 2.
    let (code, err) = status(&[]);
    assert_eq!(code, Some(2));
    assert!(err.contains("Usage") && err.contains("render"), "{err}");
}

#[test]
fn usage_errors_name_the_flag_and_exit_2() {
    let out = scratch("usage");
    let o = s(&out);
    for (args, names) in [
        (
            &["render", SCENE, "--out", o, "--frobnicate", "1"][..],
            "--frobnicate",
        ),
        (&["render", SCENE, "--out"], "--out"),
        (&["render", SCENE], "--out"),
        (&["render", SCENE, "--out", o, "--frame", "x"], "--frame"),
        (
            &["render", SCENE, "--out", o, "--frame", "1", "--frame", "2"],
            "--frame",
        ),
        (
            &["render", SCENE, "--out", o, "--tile", "0/70000"],
            "--tile",
        ),
        (
            &["farm", "slurm", SCENE, "--out", o, "--tiles", "0"],
            "--tiles",
        ),
        (
            &[
                "farm",
                "slurm",
                SCENE,
                "--out",
                o,
                "--tiles",
                "4",
                "--throttle",
                "0",
            ],
            "--throttle",
        ),
        (
            &[
                "farm", "slurm", SCENE, "--out", o, "--tiles", "4", "--dir", o,
            ],
            "--dir",
        ),
        (
            &[
                "farm", "openjd", SCENE, "--out", o, "--tiles", "4", "--file", o,
            ],
            "--file",
        ),
        (
            &["prepare", SCENE, "--out", o, "--frames", "2-1"],
            "--frames",
        ),
        (&["farm", "nomad", SCENE], "nomad"),
    ] {
        let (code, err) = status(args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains(names), "{args:?}: {err}");
    }
    let (code, err) = status(&["render", SCENE, "--out", o, "--tile", "0/70000"]);
    assert!(
        code == Some(2) && err.contains("0/70000") && err.contains("65536"),
        "{err}"
    );
}

#[test]
fn an_unwritable_out_is_refused_by_name_before_any_work() {
    let dir = scratch("unwritable");
    let file = dir.join("a-file");
    std::fs::write(&file, b"not a folder").unwrap();
    let bad = file.join("run");
    for args in [
        &["render", SCENE, "--tile", "0/4", "--out", s(&bad)][..],
        &["prepare", SCENE, "--out", s(&bad)],
        &["farm", "slurm", SCENE, "--out", s(&bad), "--tiles", "4"],
        &["farm", "openjd", SCENE, "--out", s(&bad), "--tiles", "4"],
        &[
            "farm",
            "openjd",
            SCENE,
            "--out",
            s(&dir.join("ok")),
            "--tiles",
            "4",
            "--job-dir",
            s(&bad),
        ],
    ] {
        let (code, err) = status(args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(
            err.contains(s(&bad)) && err.contains("cannot write"),
            "{args:?}: {err}"
        );
    }
    // Nothing written.
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, ["a-file"]);
}

#[test]
fn job_files_go_into_the_job_directory_for_both_engines() {
    let out = scratch("jobdir");
    let jobs = out.join("jobs");
    let o = s(&out);
    ok(
        1,
        &[
            "farm",
            "slurm",
            SCENE,
            "--out",
            o,
            "--tiles",
            "4",
            "--job-dir",
            s(&jobs),
        ],
    );
    ok(
        1,
        &[
            "farm",
            "openjd",
            SCENE,
            "--out",
            o,
            "--tiles",
            "4",
            "--job-dir",
            s(&jobs),
        ],
    );
    for f in [
        "prepare.sbatch",
        "render.sbatch",
        "assemble.sbatch",
        "submit.sh",
        "natura.openjd.yaml",
    ] {
        assert!(jobs.join(f).is_file(), "{f}");
    }
}

/// The fenced blocks of `lang` in docs/farm.md.
fn doc_blocks(lang: &str) -> Vec<String> {
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/farm.md")).unwrap();
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in doc.lines() {
        match (&mut current, line.trim_end()) {
            (None, l) if l == format!("```{lang}") => current = Some(String::new()),
            (Some(_), "```") => blocks.push(current.take().unwrap()),
            (Some(b), l) => {
                b.push_str(l);
                b.push('\n');
            }
            _ => {}
        }
    }
    blocks
}

/// The scene of docs/farm.md: `natura print-scene` with its last section,
/// `[animation]`, replaced by the doc's animation block, as the doc says.
fn doc_scene(dir: &Path) -> std::path::PathBuf {
    let printed = ok(1, &["print-scene"]);
    let at = printed
        .find("\n[animation]")
        .expect("print-scene ends with [animation]");
    let block = doc_blocks("toml")
        .into_iter()
        .find(|b| b.starts_with("[animation]"))
        .expect("docs/farm.md has an [animation] block");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, format!("{}\n{block}", &printed[..at])).unwrap();
    scene
}

#[test]
fn the_docs_animation_block_pastes_into_print_scene() {
    let dir = scratch("doc-scene");
    let scene = doc_scene(&dir);
    // The pasted scene loads: a job over its 48 frames is written.
    let out = ok(
        1,
        &[
            "farm",
            "openjd",
            s(&scene),
            "--out",
            s(&dir.join("run")),
            "--tiles",
            "4",
        ],
    );
    assert!(out.contains("natura.openjd.yaml"), "{out}");
    let text = std::fs::read_to_string(dir.join("run/natura.openjd.yaml")).unwrap();
    assert!(text.contains("range: '0-47'"), "{text}");
}

#[test]
fn the_farm_commands_of_the_docs_run_as_written() {
    let dir = scratch("doc-commands");
    doc_scene(&dir);
    let mut ran = 0;
    for block in doc_blocks("sh") {
        for line in block.lines() {
            let Some(rest) = line.strip_prefix("natura farm ") else {
                continue;
            };
            let args: Vec<&str> = rest
                .split_whitespace()
                .take_while(|w| !w.starts_with('#'))
                .collect();
            let o = Command::new(env!("CARGO_BIN_EXE_natura"))
                .arg("farm")
                .args(&args)
                .current_dir(&dir)
                .output()
                .unwrap();
            assert!(
                o.status.success(),
                "{line}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            ran += 1;
        }
    }
    assert!(ran >= 2, "docs/farm.md shows both engines");
    for f in [
        "run/slurm/submit.sh",
        "run/slurm/render.sbatch",
        "run/natura.openjd.yaml",
    ] {
        assert!(dir.join(f).is_file(), "{f}");
    }
}

/// A slow job (the tiny scene at 1024 × 576 pixels and 16 samples, whole)
/// stopped by `signal` after it started: it removes its temporary files
/// and exits with status 130.
fn interrupted(signal: &str) {
    let dir = scratch(&format!("signal-{signal}"));
    let scene = dir.join("slow.toml");
    let text = std::fs::read_to_string(SCENE)
        .unwrap()
        .replace("width = 64", "width = 1024")
        .replace("height = 36", "height = 576")
        .replace("spp = 2", "spp = 16");
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_natura"))
        .args(["render", s(&scene), "--tile", "0/1", "--out", s(&out)])
        .env("RAYON_NUM_THREADS", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Once the job has its output folder it is past start-up, with the
    // handler installed, and far from done.
    for _ in 0..600 {
        if out.join("cache").exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let k = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(k.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{signal}: {status:?}");
    let mut left = Vec::new();
    let mut stack = vec![dir.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            if e.path().is_dir() {
                stack.push(e.path());
            } else if e.file_name().to_string_lossy().starts_with(".natura-tmp") {
                left.push(e.path());
            }
        }
    }
    assert!(left.is_empty(), "{signal}: left behind {left:?}");
}

#[test]
fn sigterm_and_sigint_leave_no_temporary_files() {
    interrupted("TERM");
    interrupted("INT");
}

#[test]
fn a_closed_pipe_ends_print_scene_quietly() {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let o = Command::new(env!("CARGO_BIN_EXE_natura"))
        .arg("print-scene")
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && err.is_empty(),
        "{:?}: {err}",
        o.status
    );
    // And through a shell, as people type it.
    let sh = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "set -o pipefail; '{}' print-scene | head -1",
            env!("CARGO_BIN_EXE_natura")
        ))
        .output()
        .unwrap();
    assert!(
        sh.status.success(),
        "{}",
        String::from_utf8_lossy(&sh.stderr)
    );
    assert_eq!(String::from_utf8_lossy(&sh.stdout).lines().count(), 1);
}
