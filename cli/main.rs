//! `natura`: render scenes as deterministic shards that any farm can run.
//!
//! ```text
//! natura render SCENE.toml [--frame F] [--tile I/N] --out DIR [--cache DIR]
//! natura assemble DIR [--frame F]
//! natura prepare SCENE.toml --out DIR [--frames A-B] [--cache DIR]
//! natura farm slurm SCENE.toml --out DIR --tiles N [--frames A-B] [--throttle K] [--cpus C] [--dir D]
//! natura farm openjd SCENE.toml --out DIR --tiles N [--frames A-B] [--file T]
//! natura print-scene
//! ```
//!
//! A tile is a pure function of scene, frame, tile, seed and version;
//! `assemble` checks every tile's SHA-256 and writes the frame byte for byte
//! as a single-process `render` without `--tile` writes it. See docs/farm.md.

mod cache;
mod error;
mod farm;
mod manifest;
mod shard;
mod tiles;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use error::{CliError, Result};

const USAGE: &str = "\
natura — render scenes as deterministic shards that any farm can run

usage:
  natura render SCENE.toml [--frame F] [--tile I/N] --out DIR [--cache DIR]
      without --tile: the whole frame in this process (DIR/frame_FFFF.{exr,png});
      with --tile: tile I of N (DIR/tiles/frame_FFFF/tile_IIII_of_NNNN.{exr,json})
  natura assemble DIR [--frame F]
      check every tile's SHA-256 and write DIR/frame_FFFF.{exr,png} (all frames by default)
  natura prepare SCENE.toml --out DIR [--frames A-B] [--cache DIR]
      compute (or check) the world cache shared by every tile and frame, and
      the frame cache (clouds, forest) each frame's tiles share (all frames by default)
  natura farm slurm SCENE.toml --out DIR --tiles N [--frames A-B] [--throttle K] [--cpus C] [--dir D]
      write D (default DIR/slurm): prepare/render/assemble .sbatch and submit.sh
  natura farm openjd SCENE.toml --out DIR --tiles N [--frames A-B] [--file T]
      write an Open Job Description template T (default DIR/natura.openjd.yaml)
  natura print-scene
      print the built-in scene with every key documented (including [animation])

The cache directory defaults to DIR/cache. Threads: RAYON_NUM_THREADS.
";

/// The arguments after the command: positionals and `--flag value` pairs.
struct Args {
    positional: Vec<String>,
    flags: Vec<(String, String)>,
}

impl Args {
    fn parse(args: &[String]) -> Result<Self> {
        let (mut positional, mut flags) = (Vec::new(), Vec::new());
        let mut it = args.iter();
        while let Some(a) = it.next() {
            if let Some(name) = a.strip_prefix("--") {
                let v = it
                    .next()
                    .ok_or_else(|| CliError::usage(format!("--{name} needs a value")))?;
                flags.push((name.to_owned(), v.clone()));
            } else {
                positional.push(a.clone());
            }
        }
        Ok(Self { positional, flags })
    }

    /// Takes flag `name`, refusing it twice.
    fn take(&mut self, name: &str) -> Result<Option<String>> {
        let mut found = None;
        while let Some(i) = self.flags.iter().position(|(n, _)| n == name) {
            if found.is_some() {
                return Err(CliError::usage(format!("--{name} given twice")));
            }
            found = Some(self.flags.remove(i).1);
        }
        Ok(found)
    }

    fn number(&mut self, name: &str) -> Result<Option<u32>> {
        self.take(name)?
            .map(|v| {
                v.parse().map_err(|_| {
                    CliError::usage(format!("--{name} {v:?}: expected a whole number"))
                })
            })
            .transpose()
    }

    fn path(&mut self, name: &str) -> Result<PathBuf> {
        self.take(name)?
            .map(PathBuf::from)
            .ok_or_else(|| CliError::usage(format!("--{name} is required")))
    }

    /// The only positional argument, named `what`; refuses leftovers.
    fn finish(self, what: &str) -> Result<PathBuf> {
        if let Some((n, _)) = self.flags.first() {
            return Err(CliError::usage(format!("unknown option --{n}")));
        }
        match &self.positional[..] {
            [one] => Ok(PathBuf::from(one)),
            [] => Err(CliError::usage(format!("missing {what}"))),
            more => Err(CliError::usage(format!(
                "unexpected arguments {:?}",
                &more[1..]
            ))),
        }
    }
}

fn cache_dir(args: &mut Args, out: &Path) -> Result<PathBuf> {
    Ok(args
        .take("cache")?
        .map_or_else(|| out.join("cache"), PathBuf::from))
}

fn mkdir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| crate::error::io(dir, e))
}

fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).map_err(|e| crate::error::io(p, e))
}

fn run(argv: &[String]) -> Result<()> {
    let Some((cmd, rest)) = argv.split_first() else {
        return Err(CliError::usage("no command"));
    };
    let mut a = Args::parse(rest)?;
    match cmd.as_str() {
        "render" => {
            let frame = a.number("frame")?.unwrap_or(0);
            let tile = a.take("tile")?.map(|t| tiles::parse_tile(&t)).transpose()?;
            let out = a.path("out")?;
            let cache = cache_dir(&mut a, &out)?;
            let scene = shard::Scene::load(&a.finish("scene file")?)?;
            mkdir(&out)?;
            match tile {
                None => println!(
                    "wrote {}",
                    shard::render_frame(&scene, frame, &out)?.display()
                ),
                Some((i, n)) => {
                    let line = shard::render_tile(&scene, frame, i, n, &out, &cache)?;
                    println!(
                        "frame {frame} tile {i}/{n}: {} sha256 {}",
                        line.file, line.sha256
                    );
                }
            }
        }
        "assemble" => {
            let frame = a.number("frame")?;
            let out = a.finish("output directory")?;
            let frames = match frame {
                Some(f) => vec![f],
                None => shard::frames_present(&out)?,
            };
            if frames.is_empty() {
                return Err(CliError::Other(format!(
                    "no frames under {}",
                    out.join("tiles").display()
                )));
            }
            let mut problems = Vec::new();
            for f in frames {
                match shard::assemble(&out, f) {
                    Ok(png) => println!("wrote {}", png.display()),
                    Err(CliError::Assemble(p)) => problems.extend(p),
                    Err(e) => return Err(e),
                }
            }
            if !problems.is_empty() {
                return Err(CliError::Assemble(problems));
            }
        }
        "prepare" => {
            let out = a.path("out")?;
            let cache = cache_dir(&mut a, &out)?;
            let frames = a.take("frames")?;
            let scene = shard::Scene::load(&a.finish("scene file")?)?;
            let total = scene.desc.animation.frames;
            let (first, last) = match frames {
                None => (0, total - 1),
                Some(f) => parse_frames(&f)?,
            };
            check_frames(first, last, total)?;
            let prepared = shard::prepare(&scene, &cache, first, last)?;
            let (world, source) = &prepared.world;
            println!("world cache {} ({source:?})", world.display());
            for (frame, path, source) in &prepared.frames {
                println!("frame {frame}: frame cache {} ({source:?})", path.display());
            }
        }
        "farm" => {
            let Some(engine) = a.positional.first().cloned() else {
                return Err(CliError::usage("farm: which engine? slurm or openjd"));
            };
            a.positional.remove(0);
            let out = absolute(&a.path("out")?)?;
            let n = a
                .number("tiles")?
                .ok_or_else(|| CliError::usage("--tiles is required"))?;
            let frames = a.take("frames")?;
            let throttle = a.number("throttle")?.unwrap_or(2);
            let cpus = a.number("cpus")?.unwrap_or(1);
            let target = a.take("dir")?.or(a.take("file")?);
            let scene_path = absolute(&a.finish("scene file")?)?;
            let scene = shard::Scene::load(&scene_path)?;
            let total = scene.desc.animation.frames;
            let (first, last) = match frames {
                None => (0, total - 1),
                Some(f) => parse_frames(&f)?,
            };
            check_frames(first, last, total)?;
            let r = &scene.desc.render;
            tiles::grid(r.width, r.height, n)?;
            if throttle == 0 || cpus == 0 {
                return Err(CliError::usage("--throttle and --cpus must be at least 1"));
            }
            let natura = std::env::current_exe().map_err(|e| CliError::Other(e.to_string()))?;
            let job = farm::Job {
                natura,
                scene: scene_path,
                out: out.clone(),
                first,
                last,
                tiles: n,
                throttle,
                cpus,
            };
            match engine.as_str() {
                "slurm" => {
                    let dir = target.map_or_else(|| out.join("slurm"), PathBuf::from);
                    mkdir(&dir)?;
                    for (name, text) in farm::slurm(&job) {
                        let p = dir.join(name);
                        natura::core::io::write_bytes_atomic(&p, text.as_bytes())?;
                        #[cfg(unix)]
                        {
                            use std::os::unix::fs::PermissionsExt;
                            std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755))
                                .map_err(|e| error::io(&p, e))?;
                        }
                        println!("wrote {}", p.display());
                    }
                }
                "openjd" => {
                    let file = absolute(
                        &target.map_or_else(|| out.join("natura.openjd.yaml"), PathBuf::from),
                    )?;
                    let dir = file.parent().unwrap_or(Path::new("/"));
                    mkdir(dir)?;
                    natura::core::io::write_bytes_atomic(
                        &file,
                        farm::openjd(&job, dir).as_bytes(),
                    )?;
                    println!("wrote {}", file.display());
                }
                other => {
                    return Err(CliError::usage(format!(
                        "farm {other:?}: expected slurm or openjd"
                    )));
                }
            }
        }
        "print-scene" => print!("{}", natura::render::DEFAULT_SCENE_TOML),
        "help" | "--help" | "-h" => print!("{USAGE}"),
        other => return Err(CliError::usage(format!("unknown command {other:?}"))),
    }
    Ok(())
}

/// Parses `A-B` (or `A`) into an inclusive frame range.
fn check_frames(first: u32, last: u32, total: u32) -> Result<()> {
    if last >= total {
        return Err(CliError::usage(format!(
            "--frames {first}-{last}: the scene has frames 0 to {}",
            total - 1
        )));
    }
    Ok(())
}

fn parse_frames(text: &str) -> Result<(u32, u32)> {
    let bad = || CliError::usage(format!("--frames {text:?}: expected A-B or A"));
    let (a, b) = text.split_once('-').unwrap_or((text, text));
    let (a, b): (u32, u32) = (a.parse().map_err(|_| bad())?, b.parse().map_err(|_| bad())?);
    if a > b {
        return Err(bad());
    }
    Ok((a, b))
}

fn main() -> ExitCode {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    match run(&argv) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("natura: error: {e}");
            ExitCode::from(if matches!(e, CliError::Usage(_)) {
                2
            } else {
                1
            })
        }
    }
}
