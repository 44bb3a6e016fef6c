//! A 360° panorama of a synthetic landscape through Musgrave's panoramic
//! virtual screen (dissertation appendix B), optionally as a stereo pair.
//!
//! ```text
//! cargo run --release --example trace_panorama                        # 360° × 120°, spherical
//! cargo run --release --example trace_panorama -- --projection cylindrical --vfov 100
//! cargo run --release --example trace_panorama -- --stereo 40         # left and right eyes, 40 m apart
//! ```
//!
//! Columns are equal steps of azimuth; with the spherical (equirectangular)
//! screen rows are equal steps of elevation, so straight valleys bow, as in
//! Musgrave's Valles Marineris panorama (Plate 8.1).

mod common;

use common::scene::{LatticeTerrain, albedo, lattice_terrain};
use natura::core::Seed;
use natura::core::glam::Vec3;
use natura::trace::{
    Eye, Hit, MipmapTracer, PanoramicCamera, Projection, Ray, RenderOptions, Stereo, Tracer,
    trace_image,
};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let size: usize = args.value("--size", if quick { 257 } else { 1025 }, "samples per side");
    let seed: u64 = args.value("--seed", 11, "random seed");
    let width: u32 = args.ranged(
        "--width",
        if quick { 384 } else { 2048 },
        16..=16384,
        "image width, pixels",
    );
    let hfov: f32 = args.ranged(
        "--hfov",
        360.0,
        1.0..=360.0,
        "horizontal field of view, degrees",
    );
    let vfov: f32 = args.ranged(
        "--vfov",
        120.0,
        1.0..=180.0,
        "vertical field of view, degrees",
    );
    let proj: String = args.value(
        "--projection",
        "spherical".to_string(),
        "spherical | cylindrical",
    );
    let stereo: Option<f32> = args.optional(
        "--stereo",
        "render a stereo pair with this eye separation, metres",
    );
    let spp: u32 = args.value("--spp", if quick { 1 } else { 2 }, "samples per pixel");
    let out = args.out_dir("docs/gallery/trace");
    args.finish();

    let projection = match proj.as_str() {
        "spherical" => Projection::Spherical,
        "cylindrical" => Projection::Cylindrical,
        other => common::fail(&format!(
            "unknown projection `{other}` (spherical | cylindrical)"
        )),
    };
    let height = ((width as f32 * vfov / hfov).round() as u32).max(1);
    let hf = common::check(lattice_terrain(
        size,
        25600.0 / (size.max(2) - 1) as f32,
        Seed(seed),
        &LatticeTerrain::HETERO,
    ));
    let tracer = common::check(MipmapTracer::new(&hf));
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
    let camera = common::check(PanoramicCamera::new(
        eye,
        Vec3::new(1.0, 0.4, 0.0),
        Vec3::Z,
        hfov.to_radians(),
        vfov.to_radians(),
        projection,
        width,
        height,
    ));
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
                common::check(camera.with_stereo(Stereo {
                    eye: Eye::Left,
                    separation: sep,
                })),
            ),
            (
                "trace_panorama_right.png",
                common::check(camera.with_stereo(Stereo {
                    eye: Eye::Right,
                    separation: sep,
                })),
            ),
        ],
    };
    for (name, cam) in views {
        let img = common::check(trace_image(&tracer, &cam, &options, &bar, shade));
        let path = out.join(name);
        common::check(img.save_png(&path));
        println!("wrote {} ({width} × {height}, {proj})", path.display());
    }
}
