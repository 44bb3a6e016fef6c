//! The `natura` binary end to end: frames assembled from 1, 4 and 25 tiles
//! on 1 thread and from 1 and 4 on 2 equal a single-process render byte for byte (SHA-256
//! of the EXR and PNG); a shard re-run reproduces its hash, with or without
//! the world cache; tampered, missing and mismatched tiles, bad tile
//! arguments and a cache of another version are refused with clear errors;
//! the farm job files are well formed (and pass `openjd check` when the
//! `openjd` tool is installed).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/farm_tiny.toml");

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("farm-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn natura(threads: u32, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_natura"))
        .args(args)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .output()
        .expect("the natura binary runs")
}

fn ok(threads: u32, args: &[&str]) -> String {
    let o = natura(threads, args);
    assert!(
        o.status.success(),
        "natura {args:?} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout).unwrap()
}

/// The error text of a run that must fail.
fn fails(args: &[&str]) -> String {
    let o = natura(1, args);
    assert!(!o.status.success(), "natura {args:?} should have failed");
    String::from_utf8(o.stderr).unwrap()
}

fn sha(path: &Path) -> String {
    use sha2::Digest;
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    format!("{:x}", sha2::Sha256::digest(bytes))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn render_tiles(out: &Path, frame: u32, n: u32, threads: u32) {
    let f = frame.to_string();
    let tile = |i: u32| {
        let t = format!("{i}/{n}");
        ok(
            threads,
            &[
                "render",
                SCENE,
                "--frame",
                &f,
                "--tile",
                &t,
                "--out",
                s(out),
            ],
        );
    };
    // Tiles of one thread run two at a time, as a farm's do side by side:
    // their processes share the output folder.
    let side_by_side = if threads == 1 { 2 } else { 1 };
    let tiles: Vec<u32> = (0..n).collect();
    for pair in tiles.chunks(side_by_side) {
        std::thread::scope(|scope| {
            for &i in pair {
                scope.spawn(move || tile(i));
            }
        });
    }
}

#[test]
fn assembled_frames_equal_the_single_process_render() {
    // Frame 2: the camera and sun moved by the animation's keys.
    let frame = 2;
    let reference = scratch("reference");
    ok(
        1,
        &["render", SCENE, "--frame", "2", "--out", s(&reference)],
    );
    let want = [
        sha(&reference.join("frame_0002.exr")),
        sha(&reference.join("frame_0002.png")),
    ];
    // 1, 4 and 25 tiles on one thread (25: a 5 × 5 grid, columns of 12
    // and 13 pixels and rows of 7 and 8, so tiles of four sizes meet); on
    // two, 1 and 4 tiles (each tile is a process that prepares the frame,
    // so many tiles twice was most of this test binary's time; thread
    // independence of regions is also checked in natura-render's tests).
    for (threads, counts) in [(1, &[1, 4, 25][..]), (2, &[1, 4][..])] {
        for &n in counts {
            let out = scratch(&format!("tiles{n}-threads{threads}"));
            render_tiles(&out, frame, n, threads);
            ok(threads, &["assemble", s(&out), "--frame", "2"]);
            let got = [
                sha(&out.join("frame_0002.exr")),
                sha(&out.join("frame_0002.png")),
            ];
            assert_eq!(got, want, "{n} tiles on {threads} threads");
        }
    }
    // The reference on two threads is the same frame.
    let two = scratch("reference2");
    ok(2, &["render", SCENE, "--frame", "2", "--out", s(&two)]);
    assert_eq!(sha(&two.join("frame_0002.png")), want[1]);
}

#[test]
fn frames_of_an_animation_differ() {
    let out = scratch("frames");
    ok(1, &["render", SCENE, "--frame", "0", "--out", s(&out)]);
    ok(1, &["render", SCENE, "--frame", "1", "--out", s(&out)]);
    assert_ne!(
        sha(&out.join("frame_0000.exr")),
        sha(&out.join("frame_0001.exr"))
    );
}

fn manifest(out: &Path, frame: u32, i: u32, n: u32) -> PathBuf {
    out.join(format!("tiles/frame_{frame:04}/tile_{i:04}_of_{n:04}.json"))
}

fn tile_sha(out: &Path, i: u32, n: u32) -> String {
    let line = std::fs::read_to_string(manifest(out, 0, i, n)).unwrap();
    let v: serde_json::Value = serde_json::from_str(&line).unwrap();
    v["sha256"].as_str().unwrap().to_owned()
}

/// A tile's hash as assemble checks it: over a header naming the scene's
/// hash, the frame, the tile and the tile count, then the EXR file.
fn bound_sha(out: &Path, frame: u32, i: u32, n: u32) -> String {
    use sha2::Digest;
    let line = std::fs::read_to_string(manifest(out, frame, i, n)).unwrap();
    let v: serde_json::Value = serde_json::from_str(&line).unwrap();
    let scene = v["scene_sha256"].as_str().unwrap();
    let exr = out.join(format!("tiles/frame_{frame:04}/tile_{i:04}_of_{n:04}.exr"));
    let mut h = sha2::Sha256::new();
    h.update(format!("natura tile\nscene {scene}\nframe {frame}\ntile {i} of {n}\n\n").as_bytes());
    h.update(std::fs::read(exr).unwrap());
    format!("{:x}", h.finalize())
}

#[test]
fn a_shard_rerun_alone_reproduces_its_hash() {
    let out = scratch("rerun");
    let run = || ok(1, &["render", SCENE, "--tile", "2/4", "--out", s(&out)]);
    run();
    let first = tile_sha(&out, 2, 4);
    assert_eq!(first, bound_sha(&out, 0, 2, 4));
    run(); // from the cache
    assert_eq!(tile_sha(&out, 2, 4), first);
    std::fs::remove_dir_all(out.join("cache")).unwrap();
    run(); // the cache recomputed
    assert_eq!(tile_sha(&out, 2, 4), first);
    // On two threads, into another directory with its own cache.
    let other = scratch("rerun2");
    ok(2, &["render", SCENE, "--tile", "2/4", "--out", s(&other)]);
    assert_eq!(tile_sha(&other, 2, 4), first);
}

#[test]
fn tampered_missing_and_mismatched_tiles_are_reported_by_index() {
    let out = scratch("tamper");
    render_tiles(&out, 0, 4, 1);
    ok(1, &["assemble", s(&out)]);
    // A flipped byte in tile 1's EXR, tile 3 gone.
    let exr = out.join("tiles/frame_0000/tile_0001_of_0004.exr");
    let mut bytes = std::fs::read(&exr).unwrap();
    let k = bytes.len() - 9;
    bytes[k] ^= 0x20;
    std::fs::write(&exr, bytes).unwrap();
    std::fs::remove_file(manifest(&out, 0, 3, 4)).unwrap();
    let err = fails(&["assemble", s(&out)]);
    assert!(
        err.contains("tile 1 of 4") && err.contains("SHA-256"),
        "{err}"
    );
    assert!(err.contains("tile 3 of 4: missing"), "{err}");

    // A tile of another version, and one of another scene.
    let out = scratch("mismatch");
    render_tiles(&out, 0, 4, 1);
    let m = manifest(&out, 0, 2, 4);
    let line = std::fs::read_to_string(&m).unwrap();
    std::fs::write(&m, line.replace(env!("CARGO_PKG_VERSION"), "0.0.1")).unwrap();
    let m1 = manifest(&out, 0, 1, 4);
    let line = std::fs::read_to_string(&m1).unwrap();
    std::fs::write(&m1, line.replace(std::env::consts::ARCH, "elsewhere")).unwrap();
    let other = out.join("other.toml");
    let text = std::fs::read_to_string(SCENE)
        .unwrap()
        .replace("seed = 7", "seed = 8");
    std::fs::write(&other, text).unwrap();
    ok(1, &["render", s(&other), "--tile", "0/4", "--out", s(&out)]);
    let err = fails(&["assemble", s(&out)]);
    assert!(
        err.contains("tile 2 of 4: rendered by natura 0.0.1"),
        "{err}"
    );
    assert!(
        err.contains("tile 0 of 4: rendered from another scene"),
        "{err}"
    );
    assert!(err.contains("tile 1 of 4: rendered on elsewhere-"), "{err}");
    assert!(!out.join("frame_0000.png").exists());
}

#[test]
fn bad_arguments_and_caches_get_clear_errors() {
    let out = scratch("bad");
    let o = s(&out);
    let err = fails(&["render", SCENE, "--tile", "4/4", "--out", o]);
    assert!(err.contains("out of range"), "{err}");
    let err = fails(&["render", SCENE, "--tile", "0/0", "--out", o]);
    assert!(err.contains("N = 0"), "{err}");
    let err = fails(&["render", SCENE, "--frame", "3", "--out", o]);
    assert!(
        err.contains("frame") && err.contains("animation.frames = 3"),
        "{err}"
    );
    let err = fails(&["render", SCENE, "--tile", "0/3000", "--out", o]);
    assert!(err.contains("3000 tiles cannot cut"), "{err}");

    // A cache written by another version is refused, never used; a corrupt
    // one too. Both of frame 0's caches in turn: the world's and the frame's.
    ok(1, &["prepare", SCENE, "--frames", "0", "--out", o]);
    let mut caches: Vec<_> = std::fs::read_dir(out.join("cache"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    caches.sort();
    let names: Vec<String> = caches
        .iter()
        .map(|c| c.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.len() == 2 && names[0].starts_with("frame_") && names[1].starts_with("world_"),
        "{names:?}"
    );
    for cache in &caches {
        let bytes = std::fs::read(cache).unwrap();
        let version = format!("natura {}\n", env!("CARGO_PKG_VERSION"));
        let at = bytes
            .windows(version.len())
            .position(|w| w == version.as_bytes())
            .unwrap();
        let mut old = bytes[..at].to_vec();
        old.extend_from_slice(b"natura 0.0.1\n");
        old.extend_from_slice(&bytes[at + version.len()..]);
        std::fs::write(cache, &old).unwrap();
        let err = fails(&["render", SCENE, "--tile", "0/4", "--out", o]);
        assert!(
            err.contains("written by natura 0.0.1") && err.contains("delete it"),
            "{err}"
        );
        let mut corrupt = bytes.clone();
        let k = corrupt.len() - 5;
        corrupt[k] ^= 1;
        std::fs::write(cache, &corrupt).unwrap();
        let err = fails(&["render", SCENE, "--tile", "0/4", "--out", o]);
        assert!(err.contains("does not match its SHA-256"), "{err}");
        std::fs::write(cache, &bytes).unwrap();
    }
}

#[test]
fn farm_job_files_are_written_and_valid() {
    let out = scratch("jobs");
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
            "16",
            "--throttle",
            "2",
        ],
    );
    let render = std::fs::read_to_string(out.join("slurm/render.sbatch")).unwrap();
    assert!(render.contains("#SBATCH --array=0-47%2"), "{render}");
    assert!(render.contains("frame=$(( 0 + i / 16 ))") && render.contains("tile=$(( i % 16 ))"));
    let submit = std::fs::read_to_string(out.join("slurm/submit.sh")).unwrap();
    assert!(
        submit.contains("--dependency=afterok:$render assemble.sbatch"),
        "{submit}"
    );
    let err = fails(&[
        "farm", "slurm", SCENE, "--out", o, "--tiles", "16", "--frames", "0-3",
    ]);
    assert!(err.contains("frames 0 to 2"), "{err}");

    ok(
        1,
        &[
            "farm", "openjd", SCENE, "--out", o, "--tiles", "4", "--frames", "1-2",
        ],
    );
    let template = out.join("natura.openjd.yaml");
    assert!(!out.join("slurm/natura.openjd.yaml").exists());
    let text = std::fs::read_to_string(&template).unwrap();
    assert!(
        text.contains("range: '1-2'") && text.contains("range: '0-3'"),
        "{text}"
    );
    match Command::new("openjd").arg("check").arg(&template).output() {
        Ok(o) => assert!(
            o.status.success(),
            "openjd check: {}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ),
        Err(_) => eprintln!("openjd not installed: template checked by content only"),
    }
}

#[path = "farm/cli.rs"]
mod cli;
#[path = "farm/robust.rs"]
mod robust;
