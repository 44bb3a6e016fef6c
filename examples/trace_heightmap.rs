//! Ray traces a height map — yours or a synthetic one — with Lambert shading
//! and sun shadows, using natura-trace's maximum-mipmap tracer, and writes a PNG.
//!
//! ```text
//! cargo run --release --example trace_heightmap                    # a synthetic 1025² field
//! cargo run --release --example trace_heightmap -- --quick --out /tmp/trace
//! cargo run --release --example trace_heightmap -- --input dem.png --cell-size 30 --range 0,4000
//! cargo run --release --example trace_heightmap -- --input dem.exr --eye 500,300,2500 --target 8000,9000,1200
//! cargo run --release --example trace_heightmap -- --help          # every flag and its default
//! ```
//!
//! Writes `trace_heightmap.png` into `--out` (default: `./trace_heightmap/`),
//! with a progress bar while tracing. A 16-bit PNG maps grey 0…65535 to the
//! `--range` heights (or the range stored in the file by natura); an EXR
//! holds metres directly. Without `--eye`/`--target`, the camera stands above
//! one corner looking across the field. Without `--input`, the field is
//! synthesised from natura-core alone (heterogeneous sums of bilinearly
//! interpolated Gaussian lattices).

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::scene::{LatticeTerrain, albedo, lattice_terrain};
use common::{Run, outln};
use natura::core::glam::Vec3;
use natura::core::{HeightField, Seed};
use natura::trace::{
    Camera, Hit, MipmapTracer, OrthographicCamera, PinholeCamera, Ray, RenderOptions, Tracer,
    trace_image,
};

/// Ray traces a height map (a file, or a synthetic field made by
/// natura-core alone) with Lambert shading and sun shadows through
/// natura-trace's maximum-mipmap tracer. Writes trace_heightmap.png.
#[derive(Parser)]
#[command(name = "trace_heightmap", version)]
struct Cli {
    /// Small field and image (CI)
    #[arg(long)]
    quick: bool,
    /// Height map to load (.png 16-bit or .exr) instead of the synthetic
    /// field [default: none, the synthetic field]
    #[arg(long, value_name = "FILE")]
    input: Option<PathBuf>,
    /// Metres between samples, overriding the file's [default: the file's;
    /// for the synthetic field, what makes it 20 km across]
    #[arg(long, value_name = "METRES", allow_negative_numbers = true)]
    cell_size: Option<f32>,
    /// Heights in metres of grey 0 and 65535 in a PNG [default: the range
    /// stored in the file]
    #[arg(long, value_name = "LO,HI", value_parser = common::parse_range, allow_hyphen_values = true)]
    range: Option<(f32, f32)>,
    /// Samples per side of the synthetic field [default: 1025; 193 with
    /// --quick]
    #[arg(long)]
    size: Option<usize>,
    /// Random seed (synthetic field and pixel samples)
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Image width, pixels [default: 1280; 320 with --quick]
    #[arg(long)]
    width: Option<u32>,
    /// Image height, pixels [default: 720; 180 with --quick]
    #[arg(long)]
    height: Option<u32>,
    /// Samples per pixel [default: 4; 1 with --quick]
    #[arg(long)]
    spp: Option<u32>,
    /// Vertical field of view, degrees
    #[arg(
        long,
        value_name = "DEGREES",
        default_value_t = 40.0,
        allow_negative_numbers = true
    )]
    vfov: f32,
    /// Camera position, metres [default: above one corner of the field]
    #[arg(long, value_name = "X,Y,Z", value_parser = parse3, allow_hyphen_values = true)]
    eye: Option<Vec3>,
    /// Point looked at, metres [default: across the field from the corner]
    #[arg(long, value_name = "X,Y,Z", value_parser = parse3, allow_hyphen_values = true)]
    target: Option<Vec3>,
    /// An orthographic view straight down instead
    #[arg(long)]
    top_down: bool,
    /// Sun azimuth, degrees counterclockwise from +x
    #[arg(
        long,
        value_name = "DEGREES",
        default_value_t = 135.0,
        value_parser = common::in_range(-360.0f32, 360.0),
        allow_negative_numbers = true
    )]
    sun_azimuth: f32,
    /// Sun elevation, degrees
    #[arg(
        long,
        value_name = "DEGREES",
        default_value_t = 20.0,
        value_parser = common::in_range(-90.0f32, 90.0),
        allow_negative_numbers = true
    )]
    sun_elevation: f32,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "trace_heightmap")]
    out: PathBuf,
}

/// `X,Y,Z` as a point (the camera checks that it is finite).
fn parse3(s: &str) -> Result<Vec3, String> {
    let v = s
        .split(',')
        .map(|p| p.trim().parse::<f32>().map_err(|e| e.to_string()))
        .collect::<Result<Vec<f32>, String>>()?;
    match v[..] {
        [x, y, z] => Ok(Vec3::new(x, y, z)),
        _ => Err("needs X,Y,Z".to_owned()),
    }
}

fn main() -> ExitCode {
    common::run(trace)
}

/// The program: every error returns through [`common::run`].
fn trace() -> Run {
    let cli: Cli = common::parse();
    let quick = cli.quick;
    let size = cli.size.unwrap_or(if quick { 193 } else { 1025 });
    let width = cli.width.unwrap_or(if quick { 320 } else { 1280 });
    let height = cli.height.unwrap_or(if quick { 180 } else { 720 });
    let spp = cli.spp.unwrap_or(if quick { 1 } else { 4 });
    let (seed, vfov) = (cli.seed, cli.vfov);
    let (sun_az, sun_el) = (cli.sun_azimuth, cli.sun_elevation);
    let out = common::out_dir(&cli.out)?;

    let hf = match &cli.input {
        Some(path) => HeightField::load(path, cli.cell_size, cli.range)?,
        // Keep the synthetic landscape about 20 km across whatever its resolution.
        None => lattice_terrain(
            size,
            cli.cell_size.unwrap_or(20480.0 / (size.max(2) - 1) as f32),
            Seed(seed),
            &LatticeTerrain::HETERO,
        )?,
    };
    let bar = common::Bar::new();
    let tracer = MipmapTracer::new(&hf)?;
    let (lo, hi) = hf.min_max();
    let e = hf.extent();
    let relief = (hi - lo).max(1.0);

    let (el, az) = (sun_el.to_radians(), sun_az.to_radians());
    let sun = Vec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
    let sun_colour = Vec3::new(1.0, 0.93, 0.82) * 3.0;
    let sky_colour = Vec3::new(0.35, 0.5, 0.8);
    let haze = Vec3::new(0.62, 0.72, 0.88);
    let scene_size = e.length().max(relief);

    // Primary rays are traced a tile at a time by `trace_image` (the batch
    // path); `shade` lights each hit.
    let shade = |ray: &Ray, hit: Option<&Hit>| -> Vec3 {
        match hit.copied() {
            None => {
                let up = ray.dir.z.max(0.0);
                haze.lerp(sky_colour, up.powf(0.6))
            }
            Some(h) => {
                let n = h.smooth_normal;
                let albedo = albedo(((h.point.z - lo) / relief).clamp(0.0, 1.0), n.z);
                let lambert = n.dot(sun).max(0.0);
                let lit = if lambert > 0.0 && h.geometric_normal.dot(sun) > 0.0 {
                    // Shadow ray toward the sun, from just above the surface.
                    let o = h.point + h.geometric_normal * (1e-3 * relief + 1e-4 * scene_size);
                    !tracer.occluded(&Ray::new(o, sun), 0.0, f32::INFINITY)
                } else {
                    false
                };
                let direct = if lit {
                    sun_colour * lambert
                } else {
                    Vec3::ZERO
                };
                let ambient = sky_colour * (0.35 + 0.25 * n.z);
                let c = albedo * (direct + ambient);
                // Light aerial perspective so distance reads.
                let d = (h.t * ray.dir.length() / scene_size).min(4.0);
                c.lerp(haze, 1.0 - (-0.8 * d).exp())
            }
        }
    };

    let options = RenderOptions {
        samples_per_pixel: spp,
        seed: Seed(seed),
        ..RenderOptions::default()
    };
    let img = if cli.top_down {
        let c = Vec3::new(0.5 * e.x, 0.5 * e.y, hi + relief);
        let cam = OrthographicCamera::look_at(
            c,
            c - Vec3::Z,
            Vec3::Y,
            e.y.max(e.x * height as f32 / width as f32),
            width,
            height,
        )?;
        trace_image(&tracer, &cam, &options, &bar, shade)?
    } else {
        let eye = cli.eye.unwrap_or_else(|| {
            let (x, y) = (0.1 * e.x, 0.06 * e.y);
            let ground = hf.height_at(x, y).unwrap_or(hi);
            Vec3::new(
                x,
                y,
                ground.max(lo + 0.5 * relief) + 0.12 * relief + 0.02 * e.x,
            )
        });
        let target = cli
            .target
            .unwrap_or_else(|| Vec3::new(0.62 * e.x, 0.75 * e.y, lo + 0.3 * relief));
        let cam = PinholeCamera::look_at(eye, target, Vec3::Z, vfov.to_radians(), width, height)?;
        outln(format_args!(
            "camera at {eye}, looking at {target}, {}",
            fmt_res(&cam)
        ))?;
        trace_image(&tracer, &cam, &options, &bar, shade)?
    };
    let png = out.join("trace_heightmap.png");
    img.save_png(&png)?;
    outln(format_args!(
        "{} × {} samples, cell {} m, heights {lo:.1} … {hi:.1} m; max-mipmap {:.2} MB",
        hf.nx(),
        hf.ny(),
        hf.cell_size(),
        tracer.memory_bytes() as f64 / 1e6
    ))?;
    outln(format_args!("wrote {}", png.display()))
}

fn fmt_res(cam: &impl Camera) -> String {
    let r = cam.resolution();
    format!("{} × {} pixels", r.x, r.y)
}
