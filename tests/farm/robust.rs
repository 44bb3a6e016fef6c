//! Hostile input: paths that a shell or YAML would read as code, manifest
//! lines with impossible fields, job sizes beyond the stated limits, tiles
//! swapped between indices.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::{SCENE, fails, manifest, natura, ok, render_tiles, s, scratch};

/// A folder name holding everything a shell, Slurm or YAML treats as special.
/// (A backslash has a test of its own: Slurm refuses it in log paths.)
const HOSTILE: &str = r#"sp ace 'q' "dq" $(touch PWNED1) `touch PWNED2` %A %% #c ;x {{x}}"#;

/// Every file under `dir`.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p.clone());
            }
            out.push(p);
        }
    }
    out
}

fn no_injection(root: &Path) {
    let pwned: Vec<_> = files(root)
        .into_iter()
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("PWNED")
        })
        .collect();
    assert!(pwned.is_empty(), "a command was injected: {pwned:?}");
}

#[test]
fn job_files_quote_every_value_and_run_as_written() {
    let root = scratch("hostile");
    let weird = root.join(HOSTILE);
    std::fs::create_dir_all(&weird).unwrap();
    let scene = weird.join(format!("{HOSTILE}.toml"));
    std::fs::copy(SCENE, &scene).unwrap();
    let out = weird.join("out");
    let jobs = weird.clone();
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_natura"))
            .args(args)
            .current_dir(&root)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    let common = [
        s(&scene),
        "--out",
        s(&out),
        "--frames",
        "0",
        "--job-dir",
        s(&jobs),
    ];
    run(&[&["farm", "slurm"][..], &common, &["--tiles", "2"]].concat());
    run(&[&["farm", "openjd"][..], &common, &["--tiles", "2"]].concat());
    for f in [
        "prepare.sbatch",
        "render.sbatch",
        "assemble.sbatch",
        "submit.sh",
    ] {
        let script = jobs.join(f);
        let text = std::fs::read_to_string(&script).unwrap();
        for line in text.lines().filter(|l| l.starts_with("#SBATCH")) {
            assert!(!line.contains("sp ace"), "{f}: a path in {line}");
        }
        let check = Command::new("bash")
            .arg("-n")
            .arg(&script)
            .output()
            .unwrap();
        assert!(
            check.status.success(),
            "bash -n {f}: {}",
            String::from_utf8_lossy(&check.stderr)
        );
    }

    // submit.sh with a stand-in sbatch that records its arguments.
    let bin = root.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let record = root.join("sbatch-args");
    let fake = bin.join("sbatch");
    std::fs::write(
        &fake,
        format!(
            "#!/bin/bash\nprintf '%s\\n' \"$@\" >> '{}'\necho 42\n",
            s(&record)
        ),
    )
    .unwrap();
    Command::new("chmod").arg("+x").arg(&fake).status().unwrap();
    let path = format!("{}:{}", s(&bin), std::env::var("PATH").unwrap());
    let submitted = Command::new("bash")
        .arg(jobs.join("submit.sh"))
        .arg("--partition=x y")
        .env("PATH", &path)
        .current_dir(&root)
        .output()
        .unwrap();
    assert!(
        submitted.status.success(),
        "{}",
        String::from_utf8_lossy(&submitted.stderr)
    );
    assert_eq!(
        String::from_utf8_lossy(&submitted.stdout).trim(),
        "42 42 42"
    );
    let args = std::fs::read_to_string(&record).unwrap();
    let logs = format!("{}/logs", s(&out)).replace('%', "%%");
    assert!(
        args.contains(&format!("--output={logs}/render-%A_%a.log\n")),
        "{args}"
    );
    assert!(args.contains("--partition=x y\n"), "{args}");
    assert!(out.join("logs").is_dir());

    // The three scripts run by bash as Slurm would: a frame comes out.
    for (f, task) in [
        ("prepare", "0"),
        ("render", "0"),
        ("render", "1"),
        ("assemble", "0"),
    ] {
        let o = Command::new("bash")
            .arg(jobs.join(format!("{f}.sbatch")))
            .env("SLURM_ARRAY_TASK_ID", task)
            .env("RAYON_NUM_THREADS", "1")
            .current_dir(&root)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{f} {task}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    assert!(out.join("frame_0000.png").is_file());

    // The template: values read back exactly; `openjd check` when installed.
    let template = jobs.join("natura.openjd.yaml");
    let text = std::fs::read_to_string(&template).unwrap();
    let name = text.lines().find(|l| l.starts_with("name: ")).unwrap();
    assert!(!name.contains("{{") && !name.contains('$'), "{name}");
    let defaults: Vec<String> = text
        .lines()
        .filter_map(|l| l.strip_prefix("  default: "))
        .map(|v| serde_json::from_str(v).unwrap())
        .collect();
    let want = [
        format!("{HOSTILE}.toml"),
        "out".to_owned(),
        env!("CARGO_BIN_EXE_natura").to_owned(),
    ];
    assert_eq!(defaults, want);
    match Command::new("openjd").arg("check").arg(&template).output() {
        Ok(o) => assert!(
            o.status.success(),
            "openjd check: {}",
            String::from_utf8_lossy(&o.stderr)
        ),
        Err(_) => eprintln!("openjd not installed: template checked by content only"),
    }
    no_injection(&root);
}

#[test]
fn newlines_in_paths_are_refused_by_flag_and_nothing_is_written() {
    let root = scratch("newline");
    let scene = root.join("sc\nene.toml");
    std::fs::copy(SCENE, &scene).unwrap();
    let out = root.join("o\nut");
    for engine in ["slurm", "openjd"] {
        let o = natura(
            1,
            &["farm", engine, SCENE, "--out", s(&out), "--tiles", "2"],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("--out") && err.contains("\\n"), "{err}");
        let jobs = root.join("j\rd");
        let o = natura(
            1,
            &[
                "farm",
                engine,
                SCENE,
                "--out",
                s(&root.join("o")),
                "--tiles",
                "2",
                "--job-dir",
                s(&jobs),
            ],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            o.status.code() == Some(2) && err.contains("--job-dir"),
            "{err}"
        );
        let o = natura(
            1,
            &[
                "farm",
                engine,
                s(&scene),
                "--out",
                s(&root.join("o")),
                "--tiles",
                "2",
            ],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.code() == Some(2) && err.contains("SCENE"), "{err}");
    }
    let left: Vec<_> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, [scene.file_name().unwrap()], "written: {left:?}");
    // A backslash would turn off Slurm's %A/%a in the log file names.
    let o = natura(
        1,
        &[
            "farm",
            "slurm",
            SCENE,
            "--out",
            s(&root.join(r"a\b")),
            "--tiles",
            "2",
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.code() == Some(2) && err.contains("--out") && err.contains("backslash"),
        "{err}"
    );
}

#[test]
fn frames_times_tiles_beyond_the_limit_is_refused_by_flag() {
    let root = scratch("tasks");
    let scene = root.join("long.toml");
    let text = std::fs::read_to_string(SCENE)
        .unwrap()
        .replace("frames = 3", "frames = 1000000")
        .replace("width = 64", "width = 1024")
        .replace("height = 36", "height = 8192");
    std::fs::write(&scene, text).unwrap();
    // 1 000 000 × 4296 tasks wrap a 32-bit count.
    let o = natura(
        1,
        &[
            "farm",
            "slurm",
            s(&scene),
            "--out",
            s(&root),
            "--tiles",
            "4296",
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--frames 0-999999")
            && err.contains("--tiles 4296")
            && err.contains("4000000"),
        "{err}"
    );
    assert!(!root.join("slurm").exists());
    let o = natura(
        1,
        &[
            "farm",
            "openjd",
            s(&scene),
            "--out",
            s(&root),
            "--tiles",
            "16",
            "--frames",
            "0-999",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Rewrites field `key` of tile `i` of 4's manifest line in frame 0.
fn set_field(out: &Path, i: u32, key: &str, value: serde_json::Value) {
    let m = manifest(out, 0, i, 4);
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&m).unwrap()).unwrap();
    v[key] = value;
    std::fs::write(&m, v.to_string()).unwrap();
}

#[test]
fn impossible_manifest_fields_are_refused_by_name() {
    let out = scratch("fields");
    render_tiles(&out, 0, 4, 1);
    let line = std::fs::read_to_string(manifest(&out, 0, 0, 4)).unwrap();
    let cases: Vec<(&str, serde_json::Value, &str)> = vec![
        ("scene_sha256", "ééééééééééééé".into(), "64 lower-case hex"),
        ("sha256", "00".into(), "64 lower-case hex"),
        ("tiles", 4_294_967_295u32.into(), "1 to 65536"),
        ("tile", 9.into(), "0 to 3"),
        ("frame_width", 0.into(), "1 to 16384"),
        ("width", 100_000.into(), "pixels"),
        (
            "file",
            "../../../../etc/passwd".into(),
            "this tile's own file",
        ),
        ("platform", "x\u{1b}[31m".into(), "printable"),
    ];
    for (key, value, want) in cases {
        std::fs::write(manifest(&out, 0, 0, 4), &line).unwrap();
        set_field(&out, 0, key, value);
        let o = natura(1, &["assemble", s(&out)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{key}: {err}");
        assert!(
            err.contains(&format!("`{key}`")) && err.contains(want),
            "{key}: {err}"
        );
    }
    // An oversized manifest is refused before it is read.
    std::fs::write(manifest(&out, 0, 0, 4), vec![b' '; 70_000]).unwrap();
    let err = fails(&["assemble", s(&out)]);
    assert!(err.contains("65536 bytes"), "{err}");
}

#[test]
fn many_missing_tiles_are_reported_as_ranges() {
    let out = scratch("ranges");
    render_tiles(&out, 0, 4, 1);
    // Tile 0 claims a tiling of 64 tiles: 63 of them are missing.
    let m = manifest(&out, 0, 0, 4);
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&m).unwrap()).unwrap();
    v["tiles"] = 64.into();
    v["file"] = "tiles/frame_0000/tile_0000_of_0064.exr".into();
    for i in 1..4 {
        std::fs::remove_file(manifest(&out, 0, i, 4)).unwrap();
    }
    std::fs::remove_file(&m).unwrap();
    std::fs::write(manifest(&out, 0, 0, 64), v.to_string()).unwrap();
    let err = fails(&["assemble", s(&out)]);
    assert!(err.contains("tiles 1 to 63 of 64: missing"), "{err}");
    assert!(err.lines().count() < 10, "{err}");
}

#[test]
fn tiles_swapped_between_indices_are_refused() {
    let out = scratch("swap");
    render_tiles(&out, 0, 4, 1);
    let exr = |i: u32| out.join(format!("tiles/frame_0000/tile_{i:04}_of_0004.exr"));
    let (a, b) = (
        std::fs::read(exr(1)).unwrap(),
        std::fs::read(exr(2)).unwrap(),
    );
    assert_ne!(a, b);
    std::fs::write(exr(1), &b).unwrap();
    std::fs::write(exr(2), &a).unwrap();
    // Each manifest line takes the other's hash, as a copy would carry it.
    let sha = |i: u32| -> serde_json::Value {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(manifest(&out, 0, i, 4)).unwrap())
                .unwrap();
        v["sha256"].clone()
    };
    let (s1, s2) = (sha(1), sha(2));
    set_field(&out, 1, "sha256", s2);
    set_field(&out, 2, "sha256", s1);
    let err = fails(&["assemble", s(&out)]);
    assert!(
        err.contains("tile 1 of 4") && err.contains("tile 2 of 4") && err.contains("SHA-256"),
        "{err}"
    );
    assert!(!out.join("frame_0000.png").exists());
    let o = ok(1, &["render", SCENE, "--tile", "1/4", "--out", s(&out)]);
    assert!(o.contains("sha256"));
}
