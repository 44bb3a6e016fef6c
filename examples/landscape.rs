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
//! ```
//!
//! Writes `landscape.png` (tone-mapped sRGB) and `landscape.exr` (linear
//! radiance) into `--out` (default: the current directory), with a progress
//! bar per stage.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use common::{Run, outln};
use natura::render::{SceneDesc, World, render_world};

fn main() -> ExitCode {
    common::run(landscape)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn landscape() -> Run {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small terrain and image (CI)");
    let print = args.switch("--print-scene", "print the scene as TOML and exit");
    let maps = args.switch(
        "--maps",
        "also write the terrain's relief map and 16-bit height map",
    );
    let closeup = args.switch(
        "--closeup",
        "a low camera looking down into the nearby slopes (for the detail)",
    );
    let no_detail = args.switch("--no-detail", "trace the stored terrain without detail");
    let no_clouds = args.switch(
        "--no-clouds",
        "a clear sky (no layer clouds or their shadows)",
    );
    let no_textures = args.switch("--no-textures", "no strata or grain on the surface");
    let no_terraces = args.switch(
        "--no-terraces",
        "no cliffs and benches where the strata show (the eroded terrain as it is)",
    );
    let no_forest = args.switch("--no-forest", "grow no trees");
    let scene_file: Option<PathBuf> = args.optional("--scene", "scene description (TOML)");
    let seed: Option<u64> = args.optional("--seed", "random seed");
    let size: Option<usize> = args.optional("--size", "terrain samples per side");
    let width: Option<u32> = args.optional("--width", "image width, pixels");
    let height: Option<u32> = args.optional("--height", "image height, pixels");
    let spp: Option<u32> = args.optional("--spp", "samples per pixel");
    let out = args.out_dir(".");
    args.finish();

    let mut scene = match &scene_file {
        Some(p) => SceneDesc::load(p)?,
        None => SceneDesc::default(),
    };
    if quick {
        scene.terrain.size = 256;
        scene.terrain.cell_size_m *= 8.0;
        scene.erosion.stream_power_steps = scene.erosion.stream_power_steps.min(5);
        scene.erosion.hydraulic_steps = scene.erosion.hydraulic_steps.min(20);
        scene.erosion.thermal_steps = scene.erosion.thermal_steps.min(5);
        scene.render.width = 320;
        scene.render.height = 180;
        scene.render.spp = 1;
        scene.clouds.voxel_m *= 4.0;
        scene.clouds.shadow_cell_m *= 4.0;
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
        scene.terrain.cell_size_m *= scene.terrain.size as f32 / s as f32;
        scene.terrain.size = s;
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
