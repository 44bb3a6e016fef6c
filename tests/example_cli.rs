//! Every example's command line, run as a user runs it (the binaries
//! `cargo test` builds next to this test): `--help` exits 0 and names every
//! flag with its default; `--version` prints the crate version; an unknown
//! flag, a flag without its value and an `--out` that cannot be written are
//! errors that name the flag or the path, exit with status 2 and write
//! nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The examples, from the `examples/` folder (every `.rs` file there is one).
fn examples() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(names.len() >= 20, "examples found: {names:?}");
    names
}

/// The built example `name` (target/<profile>/examples/, beside this
/// test's own deps/ folder). A missing binary fails: `cargo test` builds
/// every example.
fn binary(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile = exe.parent().unwrap().parent().unwrap();
    let bin = profile
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(bin.is_file(), "{} was not built", bin.display());
    bin
}

fn run(name: &str, args: &[&str]) -> Output {
    Command::new(binary(name))
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// One option of clap's help: its first line and the lines that continue
/// its description.
struct Entry {
    flag: String,
    takes_value: bool,
    text: String,
}

/// The options listed in `help` (clap's `--help` layout: an option's first
/// line starts with `-x, --flag` or `--flag`, its description may wrap).
fn entries(help: &str) -> Vec<Entry> {
    let mut out: Vec<Entry> = Vec::new();
    let mut in_options = false;
    for line in help.lines() {
        if line.starts_with("Options:") {
            in_options = true;
            continue;
        }
        if line.trim().is_empty() {
            // clap's long layout separates options with blank lines.
            continue;
        }
        if !line.starts_with(' ') {
            in_options = false;
            continue;
        }
        if !in_options {
            continue;
        }
        let t = line.trim_start();
        if t.starts_with('-') {
            let long = t
                .split_whitespace()
                .find(|w| w.starts_with("--"))
                .map(|w| w.trim_end_matches(','));
            if let Some(flag) = long {
                let head = t.split("  ").next().unwrap_or(t);
                out.push(Entry {
                    flag: flag.to_owned(),
                    takes_value: head.contains('<'),
                    text: t.to_owned(),
                });
                continue;
            }
        }
        if let Some(e) = out.last_mut() {
            e.text.push(' ');
            e.text.push_str(t);
        }
    }
    out
}

#[test]
fn help_names_every_flag_with_its_default() {
    for name in examples() {
        let o = run(&name, &["--help"]);
        let help = text(&o.stdout);
        assert!(
            o.status.success(),
            "{name} --help: {:?}\n{}",
            o.status,
            text(&o.stderr)
        );
        let es = entries(&help);
        let flags: Vec<&str> = es.iter().map(|e| e.flag.as_str()).collect();
        for f in ["--help", "--version", "--out", "--quick"] {
            assert!(flags.contains(&f), "{name} --help lacks {f}:\n{help}");
        }
        for e in &es {
            if e.takes_value {
                assert!(
                    e.text.contains("[default:"),
                    "{name} --help: {} shows no default: {}",
                    e.flag,
                    e.text
                );
            }
        }
        let out = es.iter().find(|e| e.flag == "--out").unwrap();
        assert!(
            out.text.contains(&format!("[default: {name}]")),
            "{name}: --out must default to ./{name}/: {}",
            out.text
        );
        assert!(
            help.contains(&format!("Usage: {name}")),
            "{name} --help:\n{help}"
        );
    }
}

#[test]
fn version_prints_the_crate_version() {
    for name in examples() {
        let o = run(&name, &["--version"]);
        assert!(o.status.success(), "{name} --version: {:?}", o.status);
        assert_eq!(
            text(&o.stdout).trim(),
            format!("{name} {}", env!("CARGO_PKG_VERSION")),
            "{name} --version"
        );
    }
}

#[test]
fn unknown_flags_are_errors_naming_them() {
    for name in examples() {
        let o = run(&name, &["--quick", "--no-such-flag"]);
        assert_eq!(o.status.code(), Some(2), "{name} --no-such-flag");
        assert!(
            text(&o.stderr).contains("--no-such-flag"),
            "{name}: {}",
            text(&o.stderr)
        );
        assert!(
            o.stdout.is_empty(),
            "{name} wrote to stdout: {}",
            text(&o.stdout)
        );
    }
}

#[test]
fn a_flag_without_its_value_is_an_error_naming_it() {
    for name in examples() {
        let help = text(&run(&name, &["--help"]).stdout);
        for e in entries(&help).iter().filter(|e| e.takes_value) {
            let o = run(&name, &[e.flag.as_str()]);
            assert_eq!(o.status.code(), Some(2), "{name} {} (no value)", e.flag);
            let err = text(&o.stderr);
            assert!(err.contains(&e.flag), "{name} {}: {err}", e.flag);
        }
    }
}

#[test]
fn an_unwritable_out_is_an_error_naming_it_and_writes_nothing() {
    let scratch = std::env::temp_dir().join(format!("natura-example-cli-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    std::fs::create_dir_all(&scratch).unwrap();
    // A regular file where a directory is needed: creating `--out` fails
    // for every user, root included.
    let file = scratch.join("a-file");
    std::fs::write(&file, b"not a directory").unwrap();
    let out = file.join("out");
    let out_arg = out.to_str().unwrap();
    for name in examples() {
        let o = run(&name, &["--quick", "--out", out_arg]);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name} --out {out_arg}: {err}");
        assert!(
            err.contains("--out") && err.contains(out_arg),
            "{name}: {err}"
        );
        let left: Vec<_> = std::fs::read_dir(&scratch)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left.len(), 1, "{name} wrote {left:?}");
    }
    std::fs::remove_dir_all(&scratch).unwrap();
}
