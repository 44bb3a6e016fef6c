//! `natura`: render scenes as deterministic shards that any farm can run.
//!
//! ```text
//! natura render SCENE.toml [--frame F] [--tile I/N] --out DIR [--cache DIR]
//! natura assemble DIR [--frame F]
//! natura prepare SCENE.toml --out DIR [--frames A-B] [--cache DIR]
//! natura farm slurm SCENE.toml --out DIR --tiles N [--frames A-B] [--throttle K] [--cpus C] [--job-dir D]
//! natura farm openjd SCENE.toml --out DIR --tiles N [--frames A-B] [--job-dir D]
//! natura print-scene
//! ```
//!
//! A tile is a pure function of scene, frame, tile, seed and version;
//! `assemble` checks every tile's SHA-256 and writes the frame byte for byte
//! as a single-process `render` without `--tile` writes it. See docs/farm.md.

mod cache;
mod check;
mod error;
mod farm;
mod interrupt;
mod limits;
mod manifest;
mod progress;
mod shard;
mod tiles;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

use error::{CliError, Result};
use interrupt::say;
use limits::{MAX_TASKS, MAX_TILES};

/// natura: render scenes as deterministic shards that any farm can run.
///
/// A tile is a pure function of scene, frame, tile, seed and version;
/// `assemble` checks every tile's SHA-256 and writes the frame byte for
/// byte as a single-process render writes it. Threads per process:
/// RAYON_NUM_THREADS (the result does not depend on it). See docs/farm.md.
#[derive(Debug, Parser)]
#[command(name = "natura", version, arg_required_else_help = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Render a whole frame (DIR/frame_FFFF.{exr,png}), or with --tile one
    /// tile of it (DIR/tiles/frame_FFFF/tile_IIII_of_NNNN.{exr,json})
    Render(RenderArgs),
    /// Check every tile's SHA-256 and write DIR/frame_FFFF.{exr,png}
    Assemble(AssembleArgs),
    /// Compute (or check) the world cache shared by every tile and frame,
    /// and the frame cache (clouds, forest) each frame's tiles share
    Prepare(PrepareArgs),
    /// Write the job files of a farm engine
    #[command(subcommand, arg_required_else_help = true)]
    Farm(Farm),
    /// Print the built-in scene with every key documented (its last
    /// section is [animation])
    PrintScene,
}

#[derive(Debug, Args)]
struct RenderArgs {
    /// The scene file (TOML; `natura print-scene` shows every key)
    scene: PathBuf,
    /// The frame to render
    #[arg(long, value_name = "F", default_value_t = 0)]
    frame: u32,
    /// Render only tile I of N (0 ≤ I < N ≤ 65536)
    #[arg(long, value_name = "I/N", value_parser = tiles::parse_tile)]
    tile: Option<(u32, u32)>,
    /// The output directory
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// The cache directory [default: DIR/cache]
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct AssembleArgs {
    /// The output directory the tiles were rendered into
    dir: PathBuf,
    /// The frame to assemble [default: every frame under DIR/tiles]
    #[arg(long, value_name = "F")]
    frame: Option<u32>,
}

#[derive(Debug, Args)]
struct PrepareArgs {
    /// The scene file
    scene: PathBuf,
    /// The output directory
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// The frames to prepare, A-B or A [default: every frame of the scene]
    #[arg(long, value_name = "A-B", value_parser = parse_frames)]
    frames: Option<(u32, u32)>,
    /// The cache directory [default: DIR/cache]
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
enum Farm {
    /// Write prepare/render/assemble .sbatch scripts and submit.sh into
    /// --job-dir [default: DIR/slurm]
    Slurm(SlurmArgs),
    /// Write an Open Job Description template natura.openjd.yaml into
    /// --job-dir [default: DIR]
    Openjd(FarmArgs),
}

#[derive(Debug, Args)]
struct FarmArgs {
    /// The scene file
    scene: PathBuf,
    /// The output directory the farm renders into (a folder every node sees)
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Tiles per frame
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_TILES)))]
    tiles: u32,
    /// The frames to render, A-B or A [default: every frame of the scene]
    #[arg(long, value_name = "A-B", value_parser = parse_frames)]
    frames: Option<(u32, u32)>,
    /// The directory the job files are written into [default: DIR/slurm
    /// for Slurm, DIR for Open Job Description]
    #[arg(long, value_name = "D")]
    job_dir: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct SlurmArgs {
    #[command(flatten)]
    job: FarmArgs,
    /// Most render tasks running at once (the array's %K)
    #[arg(long, value_name = "K", default_value_t = 2, value_parser = clap::value_parser!(u32).range(1..))]
    throttle: u32,
    /// CPUs (and threads) per task
    #[arg(long, value_name = "C", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=4096))]
    cpus: u32,
}

/// Parses `A-B` (or `A`) into an inclusive frame range.
fn parse_frames(text: &str) -> std::result::Result<(u32, u32), String> {
    let bad = || {
        format!(
            "expected A-B or A with 0 ≤ A ≤ B < {}",
            manifest::MAX_FRAMES
        )
    };
    let (a, b) = text.split_once('-').unwrap_or((text, text));
    let (a, b): (u32, u32) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if a > b || b >= manifest::MAX_FRAMES {
        return Err(bad());
    }
    Ok((a, b))
}

/// The frames `range` (all frames of a scene of `total` when `None`),
/// checked against the scene.
fn frames(range: Option<(u32, u32)>, total: u32) -> Result<(u32, u32)> {
    let (first, last) = range.unwrap_or((0, total.saturating_sub(1)));
    if last >= total {
        return Err(CliError::usage(format!(
            "--frames {first}-{last}: the scene has frames 0 to {}",
            total.saturating_sub(1)
        )));
    }
    Ok((first, last))
}

/// Makes the directory `dir` (given as `flag`) and checks a file can be
/// written in it, before any work: an error names the flag and the path.
fn writable_dir(dir: &Path, flag: &str) -> Result<()> {
    let refuse = |e: &dyn std::fmt::Display| {
        CliError::usage(format!("{flag} {}: cannot write there: {e}", dir.display()))
    };
    std::fs::create_dir_all(dir).map_err(|e| refuse(&e))?;
    natura::core::io::check_writable(dir.join("natura-probe")).map_err(|e| refuse(&e))
}

fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).map_err(|e| crate::error::io(p, e))
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(a) => {
            let scene = shard::Scene::load(&a.scene)?;
            writable_dir(&a.out, "--out")?;
            match a.tile {
                None => say(&format!(
                    "wrote {}\n",
                    shard::render_frame(&scene, a.frame, &a.out, &progress::Bar::new())?.display()
                ))?,
                Some((i, n)) => {
                    let cache = a.cache.unwrap_or_else(|| a.out.join("cache"));
                    writable_dir(&cache, "--cache")?;
                    let line = shard::render_tile(
                        &scene,
                        a.frame,
                        i,
                        n,
                        &a.out,
                        &cache,
                        &progress::Bar::new(),
                    )?;
                    say(&format!(
                        "frame {} tile {i}/{n}: {} sha256 {}\n",
                        a.frame, line.file, line.sha256
                    ))?;
                }
            }
        }
        Command::Assemble(a) => {
            let frames = match a.frame {
                Some(f) => vec![f],
                None => shard::frames_present(&a.dir)?,
            };
            if frames.is_empty() {
                return Err(CliError::Other(format!(
                    "no frames under {}",
                    a.dir.join("tiles").display()
                )));
            }
            writable_dir(&a.dir, "DIR")?;
            let mut problems = Vec::new();
            for f in frames {
                match shard::assemble(&a.dir, f) {
                    Ok(png) => say(&format!("wrote {}\n", png.display()))?,
                    Err(CliError::Assemble(p)) => problems.extend(p),
                    Err(e) => return Err(e),
                }
            }
            if !problems.is_empty() {
                return Err(CliError::Assemble(problems));
            }
        }
        Command::Prepare(a) => {
            let scene = shard::Scene::load(&a.scene)?;
            let (first, last) = frames(a.frames, scene.desc.animation.frames)?;
            let cache = a.cache.unwrap_or_else(|| a.out.join("cache"));
            writable_dir(&a.out, "--out")?;
            writable_dir(&cache, "--cache")?;
            let prepared = shard::prepare(&scene, &cache, first, last, &progress::Bar::new())?;
            let (world, source) = &prepared.world;
            say(&format!("world cache {} ({source:?})\n", world.display()))?;
            for (frame, path, source) in &prepared.frames {
                say(&format!(
                    "frame {frame}: frame cache {} ({source:?})\n",
                    path.display()
                ))?;
            }
        }
        Command::Farm(engine) => farm_files(engine)?,
        Command::PrintScene => say(natura::render::DEFAULT_SCENE_TOML)?,
    }
    Ok(())
}

/// `natura farm slurm|openjd`: checks the job against the scene and the
/// stated limits, then writes its job files into the job directory.
fn farm_files(engine: Farm) -> Result<()> {
    let (name, a, throttle, cpus) = match engine {
        Farm::Slurm(s) => ("slurm", s.job, s.throttle, s.cpus),
        Farm::Openjd(j) => ("openjd", j, 1, 1),
    };
    let scene_path = absolute(&a.scene)?;
    let scene = shard::Scene::load(&scene_path)?;
    let (first, last) = frames(a.frames, scene.desc.animation.frames)?;
    let r = &scene.desc.render;
    tiles::grid(r.width, r.height, a.tiles)?;
    let tasks = (u64::from(last - first) + 1) * u64::from(a.tiles);
    if tasks > MAX_TASKS {
        return Err(CliError::usage(format!(
            "--frames {first}-{last} × --tiles {}: {tasks} render tasks; a job holds at most \
             {MAX_TASKS} (Slurm's largest array): split it into ranges of frames",
            a.tiles
        )));
    }
    let out = absolute(&a.out)?;
    let given_job_dir = a.job_dir.is_some();
    let job_dir = absolute(&a.job_dir.unwrap_or_else(|| match name {
        "slurm" => out.join("slurm"),
        _ => out.clone(),
    }))?;
    let natura = std::env::current_exe().map_err(|e| CliError::Other(e.to_string()))?;
    let job = farm::Job {
        natura,
        scene: scene_path,
        out,
        job_dir,
        first,
        last,
        tiles: a.tiles,
        throttle,
        cpus,
    };
    farm::check(&job, name)?;
    let files = match name {
        "slurm" => farm::slurm(&job)?,
        _ => vec![("natura.openjd.yaml", farm::openjd(&job)?)],
    };
    // A job directory given apart from --out is checked first, so a bad
    // one leaves no new output folder behind.
    if given_job_dir {
        writable_dir(&job.job_dir, "--job-dir")?;
        writable_dir(&job.out, "--out")?;
    } else {
        writable_dir(&job.out, "--out")?;
        writable_dir(&job.job_dir, "--job-dir")?;
    }
    for (file, text) in files {
        let p = job.job_dir.join(file);
        natura::core::io::write_bytes_atomic(&p, text.as_bytes())?;
        #[cfg(unix)]
        if name == "slurm" {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755))
                .map_err(|e| error::io(&p, e))?;
        }
        say(&format!("wrote {}\n", p.display()))?;
    }
    Ok(())
}

fn main() -> ExitCode {
    interrupt::install();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version go to standard output (status 0), usage
            // errors to standard error (status 2); a closed pipe is ignored.
            let _ = e.print();
            return ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2));
        }
    };
    match run(cli) {
        Ok(()) | Err(CliError::Closed) => ExitCode::SUCCESS,
        Err(e) => {
            use std::io::Write as _;
            let _ = writeln!(std::io::stderr(), "natura: error: {e}");
            ExitCode::from(if matches!(e, CliError::Usage(_)) {
                2
            } else {
                1
            })
        }
    }
}
