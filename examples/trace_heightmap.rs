//! Ray traces a height map — yours or a synthetic one — with Lambert shading
//! and sun shadows, using natura-trace's maximum-mipmap tracer, and writes a PNG.
//!
//! ```text
//! cargo run --release --example trace_heightmap                    # a synthetic 1024² field
//! cargo run --release --example trace_heightmap -- --input dem.png --cell-size 30 --range 0,4000
//! cargo run --release --example trace_heightmap -- --input dem.exr --eye 500,300,2500 --target 8000,9000,1200
//! ```
//!
//! A 16-bit PNG maps grey 0…65535 to the `--range` heights (or the range
//! stored in the file by natura); an EXR holds metres directly. Without
//! `--eye`/`--target`, the camera stands above one corner looking across the
//! field. Without `--input`, the field is synthesised from natura-core alone
//! (heterogeneous sums of bilinearly interpolated Gaussian lattices).

mod common;

use common::scene::{LatticeTerrain, albedo, lattice_terrain};
use natura::core::glam::Vec3;
use natura::core::{HeightField, Seed};
use natura::trace::{
    Camera, Hit, MipmapTracer, OrthographicCamera, PinholeCamera, Ray, RenderOptions, Tracer,
    trace_image,
};

fn parse3(s: &str, flag: &str) -> Vec3 {
    let v: Vec<f32> = s
        .split(',')
        .map(|p| common::check(p.trim().parse::<f32>()))
        .collect();
    if v.len() != 3 {
        common::fail(&format!("{flag} needs X,Y,Z"));
    }
    Vec3::new(v[0], v[1], v[2])
}

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let input: Option<std::path::PathBuf> =
        args.optional("--input", "height map to load (.png 16-bit or .exr)");
    let cell: Option<f32> =
        args.optional("--cell-size", "metres between samples (overrides the file)");
    let range: Option<String> = args.optional("--range", "LO,HI metres for grey 0 and 65535 (PNG)");
    let size: usize = args.value(
        "--size",
        if quick { 193 } else { 1025 },
        "samples per side (synthetic)",
    );
    let seed: u64 = args.value("--seed", 7, "random seed (synthetic)");
    let width: u32 = args.value(
        "--width",
        if quick { 320 } else { 1280 },
        "image width, pixels",
    );
    let height: u32 = args.value(
        "--height",
        if quick { 180 } else { 720 },
        "image height, pixels",
    );
    let spp: u32 = args.value("--spp", if quick { 1 } else { 4 }, "samples per pixel");
    let vfov: f32 = args.value("--vfov", 40.0, "vertical field of view, degrees");
    let eye: Option<String> = args.optional("--eye", "camera position X,Y,Z metres");
    let target: Option<String> = args.optional("--target", "point looked at X,Y,Z metres");
    let ortho = args.switch("--top-down", "orthographic view straight down instead");
    let sun_az: f32 = args.value(
        "--sun-azimuth",
        135.0,
        "sun azimuth, degrees counterclockwise from +x",
    );
    let sun_el: f32 = args.value("--sun-elevation", 20.0, "sun elevation, degrees");
    let out = args.out_dir("docs/gallery/trace");
    args.finish();

    let range = range.map(|r| {
        let v: Vec<f32> = r
            .split(',')
            .map(|s| common::check(s.trim().parse::<f32>()))
            .collect();
        if v.len() != 2 {
            common::fail("--range needs LO,HI");
        }
        (v[0], v[1])
    });
    let hf = match &input {
        Some(path) => common::check(HeightField::load(path, cell, range)),
        // Keep the synthetic landscape about 20 km across whatever its resolution.
        None => common::check(lattice_terrain(
            size,
            cell.unwrap_or(20480.0 / (size.max(2) - 1) as f32),
            Seed(seed),
            &LatticeTerrain::HETERO,
        )),
    };
    let bar = common::Bar::new();
    let tracer = common::check(MipmapTracer::new(&hf));
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
    let img = if ortho {
        let c = Vec3::new(0.5 * e.x, 0.5 * e.y, hi + relief);
        let cam = common::check(OrthographicCamera::look_at(
            c,
            c - Vec3::Z,
            Vec3::Y,
            e.y.max(e.x * height as f32 / width as f32),
            width,
            height,
        ));
        common::check(trace_image(&tracer, &cam, &options, &bar, shade))
    } else {
        let eye = eye.map(|s| parse3(&s, "--eye")).unwrap_or_else(|| {
            let (x, y) = (0.1 * e.x, 0.06 * e.y);
            let ground = hf.height_at(x, y).unwrap_or(hi);
            Vec3::new(
                x,
                y,
                ground.max(lo + 0.5 * relief) + 0.12 * relief + 0.02 * e.x,
            )
        });
        let target = target
            .map(|s| parse3(&s, "--target"))
            .unwrap_or_else(|| Vec3::new(0.62 * e.x, 0.75 * e.y, lo + 0.3 * relief));
        let cam = common::check(PinholeCamera::look_at(
            eye,
            target,
            Vec3::Z,
            vfov.to_radians(),
            width,
            height,
        ));
        println!("camera at {eye}, looking at {target}, {}", fmt_res(&cam));
        common::check(trace_image(&tracer, &cam, &options, &bar, shade))
    };
    let png = out.join("trace_heightmap.png");
    common::check(img.save_png(&png));
    println!(
        "{} × {} samples, cell {} m, heights {lo:.1} … {hi:.1} m; max-mipmap {:.2} MB",
        hf.nx(),
        hf.ny(),
        hf.cell_size(),
        tracer.memory_bytes() as f64 / 1e6
    );
    println!("wrote {}", png.display());
}

fn fmt_res(cam: &impl Camera) -> String {
    let r = cam.resolution();
    format!("{} × {} pixels", r.x, r.y)
}
