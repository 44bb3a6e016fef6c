//! The main natura picture: an eroded fractal landscape under a physical sky.
//!
//! ```text
//! cargo run --release --example landscape                    # the built-in scene
//! cargo run --release --example landscape -- --quick         # small and fast
//! cargo run --release --example landscape -- --scene my.toml --spp 16 --out renders
//! cargo run --release --example landscape -- --print-scene > my.toml
//! cargo run --release --example landscape -- --closeup --no-detail  # the foreground without detail
//! cargo run --release --example landscape -- --no-clouds --no-textures  # clear sky, plain materials
//! cargo run --release --example landscape -- --closeup --no-forest  # the slopes without trees
//! cargo run --release --example landscape -- --no-terraces  # the eroded terrain without cliffs
//! cargo run --release --example landscape -- --help          # every flag and its default
//! ```
//!
//! Writes `landscape.png` (tone-mapped sRGB) and `landscape.exr` (linear
//! radiance) into `--out` (default: `./landscape/`), with a progress bar per
//! stage.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::render::{SceneDesc, World, render_world};

/// The main natura picture: an eroded fractal landscape under a physical
/// sky, rendered from a scene description (the built-in one unless
/// --scene). Writes landscape.png (sRGB) and landscape.exr (linear
/// radiance).
#[derive(Parser)]
#[command(name = "landscape", version)]
struct Cli {
    /// A preview in seconds: the scene's world coarsened (256 terrain
    /// samples over the same extent, fewer erosion steps, coarser clouds)
    /// in a 320 × 180 picture at 4 samples a pixel
    #[arg(long)]
    quick: bool,
    /// Print the scene as TOML (with --scene, that scene after the flags)
    /// and exit
    #[arg(long)]
    print_scene: bool,
    /// Also write the terrain's relief map and 16-bit height map
    #[arg(long)]
    maps: bool,
    /// A low camera looking down into the nearby slopes (for the detail)
    #[arg(long)]
    closeup: bool,
    /// Trace the stored terrain without detail
    #[arg(long)]
    no_detail: bool,
    /// A clear sky (no layer clouds or their shadows)
    #[arg(long)]
    no_clouds: bool,
    /// No strata or grain on the surface
    #[arg(long)]
    no_textures: bool,
    /// No cliffs and benches where the strata show (the eroded terrain as it
    /// is)
    #[arg(long)]
    no_terraces: bool,
    /// Grow no trees
    #[arg(long)]
    no_forest: bool,
    /// Scene description (TOML; --print-scene shows every key) [default:
    /// the built-in scene]
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Random seed [default: the scene's]
    #[arg(long)]
    seed: Option<u64>,
    /// Terrain samples per side; the world keeps its size in metres
    /// [default: the scene's]
    #[arg(long)]
    size: Option<usize>,
    /// Image width, pixels [default: the scene's]
    #[arg(long)]
    width: Option<u32>,
    /// Image height, pixels [default: the scene's]
    #[arg(long)]
    height: Option<u32>,
    /// Samples per pixel [default: the scene's]
    #[arg(long)]
    spp: Option<u32>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "landscape")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(landscape)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn landscape() -> Run {
    let cli: Cli = common::parse();
    let Cli {
        quick,
        print_scene: print,
        maps,
        closeup,
        no_detail,
        no_clouds,
        no_textures,
        no_terraces,
        no_forest,
        scene: scene_file,
        seed,
        size,
        width,
        height,
        spp,
        out,
    } = cli;

    let mut scene = match &scene_file {
        Some(p) => SceneDesc::load(p)?,
        None => SceneDesc::default(),
    };
    if quick {
        scene = scene.quick();
        scene.render.width = 320;
        scene.render.height = 180;
        scene.render.spp = 4;
    }
    if closeup {
        scene.camera.height_above_ground_m = 12.0;
        scene.camera.pitch_deg = -14.0;
        scene.camera.vfov_deg = 30.0;
    }
    if no_detail {
        scene.detail.enabled = false;
    }
    if no_clouds {
        scene.clouds.enabled = false;
    }
    if no_terraces {
        scene.terraces.enabled = false;
    }
    if no_textures {
        scene.textures.enabled = false;
    }
    if no_forest {
        scene.vegetation.enabled = false;
    }
    if let Some(s) = seed {
        scene.seed = s;
    }
    if let Some(s) = size {
        // Keep the world the same size in metres.
        scene.terrain.resample(s);
    }
    if let Some(w) = width {
        scene.render.width = w;
    }
    if let Some(h) = height {
        scene.render.height = h;
    }
    if let Some(s) = spp {
        scene.render.spp = s;
    }
    if print {
        // The built-in scene with its comments, which document every key.
        if scene == SceneDesc::default() {
            return common::out(natura::render::DEFAULT_SCENE_TOML);
        }
        return common::out(scene.to_toml_string()?);
    }
    scene.validate()?;
    let out = common::out_dir(&out)?;
    let png = out.join("landscape.png");
    let exr = out.join("landscape.exr");
    let relief = out.join("landscape_relief.png");
    let height = out.join("landscape_height.png");
    // The run's outputs as one set: every path is checked before minutes of
    // work, and all of them appear at the end or none does.
    let mut targets = vec![&png, &exr];
    if maps {
        targets.extend([&relief, &height]);
    }
    let set = natura::core::io::OutputSet::new(targets)?;

    let bar = common::Bar::new();
    let world = World::build(&scene, &bar)?;
    if maps {
        world.relief_map()?.save_png(set.stage(&relief)?)?;
        world
            .terrain
            .save_png16(set.stage(&height)?, world.terrain.min_max())?;
    }
    let rendered = render_world(&world, &bar)?;
    rendered.save_staged(&set, &png, &exr)?;
    set.commit()?;
    if maps {
        outln(format_args!(
            "wrote {} and {}",
            relief.display(),
            height.display()
        ))?;
    }
    for (stage, d) in &rendered.times.stages {
        outln(format_args!("{stage:>14}: {:7.2} s", d.as_secs_f64()))?;
    }
    outln(format_args!(
        "{:>14}: {:7.2} s",
        "total",
        rendered.times.total().as_secs_f64()
    ))?;
    if let Some(f) = &rendered.forest {
        outln(format_args!(
            "forest: {} plants, {} trees ({} in full detail), {} meshes of {} triangles; \
             ecosystem {:.2} s, prototypes {:.2} s, instance BVH {:.3} s",
            f.plants,
            f.instances,
            f.near,
            f.meshes,
            f.triangles,
            f.ecosystem.as_secs_f64(),
            f.prototypes.as_secs_f64(),
            f.tlas.as_secs_f64()
        ))?;
    }
    outln(format_args!("exposure {:+.2} EV", rendered.exposure_ev))?;
    outln(format_args!("wrote {}", png.display()))?;
    outln(format_args!("wrote {}", exr.display()))
}
