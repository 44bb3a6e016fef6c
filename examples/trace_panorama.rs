//! A 360° panorama of a synthetic landscape through Musgrave's panoramic
//! virtual screen (dissertation appendix B), optionally as a stereo pair.
//!
//! ```text
//! cargo run --release --example trace_panorama                        # 360° × 120°, spherical
//! cargo run --release --example trace_panorama -- --quick --out /tmp/panorama
//! cargo run --release --example trace_panorama -- --projection cylindrical --vfov 100
//! cargo run --release --example trace_panorama -- --stereo 40         # left and right eyes, 40 m apart
//! cargo run --release --example trace_panorama -- --help              # every flag and its default
//! ```
//!
//! Writes `trace_panorama.png` (or `trace_panorama_left.png` and
//! `trace_panorama_right.png` with `--stereo`) into `--out` (default:
//! `./trace_panorama/`), with a progress bar while tracing. Columns are equal
//! steps of azimuth; with the spherical (equirectangular) screen rows are
//! equal steps of elevation, so straight valleys bow, as in Musgrave's Valles
//! Marineris panorama (Plate 8.1).

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use clap::builder::PossibleValuesParser;
use common::scene::{LatticeTerrain, albedo, lattice_terrain};
use common::{Run, outln};
use natura::core::Seed;
use natura::core::glam::Vec3;
use natura::trace::{
    Eye, Hit, MipmapTracer, PanoramicCamera, Projection, Ray, RenderOptions, Stereo, Tracer,
    trace_image,
};

/// A panorama of a synthetic landscape (25 km across) through Musgrave's
/// panoramic virtual screen, optionally as a stereo pair. Writes
/// trace_panorama.png, or trace_panorama_left.png and
/// trace_panorama_right.png with --stereo.
#[derive(Parser)]
#[command(name = "trace_panorama", version)]
struct Cli {
    /// Small field and image (CI)
    #[arg(long)]
    quick: bool,
    /// Samples per side of the field [default: 1025; 257 with --quick]
    #[arg(long)]
    size: Option<usize>,
    /// Random seed
    #[arg(long, default_value_t = 11)]
    seed: u64,
    /// Image width, pixels (the height follows from the fields of view)
    /// [default: 2048; 384 with --quick]
    #[arg(long, value_parser = common::in_range(16u32, 16384))]
    width: Option<u32>,
    /// Horizontal field of view, degrees
    #[arg(
        long,
        value_name = "DEGREES",
        default_value_t = 360.0,
        value_parser = common::in_range(1.0f32, 360.0),
        allow_negative_numbers = true
    )]
    hfov: f32,
    /// Vertical field of view, degrees
    #[arg(
        long,
        value_name = "DEGREES",
        default_value_t = 120.0,
        value_parser = common::in_range(1.0f32, 180.0),
        allow_negative_numbers = true
    )]
    vfov: f32,
    /// The virtual screen: rows in equal steps of elevation (spherical) or
    /// of its tangent (cylindrical)
    #[arg(
        long,
        default_value = "spherical",
        value_parser = PossibleValuesParser::new(["spherical", "cylindrical"])
    )]
    projection: String,
    /// Render a stereo pair with this eye separation, metres [default: one
    /// view, no pair]
    #[arg(long, value_name = "METRES", allow_negative_numbers = true)]
    stereo: Option<f32>,
    /// Samples per pixel [default: 2; 1 with --quick]
    #[arg(long)]
    spp: Option<u32>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "trace_panorama")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(panorama)
}

/// The program: every error returns through [`common::run`].
fn panorama() -> Run {
    let cli: Cli = common::parse();
    let quick = cli.quick;
    let size = cli.size.unwrap_or(if quick { 257 } else { 1025 });
    let seed = cli.seed;
    let width = cli.width.unwrap_or(if quick { 384 } else { 2048 });
    let (hfov, vfov) = (cli.hfov, cli.vfov);
    let proj = cli.projection;
    let stereo = cli.stereo;
    let spp = cli.spp.unwrap_or(if quick { 1 } else { 2 });
    let projection = match proj.as_str() {
        "cylindrical" => Projection::Cylindrical,
        _ => Projection::Spherical,
    };
    let out = common::out_dir(&cli.out)?;

    let height = ((width as f32 * vfov / hfov).round() as u32).max(1);
    let hf = lattice_terrain(
        size,
        25600.0 / (size.max(2) - 1) as f32,
        Seed(seed),
        &LatticeTerrain::HETERO,
    )?;
    let tracer = MipmapTracer::new(&hf)?;
    let (lo, hi) = hf.min_max();
    let relief = (hi - lo).max(1.0);
    let e = hf.extent();
    let (x, y) = (0.5 * e.x, 0.45 * e.y);
    let eye = Vec3::new(x, y, hf.height_at(x, y).unwrap_or(hi) + 0.15 * relief);

    let sun = Vec3::new(-0.5, 0.6, 0.35).normalize();
    let sky = Vec3::new(0.35, 0.5, 0.8);
    let haze = Vec3::new(0.65, 0.74, 0.88);
    let scene = e.length();
    // Primary rays are traced a tile at a time by `trace_image` (the batch
    // path); `shade` lights each hit.
    let shade = |ray: &Ray, hit: Option<&Hit>| -> Vec3 {
        match hit.copied() {
            None => haze.lerp(sky, ray.dir.z.max(0.0).powf(0.5)),
            Some(h) => {
                let n = h.smooth_normal;
                let albedo = albedo(((h.point.z - lo) / relief).clamp(0.0, 1.0), n.z);
                let o = h.point + h.geometric_normal * (1e-3 * relief);
                let lit =
                    n.dot(sun) > 0.0 && !tracer.occluded(&Ray::new(o, sun), 0.0, f32::INFINITY);
                let direct = if lit {
                    Vec3::new(3.0, 2.8, 2.5) * n.dot(sun)
                } else {
                    Vec3::ZERO
                };
                let c = albedo * (direct + sky * (0.35 + 0.25 * n.z));
                c.lerp(haze, 1.0 - (-2.5 * h.t / scene).exp())
            }
        }
    };
    let camera = PanoramicCamera::new(
        eye,
        Vec3::new(1.0, 0.4, 0.0),
        Vec3::Z,
        hfov.to_radians(),
        vfov.to_radians(),
        projection,
        width,
        height,
    )?;
    let options = RenderOptions {
        samples_per_pixel: spp,
        seed: Seed(seed),
        ..RenderOptions::default()
    };
    let bar = common::Bar::new();
    let views: Vec<(&str, PanoramicCamera)> = match stereo {
        None => vec![("trace_panorama.png", camera)],
        Some(sep) => vec![
            (
                "trace_panorama_left.png",
                camera.with_stereo(Stereo {
                    eye: Eye::Left,
                    separation: sep,
                })?,
            ),
            (
                "trace_panorama_right.png",
                camera.with_stereo(Stereo {
                    eye: Eye::Right,
                    separation: sep,
                })?,
            ),
        ],
    };
    for (name, cam) in views {
        let img = trace_image(&tracer, &cam, &options, &bar, shade)?;
        let path = out.join(name);
        img.save_png(&path)?;
        outln(format_args!(
            "wrote {} ({width} × {height}, {proj})",
            path.display()
        ))?;
    }
    Ok(())
}
